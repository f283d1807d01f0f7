#include "clearshape/rig/offline.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "sensors.hpp"

namespace clearshape::rig {

void RunOptions::validate() const {
  require_positive("duration_s", duration_s);
  require_in_closed("output_rate_hz", output_rate_hz, 1.0, 1e6);
  require_in_closed("initial_play_fraction", initial_play_fraction, -1.0, 1.0);
}

namespace {

// The command on the output grid: linear interpolation of the given samples, held before the
// first and after the last (exact when the grids coincide).
UniformSeries resample(const UniformSeries& command, std::size_t n, double ts) {
  if (command.values.empty()) {
    throw InvalidArgument("command: the series is empty; give at least one sample");
  }
  require_positive("command.sample_time_s", command.sample_time_s);
  UniformSeries out;
  out.start_s = 0.0;
  out.sample_time_s = ts;
  out.values.resize(n);
  const std::size_t last = command.values.size() - 1;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = (static_cast<double>(k) * ts - command.start_s) / command.sample_time_s;
    double v;
    if (!(r > 0.0)) {
      v = command.values.front();
    } else if (r >= static_cast<double>(last)) {
      v = command.values.back();
    } else {
      const double rounded = std::round(r);
      if (std::abs(r - rounded) < 1e-9) {
        v = command.values[static_cast<std::size_t>(rounded)];
      } else {
        const auto i = static_cast<std::size_t>(std::floor(r));
        const double f = r - static_cast<double>(i);
        v = (1.0 - f) * command.values[i] + f * command.values[i + 1];
      }
    }
    if (!std::isfinite(v)) throw_invalid("command value", v, "finite numbers");
    out.values[k] = v;
  }
  return out;
}

// Rigid attachment (clearance 0): the link moves with the motor; the shaft's torque on it is
// J·α + b·ω (α by central differences of the motor rate, one-sided at the ends).
void make_rigid(plant::Simulation& s, const plant::Link& link, double ts) {
  const std::size_t n = s.size();
  s.link_angle_rad = s.motor_angle_rad;
  s.link_rate_rad_s = s.motor_rate_rad_s;
  std::fill(s.relative_angle_rad.begin(), s.relative_angle_rad.end(), 0.0);
  std::fill(s.penetration.begin(), s.penetration.end(), 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    double alpha = 0.0;
    if (n > 1) {
      const std::size_t a = k == 0 ? 0 : k - 1;
      const std::size_t b = k + 1 == n ? k : k + 1;
      alpha = (s.motor_rate_rad_s[b] - s.motor_rate_rad_s[a]) / (static_cast<double>(b - a) * ts);
    }
    const double torque = link.inertia_kg_m2 * alpha +
                          link.ground_viscous_n_m_s_per_rad * s.motor_rate_rad_s[k] -
                          link.external_torque_n_m;
    s.contact_torque_n_m[k] = torque;
    if (k < s.normal_force.size()) s.normal_force[k] = std::abs(torque);
  }
  s.events.clear();
  s.stats.events = 0;
}

}  // namespace

RunRecord simulate_run(const RigTruth& truth, CommandMode mode, const UniformSeries& command,
                       const RunOptions& options) {
  truth.validate();
  options.validate();
  const double ts = 1.0 / options.output_rate_hz;
  const std::size_t n = sample_count(options.duration_s, ts);
  const UniformSeries request = resample(command, n, ts);

  RunRecord run;
  run.mode = mode;
  run.rigid = truth.clearance_rad == 0.0;
  UniformSeries drive_command;
  if (mode == CommandMode::position) {
    // The drive starts at rest at 0 (its state below is zero), so the pulse train starts from 0
    // too: a command already away from 0 at t = 0 is reached through pulses at the capped rate.
    if (options.realtime_command_path) {
      drive_command = signal::apply_realtime_position_path(request, truth.pulse_train);
    } else {
      const signal::PositionPathResult path = signal::apply_position_path(request, truth.pulse_train, 0.0);
      drive_command = path.commanded_rad;
      run.limited_commands = path.saturated_updates;
    }
    for (double& v : drive_command.values) v = drive_units(mode, v);
  } else {
    const signal::SpeedPathResult path = signal::apply_speed_path(request, truth.analog_output);
    drive_command = path.commanded;
    run.limited_commands = path.clipped_samples;
  }
  run.command_drive = drive_command.values;

  const plant::PlantModel model = plant_model(truth, mode);
  plant::SimulationOptions sim_options;
  sim_options.duration_s = options.duration_s;
  sim_options.output_rate_hz = options.output_rate_hz;
  sim_options.solver = truth.solver;
  sim_options.record_energy = false;  // a rig run records what its sensors and logs would
  sim_options.initial.relative_angle_rad =
      run.rigid ? 0.0 : options.initial_play_fraction * truth.half_play_rad();
  // The rig rests at zero before t = 0 (a command at t = 0 is a step at t = 0⁺).
  sim_options.initial.drive_state = Eigen::VectorXd::Zero(model.drive.order());
  // Speed mode: the D/A holds each sample (zero-order hold). Position mode: the driver counts
  // pulses arriving at a constant rate within each update period, a staircase of 0.12° counts
  // that linear interpolation of the 1 kHz samples follows more closely than a 1 ms hold.
  const plant::Command plant_command(std::move(drive_command),
                                     mode == CommandMode::position ? plant::Interpolation::linear
                                                                   : plant::Interpolation::zero_order_hold);
  run.simulation = plant::simulate(model, plant_command, sim_options);
  if (run.rigid) make_rigid(run.simulation, truth.link, ts);

  const std::size_t m = run.simulation.size();
  run.command_drive.resize(m, run.command_drive.empty() ? 0.0 : run.command_drive.back());
  const plant::Encoder encoder(truth.encoder);
  plant::Gyroscope gyro(detail::gyro_config(truth, options.output_rate_hz, options.seed,
                                            options.sensor_noise));
  run.encoder_counts.resize(m);
  run.encoder_angle_rad.resize(m);
  run.gyro_raw.resize(m);
  run.gyro_rate_rad_s.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    run.encoder_counts[k] = encoder.count(run.simulation.motor_angle_rad[k]);
    run.encoder_angle_rad[k] = encoder.angle_rad(run.encoder_counts[k]);
    const plant::GyroSample g = gyro.sample(run.simulation.link_rate_rad_s[k]);
    run.gyro_raw[k] = g.raw;
    run.gyro_rate_rad_s[k] = g.rate_rad_s;
  }
  return run;
}

}  // namespace clearshape::rig
