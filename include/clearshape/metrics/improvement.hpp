#pragma once
// Improvement of a figure of merit by shaping (thesis §5.1.2 and Appendix B):
//   improvement % = (without − with) / without · 100.
#include <span>

namespace clearshape::metrics {

/// Throws InvalidArgument unless `without` > 0 and `with` >= 0 (both finite).
double improvement_percent(double without, double with);

/// Arithmetic mean of a non-empty list of finite values (the "mean" rows of Tables 5.1, B.x).
double mean_of(std::span<const double> values);

}  // namespace clearshape::metrics
