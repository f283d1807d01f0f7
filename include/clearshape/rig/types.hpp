#pragma once
// Value types exchanged with a rig in its real-time loop (after ros2_control's command and
// state interfaces). Plain data: copying them never allocates.
#include <cmath>
#include <cstdint>
#include <string_view>

#include "clearshape/core/status.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::rig {

/// The driver's operation mode (thesis §3.2, Table A.6 PE-601).
enum class CommandMode : std::uint8_t {
  position,  ///< pulse-train position command (thesis §4.1.2)
  speed,     ///< ±10 V analog speed command (thesis §4.1.1)
};
std::string_view to_string(CommandMode mode) noexcept;
/// Parses "position" or "speed"; throws InvalidArgument listing both.
CommandMode command_mode_from_string(std::string_view name);

/// One command to the drive, held until the next write.
///   position mode: `value` is the motor-angle target in rad (the rig turns it into pulses);
///   speed mode:    `value` is the analog speed command at the driver input in V.
struct Command {
  CommandMode mode = CommandMode::position;
  double value = 0.0;

  static constexpr Command position_rad(double angle_rad) noexcept {
    return {CommandMode::position, angle_rad};
  }
  static constexpr Command position_deg(double angle_deg) noexcept {
    return {CommandMode::position, deg_to_rad(angle_deg)};
  }
  static constexpr Command speed_v(double volts) noexcept { return {CommandMode::speed, volts}; }
};

/// The check every rig makes on a write: the configured mode (else Status::out_of_range) and a
/// finite value (else Status::not_finite). Real-time safe.
inline Status check_command(const Command& command, CommandMode configured) noexcept {
  if (command.mode != configured) return Status::out_of_range;
  if (!std::isfinite(command.value)) return Status::not_finite;
  return Status::ok;
}

/// Bits of Measurement::flags.
enum class MeasurementFlag : std::uint32_t {
  gyro_saturated = 1u << 0,     ///< the gyroscope sample hit its full-scale range
  command_limited = 1u << 1,    ///< the last command was clipped (D/A range, pulse-rate cap)
  overrun = 1u << 2,            ///< the sample came later than its wall-clock deadline
  command_rejected = 1u << 3,   ///< the last write was rejected (wrong mode or not finite)
  watchdog = 1u << 4,           ///< the board's command watchdog holds the command safe
  sensor_error = 1u << 5,       ///< a sensor read failed; the sensor value repeats the last one
  samples_lost = 1u << 6,       ///< samples before this one were lost (sequence has a gap)
  commands_lost = 1u << 7,      ///< the device rejected host frames since the last sample: a
                                ///< command may not have arrived (serial rig, CS_SAMPLE_RX_REJECTED)
};
constexpr std::uint32_t bit(MeasurementFlag flag) noexcept {
  return static_cast<std::uint32_t>(flag);
}

/// One sample of the rig's sensors.
struct Measurement {
  double time_s = 0.0;               ///< rig clock at the sample (0 at activation)
  std::uint64_t sequence = 0;        ///< sample number since activation (0, 1, …)
  std::int64_t encoder_counts = 0;   ///< motor encoder counter (thesis §3.2: 3000 lines)
  double motor_angle_rad = 0.0;      ///< encoder_counts × resolution
  std::int16_t gyro_raw = 0;         ///< gyroscope output word, LSB (ITG-3205: 14.375 LSB/(°/s))
  double gyro_rate_rad_s = 0.0;      ///< gyro_raw / sensitivity
  double command_applied = 0.0;      ///< what the driver received (rad or V, see Command)
  std::uint32_t flags = 0;           ///< MeasurementFlag bits

  double motor_angle_deg() const noexcept { return rad_to_deg(motor_angle_rad); }
  double gyro_rate_deg_s() const noexcept { return rad_to_deg(gyro_rate_rad_s); }
  bool has(MeasurementFlag flag) const noexcept { return (flags & bit(flag)) != 0; }
};

}  // namespace clearshape::rig
