#include "clearshape/metrics/consistency.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "validate.hpp"

namespace clearshape::metrics {

ConsistencyResult consistency_errors(std::span<const std::vector<double>> runs) {
  if (runs.size() < 2) {
    throw InvalidArgument("runs = " + std::to_string(runs.size()) +
                          " is out of range; allowed: >= 2 repeated runs (Eq. 4.1 compares each "
                          "run with the mean of all). Record more repetitions");
  }
  const std::size_t n = runs.front().size();
  detail::require_min_size("run 1", n, 1);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string name = "run " + std::to_string(i + 1);
    detail::require_same_size("run 1", n, name, runs[i].size());
    detail::require_finite_samples(name, runs[i]);
  }

  ConsistencyResult result;
  result.mean_signal.assign(n, 0.0);
  const double count = static_cast<double>(runs.size());
  for (const auto& run : runs) {
    for (std::size_t j = 0; j < n; ++j) result.mean_signal[j] += run[j] / count;  // m_j
  }
  const auto [lo, hi] = std::minmax_element(result.mean_signal.begin(), result.mean_signal.end());
  result.range = *hi - *lo;  // r: total range of the mean signal (Eq. 4.1)
  if (!(result.range > 0.0)) {
    throw InvalidArgument("range of the mean signal = " + std::to_string(result.range) +
                          " is out of range; allowed: > 0 (Eq. 4.1 divides by it). The runs "
                          "are constant: use a signal that moves");
  }

  result.errors.reserve(runs.size());
  double sum_errors = 0.0;
  for (const auto& run : runs) {
    double sum_sq = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      const double d = result.mean_signal[j] - run[j];
      sum_sq += d * d;
    }
    const double e = std::sqrt(sum_sq / static_cast<double>(n)) / result.range;  // Eq. 4.1
    result.errors.push_back(e);
    sum_errors += e;
  }
  result.mean_error = sum_errors / count;
  return result;
}

}  // namespace clearshape::metrics
