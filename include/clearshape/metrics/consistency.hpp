#pragma once
// Repeatability of repeated runs (thesis Eq. 4.1, §4.1.1):
//   E_i = sqrt( Σ_j (m_j − t_ij)² / n ) / r,   m_j = mean over runs at sample j,
//   r = max_j m_j − min_j m_j (the total range of the mean signal).
#include <span>
#include <vector>

namespace clearshape::metrics {

struct ConsistencyResult {
  std::vector<double> errors;       ///< E_i for each run (dimensionless)
  double mean_error = 0.0;          ///< mean of E_i (the "mean" row of Tables 4.1–4.2)
  std::vector<double> mean_signal;  ///< m_j
  double range = 0.0;               ///< r, in the units of the runs
};

/// Eq. 4.1 for `runs` (each one output signal sampled on the same grid). Throws
/// InvalidArgument for fewer than 2 runs, unequal or zero lengths, non-finite samples, or a
/// mean signal with zero range (E_i undefined).
ConsistencyResult consistency_errors(std::span<const std::vector<double>> runs);

}  // namespace clearshape::metrics
