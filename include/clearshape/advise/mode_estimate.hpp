#pragma once
// The vibration mode(s) of a measured spectrum, with their uncertainty (docs/recommend.md):
//   * spectrum: the highest peak (parabolic vertex), its half-power bandwidth B (corrected for
//     the window's own width) → ζ = B / (2 f); σ_f from the grid, the Welch average and the
//     peak's offset from ωn; a second mode when a second peak stands out;
//   * free decay: when the record is a free decay (the damped-sinusoid fit of ident::modes
//     explains ≥ 80 % of it and matches the peaks), its ωn, ζ and 1σ replace the spectral ones.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::advise {

/// A spectrum without a resonance a shaper could be designed for (a run-time failure: exit 1).
class NoUsableResonance : public RuntimeError {
 public:
  using RuntimeError::RuntimeError;
};

struct ModeEstimate {
  double frequency_hz = 0.0;          ///< natural frequency
  double frequency_std_hz = 0.0;      ///< 1σ
  double damping_ratio = 0.0;
  double damping_ratio_std = 0.0;
  double peak_power = 0.0;            ///< PSD at the peak (0 for a fit-only mode)
  double prominence = 0.0;            ///< the line's peak over the local PSD floor (median within f/3 … 3f)
  double half_power_low_hz = 0.0;     ///< half-power crossings of the peak (spectrum)
  double half_power_high_hz = 0.0;
  std::string source;                 ///< "spectrum" or "free-decay fit"
  /// The damping ratios the data cannot exclude, when wider than ζ ± σ (set when shoulders widen
  /// the fitted line beyond the peak's half-power band): the worst case covers them.
  std::optional<std::pair<double, double>> damping_ratio_range;
  std::string note;                   ///< a remark on the estimate (e.g. shoulders)
};

struct ModeEstimateOptions {
  std::size_t max_modes = 2;             ///< 1 or 2
  std::optional<double> min_frequency_hz;  ///< ignore bins below; default 2 × the resolution
  /// A mode stands out: its fitted peak ≥ this × the local PSD floor (the median power within
  /// f/3 … 3f). Below it (or with ζ on the fit's bound) the highest peak is no usable resonance.
  double min_prominence = 4.0;
  /// Relevance floor of a second peak: power ≥ this × the highest (1 %: 10 % of its amplitude;
  /// detection itself is by significance). On a clean decay the two-line test finds any mismatch
  /// of the line's shape significant; a peak 40 dB down is no mode to shape.
  double second_peak_min_ratio = 0.01;
  double second_peak_min_prominence = 0.25;  ///< a second peak's prominence ≥ this × its own power
  std::size_t second_peak_tries = 6;     ///< at most this many peaks get the two-line significance test
  bool free_decay_fit = true;            ///< try the ident::modes free-decay fit on the record
  std::size_t free_decay_max_samples = 20000;  ///< skip the fit on longer records (cost)
};

struct ModeEstimation {
  std::vector<ModeEstimate> modes;           ///< the modes used (dominant first)
  std::vector<ModeEstimate> spectral_modes;  ///< the spectral estimates (always)
  bool free_decay_used = false;
  double free_decay_fit_percent = 0.0;       ///< NRMSE fit of the free-decay model (0: not tried)
  std::string note;                          ///< why the free-decay fit was or was not used
};

/// Spectral modes of one spectrum (no fit). Throws NoUsableResonance ("no usable resonance in
/// <source>: <why>; <what to record instead>") when the spectrum has no peak, or its highest
/// peak does not stand out of the local floor or fits only with ζ on a bound.
std::vector<ModeEstimate> spectral_modes(const MeasuredSpectrum& spectrum, const ModeEstimateOptions& options = {});

/// Modes of a set of spectra (the first is the reference; the others only for the free-decay
/// fit when they carry a record). Throws InvalidArgument for no spectra or max_modes ∉ {1, 2}.
ModeEstimation estimate_modes(const std::vector<MeasuredSpectrum>& spectra, const ModeEstimateOptions& options = {});

}  // namespace clearshape::advise
