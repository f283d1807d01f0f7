#include "clearshape/study/model.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/fixed_step.hpp"
#include "clearshape/plant/joint.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/speed_path.hpp"

namespace clearshape::study {

namespace {

// The command on the output grid: held between samples, held after the end.
UniformSeries on_grid(const UniformSeries& command, std::size_t n, double ts) {
  UniformSeries out;
  out.sample_time_s = ts;
  out.values.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * ts;
    const double r = (t - command.start_s) / command.sample_time_s;
    std::size_t i = 0;
    if (r > 0.0) i = static_cast<std::size_t>(std::floor(r + 1e-9));
    out.values[k] = command.values.empty() ? 0.0 : command.values[std::min(i, command.values.size() - 1)];
  }
  return out;
}


// The steps per sample for the fixed-step path (plant/fixed_step.hpp): ω·h ≤ 0.05 on the linear
// flank's mode √(K/J), h·c/(v_t·J) ≤ 0.5 on the friction's tanh; at least 4.
int fixed_substeps(const ClearanceModel& m, double ts) {
  const double flank = std::sqrt(m.stiffness / m.link_inertia_kg_m2) * ts / 0.05;
  const double friction = ts * m.coulomb_n_m / (m.friction_regularization_rad_s * m.link_inertia_kg_m2) / 0.5;
  // The drive's fastest pole |p|·h ≤ 0.5 (RK4 is stable to |p|·h ≈ 2.8): an identified drive with
  // a near-zero time constant is stiff and goes to CVODE (fixed_step_covers).
  double drive = 0.0;
  for (const auto& p : m.drive.poles()) drive = std::max(drive, std::abs(p) * ts / 0.5);
  return static_cast<int>(std::clamp(std::ceil(std::max({4.0, flank, friction, drive})), 4.0, 1000.0));
}

// A design loop's fast path: the dashpot law with a linear flank (smooth but for its kinks) and
// a small enough step (plant/fixed_step.hpp); anything stiffer keeps CVODE.
bool fixed_step_covers(const ClearanceModel& m, double ts) {
  return m.play_rad > 0.0 && m.contact_law == ContactLawChoice::dashpot && m.exponent == 1.0 &&
         fixed_substeps(m, ts) < 1000;
}

}  // namespace

namespace {

// The fixed-step path's options for the model (fixed_step_covers).
plant::FixedStepOptions fixed_options(const ClearanceModel& m, double ts, double initial_play_fraction) {
  plant::FixedStepOptions options;
  options.substeps = fixed_substeps(m, ts);
  options.initial_relative_angle_rad = initial_play_fraction * 0.5 * m.play_rad;
  return options;
}

// A fixed-step simulation sampled like a record.
ModelResponse response_of(const plant::FixedStepResponse& sim, const UniformSeries& u) {
  ModelResponse r;
  r.sample_time_s = u.sample_time_s;
  const std::size_t n = u.values.size();
  r.time_s.assign(n, 0.0);
  r.drive_command = u.values;
  r.motor_angle_deg.assign(n, 0.0);
  r.motor_rate_deg_s.assign(n, 0.0);
  r.link_angle_deg.assign(n, 0.0);
  r.link_rate_deg_s.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    r.time_s[k] = static_cast<double>(k) * u.sample_time_s;
    r.motor_angle_deg[k] = rad_to_deg(sim.motor_angle_rad[k]);
    r.motor_rate_deg_s[k] = rad_to_deg(sim.motor_rate_rad_s[k]);
    r.link_angle_deg[k] = rad_to_deg(sim.link_angle_rad[k] - sim.link_angle_rad[0]);
    r.link_rate_deg_s[k] = rad_to_deg(sim.link_rate_rad_s[k]);
  }
  return r;
}

// The design loop's fast path (fixed_step_covers): the same model, sampled like a record.
ModelResponse simulate_fixed(const ClearanceModel& m, const plant::PlantModel& model, const UniformSeries& u,
                             double initial_play_fraction) {
  return response_of(plant::simulate_fixed_step(model, u, fixed_options(m, u.sample_time_s, initial_play_fraction)), u);
}

}  // namespace

