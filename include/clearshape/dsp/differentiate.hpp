#pragma once
// Differentiation of uniformly sampled signals (thesis §3.3/§4.1.1: the encoder angle is
// differentiated with respect to time to obtain the angular speed).
#include <cstddef>
#include <span>
#include <vector>

namespace clearshape::dsp {

/// Backward difference y[n] = (x[n] − x[n−1]) / T, the real-time derivative. The signal is
/// taken to have rested at x[0] before the first sample, so y[0] = 0 (Simulink's Discrete
/// Derivative with its initial condition set to the first input). Empty in, empty out.
/// Throws InvalidArgument if sample_time_s is not > 0.
std::vector<double> backward_difference(std::span<const double> input, double sample_time_s);

/// Accuracy of the one-sided differences at the two ends of central_difference.
enum class EdgeOrder { first = 1, second = 2 };

/// numpy.gradient(x, T, edge_order=…): central differences (x[n+1] − x[n−1]) / 2T inside;
/// at the ends first-order one-sided differences (numpy's default, EdgeOrder::first) or
/// second-order ones (−3x0 + 4x1 − x2) / 2T. Needs at least edge_order + 1 samples
/// (throws InvalidArgument otherwise, as numpy raises).
std::vector<double> central_difference(std::span<const double> input, double sample_time_s,
                                       EdgeOrder edge_order = EdgeOrder::first);

/// Real-time backward difference; the first step() primes the history and returns 0.
class StreamingDifference {
 public:
  /// Throws InvalidArgument if sample_time_s is not > 0.
  explicit StreamingDifference(double sample_time_s);
  double step(double input) noexcept;
  /// Forget the history: the next step() returns 0 again.
  void reset() noexcept { primed_ = false; }
  double sample_time_s() const noexcept { return 1.0 / inverse_sample_time_; }

 private:
  double inverse_sample_time_;
  double previous_ = 0.0;
  bool primed_ = false;
};

}  // namespace clearshape::dsp
