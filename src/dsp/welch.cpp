#include "clearshape/dsp/welch.hpp"

#include <cmath>
#include <complex>

#include <fmt/format.h>
#include <unsupported/Eigen/FFT>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

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

Spectrum welch(std::span<const double> input, double sample_rate_hz, const WelchOptions& options) {
  require_positive("sample_rate_hz", sample_rate_hz);
  const std::size_t nperseg = options.segment_length;
  if (nperseg == 0) throw_invalid("segment_length", 0.0, ">= 1");
  const std::size_t noverlap = options.overlap.value_or(nperseg / 2);
  const std::size_t nfft = options.fft_length.value_or(nperseg);
  if (noverlap >= nperseg) {
    throw_invalid("overlap", static_cast<double>(noverlap), fmt::format("< segment_length = {}", nperseg));
  }
  if (nfft < nperseg) {
    throw_invalid("fft_length", static_cast<double>(nfft), fmt::format(">= segment_length = {}", nperseg));
  }
  if (input.size() < nperseg) {
    throw InvalidArgument(fmt::format(
        "welch: the signal has {} samples; allowed: at least segment_length = {}. Use a shorter "
        "segment_length or a longer record", input.size(), nperseg));
  }
  for (std::size_t i = 0; i < input.size(); ++i) {
    if (!std::isfinite(input[i])) {
      throw InvalidArgument(fmt::format("welch: sample {} is not finite ({})", i, input[i]));
    }
  }

  const std::vector<double> window = make_window(options.window, nperseg);
  double sum_w = 0.0;
  double sum_w2 = 0.0;
  for (double w : window) {
    sum_w += w;
    sum_w2 += w * w;
  }
  // Welch (1967): density scale 1/(fs·Σw²) gives unit²/Hz; spectrum scale 1/(Σw)² gives unit².
  const double scale = options.scaling == SpectralScaling::density ? 1.0 / (sample_rate_hz * sum_w2)
                                                                   : 1.0 / (sum_w * sum_w);
  const std::size_t step = nperseg - noverlap;
  const std::size_t segments = (input.size() - noverlap) / step;
  const std::size_t bins = nfft / 2 + 1;

  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  std::vector<double> segment(nfft, 0.0);
  std::vector<std::complex<double>> transform;
  std::vector<double> accumulated(bins, 0.0);
  for (std::size_t s = 0; s < segments; ++s) {
    const std::size_t start = s * step;
    std::fill(segment.begin(), segment.end(), 0.0);
    for (std::size_t i = 0; i < nperseg; ++i) segment[i] = input[start + i];
    detrend(segment, nperseg, options.detrend);
    for (std::size_t i = 0; i < nperseg; ++i) segment[i] *= window[i];
    fft.fwd(transform, segment);
    for (std::size_t k = 0; k < bins; ++k) accumulated[k] += std::norm(transform[k]);
  }

  Spectrum out;
  out.segments = segments;
  out.frequency_hz.resize(bins);
  out.power.resize(bins);
  const double df = 1.0 / (static_cast<double>(nfft) * (1.0 / sample_rate_hz));  // numpy rfftfreq
  for (std::size_t k = 0; k < bins; ++k) {
    out.frequency_hz[k] = static_cast<double>(k) * df;
    // One-sided: double every bin except DC and (even nfft) Nyquist.
    const bool single = k == 0 || (nfft % 2 == 0 && k == bins - 1);
    out.power[k] = accumulated[k] * scale * (single ? 1.0 : 2.0) / static_cast<double>(segments);
  }
  return out;
}

}  // namespace clearshape::dsp
