#include "clearshape/export/fixed_point.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::exports {

FixedPointTaps quantize_taps(std::span<const double> weights, int fraction_bits) {
  require_in_closed("fraction_bits", fraction_bits, 1, 62);
  if (weights.empty()) throw InvalidArgument("quantize_taps: no taps to quantise");
  double sum = 0.0;
  for (std::size_t j = 0; j < weights.size(); ++j) {
    if (!std::isfinite(weights[j])) {
      throw InvalidArgument(fmt::format("quantize_taps: tap {} weight = {} is not finite", j + 1, weights[j]));
    }
    sum += weights[j];
  }
  if (!(std::abs(sum - 1.0) <= 1e-9)) {
    throw_invalid("quantize_taps: sum of tap weights", sum, "1 ± 1e-9",
                  "Fixed-point taps are scaled so that they sum to 1.0 exactly.");
  }
  FixedPointTaps out;
  out.fraction_bits = fraction_bits;
  const double scale = std::ldexp(1.0, fraction_bits);  // 2^n, exact
  const auto one = static_cast<std::int64_t>(1) << fraction_bits;
  for (std::size_t j = 0; j < weights.size(); ++j) {
    if (weights[j] < 0.0) {
      out.why_not = fmt::format("tap {} weight = {} is negative (a negative shaper); fixed-point taps are "
                                "offered for positive shapers only", j + 1, weights[j]);
      return out;
    }
  }
  std::vector<double> scaled(weights.size());
  out.q.resize(weights.size());
  for (std::size_t j = 0; j < weights.size(); ++j) {
    scaled[j] = weights[j] * scale;  // exact: a power-of-two scaling
    out.q[j] = std::llround(scaled[j]);
  }
  // Correct Σq to 2^n, one LSB at a time on the taps with the largest rounding error.
  std::int64_t deficit = one - std::accumulate(out.q.begin(), out.q.end(), std::int64_t{0});
  std::vector<std::size_t> order(weights.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const int direction = deficit > 0 ? 1 : -1;
  // Largest (scaled − q)·direction first: the taps rounded the wrong way the most.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return (scaled[a] - static_cast<double>(out.q[a])) * direction >
           (scaled[b] - static_cast<double>(out.q[b])) * direction;
  });
  for (std::size_t i = 0; deficit != 0; ++i) {
    if (i == order.size()) {
      out.why_not = fmt::format("the rounding of {} taps cannot be corrected to sum 2^{}", weights.size(), fraction_bits);
      return out;
    }
    out.q[order[i]] += direction;
    deficit -= direction;
  }
  for (std::size_t j = 0; j < weights.size(); ++j) {
    if (out.q[j] >= one || out.q[j] < 0) {
      out.why_not = fmt::format("tap {} weight = {} rounds to {} / 2^{}, outside [0, 1 − 2^−{}]", j + 1,
                                weights[j], out.q[j], fraction_bits, fraction_bits);
      return out;
    }
    const double error = std::abs(static_cast<double>(out.q[j]) / scale - weights[j]);
    out.abs_error_sum += error;
    out.max_abs_error = std::max(out.max_abs_error, error);
  }
  out.representable = true;
  return out;
}

}  // namespace clearshape::exports
