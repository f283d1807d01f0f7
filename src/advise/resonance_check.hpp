#pragma once
// Whether a fitted spectral line is a resonance a shaper can be designed for (private to advise;
// docs/recommend.md "No usable resonance"): its peak must stand out of the local PSD floor by a
// prominence ratio, and its damping ratio must not sit on a bound of the fit (a line fitted to
// a flat or noisy stretch ends on the widest or narrowest line the fit allows).
#include <cstddef>
#include <string>

#include "clearshape/advise/spectrum_input.hpp"
#include "peak_fit.hpp"

namespace clearshape::advise::detail {

/// The local PSD floor at f0: the median power of the bins within f0/3 … 3·f0 (from `lowest` on).
double local_floor(const MeasuredSpectrum& spectrum, double f0_hz, std::size_t lowest);

struct LineVerdict {
  double prominence = 0.0;  ///< the line's peak power / local floor
  std::string problem;      ///< empty: usable; else why not (for the refusal)
};

/// `peak_power`: the measured power at the line's peak bin (used when the fit did not converge).
LineVerdict judge_line(const MeasuredSpectrum& spectrum, const LineFit& fit, double peak_hz, double peak_power, std::size_t lowest,
                       double min_prominence);

/// What to record instead when no usable resonance is found (the end of the refusal).
std::string what_to_record();

}  // namespace clearshape::advise::detail
