#pragma once
// The emulator's plant: clearshape's own rig truth (rig/truth.hpp: drive model, link with
// clearance, encoder, gyroscope) advanced in lockstep with the AVR's clock. Inputs are what the
// board puts on its wires (A/B edges counted x4, the MCP4725 code, servo-on); outputs are what
// the drive and the gyroscope put on theirs (encoder count, gyro word).
#include <cstdint>
#include <optional>

#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/rig/truth.hpp"

namespace clearshape::emulator {

struct RigPlantOptions {
  std::uint64_t seed = 1;
  bool noise = true;                 ///< gyroscope rate noise of the truth
  double initial_play_fraction = 0;  ///< φ(0)/β in [−1, 1]
};

class RigPlant {
 public:
  RigPlant(const rig::RigTruth& truth, const RigPlantOptions& options);

  /// Restarts the plant at rest in `mode` at AVR time `t_s` (the host's CONFIGURE chose it).
  void restart(rig::CommandMode mode, double t_s);
  rig::CommandMode mode() const noexcept { return mode_; }

  /// Advances to AVR time t_s with the drive input held since the last call. Position mode:
  /// `pulse_edges` A/B edges received (x4); speed mode: the MCP4725 code. Servo off: the drive
  /// ignores pulses and sees 0 V. Returns false (and error_message()) on an integration failure.
  bool advance(double t_s, std::int64_t pulse_edges, std::uint16_t dac_code, bool servo_on);

  /// The drive's encoder output count (x4, 12000 per revolution for the thesis rig).
  std::int64_t encoder_count() const noexcept;
  /// One gyroscope sample of the link rate at `rate_hz` (the ITG-3205's output data rate).
  plant::GyroSample gyro_sample(double rate_hz) noexcept;
  double motor_angle_rad() const noexcept;
  const char* error_message() const noexcept;

  /// Speed-mode drive input of a DAC code: −10 V + 20 V · code/4096 (docs/hardware.md level
  /// shift: 0 → −10 V, 2048 → 0 V, 4095 → +9.995 V).
  static double dac_volts(std::uint16_t code) noexcept;
  /// Motor target of position mode, rad, for `edges` A/B edges (4 per command pulse).
  double pulse_target_rad(std::int64_t edges) const noexcept;

 private:
  rig::RigTruth truth_;
  RigPlantOptions options_;
  rig::CommandMode mode_ = rig::CommandMode::position;
  std::optional<plant::Simulator> simulator_;
  plant::Encoder encoder_;
  std::optional<plant::Gyroscope> gyro_;
  double gyro_rate_hz_ = 0.0;
  double t0_s_ = 0.0;
  double command_ = 0.0;
  bool rigid_ = false;
  bool failed_ = false;
};

}  // namespace clearshape::emulator
