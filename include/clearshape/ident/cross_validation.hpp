#pragma once
// Thesis §4.2 cross-validation: "Transfer function of the system is identified for each input type
// separately and all these identified transfer functions are tested for each input type to find
// out the best suitable transfer function." The model identified on experiment i is simulated on
// every experiment j; the matrix of NRMSE fits (MATLAB compare) is reported and the model with the
// highest mean fit on the OTHER experiments is the best. A model fitted on all experiments jointly
// is added for comparison.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/trust.hpp"

namespace clearshape::ident {

struct CrossValidationOptions {
  ProcessFitOptions fit;
  /// Initial state of a model simulated on another experiment: zero, estimate (MATLAB compare's
  /// default), or automatic (estimate when the record does not start at rest).
  InitialState validation_initial_state = InitialState::automatic;
  bool joint = true;  ///< also fit all experiments together
  /// Trust breaks near-ties only: a trusted model within this many points of the best mean
  /// validation fit is preferred to an untrusted best.
  double trust_tie_points = 1.0;
};

struct CrossValidation {
  std::vector<std::string> names;          ///< the experiments
  std::vector<ProcessEstimate> estimates;  ///< estimates[i]: identified on experiment i alone
  Eigen::MatrixXd fit_percent;             ///< (i, j): model i simulated on experiment j
  std::vector<double> mean_validation_fit_percent;  ///< per model: mean over j ≠ i
  /// index of the best model: ranked by mean validation fit first (a non-finite fit never wins);
  /// of the models within trust_tie_points of the highest, a trusted one (ident/trust.hpp:
  /// finite σ, parameters off their bounds) is preferred. An untrusted model with a clearly
  /// better validation fit still wins over a trusted one (best_trusted false then).
  std::size_t best = 0;
  bool best_trusted = true;               ///< the best model is trusted
  std::vector<TrustAssessment> trust;      ///< per model
  std::optional<ProcessEstimate> joint;    ///< identified on all experiments at once
  std::vector<double> joint_fit_percent;   ///< the joint model on each experiment
};

/// The best model: the highest finite mean validation fit, or a trusted one within
/// trust_tie_points of it (the highest such); nullopt when no mean is finite. Sizes must match.
std::optional<std::size_t> pick_best(const std::vector<double>& mean_validation_fit_percent, const std::vector<bool>& trusted,
                                     double trust_tie_points);

/// Needs ≥ 2 experiments. Throws as estimate_process_model.
CrossValidation cross_validate(const lti::ProcessStructure& structure, std::span<const Experiment> experiments,
                               const CrossValidationOptions& options = {});

}  // namespace clearshape::ident
