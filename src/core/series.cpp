#include "clearshape/core/series.hpp"

#include <cmath>

#include "clearshape/core/error.hpp"

namespace clearshape {

std::vector<double> UniformSeries::times_s() const {
  std::vector<double> t(values.size());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = time_s(i);
  return t;
}

std::size_t sample_count(double duration_s, double sample_time_s) {
  require_non_negative("duration_s", duration_s);
  require_positive("sample_time_s", sample_time_s);
  // Round to the nearest sample so that 5 s at 1 kHz gives 5001 samples despite rounding.
  const double n = std::floor(duration_s / sample_time_s + 1e-9);
  if (n > 1e9) throw_invalid("duration_s / sample_time_s", n, "<= 1e9 samples", "Shorten the duration or lower the rate");
  return static_cast<std::size_t>(n) + 1;
}

}  // namespace clearshape
