#pragma once
// A rig without hardware or physics, after ros2_control's mock GenericSystem ("mirrors
// commands to states"): position mode reports the commanded angle, speed mode integrates
// volts·speed_per_volt. Encoder quantization and gyroscope scaling are applied so that the
// measurement path is exercised; the gyroscope reads the motor rate (a rigid link).
// For testing control loops and the lifecycle; no noise, no clearance.
#include "clearshape/rig/rig.hpp"

namespace clearshape::rig {

struct LoopbackConfig {
  CommandMode mode = CommandMode::position;
  double sample_rate_hz = 1000.0;
  int encoder_counts_per_revolution = 12000;      ///< 3000 lines decoded ×4
  double gyro_sensitivity_lsb_per_dps = 14.375;   ///< ITG-3205
  double speed_rad_s_per_volt = 0.0;              ///< speed mode: required > 0
  void validate() const;                          ///< throws InvalidArgument naming the field
};

class LoopbackRig final : public Rig {
 public:
  explicit LoopbackRig(const LoopbackConfig& config) : config_(config) {}

  double sample_time_s() const noexcept override { return 1.0 / config_.sample_rate_hz; }
  CommandMode mode() const noexcept override { return config_.mode; }
  std::string_view name() const noexcept override { return "loopback"; }

 protected:
  void on_configure() override;
  void on_activate() override;
  void on_deactivate() noexcept override;
  void on_cleanup() noexcept override {}
  Status on_read(Measurement& measurement) noexcept override;
  Status on_write(const Command& command) noexcept override;

 private:
  LoopbackConfig config_;
  double angle_rad_ = 0.0;
  double rate_rad_s_ = 0.0;
  double command_ = 0.0;
  std::uint64_t sequence_ = 0;
  std::uint32_t pending_flags_ = 0;
};

}  // namespace clearshape::rig
