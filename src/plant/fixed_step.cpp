#include "clearshape/plant/fixed_step.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <variant>

#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

namespace {

constexpr int kStates = kMaxDriveOrder + 2;  // drive states, φ, ω, then unused slots
// Simulations stepped together (simulate_fixed_steps): two run 1.5 times as fast as one after the
// other, four no faster than two (bench_simulate; the divider is then the bottleneck).
constexpr std::size_t kLanes = 2;
using State = std::array<double, kStates>;

// The right-hand side of torsional_system.cpp in its free and contact modes (no impulse law, no
// locking): ẋ = A x + B u; φ̇ = ω − ω_m; J ω̇ = −s F(δ, δ̇) + τ_f(φ̇) + τ_g − b_g ω.
struct Rhs {
  const DriveModel* drive = nullptr;
  const Link* link = nullptr;
  const TorsionalClearance* joint = nullptr;
  const UniformSeries* input = nullptr;
  int nd = 0;
  double weight_rc = 0.0;
  ContactMemory memory{};  // the approach rate latched at the current contact's onset
  bool in_contact = false;
  double u = 0.0;          // the input over the current step (zero-order hold)

  double u_at(double t) const noexcept {
    const double r = (t - drive->delay_s()) / input->sample_time_s;
    if (r < 0.0) return 0.0;
    const auto k = static_cast<std::size_t>(std::floor(r + 1e-9));
    return input->values[std::min(k, input->values.size() - 1)];
  }

  void operator()(const State& y, State& yd, double /*t*/) const noexcept { eval(y.data(), yd.data()); }

  void eval(const double* y, double* yd) const noexcept {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd);
    const auto& a = drive->a();
    const auto& b = drive->b();
    for (int i = 0; i < nd; ++i) {
      double v = b(i) * u;
      for (int j = 0; j < nd; ++j) v += a(i, j) * y[j];
      yd[i] = v;
    }
    const double phi = y[nd];
    const double w = y[nd + 1];
    const double phi_rate = w - drive->rate_rad_s(x, u);
    const double s = phi >= 0.0 ? 1.0 : -1.0;
    const double delta = s * phi - joint->half_play_rad;  // δ = |φ| − β
    double tau = joint->joint_friction.evaluate(phi_rate).force - link->ground_viscous_n_m_s_per_rad * w +
                 link->external_torque_n_m;
    if (weight_rc != 0.0) tau -= weight_rc * std::cos(drive->angle_rad(x) + phi);  // τ_g = −m g r_c cos θ
    if (delta > 0.0) {
      const double delta_rate = s * phi_rate;
      const ContactMemory m =
          in_contact ? memory : ContactMemory{joint->law.latch_approach_rate(delta_rate), false};
      tau -= s * joint->law.evaluate(delta, delta_rate, m).force;
    }
    for (int i = nd + 2; i < kStates; ++i) yd[i] = 0.0;  // unused slots stay 0
    yd[nd] = phi_rate;
    yd[nd + 1] = tau / link->inertia_kg_m2;
  }
};

void validate(const PlantModel& model, const UniformSeries& input, const FixedStepOptions& o) {
  model.validate();
  const auto* joint = std::get_if<TorsionalClearance>(&model.joint);
  if (joint == nullptr) throw InvalidArgument("fixed-step simulation: the planar joint needs plant::simulate");
  if (joint->impact) throw InvalidArgument("fixed-step simulation: impulse impacts need plant::simulate");
  if (joint->law.switches_on_rate()) {
    throw InvalidArgument("fixed-step simulation: the thesis Kelvin–Voigt law switches on the rate; use plant::simulate");
  }
  if (input.values.empty()) throw InvalidArgument("drive_input: empty; give at least one sample");
  require_positive("drive_input.sample_time_s", input.sample_time_s);
  if (o.substeps < 1 || o.substeps > 1000) throw_invalid("substeps", o.substeps, "[1, 1000]");
  require_in_closed("initial_relative_angle_rad", o.initial_relative_angle_rad, -joint->half_play_rad,
                    joint->half_play_rad);
  require_finite("initial_link_rate_rad_s", o.initial_link_rate_rad_s);
}

using Stepper = boost::numeric::odeint::runge_kutta4<State>;

double gap_of(const Rhs& rhs, const State& y) { return std::abs(y[static_cast<std::size_t>(rhs.nd)]) - rhs.joint->half_play_rad; }