plant::PlantModel plant_of(const ClearanceModel& m) {
  plant::PlantModel model;
  model.drive = plant::DriveModel::from_process_model(
      m.mode == rig::CommandMode::position ? plant::DriveMode::position : plant::DriveMode::speed,
      m.drive);
  model.link.inertia_kg_m2 = m.link_inertia_kg_m2;
  plant::TorsionalClearance joint;
  const bool rigid = !(m.play_rad > 0.0);
  joint.half_play_rad = rigid ? 1e3 : 0.5 * m.play_rad;  // rigid: a free link, copied below
  // Eq. 4.3 (clamped), or Flores et al. 2011 as the large-play truth builds it (rig/contact.cpp).
  joint.law = m.contact_law == ContactLawChoice::flores
                  ? plant::ContactLaw::hysteresis(plant::Hysteresis::flores, m.stiffness, m.exponent, m.restitution)
                  : plant::ContactLaw::hertz_dashpot(m.stiffness, m.exponent, m.damping, plant::DampingPolicy::clamped);
  // Eq. 2.9 as a joint torque on φ̇: −c·tanh(φ̇/v_t) − b·φ̇ (plant::Friction, no Stribeck peak).
  joint.joint_friction.coulomb = m.coulomb_n_m;
  joint.joint_friction.viscous = m.viscous_n_m_s_per_rad;
  joint.joint_friction.regularization_rate = m.friction_regularization_rad_s;
  model.joint = joint;
  return model;
}

std::string to_string(ContactLawChoice law) { return law == ContactLawChoice::flores ? "flores" : "dashpot"; }

ContactLawChoice contact_law_from_string(const std::string& name) {
  if (name == "dashpot") return ContactLawChoice::dashpot;
  if (name == "flores") return ContactLawChoice::flores;
  throw InvalidArgument("contact_law: '" + name + "' is unknown; allowed: dashpot, flores");
}

ModelResponse simulate_drive_command(const ClearanceModel& m, const UniformSeries& drive_command,
                                     double duration_s, double initial_play_fraction, bool design_accuracy) {
  require_in_closed("initial_play_fraction", initial_play_fraction, -1.0, 1.0);
  require_positive("duration_s", duration_s);
  require_positive("drive_command.sample_time_s", drive_command.sample_time_s);
  const double ts = drive_command.sample_time_s;
  const std::size_t n = sample_count(duration_s, ts);
  const UniformSeries u = on_grid(drive_command, n, ts);

  const bool rigid = !(m.play_rad > 0.0);
  const plant::PlantModel model = plant_of(m);
  if (design_accuracy && fixed_step_covers(m, ts)) return simulate_fixed(m, model, u, initial_play_fraction);

  plant::SimulationOptions options;
  options.duration_s = static_cast<double>(n - 1) * ts;
  options.output_rate_hz = 1.0 / ts;
  options.record_events = false;
  if (design_accuracy) {  // a design loop compares MDs to ~1e-4 deg: looser tolerances, no energy
    options.record_energy = false;
    options.solver.relative_tolerance = 1e-6;
    options.solver.angle_tolerance_rad = 1e-9;
    options.solver.rate_tolerance_rad_s = 1e-7;
  }
  options.initial.drive_state = Eigen::VectorXd::Zero(model.drive.order());
  if (!rigid) options.initial.relative_angle_rad = initial_play_fraction * 0.5 * m.play_rad;
  const plant::Command command(u, plant::Interpolation::zero_order_hold);
  const plant::Simulation sim = plant::simulate(model, command, options);

  ModelResponse r;
  r.sample_time_s = ts;
  const std::size_t count = sim.size();
  r.time_s = sim.time_s;
  r.drive_command.assign(u.values.begin(), u.values.begin() + static_cast<std::ptrdiff_t>(std::min(count, n)));
  r.drive_command.resize(count, u.values.back());
  r.motor_angle_deg.assign(count, 0.0);
  r.motor_rate_deg_s.assign(count, 0.0);
  r.link_angle_deg.assign(count, 0.0);
  r.link_rate_deg_s.assign(count, 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    r.motor_angle_deg[k] = rad_to_deg(sim.motor_angle_rad[k]);
    r.motor_rate_deg_s[k] = rad_to_deg(sim.motor_rate_rad_s[k]);
    r.link_angle_deg[k] = rigid ? r.motor_angle_deg[k] : rad_to_deg(sim.link_angle_rad[k] - sim.link_angle_rad[0]);
    r.link_rate_deg_s[k] = rigid ? r.motor_rate_deg_s[k] : rad_to_deg(sim.link_rate_rad_s[k]);
  }
  return r;
}

