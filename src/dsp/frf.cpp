#include "clearshape/dsp/frf.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "welch_segments.hpp"

namespace clearshape::dsp {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void require_same_length(std::span<const double> x, std::span<const double> y, const char* who) {
  if (x.size() != y.size()) {
    throw InvalidArgument(fmt::format("{}: input has {} samples and output {}; allowed: the same length", who,
                                      x.size(), y.size()));
  }
}

// Auto- and cross-spectra of one pass over the segments (the same segments for all three).
struct SpectraSums {
  std::vector<double> xx, yy;
  std::vector<std::complex<double>> xy;
};

SpectraSums accumulate(std::span<const double> x, std::span<const double> y, const detail::SegmentPlan& plan) {
  detail::SegmentTransformer tx(plan), ty(plan);
  SpectraSums sums{std::vector<double>(plan.bins, 0.0), std::vector<double>(plan.bins, 0.0),
                   std::vector<std::complex<double>>(plan.bins, 0.0)};
  for (std::size_t s = 0; s < plan.segments; ++s) {
    const auto& fx = tx.transform(x, s);
    const auto& fy = ty.transform(y, s);
    for (std::size_t k = 0; k < plan.bins; ++k) {
      sums.xx[k] += std::norm(fx[k]);
      sums.yy[k] += std::norm(fy[k]);
      sums.xy[k] += std::conj(fx[k]) * fy[k];  // scipy _spectral_helper: conj(X)·Y
    }
  }
  const double n = static_cast<double>(plan.segments);
  for (std::size_t k = 0; k < plan.bins; ++k) {
    const double f = plan.scale * detail::one_sided_factor(plan, k) / n;
    sums.xx[k] *= f;
    sums.yy[k] *= f;
    sums.xy[k] *= f;
  }
  return sums;
}

std::vector<double> frequencies(const detail::SegmentPlan& plan) {
  std::vector<double> f(plan.bins);
  for (std::size_t k = 0; k < plan.bins; ++k) f[k] = static_cast<double>(k) * plan.resolution_hz;
  return f;
}

}  // namespace

CrossSpectrum csd(std::span<const double> x, std::span<const double> y, double sample_rate_hz,
                  const WelchOptions& options) {
  require_same_length(x, y, "csd");
  const auto plan = detail::plan_segments(x.size(), sample_rate_hz, options, "csd");
  detail::require_finite(x, "csd", "input");
  detail::require_finite(y, "csd", "output");
  auto sums = accumulate(x, y, plan);
  return {frequencies(plan), std::move(sums.xy), plan.segments};
}

FrequencyResponse estimate_frequency_response(std::span<const double> input, std::span<const double> output,
                                              double sample_rate_hz, const WelchOptions& options) {
  const char* who = "frequency response";
  require_same_length(input, output, who);
  const auto plan = detail::plan_segments(input.size(), sample_rate_hz, options, who);
  detail::require_finite(input, who, "input");
  detail::require_finite(output, who, "output");
  auto sums = accumulate(input, output, plan);
  bool any_power = false;
  for (double p : sums.xx) any_power = any_power || p > 0.0;
  if (!any_power) throw InvalidArgument(fmt::format("{}: the input has no power at any frequency (is it constant?)", who));
  FrequencyResponse out;
  out.frequency_hz = frequencies(plan);
  out.segments = plan.segments;
  out.response.resize(plan.bins);
  out.coherence.resize(plan.bins);
  for (std::size_t k = 0; k < plan.bins; ++k) {
    const double pxx = sums.xx[k], pyy = sums.yy[k];
    out.response[k] = pxx > 0.0 ? sums.xy[k] / pxx : std::complex<double>(kNaN, kNaN);  // H1 (Bendat & Piersol ch. 9)
    out.coherence[k] = pxx * pyy > 0.0 ? std::norm(sums.xy[k]) / (pxx * pyy) : kNaN;      // coherence (ibid.)
  }
  out.input_psd = std::move(sums.xx);
  out.output_psd = std::move(sums.yy);
  return out;
}

std::vector<double> FrequencyResponse::magnitude() const {
  std::vector<double> m(response.size());
  for (std::size_t k = 0; k < response.size(); ++k) m[k] = std::abs(response[k]);
  return m;
}

std::vector<double> FrequencyResponse::phase_deg() const {
  std::vector<double> p(response.size());
  for (std::size_t k = 0; k < response.size(); ++k) p[k] = std::arg(response[k]) * 180.0 / kPi;
  return p;
}

std::size_t matlab_default_segment_length(std::size_t samples) noexcept {
  // MATLAB tfestimate: 8 segments with 50 % overlap → L = ⌊N / 4.5⌋.
  const std::size_t length = (2 * samples) / 9;
  return length > 0 ? length : 1;
}

}  // namespace clearshape::dsp
