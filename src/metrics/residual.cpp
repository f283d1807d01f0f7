#include "clearshape/metrics/residual.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "clearshape/core/error.hpp"
#include "crossing.hpp"
#include "validate.hpp"

namespace clearshape::metrics {

double final_value(const UniformSeries& response, double fraction) {
  detail::require_min_size("response", response.size(), 1);
  require_in_closed("fraction", fraction, 1e-12, 1.0, "Use e.g. 0.1 (the last 10 % of the record)");
  const std::size_t n = response.size();
  const auto count = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(n))), 1, n);
  double sum = 0.0;
  for (std::size_t i = n - count; i < n; ++i) sum += response.values[i];
  return sum / static_cast<double>(count);
}

ResidualVibration residual_vibration(const UniformSeries& response, double after_s,
                                     std::optional<double> final) {
  detail::require_min_size("response", response.size(), 1);
  detail::require_finite_samples("response", response.values);
  require_finite("after_s", after_s);
  std::size_t first = 0;
  if (after_s > response.start_s) {
    first = static_cast<std::size_t>(
        std::ceil((after_s - response.start_s) / response.sample_time_s - 1e-9));
  }
  if (first >= response.size()) {
    throw_invalid("after_s", after_s, "<= the last sample time " + std::to_string(response.end_s()) + " s",
                  "Measure the residual vibration inside the record");
  }
  ResidualVibration r;
  r.final_value = final.value_or(final_value(response));
  require_finite("final", r.final_value);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  double sum_sq = 0.0;
  for (std::size_t i = first; i < response.size(); ++i) {
    const double y = response.values[i];
    lo = std::min(lo, y);
    hi = std::max(hi, y);
    const double d = y - r.final_value;
    sum_sq += d * d;
    r.max_abs_deviation = std::max(r.max_abs_deviation, std::abs(d));
  }
  r.samples = response.size() - first;
  r.peak_to_peak = hi - lo;
  r.rms_about_final = std::sqrt(sum_sq / static_cast<double>(r.samples));
  return r;
}

double time_to_fraction_s(const UniformSeries& response, double fraction, double initial,
                          std::optional<double> final) {
  detail::require_min_size("response", response.size(), 1);
  detail::require_finite_samples("response", response.values);
  require_in_closed("fraction", fraction, 0.0, 1.0);
  require_finite("initial", initial);
  const double yf = final.value_or(final_value(response));
  require_finite("final", yf);
  if (yf == initial) {
    throw_invalid("final - initial", 0.0, "!= 0", "The response does not move");
  }
  const double sign = yf > initial ? 1.0 : -1.0;
  const double samples =
      detail::first_reach_samples(response.values, initial + fraction * (yf - initial), sign);
  return response.start_s + samples * response.sample_time_s;  // NaN propagates
}

double shaping_delay_s(const UniformSeries& unshaped, const UniformSeries& shaped,
                       double fraction, double initial) {
  const double target = final_value(unshaped);
  return time_to_fraction_s(shaped, fraction, initial, target) -
         time_to_fraction_s(unshaped, fraction, initial, target);
}

}  // namespace clearshape::metrics
