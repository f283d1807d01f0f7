#include "clearshape/metrics/fit.hpp"

#include <cmath>

#include "clearshape/core/error.hpp"
#include "validate.hpp"

namespace clearshape::metrics {
namespace {

void validate(std::span<const double> measured, std::span<const double> model) {
  detail::require_min_size("measured", measured.size(), 1);
  detail::require_same_size("measured", measured.size(), "model", model.size());
  detail::require_finite_samples("measured", measured);
  detail::require_finite_samples("model", model);
}

double error_norm(std::span<const double> measured, std::span<const double> model) {
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const double d = measured[i] - model[i];
    sum_sq += d * d;
  }
  return std::sqrt(sum_sq);
}

}  // namespace

double fit_percent(std::span<const double> measured, std::span<const double> model) {
  validate(measured, model);
  double mean = 0.0;
  for (const double y : measured) mean += y;
  mean /= static_cast<double>(measured.size());
  double spread_sq = 0.0;
  for (const double y : measured) spread_sq += (y - mean) * (y - mean);
  const double spread = std::sqrt(spread_sq);
  if (!(spread > 0.0)) {
    throw InvalidArgument("‖measured − mean‖ = 0 is out of range; allowed: > 0 (the NRMSE fit "
                          "divides by it). A constant measurement has no fit; use rmse()");
  }
  return 100.0 * (1.0 - error_norm(measured, model) / spread);  // NRMSE fit (MATLAB compare)
}

double rmse(std::span<const double> measured, std::span<const double> model) {
  validate(measured, model);
  return error_norm(measured, model) / std::sqrt(static_cast<double>(measured.size()));
}

}  // namespace clearshape::metrics
