// advise::recommend with an update grid (RecommendOptions::update_grid_hz): every candidate is
// the snapped design (shaping::on_update_grid, itself checked against gen_grid.py), fitted and
// scored as applied; a shaper that collapses to one impulse leaves all the vibration (V = 1 at
// every frequency: remaining = 1 exactly); candidates with the same applied impulses are marked
// and never chosen; 0 leaves the recommendation as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/remaining.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/shaping/grid.hpp"
#include "golden_support.hpp"

namespace ad = clearshape::advise;
namespace sh = clearshape::shaping;
using advise_test::find;
using advise_test::load;

namespace {

using Case = advise_test::SpectrumCase;

Case one_mode(const std::string& file, const std::string& column) {
  Case c{load(file, column), {}};
  ad::ModeEstimateOptions o;
  o.free_decay_fit = false;
  o.max_modes = 1;
  c.modes = ad::estimate_modes({c.spectrum}, o).modes;
  return c;
}


// The worst-case remaining vibration of any shaper under the recommendation's scoring.
double worst(const ad::Recommendation& r, const ad::MeasuredSpectrum& s, const sh::Shaper& shaper) {
  const std::vector<ad::WeightedBins> bins{ad::weighted_bins(s, 0.05, 2.0 * s.resolution_hz)};
  return ad::worst_remaining_vibration(shaper, bins, r.test_damping_ratios, r.frequency_scales);
}

}  // namespace

// The rig's link mode (≈ 14.9 Hz) on the thesis drive's 30 Hz updates.
TEST(RecommendGrid, EveryCandidateIsItsDesignOnTheGrid) {
  const Case k = one_mode("recommend_one_mode.csv", "gyro_deg_s");
  ad::RecommendOptions o;
  o.update_grid_hz = 30.0;
  const ad::Recommendation r = ad::recommend({k.spectrum}, k.modes, o);
  for (const auto& c : r.candidates) {
    ASSERT_TRUE(c.available) << c.name << ": " << c.note;
    ASSERT_TRUE(c.designed.has_value()) << c.name;
    const sh::Shaper expected = sh::on_update_grid(*c.designed, 1.0 / 30.0);
    ASSERT_EQ(c.shaper->size(), expected.size()) << c.name;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(c.shaper->impulses()[i], expected.impulses()[i]) << c.name;
      const double k30 = c.shaper->impulses()[i].time_s * 30.0;
      EXPECT_NEAR(k30, std::round(k30), 1e-12) << c.name;
    }
    EXPECT_EQ(c.duration_s, c.shaper->duration_s());
    EXPECT_DOUBLE_EQ(c.remaining_worst, worst(r, k.spectrum, *c.shaper)) << c.name;
    EXPECT_DOUBLE_EQ(c.remaining_worst_designed, worst(r, k.spectrum, *c.designed)) << c.name;
    EXPECT_FALSE(c.duplicate_of.has_value()) << c.name;
    // The reported design frequency is the one of its grid class nearest the mode.
    EXPECT_NEAR(c.design_frequency_hz[0], k.modes[0].frequency_hz, 0.1) << c.name;
  }
}

// Off the grid the rule picks MZV (50.7 ms, 0.3 %); the drive would apply MZV on its updates,
// which leaves over 4 %. On the grid MZV is scored as applied and ZVD (on the same 66.7 ms) is
// chosen: it leaves less than a tenth of that.
TEST(RecommendGrid, TheChoiceIsTheBestAppliedShaper) {
  const Case k = one_mode("recommend_one_mode.csv", "gyro_deg_s");
  const ad::Recommendation off = ad::recommend({k.spectrum}, k.modes, {});
  ASSERT_TRUE(off.chosen.has_value());
  const ad::CandidateResult& off_pick = off.candidates[*off.chosen];
  EXPECT_EQ(off_pick.name, "mzv");
  const double snapped_off_pick = worst(off, k.spectrum, sh::on_update_grid(*off_pick.shaper, 1.0 / 30.0));
  EXPECT_GT(snapped_off_pick, 0.04);

  ad::RecommendOptions o;
  o.update_grid_hz = 30.0;
  const ad::Recommendation on = ad::recommend({k.spectrum}, k.modes, o);
  ASSERT_TRUE(on.chosen.has_value());
  const ad::CandidateResult& pick = on.candidates[*on.chosen];
  EXPECT_EQ(pick.name, "zvd");
  EXPECT_LT(pick.remaining_worst, 0.1 * snapped_off_pick);
  EXPECT_NEAR(pick.duration_s, 2.0 / 30.0, 1e-15);
  // No eligible candidate leaves less (the rule's "least" is over the applied shapers).
  for (const auto& c : on.candidates) EXPECT_GE(c.remaining_worst + 0.01, pick.remaining_worst) << c.name;
  // The grid only removes options: MZV as applied leaves more than MZV as designed.
  EXPECT_GT(find(on, "mzv").remaining_worst, find(off, "mzv").remaining_worst);
}

// A 42 Hz mode on a 15 Hz grid: ZV, MZV and SI are shorter than half an update at every
// scanned frequency, so all three become the identity, which leaves all the vibration.
TEST(RecommendGrid, CandidatesOnTheSameImpulsesAreMarkedAndNotChosen) {
  const Case k = one_mode("recommend_klipper_raw.csv", "accel_x");
  ad::RecommendOptions o;
  o.update_grid_hz = 15.0;
  const ad::Recommendation r = ad::recommend({k.spectrum}, k.modes, o);
  for (const char* name : {"zv", "mzv", "si"}) {
    const auto& c = find(r, name);
    ASSERT_EQ(c.shaper->size(), 1u) << name;
    EXPECT_EQ(c.duration_s, 0.0);
    EXPECT_DOUBLE_EQ(c.remaining_worst, 1.0) << name;
  }
  EXPECT_FALSE(find(r, "zv").duplicate_of.has_value());
  EXPECT_EQ(find(r, "mzv").duplicate_of.value_or(""), "zv");
  EXPECT_EQ(find(r, "si").duplicate_of.value_or(""), "zv");
  EXPECT_NE(find(r, "si").note.find("same impulses as zv"), std::string::npos) << find(r, "si").note;
  ASSERT_TRUE(r.chosen.has_value());
  EXPECT_FALSE(r.candidates[*r.chosen].duplicate_of.has_value());
  // Each candidate that is not a duplicate differs from every earlier one.
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    if (r.candidates[i].duplicate_of) continue;
    for (std::size_t j = 0; j < i; ++j) {
      const auto a = r.candidates[i].shaper->impulses();
      const auto b = r.candidates[j].shaper->impulses();
      EXPECT_FALSE(a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin()))
          << r.candidates[i].name << " = " << r.candidates[j].name;
    }
  }
}

TEST(RecommendGrid, ZeroIsOffAndBadRatesAreRefused) {
  const Case k = one_mode("recommend_one_mode.csv", "gyro_deg_s");
  ad::RecommendOptions o;
  o.candidates = {"zv", "zvd"};
  const ad::Recommendation r = ad::recommend({k.spectrum}, k.modes, o);
  for (const auto& c : r.candidates) {
    EXPECT_FALSE(c.designed.has_value());
    EXPECT_FALSE(c.duplicate_of.has_value());
  }
  for (const double bad : {-30.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    o.update_grid_hz = bad;
    try {
      (void)ad::recommend({k.spectrum}, k.modes, o);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const clearshape::InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("update_grid_hz"), std::string::npos) << e.what();
    }
  }
}
