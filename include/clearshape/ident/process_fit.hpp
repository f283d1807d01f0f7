#pragma once
// Process-model identification (thesis §4.2, Eq. 4.2; MATLAB procest with Focus = simulation):
// the parameters of a P0…P3[D][Z][U][I] model are fitted by minimising the SIMULATION error
//   V(θ) = Σₑ wₑ Σₖ (yₑ[k] − ŷₑ[k; θ])²,   wₑ = 1 / (Nₑ · var yₑ)  (each experiment weighs equally)
// over one or several experiments that share the plant (per-experiment initial state and offsets).
// ŷ is the exact sampled response (ZOH or FOH input, fractional delay; lti/simulate.hpp).
// Solver: Ceres Levenberg–Marquardt with an exact Jacobian from forward sensitivities (the
// discretization derivatives from Van Loan's block-triangular matrix exponential), started from
// the best of many data-derived candidates (step overshoot/peak time, a subspace model, a grid)
// ranked with the numerator (Kp, Kp·Tz), initial state and offset solved linearly.
// Why analytic derivatives: the Jacobian is exact (LM converges cleanly near ζ ≈ 1 and for
// small Tp; the covariance is trustworthy), it costs one sensitivity recursion per parameter
// (half of central differences), and ∂/∂Td needs no step size across sample boundaries.
// Uncertainty: (JᵀJ)⁻¹σ², σ² = Σ(w e)²/(N − p), from the Jacobian Ceres evaluates at the optimum
// (column-scaled SVD; NaN when the data do not determine a direction, e.g. Tz with a free initial
// state on a step applied at the first sample); when the residual fails a Ljung–Box whiteness test
// (coloured noise), the Newey–West sandwich instead (src/ident/covariance.hpp).
// Time constants, Tw and Zeta are optimised as logarithms (always positive: a stable model, as
// procest); Kp and Tz are free in sign (Tz < 0 is a right-half-plane zero, thesis speed model).
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/core/series.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::ident {

/// How the state at the first sample is obtained (MATLAB InitialCondition).
enum class InitialState {
  zero,       ///< at rest
  estimate,   ///< free parameters, fitted with the plant
  automatic,  ///< estimate when y[0] is off the rest level (0, or any level with an output
              ///< offset; tolerance max(2 % of the range, 4σ of the noise)); else fit from rest and
              ///< estimate after all if an F test at that optimum finds a free initial state
              ///< significant (p < 10⁻⁶): a record cut mid-motion. (With x0 free, a step applied at
              ///< the first sample cannot separate Tz from x0, so rest is preferred.)
};

/// Constraints on one parameter, by MATLAB name (Kp, Tp1, Tp2, Tp3, Tw, Zeta, Td, Tz).
struct ParameterSetting {
  std::optional<double> fixed;    ///< held at this value (not estimated)
  std::optional<double> initial;  ///< added as a start of the search
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

struct ProcessFitOptions {
  lti::Hold hold = lti::Hold::zoh;
  InitialState initial_state = InitialState::automatic;
  bool estimate_output_offset = false;  ///< y = ŷ + y0, y0 per experiment
  bool estimate_input_offset = false;   ///< plant input u − u0, u0 per experiment
  std::map<std::string, ParameterSetting, std::less<>> parameters;  ///< by MATLAB name
  /// false: refine from the given initial values only (every free parameter needs `initial`;
  /// MATLAB procest(data, init_sys)) — no data-derived candidates, one Levenberg–Marquardt run.
  bool search = true;
  std::size_t starts = 3;            ///< Levenberg–Marquardt runs from the best-ranked candidates
  std::size_t max_iterations = 200;  ///< per run
  double max_delay_s = 0.0;          ///< upper bound of Td; 0 = a quarter of the shortest record
  double max_zeta = 3.0;             ///< default upper bound of Zeta
};

struct ParameterEstimate {
  std::string name;      ///< MATLAB name
  double value = 0.0;
  double std_dev = 0.0;  ///< 1σ: (JᵀJ)⁻¹σ² or, coloured residual, the sandwich (0 fixed, NaN undetermined)
  bool fixed = false;
  bool at_bound = false;  ///< free and on a finite bound of the search (ident/trust.hpp)
};

/// How well a model reproduces one experiment (MATLAB compare, simulation horizon ∞).
struct ExperimentFit {
  std::string name;
  double fit_percent = 0.0;  ///< NRMSE fit 100(1 − ‖y − ŷ‖/‖y − ȳ‖) with the fit's own IC handling
  double fit_percent_zero_ic = 0.0;       ///< same with x0 = 0
  double fit_percent_estimated_ic = 0.0;  ///< same with x0 fitted by least squares (compare's default)
  double rmse = 0.0;                      ///< output units
  Eigen::VectorXd initial_state;          ///< x0 used (cascade realization of the model)
  double output_offset = 0.0;
  double input_offset = 0.0;
  UniformSeries simulated;  ///< ŷ on the experiment's grid
};

struct ProcessEstimate {
  lti::ProcessModel model{"P1", lti::ProcessParameters{}};
  std::vector<ParameterEstimate> parameters;  ///< in parameter_names() order
  Eigen::MatrixXd covariance;  ///< of the free parameters (natural units), names in free_names
  std::vector<std::string> free_names;
  std::vector<ExperimentFit> experiments;
  std::size_t samples = 0;          ///< N, all experiments
  std::size_t free_parameters = 0;  ///< p, plant plus per-experiment initial states and offsets
  double loss = 0.0;                ///< V = Σe²/N (unweighted)
  double fpe = 0.0;                 ///< Akaike FPE = V(1 + p/N)/(1 − p/N)
  double aic = 0.0;                 ///< N ln V + 2p
  double bic = 0.0;                 ///< N ln V + p ln N
  double weighted_cost = 0.0;       ///< ½ Σ wₑ e² at the optimum (what LM minimised)
  std::size_t candidates = 0;       ///< starting points ranked
  std::size_t iterations = 0;       ///< LM iterations over all runs
  bool converged = false;           ///< the best run reached a Ceres convergence criterion

  double fit_percent() const;  ///< mean over the experiments
  /// ωn = 1/Tw and ζ = Zeta (thesis §4.2) with their 1σ; nullopt without a U pair.
  std::optional<double> natural_frequency_rad_s() const;
  std::optional<double> natural_frequency_std_rad_s() const;
  std::optional<double> damping_ratio() const;
  std::optional<double> damping_ratio_std() const;
  const ParameterEstimate& parameter(std::string_view name) const;
};

/// Fits `structure` to the experiments (≥ 1, each ≥ 10 samples; sample times may differ).
/// Throws InvalidArgument on bad data or settings (unknown parameter name, fixed value out of
/// range, bounds that exclude each other) and RuntimeError if no start gives a finite cost.
ProcessEstimate estimate_process_model(const lti::ProcessStructure& structure,
                                       std::span<const Experiment> experiments,
                                       const ProcessFitOptions& options = {});

struct CompareOptions {
  InitialState initial_state = InitialState::zero;  ///< automatic = estimate if not at rest
  bool estimate_output_offset = false;
  double input_offset = 0.0;
  lti::Hold hold = lti::Hold::zoh;
};

/// Simulates `model` on an experiment and scores it (MATLAB compare): the initial state and
/// output offset, when asked, are fitted by linear least squares.
ExperimentFit compare(const lti::ProcessModel& model, const Experiment& experiment,
                      const CompareOptions& options = {});

}  // namespace clearshape::ident
