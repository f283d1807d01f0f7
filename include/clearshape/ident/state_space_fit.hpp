#pragma once
// General linear model of a chosen order from input/output data, for multi-mode systems:
// N4SID starts (subspace.hpp) at the horizons max(2n, 10), ×2, ×4, ×8 (as the record allows), the
// one with the least simulation error refined by output error (simulation) with Ceres in real modal
// form — one 2×2 block r·R(θ) per complex pole pair, a scalar per real pole, B = [0 1]ᵀ / 1 per
// block, C, D (and x0) free: a minimal parametrization whose pole parameters are the modes.
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/core/series.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/subspace.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/state_space.hpp"
#include "clearshape/lti/transfer_function.hpp"

namespace clearshape::ident {

struct StateSpaceFitOptions {
  SubspaceOptions subspace;
  bool refine = true;                               ///< output-error refinement (Ceres LM)
  InitialState initial_state = InitialState::zero;  ///< automatic behaves as estimate
  bool feedthrough = true;                          ///< D free (else 0)
  std::size_t max_iterations = 200;
};

struct StateSpaceEstimate {
  lti::DiscreteStateSpace discrete;         ///< real modal form, at the data's sample time
  Eigen::VectorXd initial_state;            ///< in the modal coordinates
  std::optional<lti::StateSpace> continuous;             ///< ZOH equivalent, when it exists
  std::optional<lti::TransferFunction> transfer_function;  ///< of `continuous`
  std::vector<ModeEstimate> modes;          ///< every complex pair, largest contribution first
  double fit_percent = 0.0;                 ///< on the estimation data
  double rmse = 0.0;
  double loss = 0.0;                        ///< V = Σe²/N
  double fpe = 0.0;                         ///< V(1 + p/N)/(1 − p/N)
  double aic = 0.0;                         ///< N ln V + 2p
  std::size_t parameters = 0;               ///< p
  bool refined = false;
  UniformSeries simulated;
};

/// Throws InvalidArgument on bad data or order; RuntimeError if the subspace step fails.
StateSpaceEstimate estimate_state_space(const Experiment& experiment, std::size_t order,
                                        const StateSpaceFitOptions& options = {});

/// Simulates the estimate on another record from its zero state (x0 = 0) and scores it:
/// NRMSE fit % and RMSE, as MATLAB compare with InitialCondition 'z'.
ExperimentFit compare(const StateSpaceEstimate& estimate, const Experiment& experiment);

}  // namespace clearshape::ident
