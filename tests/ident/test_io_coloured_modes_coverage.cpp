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
#include <cstdint>

#include <gtest/gtest.h>

#include "free_decay.hpp"
#include "io_modes_coverage.hpp"
#include "synthetic.hpp"

namespace ident = clearshape::ident;
namespace ct = clearshape::testing;

namespace {

// two_resonance_record without its white noise, plus AR(1) noise of RMS `noise` × the output's.
ident::Experiment ar1_two_resonance_record(std::uint64_t seed, double rho, double noise) {
  ident::Experiment e = ct::two_resonance_record(seed, 0.0);
  ct::add_ar1_noise(e.output, 9000 + seed, rho, noise);
  return e;
}

}  // namespace

TEST(IoColouredModesCoverage, OneAndTwoSigmaCoverTheTruthWithAr1Noise) {
  // A mode more than 0.5 Hz from its truth went unreported.
  const ct::IoCovered c =
      ct::io_modes_coverage(1001, 60, [](std::uint64_t seed) { return ar1_two_resonance_record(seed, 0.9, 0.1); }, 0.5);
  for (std::size_t k = 0; k < 4; ++k) {
    const char* name = ct::kIoCoverageNames[k];
    EXPECT_GE(c.one_sigma[k], 35U) << name;
    EXPECT_LE(c.one_sigma[k], 46U) << name;
    EXPECT_GE(c.two_sigma[k], 54U) << name;
  }
}
