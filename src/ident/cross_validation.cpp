#include "clearshape/ident/cross_validation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <limits>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::ident {

std::optional<std::size_t> pick_best(const std::vector<double>& mean_validation_fit_percent, const std::vector<bool>& trusted,
                                     double trust_tie_points) {
  const auto& means = mean_validation_fit_percent;
  if (trusted.size() != means.size()) throw InvalidArgument("pick_best: one trust flag per model is needed");
  double top = -std::numeric_limits<double>::infinity();
  for (const double mean : means) {
    if (std::isfinite(mean)) top = std::max(top, mean);
  }
  // Validation fit first (thesis §4.2); trust breaks near-ties only.
  std::optional<std::size_t> best;
  const auto rank = [&](std::size_t k) { return std::pair{static_cast<bool>(trusted[k]), means[k]}; };
  for (std::size_t i = 0; i < means.size(); ++i) {
    if (!std::isfinite(means[i]) || means[i] < top - trust_tie_points) continue;
    if (!best || rank(i) > rank(*best)) best = i;
  }
  return best;
}

CrossValidation cross_validate(const lti::ProcessStructure& structure, std::span<const Experiment> experiments,
                               const CrossValidationOptions& options) {
  const std::size_t count = experiments.size();
  if (count < 2) {
    throw InvalidArgument("cross-validation needs at least 2 experiments (got " + std::to_string(count) +
                          "); give one record per input type (step, ramp, sine, PRBS).");
  }
  CrossValidation cv;
  const auto m = static_cast<Eigen::Index>(count);
  cv.fit_percent.resize(m, m);
  for (std::size_t i = 0; i < count; ++i) {
    cv.names.push_back(experiments[i].name);
    cv.estimates.push_back(estimate_process_model(structure, experiments.subspan(i, 1), options.fit));
  }
  CompareOptions co;
  co.hold = options.fit.hold;
  co.initial_state = options.validation_initial_state;
  co.estimate_output_offset = options.fit.estimate_output_offset;
  for (const auto& e : cv.estimates) cv.trust.push_back(assess(e));
  for (std::size_t i = 0; i < count; ++i) {
    double sum = 0.0;
    for (std::size_t j = 0; j < count; ++j) {
      double f = 0.0;
      if (i == j) {
        f = cv.estimates[i].experiments[0].fit_percent;  // the estimation fit itself
      } else {
        f = compare(cv.estimates[i].model, experiments[j], co).fit_percent;
        sum += f;
      }
      cv.fit_percent(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = f;
    }
    const double mean = sum / static_cast<double>(count - 1);
    cv.mean_validation_fit_percent.push_back(mean);
  }
  std::vector<bool> trusted;
  for (const auto& t : cv.trust) trusted.push_back(t.trusted);
  const std::optional<std::size_t> best = pick_best(cv.mean_validation_fit_percent, trusted, options.trust_tie_points);
  cv.best = best.value_or(0);
  cv.best_trusted = best && trusted[*best];
  if (options.joint) {
    cv.joint = estimate_process_model(structure, experiments, options.fit);
    for (const auto& e : cv.joint->experiments) cv.joint_fit_percent.push_back(e.fit_percent);
  }
  return cv;
}

}  // namespace clearshape::ident
