#include "clearshape/plant/daq.hpp"

#include <cmath>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

Converter::Converter(const ConverterConfig& config) : config_(config) {
  require_in_closed("converter.bits", config.bits, 1.0, 24.0, "the MF-614 has 12-bit converters");
  require_finite("converter.min_v", config.min_v);
  require_finite("converter.max_v", config.max_v);
  if (!(config.max_v > config.min_v)) {
    throw_invalid("converter.max_v", config.max_v, "> converter.min_v", "e.g. -10 V … +10 V");
  }
  max_code_ = (std::int32_t{1} << config.bits) - 1;
  lsb_v_ = (config.max_v - config.min_v) / static_cast<double>(max_code_ + 1);
}

std::int32_t Converter::code(double volts) const noexcept {
  if (std::isnan(volts)) return (max_code_ + 1) / 2;
  const double c = std::nearbyint((volts - config_.min_v) / lsb_v_);  // round to nearest (even)
  if (c <= 0.0) return 0;
  if (c >= static_cast<double>(max_code_)) return max_code_;
  return static_cast<std::int32_t>(c);
}

double Converter::volts(std::int32_t c) const noexcept {
  return config_.min_v + static_cast<double>(c) * lsb_v_;
}

bool Converter::saturates(double v) const noexcept {
  return !(v >= config_.min_v - 0.5 * lsb_v_ && v <= config_.max_v - 0.5 * lsb_v_);
}

}  // namespace clearshape::plant
