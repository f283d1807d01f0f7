#include "clearshape/signal/speed_path.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::signal {

void AnalogOutputConfig::validate() const {
  require_finite("volts_per_unit", volts_per_unit);
  if (volts_per_unit == 0.0) {
    throw_invalid("volts_per_unit", volts_per_unit, "finite and non-zero",
                  "Give the volts per command unit of the driver's speed input");
  }
  if (resolution_bits < 1 || resolution_bits > 24) {
    throw_invalid("resolution_bits", resolution_bits, "an integer in [1, 24]",
                  "The thesis DAQ (Humusoft MF-614) has 12 bits");
  }
  require_positive("full_scale_v", full_scale_v, "The thesis DAQ outputs ±10 V");
}

double AnalogOutputConfig::lsb_v() const noexcept {
  return 2.0 * full_scale_v / std::ldexp(1.0, resolution_bits);
}

Status analog_output_v(const AnalogOutputConfig& config, double command, double& volts) noexcept {
  if (!std::isfinite(command)) {
    volts = 0.0;
    return Status::not_finite;
  }
  Status status = Status::ok;
  double requested_v = command * config.volts_per_unit;
  if (requested_v > config.full_scale_v || requested_v < -config.full_scale_v) {
    requested_v = std::clamp(requested_v, -config.full_scale_v, config.full_scale_v);
    status = Status::out_of_range;
  }
  // Bipolar D/A: nearest code (ties up) of LSB = 2·FS/2^bits, codes −2^(b−1) … 2^(b−1) − 1.
  const double half_codes = std::ldexp(1.0, config.resolution_bits - 1);
  const double lsb_v = config.full_scale_v / half_codes;
  const double code = std::clamp(std::floor(requested_v / lsb_v + 0.5), -half_codes, half_codes - 1.0);
  volts = code * lsb_v;
  return status;
}

SpeedPathResult apply_speed_path(const UniformSeries& command, const AnalogOutputConfig& config) {
  config.validate();
  SpeedPathResult r;
  r.volts = {command.start_s, command.sample_time_s, std::vector<double>(command.size())};
  r.commanded = r.volts;
  for (std::size_t i = 0; i < command.size(); ++i) {
    double v = 0.0;
    const Status s = analog_output_v(config, command.values[i], v);
    if (s == Status::not_finite) {
      throw_invalid(fmt::format("command sample {}", i), command.values[i], "a finite number");
    }
    if (s == Status::out_of_range) ++r.clipped_samples;
    r.volts.values[i] = v;
    r.commanded.values[i] = v / config.volts_per_unit;
  }
  return r;
}

}  // namespace clearshape::signal