// The contact's discrete memory (torsional_system.cpp): latched at onset with the approach rate
// at that instant, cleared at separation.
void update_contact(Rhs& rhs, const State& y) {
  const auto nd = static_cast<std::size_t>(rhs.nd);
  const double phi = y[nd];
  if (gap_of(rhs, y) > 0.0 && !rhs.in_contact) {
    const Eigen::Map<const Eigen::VectorXd> x(y.data(), rhs.nd);
    const double rate = (phi >= 0.0 ? 1.0 : -1.0) * (y[nd + 1] - rhs.drive->rate_rad_s(x, rhs.u));
    rhs.memory = ContactMemory{rhs.joint->law.latch_approach_rate(rate), false};
    rhs.in_contact = true;
  } else if (gap_of(rhs, y) <= 0.0) {
    rhs.in_contact = false;
  }
}

// One step of h with the contact onset or separation inside it located (the Illinois variant of
// regula falsi on δ(θh), Dowell & Jarratt 1971): RK4 to the first state past the switch, the
// contact memory updated there, RK4 over the rest. The dashpot's force jumps at onset (D·δ̇), so
// a step across it unsplit is first-order accurate; split, each piece is smooth.
void step_located(Stepper& stepper, Rhs& rhs, State& y, double t, double h) {
  const State y0 = y;
  const double g0 = gap_of(rhs, y0);
  stepper.do_step(rhs, y, t, h);
  const double g1 = gap_of(rhs, y);
  if ((g0 > 0.0) == (g1 > 0.0)) {
    update_contact(rhs, y);
    return;
  }
  double a = 0.0, b = 1.0, ga = g0, gb = g1;
  State past = y;
  for (int it = 0, side = 0; it < 6 && (b - a) * h > 1e-9; ++it) {
    const double theta = std::clamp(a + ga / (ga - gb) * (b - a), a + 1e-3 * (b - a), b - 1e-3 * (b - a));
    State trial = y0;
    stepper.do_step(rhs, trial, t, theta * h);
    const double g = gap_of(rhs, trial);
    if ((g > 0.0) == (g0 > 0.0)) {  // still before the switch
      a = theta, ga = g;
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = theta, gb = g, past = trial;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  if (b < 1.0) {
    update_contact(rhs, past);
    y = past;
    stepper.do_step(rhs, y, t + b * h, (1.0 - b) * h);
  }
  update_contact(rhs, y);
}

// One simulation in progress: its right-hand side, state and response.
struct Lane {
  const PlantModel* model = nullptr;
  Rhs rhs;
  State y{};
  FixedStepResponse out;
  double h = 0.0;

  Lane(const PlantModel& m, const UniformSeries& input, const FixedStepOptions& o)
      : model(&m),
        rhs{&m.drive, &m.link, &std::get<TorsionalClearance>(m.joint), &input, m.drive.order(),
            m.link.in_plane_weight_n() * m.link.com_distance_m},
        h(input.sample_time_s / o.substeps) {
    const auto nd = static_cast<std::size_t>(rhs.nd);
    y[nd] = o.initial_relative_angle_rad;
    y[nd + 1] = o.initial_link_rate_rad_s;
    const std::size_t n = input.values.size();
    out.sample_time_s = input.sample_time_s;
    out.motor_angle_rad.assign(n, 0.0);
    out.motor_rate_rad_s.assign(n, 0.0);
    out.link_angle_rad.assign(n, 0.0);
    out.link_rate_rad_s.assign(n, 0.0);
    sample(0, 0.0);
  }

  void sample(std::size_t k, double t) {
    const auto nd = static_cast<std::size_t>(rhs.nd);
    const Eigen::Map<const Eigen::VectorXd> x(y.data(), rhs.nd);
    out.motor_angle_rad[k] = model->drive.angle_rad(x);
    out.motor_rate_rad_s[k] = model->drive.rate_rad_s(x, rhs.u_at(t + 0.5 * h));
    out.link_angle_rad[k] = out.motor_angle_rad[k] + y[nd];
    out.link_rate_rad_s[k] = y[nd + 1];
  }

  void check_finite(std::size_t k) const {
    for (const double v : y) {
      if (!std::isfinite(v)) {
        throw RuntimeError("fixed-step simulation diverged at t = " + std::to_string(static_cast<double>(k) * out.sample_time_s) + " s");
      }
    }
  }
};

// The time of substep j of sample interval k (k ≥ 1).
double substep_time(std::size_t k, int j, int substeps, double ts) {
  return (static_cast<double>(k - 1) + static_cast<double>(j) / substeps) * ts;
}

FixedStepResponse run_one(const PlantModel& model, const UniformSeries& drive_input, const FixedStepOptions& options) {
  Lane lane(model, drive_input, options);
  Stepper stepper;
  const std::size_t n = drive_input.values.size();
  const double ts = drive_input.sample_time_s;
  for (std::size_t k = 1; k < n; ++k) {
    for (int j = 0; j < options.substeps; ++j) {
      const double t = substep_time(k, j, options.substeps, ts);
      // Held over the step: the input at its midpoint (a stage at the step's end must not see the
      // next sample; exact for a delay that is a multiple of the step).
      lane.rhs.u = lane.rhs.u_at(t + 0.5 * lane.h);
      step_located(stepper, lane.rhs, lane.y, t, lane.h);
    }
    lane.check_finite(k);
    lane.sample(k, static_cast<double>(k) * ts);
  }
  return std::move(lane.out);
}

// L simulations of the same length, sample time and substeps stepped together: one Runge–Kutta
// step of all their states at once, so the processor overlaps their independent chains of
// dependent operations (each step of one simulation waits on its friction's tanh and its
// divisions). Element by element the stepper does exactly the arithmetic of run_one, and a lane
// whose step crosses a contact onset or separation is redone alone by step_located, so each
// response is run_one's to the bit.
template <std::size_t L>
using LanesState = std::array<double, L * kStates>;

template <std::size_t L>
struct LanesRhs {
  std::array<const Rhs*, L> lane;
  void operator()(const LanesState<L>& y, LanesState<L>& yd, double /*t*/) const noexcept {
    for (std::size_t i = 0; i < L; ++i) lane[i]->eval(y.data() + i * kStates, yd.data() + i * kStates);
  }
};

template <std::size_t L>
void run_lanes(std::array<Lane*, L> lanes, std::size_t n, int substeps, double ts) {
  Stepper single;
  boost::numeric::odeint::runge_kutta4<LanesState<L>> stepper;
  LanesRhs<L> rhs;
  for (std::size_t i = 0; i < L; ++i) rhs.lane[i] = &lanes[i]->rhs;
  LanesState<L> y{};
  const double h = lanes[0]->h;
  for (std::size_t k = 1; k < n; ++k) {
    for (int j = 0; j < substeps; ++j) {
      const double t = substep_time(k, j, substeps, ts);
      for (std::size_t i = 0; i < L; ++i) {
        Lane& l = *lanes[i];
        l.rhs.u = l.rhs.u_at(t + 0.5 * h);
        std::copy(l.y.begin(), l.y.end(), y.begin() + static_cast<std::ptrdiff_t>(i * kStates));
      }
      stepper.do_step(rhs, y, t, h);
      for (std::size_t i = 0; i < L; ++i) {
        Lane& l = *lanes[i];
        State stepped;
        const auto from = y.begin() + static_cast<std::ptrdiff_t>(i * kStates);
        std::copy(from, from + kStates, stepped.begin());
        if ((gap_of(l.rhs, l.y) > 0.0) == (gap_of(l.rhs, stepped) > 0.0)) {
          l.y = stepped;
          update_contact(l.rhs, l.y);
        } else {
          step_located(single, l.rhs, l.y, t, h);  // from the step's start, alone
        }
      }
    }
    for (Lane* l : lanes) {
      l->check_finite(k);
      l->sample(k, static_cast<double>(k) * ts);
    }
  }
}

bool compatible(const FixedStepJob& a, const FixedStepJob& b) {
  return a.drive_input->values.size() == b.drive_input->values.size() &&
         a.drive_input->sample_time_s == b.drive_input->sample_time_s && a.options.substeps == b.options.substeps;
}

// Jobs [i, i + L) together.
template <std::size_t L>
void run_group(std::span<const FixedStepJob> jobs, std::size_t i, std::vector<FixedStepResponse>& out) {
  std::vector<Lane> lanes;
  lanes.reserve(L);
  std::array<Lane*, L> ptr{};
  for (std::size_t k = 0; k < L; ++k) {
    lanes.emplace_back(*jobs[i + k].model, *jobs[i + k].drive_input, jobs[i + k].options);
    ptr[k] = &lanes[k];
  }
  run_lanes<L>(ptr, jobs[i].drive_input->values.size(), jobs[i].options.substeps, jobs[i].drive_input->sample_time_s);
  for (std::size_t k = 0; k < L; ++k) out[i + k] = std::move(lanes[k].out);
}

}  // namespace

FixedStepResponse simulate_fixed_step(const PlantModel& model, const UniformSeries& drive_input,
                                      const FixedStepOptions& options) {
  validate(model, drive_input, options);
  return run_one(model, drive_input, options);
}

std::vector<FixedStepResponse> simulate_fixed_steps(std::span<const FixedStepJob> jobs) {
  for (const FixedStepJob& j : jobs) validate(*j.model, *j.drive_input, j.options);
  std::vector<FixedStepResponse> out(jobs.size());
  std::size_t i = 0;
  while (i < jobs.size()) {
    if (i + 1 < jobs.size() && compatible(jobs[i], jobs[i + 1])) {
      run_group<kLanes>(jobs, i, out);
      i += kLanes;
    } else {
      out[i] = run_one(*jobs[i].model, *jobs[i].drive_input, jobs[i].options);
      ++i;
    }
  }
  return out;
}

}  // namespace clearshape::plant
