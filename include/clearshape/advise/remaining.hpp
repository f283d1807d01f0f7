#pragma once
// The vibration a shaper leaves in a measured spectrum, measured as Klipper's calibrate_shaper
// measures it (docs/recommend.md): the shaper's residual vibration V(f, ζ) (Eq. 2.19) weighs
// the PSD bin by bin; only the part of the PSD above a threshold (5 % of its maximum — a shaper
// cannot do better than that) counts:
//   remaining = Σ max(V(f)·P(f) − P_thr, 0) / Σ max(P(f) − P_thr, 0).
// The worst case is taken over test damping ratios and over frequency scales s (the mode may
// really sit at s·f: V is evaluated at s·f).
#include <cstddef>
#include <span>
#include <vector>

#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::advise {

/// The bins of a spectrum that count (power above the threshold), prepared once per spectrum.
struct WeightedBins {
  std::vector<double> frequency_hz;
  std::vector<double> power;
  double threshold = 0.0;     ///< P_thr
  double total = 0.0;         ///< Σ max(P − P_thr, 0)
};
/// threshold_fraction in (0, 1): P_thr = fraction · max P over the bins at or above
/// min_frequency_hz (lower bins are dropped). Throws InvalidArgument for a fraction out of
/// range or no positive power.
WeightedBins weighted_bins(const MeasuredSpectrum& spectrum, double threshold_fraction = 0.05,
                           double min_frequency_hz = 0.0);

/// Klipper's normalisation of a TEST_RESONANCES PSD (shaper_calibrate.py,
/// CalibrationData.normalize_to_frequencies): P / (f + 0.1 Hz), below 10 Hz (2 × its MIN_FREQ)
/// also × exp(1 − (10 Hz / (f + 0.1 Hz))²). Throws InvalidArgument for sizes that differ.
std::vector<double> klipper_normalized_power(const std::vector<double>& frequency_hz, const std::vector<double>& power);

/// The spectrum recommend scores: one Klipper normalises (MeasuredSpectrum::klipper_normalizes)
/// with klipper_normalized_power, any other as it is — so printer data is judged by the PSD
/// Klipper's own estimate of the remaining vibration weighs.
MeasuredSpectrum scored_spectrum(const MeasuredSpectrum& spectrum);

/// remaining for one damping ratio and frequency scale.
double remaining_vibration(const shaping::Shaper& shaper, const WeightedBins& bins, double damping_ratio,
                           double frequency_scale = 1.0);

/// remaining with each bin's own damping ratio (damping_ratio_per_bin[k] for bins.frequency_hz[k]).
/// Throws InvalidArgument for a size that differs from the bins'.
double remaining_vibration(const shaping::Shaper& shaper, const WeightedBins& bins, std::span<const double> damping_ratio_per_bin,
                           double frequency_scale = 1.0);

/// The worst remaining over every spectrum, damping ratio and frequency scale.
double worst_remaining_vibration(const shaping::Shaper& shaper, const std::vector<WeightedBins>& spectra,
                                 const std::vector<double>& damping_ratios,
                                 const std::vector<double>& frequency_scales);

/// max over damping ratios and scales of V(s·f, ζ) at each frequency (the curve Klipper draws).
std::vector<double> worst_response(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                   const std::vector<double>& damping_ratios,
                                   const std::vector<double>& frequency_scales);

/// The PSD the shaper leaves: P(f) · V(f)², V the worst_response over the damping ratios and
/// scales (V is the ratio of residual to unshaped vibration amplitude, Eq. 2.19, so power scales
/// with its square; Klipper's graph draws P·V, the weighting of its remaining-vibration score).
std::vector<double> power_after_shaper(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                       const std::vector<double>& power, const std::vector<double>& damping_ratios,
                                       const std::vector<double>& frequency_scales);

}  // namespace clearshape::advise
