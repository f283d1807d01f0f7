#pragma once
// A uniformly sampled signal: values[i] is the value at start_s + i * sample_time_s.
#include <cstddef>
#include <vector>

namespace clearshape {

struct UniformSeries {
  double start_s = 0.0;
  double sample_time_s = 1e-3;
  std::vector<double> values;

  std::size_t size() const noexcept { return values.size(); }
  double time_s(std::size_t i) const noexcept {
    return start_s + static_cast<double>(i) * sample_time_s;
  }
  /// Time of the last sample (start_s for an empty series).
  double end_s() const noexcept {
    return values.empty() ? start_s : time_s(values.size() - 1);
  }
  /// The sample times as a vector (for writing).
  std::vector<double> times_s() const;
};

/// Number of samples covering [0, duration_s] at sample_time_s, inclusive of both ends.
std::size_t sample_count(double duration_s, double sample_time_s);

}  // namespace clearshape
