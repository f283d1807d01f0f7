// Clearance-aware design (study/clearance_aware.hpp): the result is a positive shaper on the
// command path's grid within the bound, never worse on the model than the unshaped step it
// starts from, independent of the thread count, and its reported cases are re-simulations.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/study/clearance_aware.hpp"
#include "clearshape/study/protocol.hpp"
#include "support/clearance_fixtures.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;

namespace {

st::ClearanceAwareRequest small_request() {
  st::ClearanceAwareRequest r;
  r.model = cs::testing::thesis_position_clearance_model();  // the thesis's position drive (Eq. 4.2)
  r.model.play_rad = cs::deg_to_rad(1.0);
  r.model.stiffness = 1e5;
  r.model.exponent = 1.5;
  r.model.damping = 2.0;
  r.moves = {5.0, 20.0};
  r.uncertainty = {{1.0, 1.0, 0.0}, {1.2, 2.0, 1.0}};
  r.max_duration_s = 0.1;  // slots 0, 1/30, 2/30, 3/30 s
  r.settle_s = 0.6;
  r.max_evaluations = 16;
  r.threads = 1;
  return r;
}

}  // namespace

TEST(ClearanceAware, PositiveOnTheGridWithinTheBoundAndNoWorseThanUnshaped) {
  const auto r = small_request();
  const auto d = st::design_clearance_aware(r);
  EXPECT_EQ(d.shaper.method(), "clearance-aware");
  EXPECT_TRUE(d.shaper.is_positive());
  EXPECT_NEAR(d.shaper.amplitude_sum(), 1.0, 1e-12);
  EXPECT_LE(d.shaper.duration_s(), r.max_duration_s + 1e-12);
  for (const auto& i : d.shaper.impulses()) {
    EXPECT_NEAR(i.time_s / r.grid_s, std::round(i.time_s / r.grid_s), 1e-9) << i.time_s;
  }
  ASSERT_EQ(d.cases.size(), 4u);
  // The unshaped step is the first start of the search and scores r = 1 in every case (each
  // case relative to itself unshaped): the result's objective max r + 0.1·mean r cannot exceed 1.1.
  double worst_unshaped = 0.0, worst_ratio = 0.0;
  for (const auto& c : d.cases) {
    worst_unshaped = std::max(worst_unshaped, c.md_unshaped_deg);
    worst_ratio = std::max(worst_ratio, c.md_shaped_deg / c.md_unshaped_deg);
  }
  EXPECT_LE(d.objective, 1.1 + 1e-12);
  EXPECT_EQ(d.worst_unshaped_md_deg, worst_unshaped);
  EXPECT_DOUBLE_EQ(d.worst_ratio, worst_ratio);
  EXPECT_EQ(d.worse_than_unshaped, worst_ratio > 1.0);
  EXPECT_GT(d.evaluations, 2);
  EXPECT_LE(d.evaluations, r.max_evaluations + 1);
  // A reported case is the model re-simulated with the result.
  const auto& c = d.cases[3];
  EXPECT_EQ(c.move_name, "20");
  EXPECT_DOUBLE_EQ(c.md_shaped_deg, st::clearance_aware_case_md(r, st::varied_model(r.model, c.point),
                                                                st::design_moves(r).at(1), c.point.initial_play_fraction,
                                                                d.shaper));
}

TEST(ClearanceAware, SameResultOnOneAndTwoThreads) {
  auto r = small_request();
  r.max_evaluations = 10;
  const auto one = st::design_clearance_aware(r);
  r.threads = 2;
  const auto two = st::design_clearance_aware(r);
  ASSERT_EQ(one.shaper.size(), two.shaper.size());
  for (std::size_t k = 0; k < one.shaper.size(); ++k) {
    EXPECT_EQ(one.shaper.impulses()[k].time_s, two.shaper.impulses()[k].time_s);
    EXPECT_EQ(one.shaper.impulses()[k].amplitude, two.shaper.impulses()[k].amplitude);
  }
  EXPECT_EQ(one.objective, two.objective);
}

TEST(ClearanceAware, RejectsBadRequests) {
  auto r = small_request();
  r.moves.clear();
  EXPECT_THROW(st::design_clearance_aware(r), cs::InvalidArgument);
  r = small_request();
  r.max_duration_s = 0.0;
  EXPECT_THROW(st::design_clearance_aware(r), cs::InvalidArgument);
  r = small_request();
  r.model.play_rad = 0.0;
  EXPECT_THROW(st::design_clearance_aware(r), cs::InvalidArgument);
  r = small_request();
  r.uncertainty = {{1.0, 1.0, 2.0}};
  EXPECT_THROW(st::design_clearance_aware(r), cs::InvalidArgument);
}

TEST(ClearanceAware, ProtocolPairsItWithTheClearanceModel) {
  const std::string head = R"(format = "clearshape-study-protocol/1"
[study]
name = "mini"
mode = "position"
rig = "large-play"
[[input]]
name = "step"
type = "step"
amplitude_deg = 10.0
start_s = 0.5
[[rig_tests.table]]
id = "T"
input = "step"
[[rig_tests.table.column]]
shaper = "none"
[[rig_tests.table.column]]
)";
  const auto p = st::parse_protocol(head + "shaper = \"clearance-aware\"\nmode_source = \"clearance-model\"\n", "mini.toml");
  EXPECT_EQ(p.rig, "large-play");
  EXPECT_EQ(p.rig_tests.tables.at(0).columns.at(1).key(), "clearance-aware@clearance-model");
  // The take-up profile (take_up.hpp) pairs the same way, in rig tests.
  const auto t = st::parse_protocol(head + "shaper = \"take-up\"\nmode_source = \"clearance-model\"\n", "mini.toml");
  EXPECT_EQ(t.rig_tests.tables.at(0).columns.at(1).key(), "take-up@clearance-model");
  for (const std::string bad : {"shaper = \"clearance-aware\"\nmode_source = \"link-mode\"\n",
                                "shaper = \"take-up\"\nmode_source = \"link-mode\"\n",
                                "shaper = \"zvdd\"\nmode_source = \"clearance-model\"\n"}) {
    try {
      (void)st::parse_protocol(head + bad, "mini.toml");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const cs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("mini.toml"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("mode_source"), std::string::npos) << e.what();
    }
  }
}

