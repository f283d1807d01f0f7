#include "rig_plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clearshape::emulator {

RigPlant::RigPlant(const rig::RigTruth& truth, const RigPlantOptions& options)
    : truth_(truth), options_(options), encoder_(truth.encoder) {
  truth_.validate();
  restart(rig::CommandMode::position, 0.0);
}

void RigPlant::restart(rig::CommandMode mode, double t_s) {
  mode_ = mode;
  rigid_ = truth_.clearance_rad == 0.0;
  plant::InitialState initial;
  initial.relative_angle_rad = rigid_ ? 0.0 : options_.initial_play_fraction * truth_.half_play_rad();
  simulator_.emplace(rig::plant_model(truth_, mode), truth_.solver, initial, 0.0);
  t0_s_ = t_s;
  command_ = 0.0;
  failed_ = false;
  gyro_.reset();
  gyro_rate_hz_ = 0.0;
}

double RigPlant::dac_volts(std::uint16_t code) noexcept {
  // MCP4725 output code/4096 · 5 V, then the op-amp stage Vout = 4 · Vdac − 10 V
  // (docs/hardware.md): code 0 → −10 V, 2048 → 0 V, 4095 → +9.995 V.
  return -10.0 + 20.0 * static_cast<double>(std::min<std::uint16_t>(code, 4095)) / 4096.0;
}

double RigPlant::pulse_target_rad(std::int64_t edges) const noexcept {
  // signal/position_path.hpp: counts_per_rev command pulses per revolution, 4 edges per pulse.
  return static_cast<double>(edges) / (4.0 * truth_.pulse_train.counts_per_rad());
}

bool RigPlant::advance(double t_s, std::int64_t pulse_edges, std::uint16_t dac_code, bool servo_on) {
  if (failed_) return false;
  const double t = t_s - t0_s_;
  if (!(t > simulator_->time_s())) return true;
  const Status status = simulator_->advance(t, command_);
  if (status != Status::ok) {
    failed_ = true;
    return false;
  }
  // The input read at t holds until the next step (zero-order hold at the plant step).
  if (mode_ == rig::CommandMode::position) {
    if (servo_on) command_ = rig::drive_units(rig::CommandMode::position, pulse_target_rad(pulse_edges));
  } else {
    command_ = servo_on ? dac_volts(dac_code) / truth_.analog_output.volts_per_unit : 0.0;
  }
  return true;
}

std::int64_t RigPlant::encoder_count() const noexcept {
  return encoder_.count(simulator_->state().motor_angle_rad);
}

double RigPlant::motor_angle_rad() const noexcept { return simulator_->state().motor_angle_rad; }

plant::GyroSample RigPlant::gyro_sample(double rate_hz) noexcept {
  if (!gyro_ || rate_hz != gyro_rate_hz_) {
    plant::GyroscopeConfig config = truth_.gyro;
    config.sample_rate_hz = rate_hz;
    config.seed = options_.seed;
    if (!options_.noise) config.noise_density_dps_per_rthz = 0.0;
    gyro_.emplace(config);
    gyro_rate_hz_ = rate_hz;
  }
  const plant::Simulator::State& s = simulator_->state();
  return gyro_->sample(rigid_ ? s.motor_rate_rad_s : s.link_rate_rad_s);
}

const char* RigPlant::error_message() const noexcept { return simulator_->error_message().c_str(); }

}  // namespace clearshape::emulator
