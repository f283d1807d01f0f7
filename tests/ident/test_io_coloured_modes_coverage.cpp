// The 1σ that `modes` reports for INPUT/OUTPUT records with COLOURED output noise must cover the
// truth at their nominal rate (issue 20): over 60 seeded records of two resonances (4 Hz ζ 0.02,
// 11 Hz ζ 0.05; a random input at 200 Hz, 2000 samples) with AR(1) output noise (ρ 0.9, RMS 10 % of
// the output's), identified with the default options (order from the stabilisation diagram), the
// truth lies within ±1σ for each mode's frequency and damping ratio in 35–46 of the 60 records
// (58.3–76.7 %; a Gaussian's P(|z| ≤ 1) = 0.6827, so a correct σ lands in this band with
// probability 0.90, exact binomial) and within ±2σ in 54–60 (90–100 %; P(|z| ≤ 2) = 0.9545:
// probability 0.98). A record whose 4 Hz mode is not reported covers nothing.
// Before input/output persistence counted poles stable in frequency (stabilisation.hpp), the
// subspace ζ of the 4 Hz mode moved more than 5 % between orders in 20 of these records, the mode
// was not persistent and went unreported: 4 Hz f and ζ were covered in 22 of 60 (36.7 %); where
// reported its σ were right (mean σ_f 0.00134 Hz against an empirical spread of 0.00139 Hz).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"
#include "free_decay.hpp"
#include "synthetic.hpp"

namespace ident = clearshape::ident;

namespace {

constexpr double kTrueHz[2] = {4.0, 11.0};
constexpr double kTrueZeta[2] = {0.02, 0.05};

// two_resonance_record without its white noise, plus AR(1) noise of RMS `noise` × the output's.
ident::Experiment ar1_two_resonance_record(std::uint64_t seed, double rho, double noise) {
  ident::Experiment e = clearshape::testing::two_resonance_record(seed, 0.0);
  clearshape::testing::add_ar1_noise(e.output, 9000 + seed, rho, noise);
  return e;
}

// Per parameter (mode 1 f, mode 1 ζ, mode 2 f, mode 2 ζ): records with |estimate − truth| ≤ kσ.
struct Covered {
  std::size_t one_sigma[4] = {0, 0, 0, 0};
  std::size_t two_sigma[4] = {0, 0, 0, 0};
  std::size_t records = 0;
};

// The reported mode within 0.5 Hz of the truth (none: the mode went unreported).
const ident::ModeEstimate* reported(const std::vector<ident::ModeEstimate>& modes, double hz) {
  for (const auto& m : modes)
    if (std::abs(m.natural_frequency_hz() - hz) < 0.5) return &m;
  return nullptr;
}

void count(Covered& c, std::size_t k, double error, double sigma) {
  c.one_sigma[k] += std::abs(error) <= sigma ? 1 : 0;  // a NaN σ covers nothing
  c.two_sigma[k] += std::abs(error) <= 2.0 * sigma ? 1 : 0;
}

Covered coverage(std::uint64_t first_seed, std::size_t records) {
  Covered c;
  ident::ModeOptions o;
  o.modes = 2;
  o.stabilisation.max_order = 12;  // as tests/ident/test_io_modes_coverage.cpp
  for (std::uint64_t seed = first_seed; seed < first_seed + records; ++seed) {
    ++c.records;
    ident::ModeIdentification r;
    try {
      r = ident::identify_modes(ar1_two_resonance_record(seed, 0.9, 0.1), o);
    } catch (const clearshape::RuntimeError&) {
      continue;  // no mode found: covers nothing
    }
    for (std::size_t i = 0; i < 2; ++i) {
      const ident::ModeEstimate* m = reported(r.modes, kTrueHz[i]);
      if (m == nullptr) continue;
      count(c, 2 * i, m->natural_frequency_hz() - kTrueHz[i], m->natural_frequency_std_hz());
      count(c, 2 * i + 1, m->damping_ratio - kTrueZeta[i], m->damping_ratio_std);
    }
  }
  return c;
}

}  // namespace

TEST(IoColouredModesCoverage, OneAndTwoSigmaCoverTheTruthWithAr1Noise) {
  const Covered c = coverage(1001, 60);
  const char* names[4] = {"4 Hz f", "4 Hz zeta", "11 Hz f", "11 Hz zeta"};
  for (std::size_t k = 0; k < 4; ++k) {
    std::printf("%-10s within 1 sigma in %zu of %zu records, within 2 sigma in %zu\n", names[k], c.one_sigma[k],
                c.records, c.two_sigma[k]);
    EXPECT_GE(c.one_sigma[k], 35U) << names[k];
    EXPECT_LE(c.one_sigma[k], 46U) << names[k];
    EXPECT_GE(c.two_sigma[k], 54U) << names[k];
  }
}
