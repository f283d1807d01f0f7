#pragma once
// Fixed-point taps for an integer controller. Qm.n as in ARM's and TI's usage: a signed word
// whose value is q / 2^n (Q15: int16_t, n = 15, range [−1, 1 − 2^−15]; Q31: int32_t, n = 31).
//   q_j = round(w_j · 2^n)   (round half away from zero, std::llround)
// then the rounding is corrected so that Σ q_j = 2^n exactly (a step reaches 1.0 exactly): while
// the sum is short (long) by one LSB, the tap that was rounded down (up) the most gains (loses)
// one LSB, lowest index first on ties — each tap moves at most once, by one LSB.
// Representable only for a positive shaper with every tap below 1 (a tap that rounds to 2^n, or a
// negative tap, is refused with the reason: the unsigned-step bound of the C header assumes both).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clearshape::exports {

struct FixedPointTaps {
  int fraction_bits = 0;             ///< n: 15 (Q15) or 31 (Q31)
  bool representable = false;
  std::string why_not;               ///< set when !representable
  std::vector<std::int64_t> q;       ///< q_j, Σ q_j = 2^n
  /// Σ_j |q_j / 2^n − w_j|: the worst-case gain error per unit of input (see c_header.hpp).
  double abs_error_sum = 0.0;
  double max_abs_error = 0.0;        ///< max_j |q_j / 2^n − w_j|
};

/// Quantises `weights` (which must sum to 1 within 1e-9) to Q(fraction_bits); fraction_bits in
/// [1, 62]. Throws InvalidArgument for an empty list, a non-finite weight or a sum far from 1.
FixedPointTaps quantize_taps(std::span<const double> weights, int fraction_bits);

}  // namespace clearshape::exports
