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
};

struct CrossValidation {
  std::vector<std::string> names;          ///< the experiments
  std::vector<ProcessEstimate> estimates;  ///< estimates[i]: identified on experiment i alone
  Eigen::MatrixXd fit_percent;             ///< (i, j): model i simulated on experiment j
  std::vector<double> mean_validation_fit_percent;  ///< per model: mean over j ≠ i
  /// index of the best model: the best mean validation fit among the trusted models
  /// (ident/trust.hpp); among all of them only when none is trusted (best_trusted false)
  std::size_t best = 0;
  bool best_trusted = true;
  std::vector<TrustAssessment> trust;      ///< per model
  std::optional<ProcessEstimate> joint;    ///< identified on all experiments at once
  std::vector<double> joint_fit_percent;   ///< the joint model on each experiment
};

/// Needs ≥ 2 experiments. Throws as estimate_process_model.
CrossValidation cross_validate(const lti::ProcessStructure& structure, std::span<const Experiment> experiments,
                               const CrossValidationOptions& options = {});

}  // namespace clearshape::ident
