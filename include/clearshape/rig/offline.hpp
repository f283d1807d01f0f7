#pragma once
// A whole run of the simulated rig in one call (what-if simulation, calibration, the
// `clearshape simulate` command): the command series goes through the mode's command path,
// the plant is integrated by plant::simulate (CVODE, stops only where the command jumps), and
// the sensors are applied to the output samples. Uses an explicit truth (truth.hpp).
//
// Differences from stepping a SimRig: the position path looks one update period ahead
// (signal::VelocityHold::lookahead, as the thesis generated its pulses from the known
// trajectory) instead of programming the last written target, and its commanded position is
// interpolated linearly between the 1 kHz samples (pulses arrive at a constant rate within an
// update period) instead of held per tick; the speed path is the same 1 kHz hold in both.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

struct RunOptions {
  double duration_s = 5.0;          ///< thesis: 5 s records
  double output_rate_hz = 1000.0;   ///< thesis: 1 kHz logging
  double initial_play_fraction = 0.0;  ///< φ(0)/β in [−1, 1]
  std::uint64_t seed = 1;           ///< gyroscope noise
  bool sensor_noise = true;         ///< false: noise-free gyroscope (quantization kept)
  /// Position mode: the pulse path of a real-time loop (signal::apply_realtime_position_path, as
  /// SimRig and the firmware run it) instead of the trajectory known beforehand (each update aims
  /// one period ahead, signal::apply_position_path; the default).
  bool realtime_command_path = false;
  void validate() const;
};

struct RunRecord {
  CommandMode mode = CommandMode::position;
  /// What reached the drive, in its command units (position: deg; speed: V), per sample.
  std::vector<double> command_drive;
  plant::Simulation simulation;       ///< time, motor, link, contact series (SI)
  std::vector<std::int64_t> encoder_counts;
  std::vector<double> encoder_angle_rad;
  std::vector<std::int16_t> gyro_raw;
  std::vector<double> gyro_rate_rad_s;
  std::size_t limited_commands = 0;   ///< D/A-clipped samples or rate-capped pulse updates
  bool rigid = false;                 ///< clearance 0: link rigidly on the shaft
};

/// Runs `command` (rig units: position rad, speed V; sampled uniformly, held after its end)
/// for options.duration_s. Throws InvalidArgument on bad input, RuntimeError if the
/// integration fails.
RunRecord simulate_run(const RigTruth& truth, CommandMode mode, const UniformSeries& command,
                       const RunOptions& options = {});

}  // namespace clearshape::rig
