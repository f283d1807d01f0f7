// on_update_grid (a shaper as a drive with update period T applies it) against the independent
// NumPy implementation in tests/golden/gen_grid.py (grid_reference.json: snapped impulses and the
// closed-form residual vibration of Eq. 2.19), and against two physical cases: a ZV whose half
// period is one update is already on the grid; a ZV that is not leaves V = |cos(π f T)|.
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/grid.hpp"
#include "clearshape/shaping/residual.hpp"
#include "support/paths.hpp"

namespace cs = clearshape::shaping;

namespace {

const nlohmann::json& reference() {
  static const nlohmann::json doc = [] {
    std::ifstream in(clearshape::testing::golden_path("grid_reference.json"));
    return nlohmann::json::parse(in);
  }();
  return doc;
}

cs::Shaper from_json(const std::string& method, const nlohmann::json& impulses) {
  std::vector<cs::Impulse> out;
  for (std::size_t i = 0; i < impulses["times_s"].size(); ++i) {
    out.push_back({impulses["times_s"][i], impulses["amplitudes"][i]});
  }
  return cs::Shaper(method, std::move(out), cs::Shaper::Normalize::no);
}

std::string what(const nlohmann::json& c) {
  return std::string(c["method"]) + " " + std::to_string(double(c["frequency_hz"])) + " Hz ζ " +
         std::to_string(double(c["zeta"])) + " on " + std::to_string(double(c["grid_hz"])) + " Hz";
}

void expect_snapped(const cs::Shaper& s, const nlohmann::json& c, double amplitude_tol, const std::string& label) {
  const auto& ref = c["snapped"];
  ASSERT_EQ(s.size(), ref["times_s"].size()) << label;
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_NEAR(s.impulses()[i].time_s, double(ref["times_s"][i]), 1e-14) << label << " t" << i + 1;
    EXPECT_NEAR(s.impulses()[i].amplitude, double(ref["amplitudes"][i]), amplitude_tol) << label << " A" << i + 1;
  }
  const cs::Mode mode = cs::Mode::from_hz(c["frequency_hz"], c["zeta"]);
  EXPECT_NEAR(cs::residual_vibration(s, mode), double(c["v_snapped"]), 1e-9) << label;
}

}  // namespace

// The golden's own designed impulses (every method, SI included), snapped here and there.
TEST(UpdateGrid, GoldenImpulsesSnapped) {
  ASSERT_GE(reference()["cases"].size(), 30u);
  for (const auto& c : reference()["cases"]) {
    const cs::Shaper designed = from_json(c["method"], c["designed"]);
    const cs::Shaper snapped = cs::on_update_grid(designed, 1.0 / double(c["grid_hz"]));
    EXPECT_EQ(snapped.method(), std::string(c["method"]));
    EXPECT_NEAR(snapped.amplitude_sum(), designed.amplitude_sum(), 1e-15);
    expect_snapped(snapped, c, 1e-14, what(c));
  }
}

// clearshape's own designs (closed forms and EI; the SI optimum is not unique in its impulses,
// so SI is covered by the test above) snapped: the same impulses as the NumPy reference.
TEST(UpdateGrid, DesignsSnappedMatchTheReference) {
  int compared = 0;
  for (const auto& c : reference()["cases"]) {
    if (c["method"] == "si") continue;
    cs::DesignRequest r;
    r.method = cs::method_from_string(std::string(c["method"]));
    r.mode = cs::Mode::from_hz(c["frequency_hz"], c["zeta"]);
    const cs::Shaper designed = cs::design(r);
    EXPECT_NEAR(cs::residual_vibration(designed, r.mode), double(c["v_designed"]), 1e-9) << what(c);
    expect_snapped(cs::on_update_grid(designed, 1.0 / double(c["grid_hz"])), c, 1e-9, what(c));
    ++compared;
  }
  EXPECT_EQ(compared, 25);
}

// ZV for 15 Hz, ζ = 0: its second impulse is at half the period, 1/30 s — one update of a 30 Hz
// drive. Snapping changes nothing and V stays 0.
TEST(UpdateGrid, ZvAtHalfTheUpdateRateIsAlreadyOnTheGrid) {
  const cs::Mode mode = cs::Mode::from_hz(15.0, 0.0);
  const cs::Shaper zv = cs::design_zv(mode);
  const cs::Shaper snapped = cs::on_update_grid(zv, 1.0 / 30.0);
  ASSERT_EQ(snapped.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(snapped.impulses()[i].time_s, zv.impulses()[i].time_s, 1e-12);
    EXPECT_NEAR(snapped.impulses()[i].amplitude, zv.impulses()[i].amplitude, 1e-12);
  }
  EXPECT_LT(cs::residual_vibration(snapped, mode), 1e-12);
}

// ZV for 14 Hz, ζ = 0: ½, ½ at 0 and 1/28 s; the drive applies the second at 1/30 s. Two equal
// impulses T apart leave |½ + ½·e^{jωT}| = |cos(ωT/2)| = |cos(π·14/30)| = 0.10453 of the
// unshaped vibration at 14 Hz.
TEST(UpdateGrid, ZvOffTheGridLeavesTheCosineOfItsTimingError) {
  const cs::Mode mode = cs::Mode::from_hz(14.0, 0.0);
  const cs::Shaper snapped = cs::on_update_grid(cs::design_zv(mode), 1.0 / 30.0);
  ASSERT_EQ(snapped.size(), 2u);
  EXPECT_NEAR(snapped.impulses()[1].time_s, 1.0 / 30.0, 1e-15);
  const double expected = std::abs(std::cos(std::numbers::pi * 14.0 / 30.0));
  EXPECT_NEAR(cs::residual_vibration(snapped, mode), expected, 1e-12);
  EXPECT_NEAR(expected, 0.104528, 1e-6);
}

TEST(UpdateGrid, MergesAndKeepsTheMethod) {
  // ZV for 40 Hz (half period 12.5 ms < 16.7 ms): both impulses land on update 0, the identity.
  const cs::Shaper one = cs::on_update_grid(cs::design_zv(cs::Mode::from_hz(40.0, 0.05)), 1.0 / 30.0);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.method(), "zv");
  EXPECT_EQ(one.impulses()[0].time_s, 0.0);
  EXPECT_NEAR(one.impulses()[0].amplitude, 1.0, 1e-15);
  // A custom list: 0.01 → 0, 0.02 and 0.04 → 1/30, 0.06 → 2/30.
  const cs::Shaper custom("custom", {{0.0, 0.1}, {0.01, 0.2}, {0.02, 0.3}, {0.04, 0.25}, {0.06, 0.15}});
  const cs::Shaper s = cs::on_update_grid(custom, 1.0 / 30.0);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(s.impulses()[0].amplitude, 0.3, 1e-15);
  EXPECT_NEAR(s.impulses()[1].amplitude, 0.55, 1e-15);
  EXPECT_NEAR(s.impulses()[2].amplitude, 0.15, 1e-15);
  EXPECT_NEAR(s.impulses()[2].time_s, 2.0 / 30.0, 1e-15);
}

TEST(UpdateGrid, RejectsABadPeriod) {
  const cs::Shaper zv = cs::design_zv(cs::Mode::from_hz(10.0, 0.1));
  for (const double bad : {0.0, -1.0 / 30.0, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity(), 1e-300}) {
    try {
      (void)cs::on_update_grid(zv, bad);
      ADD_FAILURE() << "accepted period " << bad;
    } catch (const clearshape::InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("update_period_s"), std::string::npos) << e.what();
    }
  }
}
