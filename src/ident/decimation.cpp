#include "decimation.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/dsp/peaks.hpp"
#include "clearshape/dsp/welch.hpp"

namespace clearshape::ident::detail {

std::size_t choose_decimation(const std::vector<double>& v, std::size_t peaks, std::size_t order,
                              double min_relative_power) {
  const std::size_t n = v.size();
  std::size_t seg = 1;
  while (seg * 2 <= std::min<std::size_t>(n, 2048)) seg *= 2;
  if (seg < 16) return 1;
  dsp::WelchOptions wo;
  wo.segment_length = seg;
  const dsp::Spectrum spec = dsp::welch(v, 1.0, wo);  // frequency in cycles/sample
  const auto found = dsp::spectral_peaks(spec, {}, peaks);
  double top = 0.0, f_hi = 0.0;
  for (const auto& p : found) top = std::max(top, p.power);
  for (const auto& p : found)
    if (p.power >= min_relative_power * top) f_hi = std::max(f_hi, p.interpolated_frequency_hz);
  if (!(f_hi > 0.0)) return 1;
  std::size_t q = static_cast<std::size_t>(std::floor(1.0 / (10.0 * f_hi)));
  const std::size_t q_max = n / std::max<std::size_t>(60, 6 * order);
  q = std::min(q, q_max);
  return std::max<std::size_t>(q, 1);
}

std::vector<double> block_average(const std::vector<double>& y, std::size_t q) {
  std::vector<double> averaged;
  for (std::size_t k = 0; (k + 1) * q <= y.size(); ++k) {
    double s = 0.0;
    for (std::size_t j = 0; j < q; ++j) s += y[k * q + j];
    averaged.push_back(s / static_cast<double>(q));
  }
  return averaged;
}

}  // namespace clearshape::ident::detail