std::vector<DriveCommandOutcome> simulate_drive_commands(std::span<const DriveCommandJob> jobs) {
  std::vector<DriveCommandOutcome> out(jobs.size());
  const auto alone = [&](std::size_t i) {
    try {
      const DriveCommandJob& j = jobs[i];
      out[i].response = simulate_drive_command(*j.model, *j.drive_command, j.duration_s, j.initial_play_fraction, true);
    } catch (...) {
      out[i].error = std::current_exception();
    }
  };
  // A job for the fixed-step path: its grid, plant and options (as simulate_drive_command builds them).
  struct Fixed {
    UniformSeries u;
    plant::PlantModel model;
    plant::FixedStepOptions options;
  };
  const auto fixed = [&](std::size_t i) -> std::optional<Fixed> {
    const DriveCommandJob& j = jobs[i];
    const double ts = j.drive_command->sample_time_s;
    if (!(j.duration_s > 0.0) || !(ts > 0.0) || !(j.initial_play_fraction >= -1.0 && j.initial_play_fraction <= 1.0) ||
        !fixed_step_covers(*j.model, ts)) {
      return std::nullopt;  // simulate_drive_command decides (and names any bad argument)
    }
    return Fixed{on_grid(*j.drive_command, sample_count(j.duration_s, ts), ts), plant_of(*j.model),
                 fixed_options(*j.model, ts, j.initial_play_fraction)};
  };
  std::size_t i = 0;
  while (i < jobs.size()) {
    std::optional<Fixed> a = fixed(i);
    std::optional<Fixed> b = a && i + 1 < jobs.size() ? fixed(i + 1) : std::nullopt;
    if (!b) {
      alone(i);
      ++i;
      continue;
    }
    try {
      const plant::FixedStepJob pair[2] = {{&a->model, &a->u, a->options}, {&b->model, &b->u, b->options}};
      std::vector<plant::FixedStepResponse> sims = plant::simulate_fixed_steps(pair);
      out[i].response = response_of(sims[0], a->u);
      out[i + 1].response = response_of(sims[1], b->u);
    } catch (...) {  // one of the two failed: each alone, so the error is its own
      alone(i);
      alone(i + 1);
    }
    i += 2;
  }
  return out;
}

UniformSeries drive_command_of(const ClearanceModel& m, const UniformSeries& command, double duration_s) {
  require_positive("duration_s", duration_s);
  const double ts = command.sample_time_s;
  const std::size_t n = sample_count(duration_s, ts);
  UniformSeries requested = on_grid(command, n, ts);
  UniformSeries drive;
  if (m.mode == rig::CommandMode::position) {
    // The rig's real-time pulse path (§3.2 published settings; rig/sim_rig.cpp without its drawn
    // start latency): the target taken at the first sample tick at or after each update.
    for (double& v : requested.values) v = deg_to_rad(v);
    drive = signal::apply_realtime_position_path(requested, signal::PulseTrainConfig{});
    for (double& v : drive.values) v = rad_to_deg(v);
  } else {
    const signal::SpeedPathResult path = signal::apply_speed_path(requested, signal::AnalogOutputConfig{});
    drive = path.commanded;
  }
  drive.start_s = 0.0;
  drive.sample_time_s = ts;
  return drive;
}

ModelResponse simulate_command(const ClearanceModel& m, const UniformSeries& command, double duration_s,
                               double initial_play_fraction, bool design_accuracy) {
  return simulate_drive_command(m, drive_command_of(m, command, duration_s), duration_s, initial_play_fraction,
                                design_accuracy);
}

}  // namespace clearshape::study
