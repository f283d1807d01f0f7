#include "clearshape/ident/column_check.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"

namespace clearshape::ident {

bool is_converted_copy(std::span<const double> input, std::span<const double> output, std::size_t max_hold_samples) {
  if (input.size() != output.size()) throw InvalidArgument("is_converted_copy: input and output differ in length");
  if (input.empty()) return false;
  const auto [lo, hi] = std::minmax_element(input.begin(), input.end());
  const double tolerance = kCopyTolerance * (*hi - *lo);
  if (!(tolerance > 0.0)) return false;  // a constant input proves nothing
  // A converter differs from its input only while a new value waits for the next update: in runs
  // of at most the hold, and only within the hold after the input last changed (a drive's lightly
  // damped response crosses its command every half period, but keeps differing long after it).
  std::size_t run = 0, last_change = 0;
  for (std::size_t k = 0; k < input.size(); ++k) {
    if (k > 0 && input[k] != input[k - 1]) last_change = k;
    const bool differs = std::abs(output[k] - input[k]) > tolerance;
    run = differs ? run + 1 : 0;
    if (run > max_hold_samples || (differs && k - last_change > max_hold_samples)) return false;
  }
  return true;
}

}  // namespace clearshape::ident
