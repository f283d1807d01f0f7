#pragma once
// Least-squares fit of mode lines to a PSD (private to advise). A line is the rate response of a
// mode, f·a / (f0² − f² + 2jζ f0 f); its power P(f) = a² f² / ((f0² − f²)² + (2ζ f0 f)²).
// Two lines add either as powers (incoherent: modes excited independently, e.g. two axes) or as
// complex responses with signed residues (coherent: one input drives both, the usual servo
// joint; the cross term shapes the valley between them). The model is fitted to ln P over a band
// of bins (Levenberg–Marquardt; Welch's scatter is multiplicative, so ln P has a uniform variance).
#include <cstddef>
#include <span>
#include <vector>

namespace clearshape::advise::detail {

/// The fit keeps each line's damping ratio within these bounds; a fit that ends on one has not
/// found a resonance's width.
inline constexpr double kMinLineDamping = 1e-4, kMaxLineDamping = 0.9;

struct LineStart {
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
};

struct LineFit {
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
  double residue = 0.0;            ///< a (signed when coherent)
  double frequency_var = 0.0;      ///< variance of f0 (Hz²), from s²(JᵀJ)⁻¹
  double log_damping_var = 0.0;    ///< variance of ln ζ
  bool converged = false;
};

struct LinesFit {
  std::vector<LineFit> lines;
  double cost = 0.0;               ///< Σ residual² (ln units)
  bool converged = false;
};

/// Fits the lines to bins [first, last] (inclusive) from their starts; `signs` (coherent only)
/// are the starting signs of the residues. `correlation` (≥ 1) inflates the covariance for
/// correlated bins (zero padding, window, overlap).
LinesFit fit_lines(std::span<const double> frequency_hz, std::span<const double> power, std::size_t first, std::size_t last,
                   const std::vector<LineStart>& starts, bool coherent, const std::vector<double>& signs, double correlation);

/// One fitted line's power at f.
double line_power(const LineFit& line, double frequency_hz) noexcept;

}  // namespace clearshape::advise::detail