// The flank damping's run spread enters as D × e^(∓s) at every start place, after the nominal
// points and the ±1σ corners, and varied_model scales D by it.
TEST(ClearanceAware, DampingSpreadAddsTheTwoDampingCornersAtEveryStart) {
  const auto starts = st::default_start_fractions();
  const auto nominal = st::uncertainty_set(0.0, 0.0, 0.0, starts, 0.2);
  ASSERT_EQ(nominal.size(), 3 * starts.size());
  EXPECT_DOUBLE_EQ(nominal[starts.size()].damping_factor, std::exp(-0.2));
  EXPECT_DOUBLE_EQ(nominal.back().damping_factor, std::exp(0.2));
  EXPECT_DOUBLE_EQ(nominal.back().play_factor, 1.0);
  EXPECT_EQ(st::uncertainty_set(0.05, 0.05, 0.05, starts, 0.2).size(), 5 * starts.size());
  EXPECT_EQ(st::uncertainty_set(0.0, 0.0, 0.0, starts, 0.0).size(), starts.size());
  EXPECT_THROW(st::uncertainty_set(0.0, 0.0, 0.0, starts, -0.1), cs::InvalidArgument);
  auto m = cs::testing::thesis_position_clearance_model();
  m.damping = 0.12;
  EXPECT_DOUBLE_EQ(st::varied_model(m, nominal.back()).damping, 0.12 * std::exp(0.2));
}

// The one-sided 90 % upper bound on σ: s·√((n−1)/χ²_{0.1, n−1}); the factors are SciPy's
// (scipy.stats.chi2.ppf(0.1, n − 1)): n = 3 → 3.0807826, n = 10 → 1.4694307, and 95 % at
// n = 10 → 1.6451976.
TEST(ClearanceAware, SpreadUpperBoundIsTheChiSquareBound) {
  const std::vector<double> three{-1.0, 0.0, 1.0};  // s = 1
  EXPECT_NEAR(st::spread_upper_bound(three), 3.0807826247611008, 1e-9);
  std::vector<double> ten;
  for (int k = 0; k < 10; ++k) ten.push_back(k % 2 == 0 ? 0.1 : -0.1);  // s = 0.1·√(10/9)
  const double s = 0.1 * std::sqrt(10.0 / 9.0);
  EXPECT_NEAR(st::spread_upper_bound(ten), s * 1.4694307221378702, 1e-9);
  EXPECT_NEAR(st::spread_upper_bound(ten, 0.95), s * 1.6451975743942215, 1e-9);
  EXPECT_EQ(st::spread_upper_bound({0.5, 0.7}), 0.0);
  EXPECT_EQ(st::spread_upper_bound({0.3, 0.3, 0.3}), 0.0);
  EXPECT_THROW(st::spread_upper_bound(three, 1.0), cs::InvalidArgument);
}

// The set a design from a fitted model uses: corners only when some σ reaches 2 % (a non-finite σ
// is read as 50 %), the damping spread whenever it is known.
TEST(ClearanceAware, DesignUncertaintyFollowsTheFitsSigma) {
  const std::size_t n = st::default_start_fractions().size();
  st::ClearanceModelSigma s;
  s.play_rel_sigma = 0.01;
  s.stiffness_rel_sigma = 0.01;
  s.coulomb_rel_sigma = 0.019;
  EXPECT_EQ(st::design_uncertainty(s).size(), n);
  s.damping_spread = 0.19;
  const auto with_spread = st::design_uncertainty(s);
  ASSERT_EQ(with_spread.size(), 3 * n);
  EXPECT_DOUBLE_EQ(with_spread.back().damping_factor, std::exp(0.19));
  s.coulomb_rel_sigma = 0.07;
  const auto corners = st::design_uncertainty(s);
  ASSERT_EQ(corners.size(), 5 * n);
  EXPECT_DOUBLE_EQ(corners[n].coulomb_factor, 1.07);
  s.play_rel_sigma = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(st::design_uncertainty(s)[n].play_factor, 0.5);
}

// A step move's command ends on the move itself, whatever the rounding of its start on the
// sample grid (it once ended on its last zero: every case then read MD 0 unshaped and shaped),
// and the unshaped step rings on the joint with play.
TEST(ClearanceAware, StepMovesReachTheirAmplitudeAndRing) {
  for (const double start_s : {0.2, 0.3, 0.5, 0.7}) {
    auto r = small_request();
    r.move_start_s = start_s;
    for (const auto& m : st::design_moves(r)) {
      EXPECT_DOUBLE_EQ(m.command.values.back(), std::stod(m.name)) << "start " << start_s;
    }
  }
  const auto r = small_request();
  const cs::shaping::Shaper none("none", {{0.0, 1.0}});
  for (const auto& m : st::design_moves(r)) {
    EXPECT_GT(st::clearance_aware_case_md(r, r.model, m, -1.0, none), 1e-3) << m.name;
  }
}
