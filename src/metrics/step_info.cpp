#include "clearshape/metrics/step_info.hpp"

#include <cmath>
#include <limits>
#include <span>

#include "clearshape/core/error.hpp"
#include "crossing.hpp"
#include "validate.hpp"

namespace clearshape::metrics {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void validate_step_inputs(std::span<const double> y, double sample_time_s, const StepInfoOptions& options) {
  detail::require_min_size("response", y.size(), 2);
  detail::require_finite_samples("response", y);
  require_positive("sample_time_s", sample_time_s);
  require_in_open("settling_threshold", options.settling_threshold, 0.0, 1.0, "MATLAB uses 0.02");
  require_in_closed("rise_low", options.rise_low, 0.0, 1.0);
  require_in_closed("rise_high", options.rise_high, 0.0, 1.0);
  if (!(options.rise_low < options.rise_high)) {
    throw_invalid("rise_low", options.rise_low, "< rise_high", "MATLAB uses [0.1, 0.9]");
  }
  require_finite("initial_value", options.initial_value);
}

// The step from y0 to yf on the record's time axis.
struct Step {
  double y0 = 0.0, yf = 0.0;
  double delta = 0.0;   ///< yf − y0, != 0
  double sign = 1.0;    ///< of delta
  double height = 0.0;  ///< |delta|
  double ts = 0.0;
  double offset_s = 0.0;  ///< time of sample 0 from the step time
};

Step step_of(const UniformSeries& response, const StepInfoOptions& options) {
  Step s;
  s.y0 = options.initial_value;
  s.yf = options.final_value.value_or(response.values.back());
  require_finite("final_value", s.yf);
  s.delta = s.yf - s.y0;
  if (s.delta == 0.0) {
    throw_invalid("final_value - initial_value", s.delta, "!= 0",
                  "A step response must move; give yfinal and yinit explicitly");
  }
  s.sign = s.delta > 0.0 ? 1.0 : -1.0;
  s.height = std::abs(s.delta);
  s.ts = response.sample_time_s;
  s.offset_s = response.start_s - options.step_time_s.value_or(response.start_s);
  return s;
}

// Settling: last sample outside the band |y − yf| <= threshold·|Δ|, then the band-edge crossing.
double settling_time_s(std::span<const double> y, const Step& s, double threshold) {
  const double band = threshold * s.height;
  std::size_t last_out = y.size();
  for (std::size_t i = y.size(); i-- > 0;) {
    if (std::abs(y[i] - s.yf) > band) {
      last_out = i;
      break;
    }
  }
  if (last_out == y.size()) return s.offset_s;  // inside the band from the first sample
  if (last_out == y.size() - 1) return kNaN;    // never settles within the record
  const double a = std::abs(y[last_out] - s.yf) - band;      // > 0
  const double b = std::abs(y[last_out + 1] - s.yf) - band;  // <= 0
  return (static_cast<double>(last_out) + a / (a - b)) * s.ts + s.offset_s;
}

// Settling min/max after the response has risen (first reach of the high rise level, t_high).
void settling_range(std::span<const double> y, double t_high, StepInfo& info) {
  if (std::isnan(t_high)) {
    info.settling_min = kNaN;
    info.settling_max = kNaN;
    return;
  }
  const auto first = static_cast<std::size_t>(std::ceil(t_high - 1e-12));
  info.settling_min = std::numeric_limits<double>::infinity();
  info.settling_max = -std::numeric_limits<double>::infinity();
  for (std::size_t i = first; i < y.size(); ++i) {
    info.settling_min = std::min(info.settling_min, y[i]);
    info.settling_max = std::max(info.settling_max, y[i]);
  }
}

// Overshoot and undershoot in % of |Δ| (stepinfo), and the peak |y − y0| and its time.
void excursions(std::span<const double> y, const Step& s, StepInfo& info) {
  double max_signed = -std::numeric_limits<double>::infinity();
  double min_signed = std::numeric_limits<double>::infinity();
  std::size_t peak_index = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double signed_excursion = s.sign * (y[i] - s.y0);
    max_signed = std::max(max_signed, signed_excursion);
    min_signed = std::min(min_signed, signed_excursion);
    if (std::abs(y[i] - s.y0) > std::abs(y[peak_index] - s.y0)) peak_index = i;
  }
  info.overshoot_percent = 100.0 * std::max(0.0, max_signed - s.height) / s.height;
  info.undershoot_percent = 100.0 * std::max(0.0, -min_signed) / s.height;
  info.peak = std::abs(y[peak_index] - s.y0);
  info.peak_time_s = static_cast<double>(peak_index) * s.ts + s.offset_s;
}

}  // namespace

StepInfo step_info(const UniformSeries& response, const StepInfoOptions& options) {
  const std::span<const double> y = response.values;
  validate_step_inputs(y, response.sample_time_s, options);
  const Step s = step_of(response, options);
  StepInfo info;
  info.final_value = s.yf;
  // Rise time: first reach of yinit + high·Δ minus first reach of yinit + low·Δ (stepinfo).
  const double t_low = detail::first_reach_samples(y, s.y0 + options.rise_low * s.delta, s.sign);
  const double t_high = detail::first_reach_samples(y, s.y0 + options.rise_high * s.delta, s.sign);
  info.rise_time_s = (t_high - t_low) * s.ts;  // NaN propagates when never reached
  info.settling_time_s = settling_time_s(y, s, options.settling_threshold);
  settling_range(y, t_high, info);
  excursions(y, s, info);
  if (!std::isnan(info.rise_time_s)) info.rise_time_s = std::max(info.rise_time_s, 0.0);
  return info;
}

}  // namespace clearshape::metrics
