// advise::recommend: the fitted design frequency lands on the mode, the worst case includes the
// frequency uncertainty, the delay budget and the tolerance rule pick as documented, two-mode
// convolutions appear when two modes stand out, and bad options are refused.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>

#include "clearshape/advise/recommend.hpp"
#include "clearshape/core/error.hpp"
#include "golden_support.hpp"

namespace ad = clearshape::advise;
using advise_test::find;
using advise_test::load;

namespace {

using Fixture = advise_test::SpectrumCase;

const Fixture& one_mode() {
  static const Fixture f = [] {
    Fixture x{load("recommend_one_mode.csv", "gyro_deg_s"), {}};
    ad::ModeEstimateOptions o;
    o.free_decay_fit = false;
    x.modes = ad::estimate_modes({x.spectrum}, o).modes;
    return x;
  }();
  return f;
}


}  // namespace

TEST(Recommend, EveryCandidateIsFittedNearTheMode) {
  ad::RecommendOptions o;
  o.candidates = {"zv", "mzv", "zvd", "zvdd", "zvddd", "ei", "ei2", "ei3", "si"};
  const ad::Recommendation r = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  ASSERT_EQ(r.candidates.size(), 9u);
  EXPECT_EQ(r.test_damping_ratios.size(), 3u);
  EXPECT_EQ(r.frequency_scales.size(), 3u);
  for (const auto& c : r.candidates) {
    ASSERT_TRUE(c.available) << c.name << ": " << c.note;
    // Robust shapers may sit above the mode (their band is wide); none leaves the scan range.
    EXPECT_GT(c.design_frequency_hz[0], 0.6 * 14.955) << c.name;
    EXPECT_LT(c.design_frequency_hz[0], 1.6 * 14.955) << c.name;
    EXPECT_GE(c.remaining_worst, c.remaining_nominal - 1e-15) << c.name;
    EXPECT_GT(c.duration_s, 0.0);
  }
  // ZV, the least robust, leaves the most; more derivative constraints leave less at the scan's
  // least (the fitted frequency may leave up to Klipper's near-best margin, 0.05 points, more).
  EXPECT_GT(find(r, "zv").remaining_worst, find(r, "zvd").remaining_worst);
  EXPECT_GE(find(r, "zvd").least_remaining + 1e-12, find(r, "zvdd").least_remaining);
  EXPECT_LE(find(r, "zvdd").remaining_worst, find(r, "zvdd").least_remaining * o.near_best_factor + o.near_best_offset);
  EXPECT_LT(find(r, "zv").duration_s, find(r, "zvd").duration_s);
  // ZV's least worst-case remaining vibration is at the mode (within the estimate's 2σ); the
  // fitted frequency is the shortest ZV within Klipper's near-best window (≤ 10 % higher).
  EXPECT_NEAR(find(r, "zv").least_remaining_frequency_hz, 14.955, 2.0 * r.modes[0].frequency_std_hz + 0.1);
  EXPECT_GE(find(r, "zv").design_frequency_hz[0], find(r, "zv").least_remaining_frequency_hz);
  EXPECT_LT(find(r, "zv").design_frequency_hz[0], 1.1 * 14.955);
  ASSERT_TRUE(r.chosen.has_value());
  EXPECT_FALSE(r.reason.empty());
}

TEST(Recommend, TheRuleTakesTheShortestWithinTheToleranceOfTheLeast) {
  ad::RecommendOptions o;
  o.candidates = {"zv", "zvd", "zvdd", "ei", "ei2"};
  const ad::Recommendation r = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  ASSERT_TRUE(r.chosen.has_value());
  double least = 1.0;
  for (const auto& c : r.candidates) least = std::min(least, c.remaining_worst);
  const auto& pick = r.candidates[*r.chosen];
  EXPECT_LE(pick.remaining_worst, least + o.vibration_tolerance);
  for (const auto& c : r.candidates) {
    if (c.remaining_worst <= least + o.vibration_tolerance) {
      EXPECT_GE(c.duration_s, pick.duration_s) << c.name;
    }
  }
  std::string upper = pick.name;
  for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  EXPECT_EQ(r.reason.rfind(upper + ":", 0), 0u) << r.reason;
}

