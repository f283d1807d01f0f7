#pragma once
// Agreement of a model output ŷ with a measurement y.
#include <span>

namespace clearshape::metrics {

/// NRMSE fit, as MATLAB `compare`: 100·(1 − ‖y − ŷ‖ / ‖y − ȳ‖) in percent (100 = perfect;
/// negative = worse than the mean). Throws InvalidArgument for unequal or zero lengths,
/// non-finite values or a constant y.
double fit_percent(std::span<const double> measured, std::span<const double> model);

/// Root-mean-square error sqrt(Σ(y − ŷ)² / n). Same validation (a constant y is allowed).
double rmse(std::span<const double> measured, std::span<const double> model);

}  // namespace clearshape::metrics
