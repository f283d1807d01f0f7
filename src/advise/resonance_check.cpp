#include "resonance_check.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

namespace clearshape::advise::detail {

double local_floor(const MeasuredSpectrum& s, double f0, std::size_t lowest) {
  std::vector<double> band;
  for (std::size_t k = lowest; k < s.power.size(); ++k) {
    if (s.frequency_hz[k] >= f0 / 3.0 && s.frequency_hz[k] <= 3.0 * f0) band.push_back(s.power[k]);
  }
  if (band.empty()) return 0.0;
  const auto mid = band.begin() + static_cast<std::ptrdiff_t>(band.size() / 2);
  std::nth_element(band.begin(), mid, band.end());
  return *mid;
}

LineVerdict judge_line(const MeasuredSpectrum& s, const LineFit& fit, double peak_hz, double peak_power, std::size_t lowest,
                       double min_prominence) {
  LineVerdict v;
  const double f0 = fit.converged ? fit.frequency_hz : peak_hz;
  const double peak = fit.converged ? line_power(fit, f0) : peak_power;
  const double floor = local_floor(s, f0, lowest);
  v.prominence = floor > 0.0 ? peak / floor : 0.0;
  if (fit.converged && (fit.damping_ratio >= 0.999 * kMaxLineDamping || fit.damping_ratio <= 1.001 * kMinLineDamping)) {
    v.problem = fmt::format("the line at {:.4g} Hz fits only with a damping ratio on the fit's bound ({:.4g}; allowed {:g} … {:g})",
                            f0, fit.damping_ratio, kMinLineDamping, kMaxLineDamping);
  } else if (!(v.prominence >= min_prominence)) {
    v.problem = fmt::format("the highest peak, at {:.4g} Hz, stands only {:.3g} × above the local PSD floor (the median within "
                            "f/3 … 3f); a resonance stands at least {:g} × above it",
                            f0, v.prominence, min_prominence);
  }
  return v;
}

std::string what_to_record() {
  return "record what the shaper must cancel: the link's free decay after a move (a step, then --from-s after it), or its "
         "response to broadband excitation (clearshape signal --type chirp or prbs), long enough for several periods of the "
         "mode in each of about seven Welch segments";
}

}  // namespace clearshape::advise::detail