TEST(Recommend, DelayBudgetExcludesLongShapers) {
  ad::RecommendOptions o;
  o.candidates = {"zv", "zvd", "ei3"};
  const ad::Recommendation all = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  o.max_delay_s = find(all, "zv").duration_s * 1.01;
  const ad::Recommendation r = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  ASSERT_TRUE(r.chosen.has_value());
  EXPECT_EQ(r.candidates[*r.chosen].name, "zv");
  EXPECT_FALSE(find(r, "zvd").within_budget);
  EXPECT_NE(r.reason.find("delay budget"), std::string::npos) << r.reason;
  o.max_delay_s = 1e-4;
  const ad::Recommendation none = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  EXPECT_FALSE(none.chosen.has_value());
  EXPECT_NE(none.reason.find("no candidate fits"), std::string::npos) << none.reason;
}

TEST(Recommend, FrequencyUncertaintyRaisesTheWorstCase) {
  ad::RecommendOptions o;
  o.candidates = {"zv"};
  o.frequency_sigmas = 0.0;
  const double nominal = ad::recommend({one_mode().spectrum}, one_mode().modes, o).candidates[0].remaining_worst;
  o.frequency_sigmas = 3.0;
  const ad::Recommendation r = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  EXPECT_GT(r.candidates[0].remaining_worst, nominal);
  EXPECT_NEAR(r.frequency_scales.back() - 1.0, 3.0 * r.modes[0].frequency_std_hz / r.modes[0].frequency_hz, 1e-12);
}

TEST(Recommend, TwoModesBringConvolutions) {
  const ad::MeasuredSpectrum s = load("recommend_two_modes.csv", "gyro_deg_s");
  ad::ModeEstimateOptions mo;
  mo.free_decay_fit = false;
  const auto modes = ad::estimate_modes({s}, mo).modes;
  ASSERT_EQ(modes.size(), 2u);
  ad::RecommendOptions o;
  o.candidates = {"zv", "mzv", "zv*zv", "mzv*mzv"};
  const ad::Recommendation r = ad::recommend({s}, modes, o);
  const auto& zz = find(r, "zv*zv");
  ASSERT_TRUE(zz.available) << zz.note;
  ASSERT_EQ(zz.design_frequency_hz.size(), 2u);
  EXPECT_NEAR(zz.design_frequency_hz[1], 38.0, 4.0);
  // One ZV cannot cancel both modes; the convolution does far better.
  EXPECT_LT(zz.remaining_worst, 0.5 * find(r, "zv").remaining_worst);
  EXPECT_EQ(ad::default_candidates(2).size(), ad::default_candidates(1).size() + 4);
}

TEST(Recommend, RefusesBadRequests) {
  ad::RecommendOptions o;
  o.candidates = {"zq"};
  EXPECT_THROW((void)ad::recommend({one_mode().spectrum}, one_mode().modes, o), clearshape::InvalidArgument);
  o.candidates = {"zv*zv"};
  EXPECT_THROW((void)ad::recommend({one_mode().spectrum}, one_mode().modes, o), clearshape::InvalidArgument);
  o.candidates = {"si*zv"};
  EXPECT_THROW((void)ad::recommend({one_mode().spectrum}, one_mode().modes, o), clearshape::InvalidArgument);
  o.candidates.clear();
  o.max_delay_s = -1.0;
  EXPECT_THROW((void)ad::recommend({one_mode().spectrum}, one_mode().modes, o), clearshape::InvalidArgument);
  EXPECT_THROW((void)ad::recommend({}, one_mode().modes, {}), clearshape::InvalidArgument);
  EXPECT_THROW((void)ad::recommend({one_mode().spectrum}, {}, {}), clearshape::InvalidArgument);
}

TEST(Recommend, EiBeyondItsDampingLimitIsUnavailableWithTheReason) {
  ad::RecommendOptions o;
  o.candidates = {"zv", "ei3"};
  o.design_damping = 0.4;  // EI3 exists up to ζ ≈ 0.27 at Vtol = 5 %
  const ad::Recommendation r = ad::recommend({one_mode().spectrum}, one_mode().modes, o);
  EXPECT_TRUE(find(r, "zv").available);
  EXPECT_FALSE(find(r, "ei3").available);
  EXPECT_FALSE(find(r, "ei3").note.empty());
}
