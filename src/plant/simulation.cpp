#include "clearshape/plant/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <cvode/cvode.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/series.hpp"
#include "engine.hpp"

namespace clearshape::plant {

using detail::Engine;
using detail::Sample;

std::string_view to_string(ContactMode mode) noexcept {
  switch (mode) {
    case ContactMode::free: return "free";
    case ContactMode::contact: return "contact";
    case ContactMode::persistent: return "persistent";
    case ContactMode::locked: return "locked";
  }
  return "unknown";
}

std::string_view to_string(EventKind kind) noexcept {
  switch (kind) {
    case EventKind::onset: return "onset";
    case EventKind::separation: return "separation";
    case EventKind::impact: return "impact";
    case EventKind::lock: return "lock";
    case EventKind::release: return "release";
    case EventKind::rate_switch: return "rate_switch";
    case EventKind::zeno: return "zeno";
  }
  return "unknown";
}

void SolverOptions::validate() const {
  require_in_open("solver.relative_tolerance", relative_tolerance, 0.0, 0.1,
                  "typical values are 1e-6 … 1e-10");
  require_positive("solver.angle_tolerance_rad", angle_tolerance_rad);
  require_positive("solver.rate_tolerance_rad_s", rate_tolerance_rad_s);
  require_positive("solver.length_tolerance_m", length_tolerance_m);
  require_positive("solver.speed_tolerance_m_s", speed_tolerance_m_s);
  require_non_negative("solver.max_step_s", max_step_s, "0 means unlimited");
  require_in_closed("solver.max_steps_per_output", static_cast<double>(max_steps_per_output), 1.0,
                    1e12);
  require_in_closed("solver.max_total_steps", static_cast<double>(max_total_steps), 1.0, 1e15);
  require_in_closed("solver.zeno_events", zeno_events, 2.0, 100000.0,
                    "the number of contact onsets within zeno_window_s that means persistence");
  require_positive("solver.zeno_window_s", zeno_window_s);
  require_in_half_open("solver.release_gap_fraction", release_gap_fraction, 0.0, 1.0);
}

void SimulationOptions::validate() const {
  require_positive("duration_s", duration_s);
  require_positive("output_rate_hz", output_rate_hz, "e.g. 1000 (thesis logging rate)");
  if (duration_s * output_rate_hz > 1e9) {
    throw_invalid("output_rate_hz", output_rate_hz, "<= 1e9 samples over the run",
                  "shorten the run or lower the output rate");
  }
  solver.validate();
}

double Simulation::energy_balance_j(std::size_t k) const {
  if (k >= kinetic_energy_j.size()) throw InvalidArgument("energy_balance_j: sample out of range");
  return kinetic_energy_j[k] + potential_energy_j[k] + contact_energy_j[k] - drive_work_j[k] +
         dissipated_energy_j[k];
}

namespace detail {

void EventLog::push(const ContactEvent& e) noexcept {
  ++count;
  if (!out_) return;
  if (bounded_ && out_->size() >= out_->capacity()) return;
  try {
    out_->push_back(e);
  } catch (...) {
  }
}

void ZenoGuard::configure(int events, double window_s) {
  times_.assign(static_cast<std::size_t>(events), 0.0);
  window_s_ = window_s;
  clear();
}

bool ZenoGuard::onset(double t) noexcept {
  if (times_.empty()) return false;
  const std::size_t cap = times_.size();
  times_[head_] = t;
  head_ = (head_ + 1) % cap;
  count_ = std::min(count_ + 1, cap);
  if (count_ < cap) return false;
  const double oldest = times_[head_];  // the slot about to be overwritten
  if (t - oldest <= window_s_) {
    clear();
    return true;
  }
  return false;
}

}  // namespace detail

namespace {

struct StopContext {
  const Command* command = nullptr;
  Engine* engine = nullptr;
  double delay_s = 0.0;
  double duration_s = 0.0;
  double next_after(double t) const noexcept {
    const double next = command->next_discontinuity_s(t - delay_s) + delay_s;
    return next <= duration_s ? next : std::numeric_limits<double>::infinity();
  }
};

void on_command_stop(void* context, double t, detail::JointSystem& system) {
  auto* c = static_cast<StopContext*>(context);
  system.input.held = c->command->value(t - c->delay_s);
  c->engine->set_next_stop(c->next_after(t));
}

void append(Simulation& r, double t, double command, const Sample& s, bool planar, bool energy) {
  r.time_s.push_back(t);
  r.command.push_back(command);
  r.motor_angle_rad.push_back(s.motor_angle);
  r.motor_rate_rad_s.push_back(s.motor_rate);
  r.link_angle_rad.push_back(s.link_angle);
  r.link_rate_rad_s.push_back(s.link_rate);
  r.relative_angle_rad.push_back(s.relative_angle);
  r.contact_torque_n_m.push_back(s.contact_torque);
  r.penetration.push_back(s.penetration);
  r.normal_force.push_back(s.normal_force);
  r.mode.push_back(static_cast<std::uint8_t>(s.mode));
  if (planar) {
    r.pivot_x_m.push_back(s.pivot_x);
    r.pivot_y_m.push_back(s.pivot_y);
    r.friction_force_n.push_back(s.friction_force);
  }
  if (!energy) return;
  r.kinetic_energy_j.push_back(s.kinetic);
  r.potential_energy_j.push_back(s.potential);
  r.contact_energy_j.push_back(s.contact_energy);
  r.dissipated_energy_j.push_back(s.dissipated);
  r.drive_work_j.push_back(s.drive_work);
}

bool finite_sample(const Sample& s) noexcept {
  return std::isfinite(s.motor_angle) && std::isfinite(s.motor_rate) &&
         std::isfinite(s.link_angle) && std::isfinite(s.link_rate) &&
         std::isfinite(s.normal_force) && std::isfinite(s.penetration);
}

}  // namespace

Simulation simulate(const PlantModel& model, const Command& command,
                    const SimulationOptions& options) {
  options.validate();
  Simulation result;
  Engine engine(model, options.solver, options.record_events ? &result.events : nullptr, false);
  auto& input = engine.system().input;
  input.delay_s = model.drive.delay_s();
  input.command = &command;
  input.use_held = command.interpolation() == Interpolation::zero_order_hold;
  input.held = command.value(-input.delay_s);
  StopContext ctx{&command, &engine, input.delay_s, options.duration_s};
  if (input.use_held) engine.on_stop(on_command_stop, &ctx);
  engine.start(options.initial);
  if (input.use_held) engine.set_next_stop(ctx.next_after(0.0));

  const double dt = 1.0 / options.output_rate_hz;
  const std::size_t n = sample_count(options.duration_s, dt);
  const bool planar = std::holds_alternative<PlanarClearance>(model.joint);
  for (auto* v : {&result.time_s, &result.command, &result.motor_angle_rad,
                  &result.motor_rate_rad_s, &result.link_angle_rad, &result.link_rate_rad_s,
                  &result.relative_angle_rad, &result.contact_torque_n_m, &result.penetration,
                  &result.normal_force}) {
    v->reserve(n);
  }
  if (options.record_energy) {
    for (auto* v : {&result.kinetic_energy_j, &result.potential_energy_j, &result.contact_energy_j,
                    &result.dissipated_energy_j, &result.drive_work_j}) {
      v->reserve(n);
    }
  }
  // Output sampling from CVODE's dense output: one interpolation per output time within each
  // internal step (CV_ONE_STEP) instead of one CVode call per output; an output that falls on
  // an event or command stop is taken after it (right-continuous, as the rig's hold).
  Sample s;
  const auto output_time = [&](std::size_t k) { return static_cast<double>(k) / options.output_rate_hz; };
  const auto emit = [&](double t, const double* y) {
    engine.system().sample(t, y, s);
    if (!finite_sample(s)) {
      throw RuntimeError("plant simulation diverged: non-finite output at " +
                         engine.system().describe(t, y) +
                         "; reduce the contact stiffness K or damping D, or tighten the tolerances");
    }
    append(result, t, engine.system().input.value(t), s, planar, options.record_energy);
  };
  emit(0.0, engine.state());
  const double t_end = output_time(n - 1);
  std::size_t k = 1;
  long steps_since_output = 0;
  while (k < n) {
    if (++steps_since_output > options.solver.max_steps_per_output) {
      throw RuntimeError(engine.failure(CV_TOO_MUCH_WORK));  // CVODE's mxstep, per output
    }
    double t_reached = 0.0;
    int flag = engine.step_begin(t_end, t_reached);
    if (flag < 0) throw RuntimeError(engine.failure(flag));
    if (k < n && output_time(k) <= t_reached + 1e-12 * std::max(1.0, std::abs(t_reached))) {
      steps_since_output = 0;
    }
    const double at_tol = 1e-12 * std::max(1.0, std::abs(t_reached));
    for (; k < n && output_time(k) < t_reached - at_tol; ++k) {
      const double* y = engine.interpolate(output_time(k));
      if (y == nullptr) throw RuntimeError(engine.failure(flag));
      emit(output_time(k), y);
    }
    flag = engine.step_finish();
    if (flag < 0) throw RuntimeError(engine.failure(flag));
    if (k < n && output_time(k) <= t_reached + at_tol) {
      const double t = output_time(k);
      // a discontinuity falling on this output time is taken now (right-continuous hold)
      if (input.use_held && input.held != command.value(t - input.delay_s)) {
        const int f2 = engine.set_held_input(command.value(t - input.delay_s));
        if (f2 < 0) throw RuntimeError(engine.failure(f2));
        engine.set_next_stop(ctx.next_after(t));
      }
      emit(t, engine.state());
      ++k;
    }
  }
  result.stats = engine.stats();
  return result;
}

// ---------------------------------------------------------------------------------------------
struct Simulator::Impl {
  Impl(const PlantModel& model, const SolverOptions& options)
      : engine(model, options, &events, true), planar(std::holds_alternative<PlanarClearance>(model.joint)) {
    events.reserve(4096);
  }
  std::vector<ContactEvent> events;
  Engine engine;
  bool planar;
  State state{};
  SolverStats stats{};
  std::string error;
  void refresh() noexcept {
    Sample s;
    const double t = engine.time_s();
    engine.system().sample(t, engine.state(), s);
    state.time_s = t;
    state.command = engine.system().input.held;
    state.motor_angle_rad = s.motor_angle;
    state.motor_rate_rad_s = s.motor_rate;
    state.link_angle_rad = s.link_angle;
    state.link_rate_rad_s = s.link_rate;
    state.relative_angle_rad = s.relative_angle;
    state.penetration = s.penetration;
    state.normal_force = s.normal_force;
    state.contact_torque_n_m = s.contact_torque;
    state.mode = s.mode;
    stats = engine.stats();
  }
};

Simulator::Simulator(const PlantModel& model, const SolverOptions& options,
                     const InitialState& initial, double initial_command)
    : impl_(std::make_unique<Impl>(model, options)) {
  reset(initial, initial_command);
}

Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

void Simulator::reset(const InitialState& initial, double initial_command) {
  require_finite("initial_command", initial_command);
  auto& input = impl_->engine.system().input;
  input.use_held = true;
  input.held = initial_command;
  impl_->events.clear();
  impl_->error.clear();
  impl_->engine.start(initial);
  impl_->refresh();
}

Status Simulator::advance(double t_end_s, double command) noexcept {
  if (!std::isfinite(command)) return Status::not_finite;
  if (!(t_end_s > impl_->engine.time_s())) return Status::out_of_range;
  int flag = impl_->engine.set_held_input(command);
  if (flag >= 0) flag = impl_->engine.run_to(t_end_s);
  if (flag < 0) {
    try {
      impl_->error = impl_->engine.failure(flag);
    } catch (...) {
    }
    return Status::device_error;
  }
  impl_->refresh();
  return Status::ok;
}

const Simulator::State& Simulator::state() const noexcept { return impl_->state; }
const SolverStats& Simulator::stats() const noexcept { return impl_->stats; }
const std::vector<ContactEvent>& Simulator::events() const noexcept { return impl_->events; }
void Simulator::clear_events() noexcept { impl_->events.clear(); }
const std::string& Simulator::error_message() const noexcept { return impl_->error; }

// ---------------------------------------------------------------------------------------------
SingleImpact single_impact(const ContactLaw& law, double effective_mass, double approach_rate,
                           const SolverOptions& options) {
  require_positive("effective_mass", effective_mass);
  require_positive("approach_rate", approach_rate);
  const double n = law.exponent();
  const double k = law.stiffness();
  // elastic scales: δ_max = ((n+1) m v₀²/(2K))^(1/(n+1)), t_c ≈ 3.2 δ_max/v₀ (B2)
  const double d_max = std::pow((n + 1.0) * effective_mass * approach_rate * approach_rate / (2.0 * k),
                                1.0 / (n + 1.0));
  const double t_c = 3.3 * d_max / approach_rate;
  PlantModel model;
  model.drive = DriveModel::first_order_position(1.0);  // at rest: the stop does not move
  model.link = Link{};
  model.link.inertia_kg_m2 = effective_mass;
  TorsionalClearance joint;
  joint.half_play_rad = 0.01 * d_max;  // small: δ = φ − β keeps its precision
  joint.law = law;
  model.joint = joint;
  SolverOptions o = options;
  o.angle_tolerance_rad = std::min(o.relative_tolerance, 1e-8) * 1e-2 * d_max;
  o.rate_tolerance_rad_s = std::min(o.relative_tolerance, 1e-8) * 1e-2 * approach_rate;
  o.zeno_events = std::max(o.zeno_events, 1000);
  std::vector<ContactEvent> events;
  Engine engine(model, o, &events, false);
  engine.system().input.held = 0.0;
  InitialState init;
  const double flight = 0.01 * d_max;
  init.relative_angle_rad = joint.half_play_rad - flight;
  init.link_rate_rad_s = approach_rate;
  engine.start(init);

  SingleImpact out;
  Sample s;
  double t = 0.0;
  bool in_contact_seen = false;
  const double fine = t_c / 4000.0;
  const double coarse = t_c / 40.0;
  const double t_end = 500.0 * t_c;
  double prev_d[2] = {-1.0, -1.0};  // δ at the two previous samples
  double prev_f[2] = {0.0, 0.0};
  bool have_prev = false;
  double step = fine;
  while (t < t_end) {
    step = t < 20.0 * t_c ? fine : coarse;
    const double t_next = t + step;
    const long events_before = engine.events();
    const int flag = engine.run_to(t_next);
    if (flag < 0) throw RuntimeError(engine.failure(flag));
    t = t_next;
    engine.system().sample(t, engine.state(), s);
    const double d = s.penetration;
    const double f = s.normal_force;
    if (d > 0.0) in_contact_seen = true;
    // peaks by parabolic refinement over three equally spaced samples
    if (have_prev && step == fine && prev_d[1] >= prev_d[0] && prev_d[1] >= d && prev_d[1] > 0.0) {
      const double den = prev_d[0] - 2.0 * prev_d[1] + d;
      const double p = den != 0.0 ? 0.5 * (prev_d[0] - d) / den : 0.0;
      out.max_penetration = std::max(out.max_penetration, prev_d[1] - 0.25 * (prev_d[0] - d) * p);
    }
    if (have_prev && step == fine && prev_f[1] >= prev_f[0] && prev_f[1] >= f && prev_f[1] > 0.0) {
      const double den = prev_f[0] - 2.0 * prev_f[1] + f;
      const double p = den != 0.0 ? 0.5 * (prev_f[0] - f) / den : 0.0;
      out.max_force = std::max(out.max_force, prev_f[1] - 0.25 * (prev_f[0] - f) * p);
    }
    out.max_penetration = std::max(out.max_penetration, d);
    out.max_force = std::max(out.max_force, f);
    out.min_force = std::min(out.min_force, f);
    prev_d[0] = prev_d[1];
    prev_d[1] = d;
    prev_f[0] = prev_f[1];
    prev_f[1] = f;
    have_prev = true;
    if (engine.events() > events_before && in_contact_seen && s.mode == ContactMode::free) {
      break;  // separated (the separation event was logged in this interval)
    }
  }
  engine.system().sample(t, engine.state(), s);
  const double v_out = -(s.link_rate - s.motor_rate);  // outward rate after separation
  out.separated = s.mode == ContactMode::free && s.penetration < 0.0;
  // exit rate: constant in free flight, so the rate at t equals the rate at separation
  out.restitution = out.separated ? v_out / approach_rate : 0.0;
  out.dissipated_energy = s.dissipated;
  double t_on = 0.0;
  double t_off = t;
  for (const ContactEvent& e : events) {
    if (e.kind == EventKind::onset) t_on = e.time_s;
    if (e.kind == EventKind::separation) t_off = e.time_s;
  }
  out.contact_time_s = t_off - t_on;
  return out;
}

}  // namespace clearshape::plant
