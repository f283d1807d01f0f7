#include "clearshape/plant/encoder.hpp"

#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::plant {

Encoder::Encoder(const EncoderConfig& config) : config_(config) {
  require_in_closed("encoder.lines_per_revolution", config.lines_per_revolution, 1.0, 1e9,
                    "the thesis encoder has 3000 lines per revolution");
  const int dec = static_cast<int>(config.decoding);
  if (dec != 1 && dec != 2 && dec != 4) {
    throw_invalid("encoder.decoding", dec, "1, 2 or 4", "quadrature counters decode x1, x2 or x4");
  }
  require_finite("encoder.zero_angle_rad", config.zero_angle_rad);
  counts_per_revolution_ = static_cast<std::int64_t>(config.lines_per_revolution) * dec;
  resolution_rad_ = kTwoPi / static_cast<double>(counts_per_revolution_);
}

std::int64_t Encoder::count(double angle) const noexcept {
  constexpr double kLimit = 4.611686018427387904e18;  // 2^62
  const double c = std::floor((angle - config_.zero_angle_rad) / resolution_rad_);
  if (!(c < kLimit)) return c > 0.0 || std::isnan(c) ? static_cast<std::int64_t>(kLimit) : 0;
  if (!(c > -kLimit)) return -static_cast<std::int64_t>(kLimit);
  return static_cast<std::int64_t>(c);
}

double Encoder::angle_rad(std::int64_t count) const noexcept {
  return config_.zero_angle_rad + static_cast<double>(count) * resolution_rad_;
}

}  // namespace clearshape::plant
