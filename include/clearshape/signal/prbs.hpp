#pragma once
// Maximal-length linear feedback shift registers for the PRBS command (thesis §4.1.1).
//
// Convention (Fibonacci form): the register holds the next n output bits a_k … a_{k+n−1}
// (state bit j = a_{k+j}); each step outputs bit 0 and shifts in
//   a_{k+n} = a_k ⊕ (⊕_{t ∈ taps} a_{k+t}),
// i.e. the characteristic polynomial is p(x) = x^n + Σ_{t ∈ taps} x^t + 1. With a primitive
// p(x) every non-zero seed gives a sequence of period 2^n − 1 with 2^(n−1) ones and 2^(n−1) − 1
// zeros per period (Golomb, "Shift Register Sequences", 1967). This is the convention of
// scipy.signal.max_len_seq(n, state=[seed bit 0 … n−1], taps=prbs_taps(n)).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace clearshape::signal {

inline constexpr int kPrbsMinOrder = 2;
inline constexpr int kPrbsMaxOrder = 31;

/// The feedback taps t (exponents of p(x), excluding n and 0) of a primitive polynomial for
/// order n in [2, 31] (table after Alfke, Xilinx XAPP 052, 1996). Throws InvalidArgument.
std::span<const int> prbs_taps(int order);
/// 2^order − 1. Throws InvalidArgument for an order outside [2, 31].
std::uint64_t prbs_period(int order);

/// The shift register. A value type; step() is noexcept and allocation-free.
class Lfsr {
 public:
  /// Validates order in [2, 31] and seed in [1, 2^order − 1]; throws InvalidArgument.
  Lfsr(int order, std::uint32_t seed);

  /// Outputs the next bit (0 or 1) and advances the register.
  int step() noexcept;
  /// Advances the register by `steps` without producing output: O(n² log steps).
  void jump(std::uint64_t steps) noexcept;

  int order() const noexcept { return order_; }
  std::uint32_t state() const noexcept { return state_; }

 private:
  int order_;
  std::uint32_t mask_;   // bit 0 and the taps
  std::uint32_t state_;
};

/// The first `count` output bits of the register (order, seed).
std::vector<std::uint8_t> prbs_bits(int order, std::uint32_t seed, std::size_t count);

}  // namespace clearshape::signal
