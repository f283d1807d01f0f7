#include "clearshape/signal/prbs.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/generators.hpp"
#include "time_tolerance.hpp"

namespace clearshape::signal {

namespace {

// Primitive feedback taps after Alfke, "Efficient Shift Registers, LFSR Counters, and Long
// Pseudo-Random Sequence Generators", Xilinx XAPP 052 (1996), Table 3 (order 2: x² + x + 1).
// Entry n lists t with p(x) = x^n + Σ x^t + 1. tests/signal/test_prbs.cpp proves every entry
// primitive (period exactly 2^n − 1).
struct Taps {
  std::array<int, 3> t;
  int count;
};
constexpr std::array<Taps, 32> kTaps = {{
    {{0, 0, 0}, 0},  {{0, 0, 0}, 0},                                     // 0, 1: unused
    {{1, 0, 0}, 1},  {{2, 0, 0}, 1},  {{3, 0, 0}, 1},  {{3, 0, 0}, 1},   // 2 … 5
    {{5, 0, 0}, 1},  {{6, 0, 0}, 1},  {{6, 5, 4}, 3},  {{5, 0, 0}, 1},   // 6 … 9
    {{7, 0, 0}, 1},  {{9, 0, 0}, 1},  {{6, 4, 1}, 3},  {{4, 3, 1}, 3},   // 10 … 13
    {{5, 3, 1}, 3},  {{14, 0, 0}, 1}, {{15, 13, 4}, 3}, {{14, 0, 0}, 1}, // 14 … 17
    {{11, 0, 0}, 1}, {{6, 2, 1}, 3},  {{17, 0, 0}, 1}, {{19, 0, 0}, 1},  // 18 … 21
    {{21, 0, 0}, 1}, {{18, 0, 0}, 1}, {{23, 22, 17}, 3}, {{22, 0, 0}, 1}, // 22 … 25
    {{6, 2, 1}, 3},  {{5, 2, 1}, 3},  {{25, 0, 0}, 1}, {{27, 0, 0}, 1},  // 26 … 29
    {{6, 4, 1}, 3},  {{28, 0, 0}, 1},                                    // 30, 31
}};

void require_order(int order) {
  if (order < kPrbsMinOrder || order > kPrbsMaxOrder) {
    throw_invalid("order", order, fmt::format("an integer in [{}, {}]", kPrbsMinOrder, kPrbsMaxOrder),
                  "The sequence period is 2^order - 1 bits");
  }
}

std::uint32_t feedback_mask(int order) noexcept {
  std::uint32_t mask = 1u;
  const Taps& taps = kTaps[static_cast<std::size_t>(order)];
  for (int i = 0; i < taps.count; ++i) mask |= 1u << taps.t[static_cast<std::size_t>(i)];
  return mask;
}

std::uint32_t advance(std::uint32_t state, std::uint32_t mask, int order) noexcept {
  const auto feedback = static_cast<std::uint32_t>(std::popcount(state & mask) & 1);
  return (state >> 1) | (feedback << (order - 1));
}

// Linear maps on GF(2)^n: row j is the set of input bits whose parity gives output bit j.
using Gf2Matrix = std::array<std::uint32_t, 32>;

Gf2Matrix compose(const Gf2Matrix& a, const Gf2Matrix& b, int order) noexcept {  // a ∘ b
  Gf2Matrix c{};
  for (int j = 0; j < order; ++j) {
    std::uint32_t row = 0;
    for (int i = 0; i < order; ++i) {
      if ((a[static_cast<std::size_t>(j)] >> i) & 1u) row ^= b[static_cast<std::size_t>(i)];
    }
    c[static_cast<std::size_t>(j)] = row;
  }
  return c;
}

std::uint32_t apply(const Gf2Matrix& m, std::uint32_t state, int order) noexcept {
  std::uint32_t out = 0;
  for (int j = 0; j < order; ++j) {
    out |= static_cast<std::uint32_t>(std::popcount(m[static_cast<std::size_t>(j)] & state) & 1) << j;
  }
  return out;
}

// The state after `steps` steps: the one-step map (a shift plus the feedback row) raised to
// the power `steps` by repeated squaring.
std::uint32_t jumped(std::uint32_t state, std::uint32_t mask, int order, std::uint64_t steps) noexcept {
  Gf2Matrix base{};
  for (int j = 0; j + 1 < order; ++j) base[static_cast<std::size_t>(j)] = 1u << (j + 1);
  base[static_cast<std::size_t>(order - 1)] = mask;
  while (steps != 0) {
    if (steps & 1u) state = apply(base, state, order);
    steps >>= 1;
    if (steps != 0) base = compose(base, base, order);
  }
  return state;
}

}  // namespace

std::span<const int> prbs_taps(int order) {
  require_order(order);
  const Taps& taps = kTaps[static_cast<std::size_t>(order)];
  return {taps.t.data(), static_cast<std::size_t>(taps.count)};
}

std::uint64_t prbs_period(int order) {
  require_order(order);
  return (std::uint64_t{1} << order) - 1;
}

Lfsr::Lfsr(int order, std::uint32_t seed) : order_(order), mask_(0), state_(seed) {
  require_order(order);
  const std::uint64_t period = prbs_period(order);
  if (seed == 0 || seed > period) {
    throw_invalid("seed", static_cast<double>(seed), fmt::format("an integer in [1, {}]", period),
                  "The all-zero register never leaves zero");
  }
  mask_ = feedback_mask(order);
}

int Lfsr::step() noexcept {
  const int out = static_cast<int>(state_ & 1u);
  state_ = advance(state_, mask_, order_);
  return out;
}

void Lfsr::jump(std::uint64_t steps) noexcept {
  state_ = jumped(state_, mask_, order_, steps % ((std::uint64_t{1} << order_) - 1));
}

std::vector<std::uint8_t> prbs_bits(int order, std::uint32_t seed, std::size_t count) {
  Lfsr lfsr(order, seed);
  std::vector<std::uint8_t> bits(count);
  for (auto& b : bits) b = static_cast<std::uint8_t>(lfsr.step());
  return bits;
}

// ---- Prbs (generators.hpp) -----------------------------------------------------------------

void Prbs::validate() const {
  require_order(order);
  require_positive("bit_period_s", bit_period_s);
  require_finite("amplitude", amplitude);
  require_finite("offset", offset);
  require_non_negative("start_s", start_s);
  Lfsr check(order, seed);  // validates the seed
  (void)check;
}

double Prbs::value_at(double t_s) const noexcept {
  if (!detail::reached(t_s, start_s)) return offset;
  const double k = std::max(0.0, detail::interval_index(t_s, start_s, bit_period_s));
  const std::uint64_t period = (std::uint64_t{1} << order) - 1;
  const auto index = static_cast<std::uint64_t>(std::fmod(k, static_cast<double>(period)));
  const std::uint32_t state = jumped(seed, feedback_mask(order), order, index);
  return level((state & 1u) != 0);
}

}  // namespace clearshape::signal
