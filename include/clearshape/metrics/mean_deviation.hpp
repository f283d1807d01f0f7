#pragma once
// Residual-vibration level of a response (thesis Eq. 5.1, §5.1.2):
//   MD = sqrt( Σ_{i=k}^{N−1} (M − s_i)² / n ),  n = N − k,
// where M is the mean of the response in steady state and k, the start of the steady state,
// is "the first coincide point of the system response and the mean".
//
// How k and M are computed (the thesis gives no algorithm; this is our reading):
//   1. M₀ = mean of the last `final_window_fraction` of the samples.
//   2. k(M) = the first sample index i >= `search_from_s` at which the response meets M:
//      s_i == M, or s_i − M has the opposite sign of s_{i−1} − M (the sample at or just after
//      the crossing). For a step response that is the first time the rising edge reaches M, so
//      the overshoot and the ringing count as residual vibration (Fig. 5.9).
//   3. M_{m+1} = mean(s_k … s_{N−1}) with k = k(M_m); repeat until k stops changing. At the
//      fixed point M is exactly the mean of the samples that enter Eq. 5.1 and k is the first
//      point where the response meets that mean. A repeated k that is not the previous one (a
//      cycle) or `max_iterations` ends the iteration with converged = false.
//   The search starts at the first sample at or after `search_from_s`; a sign change counts only
//   between two samples that are both in the search range. Several fixed points can exist
//   (e.g. a sample exactly equal to one mean and a later crossing of a slightly different
//   one); the iteration returns the one reached from M₀, deterministically.
//   A window that never crosses its own mean (a numerically constant tail) takes k = the first
//   sample of the window.
#include <cstddef>
#include <limits>

#include "clearshape/core/series.hpp"

namespace clearshape::metrics {

struct MeanDeviationOptions {
  double final_window_fraction = 0.2;  ///< (0, 1]: share of the record that gives M₀
  double search_from_s = -std::numeric_limits<double>::infinity();  ///< ignore earlier crossings
  int max_iterations = 100;
};

struct MeanDeviationResult {
  double mean_deviation = 0.0;  ///< MD, in the units of the response
  double steady_mean = 0.0;     ///< M
  std::size_t start_index = 0;  ///< k
  double start_time_s = 0.0;    ///< time of sample k
  std::size_t samples = 0;      ///< n = N − k
  int iterations = 0;
  bool converged = false;
};

/// Eq. 5.1. Throws InvalidArgument for fewer than 2 samples, non-finite samples, options out of
/// range, or a `search_from_s` after the last sample.
MeanDeviationResult mean_deviation(const UniformSeries& response,
                                   const MeanDeviationOptions& options = {});

}  // namespace clearshape::metrics
