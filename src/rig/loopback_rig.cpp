#include "clearshape/rig/loopback_rig.hpp"

#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::rig {

void LoopbackConfig::validate() const {
  require_in_closed("sample_rate_hz", sample_rate_hz, 1e-3, 1e6);
  if (encoder_counts_per_revolution < 1) {
    throw_invalid("encoder_counts_per_revolution", encoder_counts_per_revolution, ">= 1");
  }
  require_positive("gyro_sensitivity_lsb_per_dps", gyro_sensitivity_lsb_per_dps);
  if (mode == CommandMode::speed) {
    require_positive("speed_rad_s_per_volt", speed_rad_s_per_volt,
                     "Speed mode needs the driver's gain");
  }
}

void LoopbackRig::on_configure() { config_.validate(); }

void LoopbackRig::on_activate() {
  angle_rad_ = 0.0;
  rate_rad_s_ = 0.0;
  command_ = 0.0;
  sequence_ = 0;
  pending_flags_ = 0;
}

void LoopbackRig::on_deactivate() noexcept { command_ = 0.0; }

Status LoopbackRig::on_read(Measurement& m) noexcept {
  const double ts = sample_time_s();
  if (sequence_ > 0) {
    if (config_.mode == CommandMode::position) {
      rate_rad_s_ = (command_ - angle_rad_) / ts;
      angle_rad_ = command_;
    } else {
      rate_rad_s_ = command_ * config_.speed_rad_s_per_volt;
      angle_rad_ += rate_rad_s_ * ts;
    }
  }
  const double resolution_rad = kTwoPi / config_.encoder_counts_per_revolution;
  m.time_s = static_cast<double>(sequence_) * ts;
  m.sequence = sequence_++;
  m.encoder_counts = static_cast<std::int64_t>(std::floor(angle_rad_ / resolution_rad + 1e-9));
  m.motor_angle_rad = static_cast<double>(m.encoder_counts) * resolution_rad;
  const double lsb = std::round(rad_to_deg(rate_rad_s_) * config_.gyro_sensitivity_lsb_per_dps);
  const double clamped = std::fmin(std::fmax(lsb, -32768.0), 32767.0);
  m.gyro_raw = static_cast<std::int16_t>(clamped);
  m.gyro_rate_rad_s = deg_to_rad(m.gyro_raw / config_.gyro_sensitivity_lsb_per_dps);
  m.command_applied = command_;
  m.flags = pending_flags_ | (clamped != lsb ? bit(MeasurementFlag::gyro_saturated) : 0u);
  pending_flags_ = 0;
  return Status::ok;
}

Status LoopbackRig::on_write(const Command& command) noexcept {
  if (const Status rejected = check_command(command, config_.mode); rejected != Status::ok) {
    pending_flags_ |= bit(MeasurementFlag::command_rejected);
    return rejected;
  }
  command_ = command.value;
  return Status::ok;
}

}  // namespace clearshape::rig
