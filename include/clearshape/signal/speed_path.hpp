#pragma once
// Speed-mode drive command path (thesis §3.2, §4.1.1, Table 3.2): the velocity command goes to
// the driver as an analog voltage from the DAQ card's 12-bit D/A converter, range ±10 V.
// Conversion: requested volts = command · volts_per_unit; the D/A clips to ±full_scale_v and
// rounds to the nearest code of LSB = 2·full_scale_v / 2^bits, codes −2^(bits−1) … 2^(bits−1)−1
// (ties round up), so 0 V is exact and the top code is full_scale_v − LSB.
#include <cstddef>

#include "clearshape/core/series.hpp"
#include "clearshape/core/status.hpp"

namespace clearshape::signal {

struct AnalogOutputConfig {
  double volts_per_unit = 1.0;  ///< scale from command units to volts (non-zero; sign allowed)
  int resolution_bits = 12;     ///< D/A resolution (Humusoft MF-614: 12 bit)
  double full_scale_v = 10.0;   ///< symmetric output range ±full_scale_v (Table 3.2: ±10 V)

  /// Throws InvalidArgument naming the field (scale finite and non-zero, bits in [1, 24],
  /// full scale > 0).
  void validate() const;
  double lsb_v() const noexcept;
};

/// The voltage the D/A outputs for `command` (real-time, noexcept, allocation-free). Returns
/// Status::out_of_range when the requested voltage was outside ±full_scale_v (clipped), and
/// Status::not_finite (volts = 0) for a non-finite command. `config` must be valid.
Status analog_output_v(const AnalogOutputConfig& config, double command, double& volts) noexcept;

struct SpeedPathResult {
  UniformSeries volts;           ///< D/A output
  UniformSeries commanded;       ///< what the driver receives, back in command units (volts / scale)
  std::size_t clipped_samples = 0;
};

/// Applies the D/A to every sample. Throws InvalidArgument for an invalid config or a
/// non-finite command sample (naming its index).
SpeedPathResult apply_speed_path(const UniformSeries& command, const AnalogOutputConfig& config);

}  // namespace clearshape::signal
