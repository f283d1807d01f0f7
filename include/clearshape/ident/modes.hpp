#pragma once
// Residual-mode identification (docs/design.md §2 "Which mode to shape"): the dominant lightly damped
// modes of a link-sensor record — frequency, damping ratio, amplitude, each with its 1σ — for
// shaper design (shaping::Mode{ωn, ζ}).
//  * Free response (e.g. gyro rate after a move): ERA/Ho–Kalman on the (differenced, block-
//    averaged) record gives the poles; the record is then fitted by damped sinusoids
//    y[k] = Σ Aᵢ rᵢᵏ cos(kθᵢ + φᵢ) (+ real exponentials + offset), refined by Ceres
//    Levenberg–Marquardt from the subspace start. Uncertainty from the covariance (JᵀJ)⁻¹σ².
//  * Input/output data: N4SID, then output-error refinement in real modal form
//    (estimate_state_space); the modes are the complex pole pairs.
// A discrete pole z = r e^(iθ) maps to s = (ln r + iθ)/T: ωn = |s|, ζ = −Re s/|s| (ZOH-exact).
#include <cstddef>
#include <string>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/stabilisation.hpp"

namespace clearshape::ident {

struct ModeEstimate {
  double natural_frequency_rad_s = 0.0;
  double natural_frequency_std_rad_s = 0.0;
  double damping_ratio = 0.0;
  double damping_ratio_std = 0.0;
  /// Free response: initial amplitude of the mode's damped sinusoid (output units).
  /// Input/output: peak gain |Gᵢ(e^(jωd T))| of the mode's term (output per input unit).
  double amplitude = 0.0;
  double amplitude_std = 0.0;
  double rms_contribution = 0.0;  ///< RMS of the mode's part of the fitted output (ranking)

  double natural_frequency_hz() const noexcept;
  double damped_frequency_rad_s() const noexcept;  ///< ωn√(1−ζ²) (0 for ζ ≥ 1)
  double damped_frequency_hz() const noexcept;
  double natural_frequency_std_hz() const noexcept;
};

struct ModeOptions {
  std::size_t modes = 1;           ///< how many dominant modes to report
  std::size_t order = 0;           ///< subspace model order; 0 = chosen by the stabilisation diagram
  bool use_stabilisation = true;   ///< order 0: false = 2·modes + 2 (free) or 2·modes (I/O), as before
  StabilisationOptions stabilisation;  ///< its max_damping_ratio follows max_damping_ratio
  bool refine = true;              ///< least-squares refinement (Ceres) after the subspace step
  bool estimate_offset = true;     ///< free response: constant output offset (sensor bias)
  double max_damping_ratio = 0.7;  ///< report only modes with ζ below this ("lightly damped")
  std::size_t max_iterations = 200;
};

struct ModeIdentification {
  std::vector<ModeEstimate> modes;  ///< dominant first (by RMS contribution)
  double sample_time_s = 1.0;
  double fit_percent = 0.0;         ///< NRMSE fit of the fitted model to the record
  double rmse = 0.0;
  UniformSeries fitted;             ///< the model's output on the record's grid (same start_s)
  std::size_t decimation = 1;       ///< block-averaging factor used for the subspace step
  std::string method;               ///< "era+ls", "era", "n4sid+oe", "n4sid"
  std::size_t order = 0;            ///< model order of the fit
  /// "stabilisation" (the diagram chose it), "option" (ModeOptions::order), "modes" (2·modes(+2):
  /// the diagram was off or found no persistent mode)
  std::string order_source;
  StabilisationDiagram stabilisation;  ///< empty orders when not computed
};

/// Modes of a free response (no input). sample_time_s of the series sets the frequency unit
/// (1 → cycles/sample). Throws InvalidArgument for fewer than 50 samples, non-finite values
/// or modes = 0; RuntimeError if no oscillatory mode is found.
ModeIdentification identify_free_response_modes(const UniformSeries& response, const ModeOptions& options = {});

/// Modes of an input/output record via estimate_state_space(order). Same errors.
ModeIdentification identify_modes(const Experiment& experiment, const ModeOptions& options = {});

}  // namespace clearshape::ident
