#pragma once
// identify's residual tests (MATLAB resid; ident/residuals.hpp) per experiment: the table, the
// JSON block and the warnings (they do not change "trusted": an output-error fit models no noise).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/residuals.hpp"

namespace clearshape::cli {

struct ExperimentResiduals {
  std::string name;
  ident::ResidualTests tests;
};

/// The tests on e = y − ŷ of every experiment; --resid-lags and --resid-confidence are checked here
/// (InvalidArgument naming the option and its allowed range).
std::vector<ExperimentResiduals> test_residuals(const std::vector<ident::Experiment>& experiments,
                                                const ident::ProcessEstimate& estimate, std::size_t max_lag,
                                                double confidence);

/// One line per failed verdict, e.g. "residual of 'run' depends on the input (…)".
std::vector<std::string> residual_warnings(const std::vector<ExperimentResiduals>& residuals);

nlohmann::ordered_json residuals_json(const std::vector<ExperimentResiduals>& residuals, std::size_t max_lag);

void print_residuals(const std::vector<ExperimentResiduals>& residuals, std::size_t max_lag);

}  // namespace clearshape::cli
