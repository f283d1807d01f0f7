#include "clearshape/dsp/differentiate.hpp"

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::dsp {

std::vector<double> backward_difference(std::span<const double> input, double sample_time_s) {
  StreamingDifference difference(sample_time_s);
  std::vector<double> out(input.size());
  for (std::size_t n = 0; n < input.size(); ++n) out[n] = difference.step(input[n]);
  return out;
}

std::vector<double> central_difference(std::span<const double> input, double sample_time_s,
                                       EdgeOrder edge_order) {
  require_positive("sample_time_s", sample_time_s);
  const std::size_t n = input.size();
  const std::size_t needed = static_cast<std::size_t>(edge_order) + 1;
  if (n < needed) {
    throw InvalidArgument(fmt::format("central_difference: {} samples given; allowed: at least {} "
                                      "for edge order {}", n, needed,
                                      static_cast<int>(edge_order)));
  }
  const double dx = sample_time_s;
  std::vector<double> out(n);
  // Interior: second-order central difference (x[n+1] − x[n−1]) / 2T (numpy.gradient).
  for (std::size_t i = 1; i + 1 < n; ++i) out[i] = (input[i + 1] - input[i - 1]) / (2.0 * dx);
  if (edge_order == EdgeOrder::first) {
    out[0] = (input[1] - input[0]) / dx;  // forward difference
    out[n - 1] = (input[n - 1] - input[n - 2]) / dx;  // backward difference
  } else {
    // Second-order one-sided differences (numpy.gradient, edge_order=2).
    out[0] = (-1.5 / dx) * input[0] + (2.0 / dx) * input[1] + (-0.5 / dx) * input[2];
    out[n - 1] = (0.5 / dx) * input[n - 3] + (-2.0 / dx) * input[n - 2] + (1.5 / dx) * input[n - 1];
  }
  return out;
}

StreamingDifference::StreamingDifference(double sample_time_s)
    : inverse_sample_time_(1.0 / sample_time_s) {
  require_positive("sample_time_s", sample_time_s);
}

double StreamingDifference::step(double input) noexcept {
  // Backward difference (x[n] − x[n−1]) / T; at rest before the first sample.
  const double derivative = primed_ ? (input - previous_) * inverse_sample_time_ : 0.0;
  previous_ = input;
  primed_ = true;
  return derivative;
}

}  // namespace clearshape::dsp
