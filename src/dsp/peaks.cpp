#include "clearshape/dsp/peaks.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::dsp {

namespace {

// Local maxima; a plateau counts once at its middle sample (rounded down), as scipy's
// _local_maxima_1d. The first and last samples are never peaks.
std::vector<std::size_t> local_maxima(std::span<const double> x) {
  std::vector<std::size_t> peaks;
  if (x.size() < 3) return peaks;
  const std::size_t i_max = x.size() - 1;
  std::size_t i = 1;
  while (i < i_max) {
    if (x[i - 1] < x[i]) {
      std::size_t ahead = i + 1;
      while (ahead < i_max && x[ahead] == x[i]) ++ahead;
      if (x[ahead] < x[i]) {
        peaks.push_back((i + ahead - 1) / 2);
        i = ahead;
      }
    }
    ++i;
  }
  return peaks;
}

// Prominence with an unlimited window (scipy peak_prominences, wlen=None): the peak height above
// the higher of the lowest points reached on each side before a higher sample.
double prominence(std::span<const double> x, std::size_t peak) {
  const double h = x[peak];
  double left_min = h;
  for (std::size_t i = peak + 1; i-- > 0;) {
    if (x[i] > h) break;
    left_min = std::min(left_min, x[i]);
  }
  double right_min = h;
  for (std::size_t i = peak; i < x.size(); ++i) {
    if (x[i] > h) break;
    right_min = std::min(right_min, x[i]);
  }
  return h - std::max(left_min, right_min);
}

// scipy _select_by_peak_distance: visit peaks from the highest; drop lower peaks closer than
// `distance` samples to a kept one.
std::vector<std::size_t> select_by_distance(std::span<const double> x,
                                            const std::vector<std::size_t>& peaks,
                                            std::size_t distance) {
  const std::size_t n = peaks.size();
  std::vector<bool> keep(n, true);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return x[peaks[a]] < x[peaks[b]]; });
  for (std::size_t r = n; r-- > 0;) {
    const std::size_t j = order[r];
    if (!keep[j]) continue;
    for (std::size_t k = j; k-- > 0 && peaks[j] - peaks[k] < distance;) keep[k] = false;
    for (std::size_t k = j + 1; k < n && peaks[k] - peaks[j] < distance; ++k) keep[k] = false;
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) out.push_back(peaks[i]);
  }
  return out;
}

}  // namespace

std::vector<Peak> find_peaks(std::span<const double> values, const PeakOptions& options) {
  if (options.min_distance == 0) throw_invalid("min_distance", 0.0, ">= 1 sample");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw InvalidArgument(fmt::format("find_peaks: value {} is not finite ({})", i, values[i]));
    }
  }
  std::vector<std::size_t> candidates;
  for (std::size_t i : local_maxima(values)) {
    if (values[i] >= options.min_height) candidates.push_back(i);
  }
  if (options.min_distance > 1) candidates = select_by_distance(values, candidates, options.min_distance);
  std::vector<Peak> peaks;
  for (std::size_t i : candidates) {
    const double prom = prominence(values, i);
    if (prom >= options.min_prominence) peaks.push_back(Peak{i, values[i], prom});
  }
  return peaks;
}

std::vector<SpectralPeak> spectral_peaks(const Spectrum& spectrum, const PeakOptions& options,
                                         std::size_t max_count) {
  const std::vector<double>& p = spectrum.power;
  const std::vector<Peak> found = find_peaks(p, options);
  std::vector<SpectralPeak> out;
  out.reserve(found.size());
  const double df = spectrum.resolution_hz();
  for (const Peak& peak : found) {
    SpectralPeak s;
    s.bin = peak.index;
    s.frequency_hz = spectrum.frequency_hz[peak.index];
    s.power = peak.height;
    s.prominence = peak.prominence;
    s.interpolated_frequency_hz = s.frequency_hz;
    if (peak.index > 0 && peak.index + 1 < p.size()) {
      // Vertex of the parabola through three equally spaced points: offset
      // δ = (y₋ − y₊) / (2·(y₋ − 2y₀ + y₊)) bins.
      const double ym = p[peak.index - 1];
      const double y0 = p[peak.index];
      const double yp = p[peak.index + 1];
      const double curvature = ym - 2.0 * y0 + yp;
      if (curvature < 0.0) s.interpolated_frequency_hz += df * (ym - yp) / (2.0 * curvature);
    }
    out.push_back(s);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const SpectralPeak& a, const SpectralPeak& b) { return a.power > b.power; });
  if (max_count > 0 && out.size() > max_count) out.resize(max_count);
  return out;
}

}  // namespace clearshape::dsp
