#pragma once
// Quantiles and tails of the χ² and normal distributions, compiled once (src/core/distributions.cpp)
// for every module that tests a statistic: Boost.Math's distributions with their default policies,
// so the values are bit-for-bit those of calling Boost directly (docs/design.md, "Build time").
//
//   const double bound = distributions::chi_squared_quantile(3.0, 0.99);   // χ²₃ at 99 %
//   const double p = distributions::chi_squared_upper_tail(12.0, q);        // P(χ²₁₂ > q)

namespace clearshape::distributions {

/// The quantile of χ² with `dof` > 0 degrees of freedom at probability 0 < p < 1.
double chi_squared_quantile(double dof, double p);

/// P(X > x) for X ~ χ²(dof), x ≥ 0, computed directly (no 1 − cdf cancellation).
double chi_squared_upper_tail(double dof, double x);

/// The quantile of the standard normal distribution at probability 0 < p < 1.
double normal_quantile(double p);

}  // namespace clearshape::distributions
