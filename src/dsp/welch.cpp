#include "clearshape/dsp/welch.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <fmt/format.h>
#include <unsupported/Eigen/FFT>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "welch_segments.hpp"

namespace clearshape::dsp {

std::vector<double> make_window(Window window, std::size_t n) {
  std::vector<double> w(n, 1.0);
  if (window == Window::rectangular || n <= 1) return w;
  // Generalized Hamming, periodic (scipy general_hamming with sym=False):
  // w[k] = α + (1 − α)·cos(−π + 2πk/n), k = 0 … n−1; α = 0.5 (Hann), 0.54 (Hamming).
  const double alpha = window == Window::hann ? 0.5 : 0.54;
  const double step = 2.0 * kPi / static_cast<double>(n);
  for (std::size_t k = 0; k < n; ++k) {
    w[k] = alpha + (1.0 - alpha) * std::cos(static_cast<double>(k) * step - kPi);
  }
  return w;
}

namespace {

void detrend(std::vector<double>& x, std::size_t n, Detrend type) {
  if (type == Detrend::none || n == 0) return;
  double mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) mean += x[i];
  mean /= static_cast<double>(n);
  if (type == Detrend::constant) {
    for (std::size_t i = 0; i < n; ++i) x[i] -= mean;
    return;
  }
  // Least-squares straight line (scipy.signal.detrend type='linear'), centred time for accuracy.
  const double t_mean = (static_cast<double>(n) - 1.0) / 2.0;
  double sxy = 0.0;
  double sxx = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) - t_mean;
    sxy += t * (x[i] - mean);
    sxx += t * t;
  }
  const double slope = sxx > 0.0 ? sxy / sxx : 0.0;
  for (std::size_t i = 0; i < n; ++i) x[i] -= mean + slope * (static_cast<double>(i) - t_mean);
}

}  // namespace

namespace detail {

SegmentPlan plan_segments(std::size_t samples, double sample_rate_hz, const WelchOptions& options,
                          std::string_view who) {
  require_positive("sample_rate_hz", sample_rate_hz);
  SegmentPlan plan;
  plan.segment_length = options.segment_length;
  const std::size_t nperseg = plan.segment_length;
  if (nperseg == 0) throw_invalid("segment_length", 0.0, ">= 1");
  const std::size_t noverlap = options.overlap.value_or(nperseg / 2);
  plan.fft_length = options.fft_length.value_or(nperseg);
  if (noverlap >= nperseg) {
    throw_invalid("overlap", static_cast<double>(noverlap), fmt::format("< segment_length = {}", nperseg));
  }
  if (plan.fft_length < nperseg) {
    throw_invalid("fft_length", static_cast<double>(plan.fft_length), fmt::format(">= segment_length = {}", nperseg));
  }
  if (samples < nperseg) {
    throw InvalidArgument(fmt::format(
        "{}: the signal has {} samples; allowed: at least segment_length = {}. Use a shorter "
        "segment_length or a longer record", who, samples, nperseg));
  }
  plan.window = make_window(options.window, nperseg);
  double sum_w = 0.0;
  double sum_w2 = 0.0;
  for (double w : plan.window) {
    sum_w += w;
    sum_w2 += w * w;
  }
  // Welch (1967): density scale 1/(fs·Σw²) gives unit²/Hz; spectrum scale 1/(Σw)² gives unit².
  plan.scale = options.scaling == SpectralScaling::density ? 1.0 / (sample_rate_hz * sum_w2)
                                                           : 1.0 / (sum_w * sum_w);
  plan.step = nperseg - noverlap;
  plan.segments = (samples - noverlap) / plan.step;
  plan.bins = plan.fft_length / 2 + 1;
  plan.resolution_hz = 1.0 / (static_cast<double>(plan.fft_length) * (1.0 / sample_rate_hz));  // numpy rfftfreq
  plan.detrend = options.detrend;
  return plan;
}

void require_finite(std::span<const double> x, std::string_view who, std::string_view signal) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) {
      throw InvalidArgument(fmt::format("{}: {}sample {} is not finite ({})", who,
                                        signal.empty() ? "" : fmt::format("{} ", signal), i, x[i]));
    }
  }
}

double one_sided_factor(const SegmentPlan& plan, std::size_t k) noexcept {
  const bool single = k == 0 || (plan.fft_length % 2 == 0 && k == plan.bins - 1);
  return single ? 1.0 : 2.0;
}

SegmentTransformer::SegmentTransformer(const SegmentPlan& plan)
    : plan_(plan), segment_(plan.fft_length, 0.0) {
  fft_.SetFlag(Eigen::FFT<double>::HalfSpectrum);
}

const std::vector<std::complex<double>>& SegmentTransformer::transform(std::span<const double> x, std::size_t s) {
  const std::size_t start = s * plan_.step;
  std::fill(segment_.begin(), segment_.end(), 0.0);
  for (std::size_t i = 0; i < plan_.segment_length; ++i) segment_[i] = x[start + i];
  detrend(segment_, plan_.segment_length, plan_.detrend);
  for (std::size_t i = 0; i < plan_.segment_length; ++i) segment_[i] *= plan_.window[i];
  fft_.fwd(spectrum_, segment_);
  return spectrum_;
}

}  // namespace detail

Spectrum welch(std::span<const double> input, double sample_rate_hz, const WelchOptions& options) {
  const detail::SegmentPlan plan = detail::plan_segments(input.size(), sample_rate_hz, options, "welch");
  detail::require_finite(input, "welch", "");
  detail::SegmentTransformer transformer(plan);
  std::vector<double> accumulated(plan.bins, 0.0);
  for (std::size_t s = 0; s < plan.segments; ++s) {
    const auto& transform = transformer.transform(input, s);
    for (std::size_t k = 0; k < plan.bins; ++k) accumulated[k] += std::norm(transform[k]);
  }
  Spectrum out;
  out.segments = plan.segments;
  out.frequency_hz.resize(plan.bins);
  out.power.resize(plan.bins);
  for (std::size_t k = 0; k < plan.bins; ++k) {
    out.frequency_hz[k] = static_cast<double>(k) * plan.resolution_hz;
    out.power[k] = accumulated[k] * plan.scale * detail::one_sided_factor(plan, k) / static_cast<double>(plan.segments);
  }
  return out;
}

}  // namespace clearshape::dsp
