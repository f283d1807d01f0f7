#pragma once
// Residual vibration and robustness of an impulse sequence.
#include <cstddef>
#include <vector>

#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

/// Residual vibration V(ω, ζ) (Eq. 2.19; Magee & Book 1992) normalised by ΣA: the ratio of the
/// residual oscillation after the last impulse to that of a single unit impulse, for a mode
/// (ω, ζ) with ζ in [0, 1).
double residual_vibration(const Shaper& shaper, const Mode& actual);

struct SensitivityPoint {
  double frequency_ratio = 0.0;  ///< r = ω / ωm
  double residual = 0.0;         ///< V(r·ωm, ζ)
};

/// V over r in [ratio_from, ratio_to] at `points` evenly spaced ratios; the actual damping is
/// `actual_damping` (defaults to the design's).
std::vector<SensitivityPoint> sensitivity_curve(const Shaper& shaper, const Mode& design,
                                                double ratio_from, double ratio_to,
                                                std::size_t points);
std::vector<SensitivityPoint> sensitivity_curve(const Shaper& shaper, const Mode& design,
                                                double actual_damping, double ratio_from,
                                                double ratio_to, std::size_t points);

struct InsensitivityBand {
  double ratio_low = 1.0;   ///< lower edge r where V rises through vtol
  double ratio_high = 1.0;  ///< upper edge
  double width() const noexcept { return ratio_high - ratio_low; }
};

/// The contiguous band of r around 1 where V <= vtol (to a relative 1e-9, so shapers designed
/// to touch vtol keep their band; edges found by bracketing and
/// bisection). Width 0 when V(1) > vtol. `hump_tolerance` lets interior humps of fitted EI
/// shapers exceed vtol by that relative amount without ending the band: the band then ends
/// where V first exceeds vtol·(1 + hump_tolerance), and its edge is the last crossing of vtol
/// before that. The ratios are sampled from r = 1 outward (step 1e-3 / max(1, duration in
/// design periods)) and the edge refined by bisection to 1e-14. For a damped mode whose V
/// stays below vtol at high ratios (a small last impulse) ratio_high is capped at 10. The walk
/// skips ratios where the envelope Σ|Aᵢ|e^{−ζrω(t_N−tᵢ)}/|ΣA| (an upper bound of V) is below
/// vtol, so its cost does not grow with the shaper's duration there. Throws InvalidArgument for
/// a shaper lasting more than 10⁴ periods of the design mode (the sampling cannot resolve it).
InsensitivityBand insensitivity(const Shaper& shaper, const Mode& design, double vtol,
                                double hump_tolerance = 0.0);

}  // namespace clearshape::shaping
