// Maximal-length PRBS: period exactly 2^n − 1 and 2^(n−1) ones per period (Golomb 1967).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/generators.hpp"
#include "clearshape/signal/prbs.hpp"
#include "clearshape/signal/signal.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {
std::vector<std::uint64_t> prime_factors(std::uint64_t n) {
  std::vector<std::uint64_t> f;
  for (std::uint64_t p = 2; p * p <= n; ++p) {
    if (n % p == 0) {
      f.push_back(p);
      while (n % p == 0) n /= p;
    }
  }
  if (n > 1) f.push_back(n);
  return f;
}
}  // namespace

TEST(Prbs, PeriodAndBalanceByStepping) {
  // Every order up to 24 (16.7 M steps): the register first returns to its seed after exactly
  // 2^n − 1 steps and a period holds 2^(n−1) ones and 2^(n−1) − 1 zeros.
  for (int n = sig::kPrbsMinOrder; n <= 24; ++n) {
    const std::uint32_t seed = n == 2 ? 1u : 0x5u;
    sig::Lfsr lfsr(n, seed);
    const std::uint64_t period = sig::prbs_period(n);
    std::uint64_t ones = 0;
    std::uint64_t steps = 0;
    do {
      ones += static_cast<std::uint64_t>(lfsr.step());
      ++steps;
    } while (lfsr.state() != seed && steps <= period);
    EXPECT_EQ(steps, period) << "order " << n;
    EXPECT_EQ(ones, std::uint64_t{1} << (n - 1)) << "order " << n;
    EXPECT_EQ(period - ones, (std::uint64_t{1} << (n - 1)) - 1) << "order " << n;
  }
}

TEST(Prbs, EveryTapSetIsPrimitiveUpToOrder31) {
  // The one-step map M has order exactly 2^n − 1: M^P fixes every basis state and, for each
  // prime q | P, M^(P/q) moves some basis state. Then p(x) is primitive and every non-zero seed
  // has period 2^n − 1 (Lidl & Niederreiter, Finite Fields, Thm 3.16).
  for (int n = sig::kPrbsMinOrder; n <= sig::kPrbsMaxOrder; ++n) {
    const std::uint64_t period = sig::prbs_period(n);
    for (int j = 0; j < n; ++j) {
      sig::Lfsr l(n, 1u << j);
      l.jump(period);
      EXPECT_EQ(l.state(), 1u << j) << "order " << n;
    }
    for (const std::uint64_t q : prime_factors(period)) {
      bool moved = false;
      for (int j = 0; j < n && !moved; ++j) {
        sig::Lfsr l(n, 1u << j);
        // jump() reduces modulo the period; step the remainder for q = 1 cases (none here).
        l.jump(period / q);
        moved = l.state() != (1u << j);
      }
      EXPECT_TRUE(moved) << "order " << n << ": x^(P/" << q << ") = 1, not primitive";
    }
  }
}

TEST(Prbs, JumpMatchesStepping) {
  std::mt19937_64 rng(20150601);
  for (int n : {3, 9, 16, 23, 31}) {
    std::uniform_int_distribution<std::uint32_t> seed_dist(1, static_cast<std::uint32_t>(sig::prbs_period(n)));
    std::uniform_int_distribution<std::uint64_t> steps_dist(0, 5000);
    for (int trial = 0; trial < 5; ++trial) {
      const std::uint32_t seed = seed_dist(rng);
      const std::uint64_t k = steps_dist(rng);
      sig::Lfsr a(n, seed), b(n, seed);
      for (std::uint64_t i = 0; i < k; ++i) a.step();
      b.jump(k);
      EXPECT_EQ(a.state(), b.state()) << "order " << n << " seed " << seed << " k " << k;
    }
  }
}

TEST(Prbs, SignalLevelsBitPeriodAndValueAtAgreeWithSampling) {
  const sig::Prbs p{.order = 6, .bit_period_s = 0.02, .amplitude = 3.0, .offset = 1.0, .seed = 9, .start_s = 0.1};
  const auto bits = sig::prbs_bits(6, 9, 200);
  const auto y = sig::sample(p, 1000.0, 3.0);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = y.time_s(i);
    EXPECT_EQ(y.values[i], p.value_at(t)) << "t = " << t;
    if (t < 0.1 - 1e-9) {
      EXPECT_EQ(y.values[i], 1.0);
    } else {
      const auto k = static_cast<std::size_t>(std::floor((t - 0.1 + 1e-9) / 0.02));
      EXPECT_EQ(y.values[i], bits[k % 63] ? 4.0 : -2.0) << "t = " << t;
    }
  }
  // Far in time the jump still finds the bit: k = 10^9 + 5 ≡ k mod 63.
  const double t_far = 0.1 + (1e9 + 5.5) * 0.02;
  EXPECT_EQ(p.value_at(t_far), bits[static_cast<std::size_t>((1000000000ull + 5) % 63)] ? 4.0 : -2.0);
}

TEST(Prbs, Validation) {
  EXPECT_THROW(sig::Lfsr(1, 1), cs::InvalidArgument);
  EXPECT_THROW(sig::Lfsr(32, 1), cs::InvalidArgument);
  EXPECT_THROW(sig::Lfsr(5, 0), cs::InvalidArgument);
  EXPECT_THROW(sig::Lfsr(5, 32), cs::InvalidArgument);
  EXPECT_NO_THROW(sig::Lfsr(5, 31));
  EXPECT_THROW(sig::prbs_taps(40), cs::InvalidArgument);
  try {
    sig::Prbs{.order = 4, .seed = 16}.validate();
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("allowed: an integer in [1, 15]"), std::string::npos) << e.what();
  }
  EXPECT_THROW((sig::Prbs{.bit_period_s = 0.0}.validate()), cs::InvalidArgument);
}
