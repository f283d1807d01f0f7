#include "clearshape/metrics/step_info.hpp"

#include <cmath>
#include <limits>
#include <span>

#include "clearshape/core/error.hpp"
#include "crossing.hpp"
#include "validate.hpp"

namespace clearshape::metrics {

StepInfo step_info(const UniformSeries& response, const StepInfoOptions& options) {
  const std::span<const double> y = response.values;
  detail::require_min_size("response", y.size(), 2);
  detail::require_finite_samples("response", y);
  require_positive("sample_time_s", response.sample_time_s);
  require_in_open("settling_threshold", options.settling_threshold, 0.0, 1.0, "MATLAB uses 0.02");
  require_in_closed("rise_low", options.rise_low, 0.0, 1.0);
  require_in_closed("rise_high", options.rise_high, 0.0, 1.0);
  if (!(options.rise_low < options.rise_high)) {
    throw_invalid("rise_low", options.rise_low, "< rise_high", "MATLAB uses [0.1, 0.9]");
  }
  require_finite("initial_value", options.initial_value);

  StepInfo info;
  const double y0 = options.initial_value;
  const double yf = options.final_value.value_or(y.back());
  require_finite("final_value", yf);
  const double delta = yf - y0;
  if (delta == 0.0) {
    throw_invalid("final_value - initial_value", delta, "!= 0",
                  "A step response must move; give yfinal and yinit explicitly");
  }
  info.final_value = yf;
  const double sign = delta > 0.0 ? 1.0 : -1.0;
  const double height = std::abs(delta);
  const double ts = response.sample_time_s;
  const double offset_s = response.start_s - options.step_time_s.value_or(response.start_s);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  // Rise time: first reach of yinit + high·Δ minus first reach of yinit + low·Δ (stepinfo).
  const double t_low = detail::first_reach_samples(y, y0 + options.rise_low * delta, sign);
  const double t_high = detail::first_reach_samples(y, y0 + options.rise_high * delta, sign);
  info.rise_time_s = (t_high - t_low) * ts;  // NaN propagates when never reached

  // Settling: last sample outside the band |y − yf| <= threshold·|Δ|, then the band-edge crossing.
  const double band = options.settling_threshold * height;
  std::size_t last_out = y.size();
  for (std::size_t i = y.size(); i-- > 0;) {
    if (std::abs(y[i] - yf) > band) {
      last_out = i;
      break;
    }
  }
  if (last_out == y.size()) {
    info.settling_time_s = offset_s;  // inside the band from the first sample
  } else if (last_out == y.size() - 1) {
    info.settling_time_s = nan;  // never settles within the record
  } else {
    const double a = std::abs(y[last_out] - yf) - band;      // > 0
    const double b = std::abs(y[last_out + 1] - yf) - band;  // <= 0
    info.settling_time_s = (static_cast<double>(last_out) + a / (a - b)) * ts + offset_s;
  }

  // Settling min/max after the response has risen (first reach of the high rise level).
  if (std::isnan(t_high)) {
    info.settling_min = nan;
    info.settling_max = nan;
  } else {
    const auto first = static_cast<std::size_t>(std::ceil(t_high - 1e-12));
    info.settling_min = std::numeric_limits<double>::infinity();
    info.settling_max = -std::numeric_limits<double>::infinity();
    for (std::size_t i = first; i < y.size(); ++i) {
      info.settling_min = std::min(info.settling_min, y[i]);
      info.settling_max = std::max(info.settling_max, y[i]);
    }
  }

  double max_signed = -std::numeric_limits<double>::infinity();
  double min_signed = std::numeric_limits<double>::infinity();
  std::size_t peak_index = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double signed_excursion = sign * (y[i] - y0);
    max_signed = std::max(max_signed, signed_excursion);
    min_signed = std::min(min_signed, signed_excursion);
    if (std::abs(y[i] - y0) > std::abs(y[peak_index] - y0)) peak_index = i;
  }
  info.overshoot_percent = 100.0 * std::max(0.0, max_signed - height) / height;
  info.undershoot_percent = 100.0 * std::max(0.0, -min_signed) / height;
  info.peak = std::abs(y[peak_index] - y0);
  info.peak_time_s = static_cast<double>(peak_index) * ts + offset_s;
  if (!std::isnan(info.rise_time_s)) info.rise_time_s = std::max(info.rise_time_s, 0.0);
  return info;
}

}  // namespace clearshape::metrics
