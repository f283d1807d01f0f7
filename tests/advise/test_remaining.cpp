// advise::remaining_vibration / worst_response: the residual vibration V used for scoring equals
// the SciPy reference curves (tests/golden/gen_shaping.py) and shaping::residual_vibration; the
// Klipper measure behaves as its definition says.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/advise/remaining.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "support/alloc_counter.hpp"
#include "support/paths.hpp"

namespace ad = clearshape::advise;
namespace sh = clearshape::shaping;

namespace {

// A spectrum: a Lorentzian line (the PSD of a mode) at f0 with half-width ζ f0 on a 0.05 Hz grid.
ad::MeasuredSpectrum line(double f0, double zeta) {
  ad::MeasuredSpectrum s;
  for (int k = 0; k <= 2000; ++k) {
    const double f = 0.05 * k;
    s.frequency_hz.push_back(f);
    const double g = zeta * f0;
    s.power.push_back(1.0 / (1.0 + std::pow((f - f0) / g, 2)));
  }
  s.resolution_hz = 0.05;
  return s;
}

}  // namespace

TEST(Remaining, ResponseEqualsTheScipyCurves) {
  std::ifstream in(clearshape::testing::golden_path("shaping_reference.json"));
  const nlohmann::json doc = nlohmann::json::parse(in);
  int checked = 0;
  for (const auto& c : doc["curves"]) {
    const std::string method = c["method"];
    if (method == "um-zv" || method == "zv5d") continue;
    sh::DesignRequest r;
    r.method = sh::method_from_string(method);
    r.mode = sh::Mode::from_hz(c["frequency_hz"], c["zeta"]);
    const sh::Shaper s = sh::design(r);
    std::vector<double> f;
    for (const double ratio : c["ratios"]) f.push_back(ratio * c["frequency_hz"].get<double>());
    const std::vector<double> v = ad::worst_response(s, f, {c["actual_zeta"].get<double>()}, {1.0});
    for (std::size_t k = 0; k < f.size(); ++k) {
      ASSERT_NEAR(v[k], c["residual"][k].get<double>(), 1e-9) << method << " r = " << c["ratios"][k];
    }
    ++checked;
  }
  EXPECT_GE(checked, 30);
}

TEST(Remaining, ZvAtTheModeLeavesNothingAtTheDesignDamping) {
  const double f0 = 14.955, zeta = 0.13;
  const ad::WeightedBins bins = ad::weighted_bins(line(f0, zeta), 0.05);
  const sh::Shaper zv = sh::design_zv(sh::Mode::from_hz(f0, zeta));
  // V = 0 exactly at f0 only; the line's width leaves a little at the neighbours: small, not 0.
  const double at_design = ad::remaining_vibration(zv, bins, zeta);
  EXPECT_LT(at_design, 0.5);
  // A pure line (one bin): ~0.
  ad::MeasuredSpectrum one;
  one.frequency_hz = {f0 - 1.0, f0, f0 + 1.0};
  one.power = {0.0, 1.0, 0.0};
  EXPECT_NEAR(ad::remaining_vibration(zv, ad::weighted_bins(one, 0.05), zeta), 0.0, 1e-12);
  // Off-design damping or frequency leave more; the worst case is the largest of them.
  const double off_damping = ad::remaining_vibration(zv, bins, 0.2);
  const double off_frequency = ad::remaining_vibration(zv, bins, zeta, 1.1);
  EXPECT_GT(off_damping, at_design);
  EXPECT_GT(off_frequency, at_design);
  const double worst = ad::worst_remaining_vibration(zv, {bins}, {zeta, 0.2}, {1.0, 1.1});
  EXPECT_DOUBLE_EQ(worst, std::max(off_damping, std::max(off_frequency, ad::remaining_vibration(zv, bins, 0.2, 1.1))));
}

TEST(Remaining, WithoutShapingEverythingRemains) {
  const ad::WeightedBins bins = ad::weighted_bins(line(20.0, 0.05), 0.05);
  const sh::Shaper identity("none", {{0.0, 1.0}});
  EXPECT_NEAR(ad::remaining_vibration(identity, bins, 0.1), 1.0, 1e-12);
  // Definition: only the power above 5 % of the maximum counts.
  double total = 0.0;
  for (const double p : line(20.0, 0.05).power) total += std::max(p - 0.05, 0.0);
  EXPECT_NEAR(bins.total, total, 1e-9);
}

TEST(Remaining, EvaluationDoesNotAllocate) {
  const ad::WeightedBins bins = ad::weighted_bins(line(14.955, 0.13), 0.05);
  const sh::Shaper ei = sh::design_ei(sh::Mode::from_hz(14.955, 0.13));
  clearshape::testing::AllocationCounter counter;
  const double v = ad::remaining_vibration(ei, bins, 0.1, 1.05);
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_GE(v, 0.0);
}

// Each bin at its own ζ (recommend's per-line damping bands): the definition summed bin by bin with
// shaping::residual_vibration (Eq. 2.19 by the shaping module), ζ 0.01 on the line's bins and 0.1 on the rest.
TEST(Remaining, EachBinAtItsOwnDampingIsTheDefinition) {
  const ad::WeightedBins bins = ad::weighted_bins(line(20.0, 0.05), 0.05);
  const sh::Shaper zv = sh::design_zv(sh::Mode::from_hz(21.0, 0.05));
  std::vector<double> zeta;
  double expected = 0.0;
  for (std::size_t k = 0; k < bins.power.size(); ++k) {
    zeta.push_back(std::abs(bins.frequency_hz[k] - 20.0) <= 0.5 ? 0.01 : 0.1);
    const double v = sh::residual_vibration(zv, sh::Mode::from_hz(1.02 * bins.frequency_hz[k], zeta.back()));
    expected += std::max(v * bins.power[k] - bins.threshold, 0.0);
  }
  EXPECT_NEAR(ad::remaining_vibration(zv, bins, zeta, 1.02), expected / bins.total, 1e-12);
  EXPECT_NE(ad::remaining_vibration(zv, bins, zeta, 1.02), ad::remaining_vibration(zv, bins, 0.1, 1.02));
  zeta.pop_back();
  EXPECT_THROW(ad::remaining_vibration(zv, bins, zeta, 1.0), clearshape::InvalidArgument);
}

TEST(Remaining, RejectsABadThreshold) {
  EXPECT_THROW((void)ad::weighted_bins(line(10.0, 0.1), 1.0), clearshape::InvalidArgument);
  ad::MeasuredSpectrum zero = line(10.0, 0.1);
  for (double& p : zero.power) p = 0.0;
  EXPECT_THROW((void)ad::weighted_bins(zero, 0.05), clearshape::InvalidArgument);
}
