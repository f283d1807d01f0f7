#include "clearshape/study/measures.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/encoder_speed.hpp"

namespace clearshape::study {

std::vector<double> motor_speed_deg_s(const Record& record, bool zero_phase) {
  // Thesis §3.3: the encoder angle differentiated, then the 4th-order 30 rad/s Butterworth.
  return dsp::angle_speed_deg_s(record.motor_angle_deg, record.sample_time_s,
                                zero_phase ? dsp::Phase::zero_phase : dsp::Phase::causal);
}

std::vector<double> link_angle_deg(const Record& record, double bias_window_s) {
  const auto& w = record.link_rate_deg_s;
  const std::size_t n = w.size();
  std::vector<double> angle(n, 0.0);
  if (n == 0) return angle;
  const std::size_t nb = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::floor(bias_window_s / record.sample_time_s)), 1, n);
  double bias = 0.0;
  for (std::size_t k = 0; k < nb; ++k) bias += w[k];
  bias /= static_cast<double>(nb);
  const double half_t = 0.5 * record.sample_time_s;
  for (std::size_t k = 1; k < n; ++k) {
    angle[k] = angle[k - 1] + half_t * ((w[k - 1] - bias) + (w[k] - bias));  // trapezoidal rule
  }
  return angle;
}

UniformSeries md_series(const Record& record, const MeasureSpec& measure) {
  UniformSeries s;
  s.start_s = record.time_s.empty() ? 0.0 : record.time_s.front();
  s.sample_time_s = record.sample_time_s;
  s.values = measure.md_signal == MdSignal::link_angle_deg
                 ? link_angle_deg(record, measure.bias_window_s)
                 : record.link_rate_deg_s;
  return s;
}

metrics::MeanDeviationResult series_mean_deviation(const UniformSeries& series,
                                                   const MeasureSpec& measure, double search_from_s) {
  metrics::MeanDeviationOptions options;
  options.final_window_fraction = measure.md_final_window_fraction;
  options.search_from_s = search_from_s;
  return metrics::mean_deviation(series, options);
}

metrics::MeanDeviationResult run_mean_deviation(const Record& record, const MeasureSpec& measure,
                                                const InputSpec& input) {
  return series_mean_deviation(md_series(record, measure), measure, input.last_move_start_s);
}

double settle_time_s(std::span<const double> y, double sample_time_s, double from_s, double fraction) {
  const std::size_t n = y.size();
  if (n < 2) return from_s;
  const std::size_t tail = std::max<std::size_t>(1, n / 10);
  double final = 0.0;
  for (std::size_t k = n - tail; k < n; ++k) final += y[k];
  final /= static_cast<double>(tail);
  const double move = std::abs(final - y.front());
  if (!(move > 0.0)) return from_s;
  const auto first = static_cast<std::size_t>(std::max(0.0, std::ceil(from_s / sample_time_s)));
  std::size_t last_out = first;
  for (std::size_t k = first; k < n; ++k) {
    if (std::abs(y[k] - final) > fraction * move) last_out = k + 1;
  }
  return std::max(from_s, static_cast<double>(std::min(last_out, n - 1)) * sample_time_s);
}

MeanStd mean_std(std::span<const double> values) {
  MeanStd r;
  if (values.empty()) return r;
  for (const double v : values) r.mean += v;
  r.mean /= static_cast<double>(values.size());
  if (values.size() > 1) {
    double ss = 0.0;
    for (const double v : values) ss += (v - r.mean) * (v - r.mean);
    r.std = std::sqrt(ss / static_cast<double>(values.size() - 1));
  }
  return r;
}

}  // namespace clearshape::study
