// The 1σ that `modes` reports for INPUT/OUTPUT records must cover the truth at their nominal rate
// (issue 20): over 80 seeded records of two resonances (4 Hz ζ 0.02, 11 Hz ζ 0.05; a random input
// at 200 Hz, 2000 samples) with white output noise of 10 % of the output's RMS, identified with the
// default options (order from the stabilisation diagram), the truth lies within ±1σ for each mode's
// frequency and damping ratio in 47–62 of the 80 records (58.75–77.5 %; a Gaussian's
// P(|z| ≤ 1) = 0.6827, so a correct σ lands in this band with probability 0.946, exact binomial)
// and within ±2σ in 72–79 (90–98.75 %; P(|z| ≤ 2) = 0.9545: probability 0.99).
// Before the output-error fit was started from several subspace horizons, 30–40 of 80 (the fit
// ended in a local minimum in about 30 % of the records).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"
#include "free_decay.hpp"

namespace ident = clearshape::ident;

namespace {

constexpr double kTrueHz[2] = {4.0, 11.0};
constexpr double kTrueZeta[2] = {0.02, 0.05};

using clearshape::testing::two_resonance_record;

// Per parameter (mode 1 f, mode 1 ζ, mode 2 f, mode 2 ζ): records with |estimate − truth| ≤ kσ.
struct Covered {
  std::size_t one_sigma[4] = {0, 0, 0, 0};
  std::size_t two_sigma[4] = {0, 0, 0, 0};
  std::size_t records = 0;
};

const ident::ModeEstimate* nearest(const std::vector<ident::ModeEstimate>& modes, double hz) {
  const ident::ModeEstimate* best = nullptr;
  for (const auto& m : modes)
    if (best == nullptr || std::abs(m.natural_frequency_hz() - hz) < std::abs(best->natural_frequency_hz() - hz))
      best = &m;
  return best;
}

void count(Covered& c, std::size_t k, double error, double sigma) {
  c.one_sigma[k] += std::abs(error) <= sigma ? 1 : 0;  // a NaN σ covers nothing
  c.two_sigma[k] += std::abs(error) <= 2.0 * sigma ? 1 : 0;
}

Covered coverage(std::uint64_t first_seed, std::size_t records, double noise) {
  Covered c;
  ident::ModeOptions o;
  o.modes = 2;
  o.stabilisation.max_order = 12;  // two modes: a diagram up to order 12 (--max-order 12) holds them
  for (std::uint64_t seed = first_seed; seed < first_seed + records; ++seed) {
    ++c.records;
    ident::ModeIdentification r;
    try {
      r = ident::identify_modes(two_resonance_record(seed, noise), o);
    } catch (const clearshape::RuntimeError&) {
      continue;  // no mode found: covers nothing
    }
    for (std::size_t i = 0; i < 2; ++i) {
      const ident::ModeEstimate* m = nearest(r.modes, kTrueHz[i]);
      if (m == nullptr) continue;
      count(c, 2 * i, m->natural_frequency_hz() - kTrueHz[i], m->natural_frequency_std_hz());
      count(c, 2 * i + 1, m->damping_ratio - kTrueZeta[i], m->damping_ratio_std);
    }
  }
  return c;
}

}  // namespace

TEST(IoModesCoverage, OneAndTwoSigmaCoverTheTruthAtTenPercentNoise) {
  const Covered c = coverage(1001, 80, 0.10);
  const char* names[4] = {"4 Hz f", "4 Hz zeta", "11 Hz f", "11 Hz zeta"};
  for (std::size_t k = 0; k < 4; ++k) {
    std::printf("%-10s within 1 sigma in %zu of %zu records, within 2 sigma in %zu\n", names[k], c.one_sigma[k],
                c.records, c.two_sigma[k]);
    EXPECT_GE(c.one_sigma[k], 47U) << names[k];
    EXPECT_LE(c.one_sigma[k], 62U) << names[k];
    EXPECT_GE(c.two_sigma[k], 72U) << names[k];
    EXPECT_LE(c.two_sigma[k], 79U) << names[k];
  }
}
