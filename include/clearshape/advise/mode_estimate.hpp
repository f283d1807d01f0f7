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
#include <vector>

#include "clearshape/advise/spectrum_input.hpp"

namespace clearshape::advise {

struct ModeEstimate {
  double frequency_hz = 0.0;          ///< natural frequency
  double frequency_std_hz = 0.0;      ///< 1σ
  double damping_ratio = 0.0;
  double damping_ratio_std = 0.0;
  double peak_power = 0.0;            ///< PSD at the peak (0 for a fit-only mode)
  double half_power_low_hz = 0.0;     ///< half-power crossings of the peak (spectrum)
  double half_power_high_hz = 0.0;
  std::string source;                 ///< "spectrum" or "free-decay fit"
};

struct ModeEstimateOptions {
  std::size_t max_modes = 2;             ///< 1 or 2
  std::optional<double> min_frequency_hz;  ///< ignore bins below; default 2 × the resolution
  double second_peak_min_ratio = 0.2;    ///< a second peak stands out: power ≥ this × the highest
  double second_peak_min_prominence = 0.25;  ///< … and prominence ≥ this × its own power
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

/// Spectral modes of one spectrum (no fit). Throws RuntimeError when the spectrum has no peak.
std::vector<ModeEstimate> spectral_modes(const MeasuredSpectrum& spectrum, const ModeEstimateOptions& options = {});

/// Modes of a set of spectra (the first is the reference; the others only for the free-decay
/// fit when they carry a record). Throws InvalidArgument for no spectra or max_modes ∉ {1, 2}.
ModeEstimation estimate_modes(const std::vector<MeasuredSpectrum>& spectra, const ModeEstimateOptions& options = {});

}  // namespace clearshape::advise
