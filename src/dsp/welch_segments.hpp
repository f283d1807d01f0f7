#pragma once
// The segment engine shared by welch() and the cross-spectral estimates (frf.cpp): Welch's
// (1967) overlapping segments, each detrended, windowed and transformed, with scipy's
// _spectral_helper conventions (one-sided, density or spectrum scaling).
#include <complex>
#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include <unsupported/Eigen/FFT>

#include "clearshape/dsp/welch.hpp"

namespace clearshape::dsp::detail {

/// The validated segmentation of a record of `samples` samples.
struct SegmentPlan {
  std::size_t segment_length = 0;
  std::size_t step = 0;   ///< segment_length − overlap
  std::size_t fft_length = 0;
  std::size_t segments = 0;
  std::size_t bins = 0;   ///< fft_length / 2 + 1
  double scale = 0.0;     ///< density 1/(fs·Σw²) or spectrum 1/(Σw)² (Welch 1967)
  double resolution_hz = 0.0;
  Detrend detrend = Detrend::constant;
  std::vector<double> window;
};

/// Validates the options against a record of `samples` samples (InvalidArgument naming the option
/// and its allowed range; `who` starts the message).
SegmentPlan plan_segments(std::size_t samples, double sample_rate_hz, const WelchOptions& options,
                          std::string_view who);

/// InvalidArgument naming `who` and `signal` when a sample is not finite.
void require_finite(std::span<const double> x, std::string_view who, std::string_view signal);

/// One-sided factor of bin k: 1 at DC and (even fft_length) Nyquist, else 2.
double one_sided_factor(const SegmentPlan& plan, std::size_t k) noexcept;

/// Reusable buffers for transforming segments.
class SegmentTransformer {
 public:
  explicit SegmentTransformer(const SegmentPlan& plan);
  /// The FFT (bins 0 … fft_length/2) of segment s of `x`: detrended, then windowed.
  const std::vector<std::complex<double>>& transform(std::span<const double> x, std::size_t s);

 private:
  const SegmentPlan& plan_;
  Eigen::FFT<double> fft_;
  std::vector<double> segment_;
  std::vector<std::complex<double>> spectrum_;
};

}  // namespace clearshape::dsp::detail
