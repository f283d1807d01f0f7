#pragma once
// Linear-interpolated level crossings of a sampled signal (internal header).
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

namespace clearshape::metrics::detail {

/// Time (relative to sample 0, in samples) at which s first reaches `level` going in
/// direction `sign` (+1 upwards, −1 downwards), with linear interpolation; NaN if never.
inline double first_reach_samples(std::span<const double> s, double level, double sign) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (sign * (s[i] - level) >= 0.0) {
      if (i == 0) return 0.0;
      const double a = s[i - 1] - level;
      const double b = s[i] - level;
      return static_cast<double>(i - 1) + a / (a - b);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace clearshape::metrics::detail
