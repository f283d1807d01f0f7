// Printer data: the test damping band also covers Klipper's 0.075–0.15 (shaper_calibrate.py,
// TEST_DAMPING_RATIOS), which a PSD file's coarse bins cannot exclude (docs/recommend.md, "Scoring"
// and "On real printers' spectra"); the same spectrum read as a table keeps its measured band.
#include <gtest/gtest.h>

#include <algorithm>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "golden_support.hpp"

namespace ad = clearshape::advise;

namespace {

ad::Recommendation recommend_on(const ad::MeasuredSpectrum& s, const ad::RecommendOptions& o = {}) {
  const ad::ModeEstimation e = ad::estimate_modes({s});
  return ad::recommend({s}, e.modes, o);
}

double low(const ad::Recommendation& r) { return *std::min_element(r.test_damping_ratios.begin(), r.test_damping_ratios.end()); }
double high(const ad::Recommendation& r) { return *std::max_element(r.test_damping_ratios.begin(), r.test_damping_ratios.end()); }

}  // namespace

TEST(RecommendPrinterBand, AKlipperFileIsTestedOverKlippersDampingToo) {
  const ad::MeasuredSpectrum klipper = advise_test::load("recommend_klipper_raw_psd.csv", "psd_xyz");
  const ad::Recommendation r = recommend_on(klipper);
  EXPECT_LE(low(r), 0.075);
  EXPECT_GE(high(r), 0.15);
  // The same numbers as a table: the measured band alone (this file's lines give ζ ≈ 0.08).
  ad::MeasuredSpectrum table = klipper;
  table.format = ad::InputFormat::table;
  const ad::Recommendation t = recommend_on(table);
  EXPECT_LT(high(t), 0.15);
  EXPECT_GT(low(t), 0.05);
}

TEST(RecommendPrinterBand, AnExplicitRangeStillWins) {
  const ad::MeasuredSpectrum klipper = advise_test::load("recommend_klipper_raw_psd.csv", "psd_xyz");
  ad::RecommendOptions o;
  o.damping_low = 0.09;
  o.damping_high = 0.11;
  const ad::Recommendation r = recommend_on(klipper, o);
  EXPECT_DOUBLE_EQ(low(r), 0.09);
  EXPECT_DOUBLE_EQ(high(r), 0.11);
}
