#pragma once
// A/D and D/A conversion of the DAQ card (thesis §3.2: Humusoft MF-614, 12 bit, ±10 V).
// Convention: offset binary, code = round((v − v_min)/LSB) clamped to [0, 2^bits − 1],
// LSB = (v_max − v_min)/2^bits (4.8828 mV for 12 bit ±10 V); the code's voltage is
// v_min + code·LSB, so the top code reads v_max − LSB. Round-to-nearest for both directions.
// A small value object; every member is noexcept and allocation-free.
#include <cstdint>

namespace clearshape::plant {

struct ConverterConfig {
  int bits = 12;
  double min_v = -10.0;
  double max_v = 10.0;
};

class Converter {
 public:
  /// Throws InvalidArgument for bits outside 1…24 or min_v ≥ max_v.
  explicit Converter(const ConverterConfig& config = {});
  double lsb_v() const noexcept { return lsb_v_; }
  std::int32_t max_code() const noexcept { return max_code_; }
  /// Code for a voltage; NaN maps to the mid code; out-of-range voltages saturate.
  std::int32_t code(double volts) const noexcept;
  double volts(std::int32_t code) const noexcept;
  /// volts(code(v)).
  double quantize(double volts) const noexcept { return this->volts(code(volts)); }
  /// True if v lies outside the representable range [min_v, max_v − LSB/2].
  bool saturates(double volts) const noexcept;
  const ConverterConfig& config() const noexcept { return config_; }

 private:
  ConverterConfig config_;
  double lsb_v_ = 0.0;
  std::int32_t max_code_ = 0;
};

/// The MF-614's converters (A/D for the measured-speed input, D/A for the velocity command).
using AnalogInput = Converter;
using AnalogOutput = Converter;

}  // namespace clearshape::plant
