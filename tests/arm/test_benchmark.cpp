// The arm's pick-and-place benchmark (arm/benchmark.hpp): the moves are reproducible and stay
// in the workspace; the tool residual is Eq. 5.1, an RMS about the settled mean (a steady sine of
// amplitude A gives A/√2, an identity); a stiff arm without play driven by shapers at its
// own modes keeps almost none of its unshaped residual (linear theory, Singer & Seering 1990).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "clearshape/arm/benchmark.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {
namespace {

const std::vector<signal::AxisLimits> kLimits{{2.0, 20.0, 400.0}, {3.0, 30.0, 600.0}};

TEST(ArmBenchmark, MovesAreChainedReproducibleAndInsideTheNarrowedRanges) {
  const ArmModel arm = builtin_arm("scara-2");
  const auto moves = pick_and_place_moves(arm, 12, 7, 0.1);
  ASSERT_EQ(moves.size(), 12u);
  EXPECT_TRUE(moves.front().from_rad.isApprox(workspace_centre(arm)));
  for (std::size_t m = 1; m < moves.size(); ++m) EXPECT_EQ(moves[m].from_rad, moves[m - 1].to_rad);
  const auto& joints = arm.chain.joints();
  for (const PointToPoint& m : moves) {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const double span = joints[i].upper_rad - joints[i].lower_rad;
      EXPECT_GE(m.to_rad(static_cast<Eigen::Index>(i)), joints[i].lower_rad + 0.1 * span - 1e-12);
      EXPECT_LE(m.to_rad(static_cast<Eigen::Index>(i)), joints[i].upper_rad - 0.1 * span + 1e-12);
    }
  }
  const auto again = pick_and_place_moves(arm, 12, 7, 0.1);
  for (std::size_t m = 0; m < moves.size(); ++m) EXPECT_EQ(moves[m].to_rad, again[m].to_rad);
  EXPECT_NE(pick_and_place_moves(arm, 12, 8, 0.1).back().to_rad, moves.back().to_rad);
  EXPECT_THROW(pick_and_place_moves(arm, 0), InvalidArgument);
  EXPECT_THROW(pick_and_place_moves(arm, 3, 1, 0.5), InvalidArgument);
}

TEST(ArmBenchmark, ToolResidualOfASteadySineIsAOverRootTwo) {
  ArmTrace t;
  const double a_m = 2e-4, f_hz = 20.0, ts = 1e-3;
  const int n = 2001;  // 0 … 2 s: a whole number of periods after 0.5 s
  t.tool_position_m = Eigen::MatrixXd::Zero(n, 3);
  for (int k = 0; k < n; ++k) {
    t.time_s.push_back(k * ts);
    t.tool_position_m(k, 0) = 0.3 + a_m * std::sin(2.0 * std::numbers::pi * f_hz * k * ts);
    t.tool_position_m(k, 1) = -0.1;
  }
  EXPECT_NEAR(tool_residual_m(t, 0.5), a_m / std::numbers::sqrt2, 2e-3 * a_m);  // Eq. 5.1 of x; y is still
  t.tool_position_m.col(0).setConstant(0.3);
  EXPECT_NEAR(tool_residual_m(t, 0.5), 0.0, 1e-14);
}

TEST(ArmBenchmark, AStiffArmShapedAtItsOwnModesKeepsAlmostNothing) {
  ArmModel arm = builtin_arm("scara-2");
  for (ArmJoint& j : arm.joints) j.half_play_rad = 0.0;  // the same flanks, linear
  MovePlayOptions o;
  o.limits = kLimits;
  const auto moves = pick_and_place_moves(arm, 3, 1);
  const std::vector<MoveShaping> designs{{.schedule = ShaperSchedule::none},
                                         {.schedule = ShaperSchedule::end_pose, .every_mode = true}};
  const auto r = run_benchmark(arm, moves, designs, o);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].improvement, 0.0);
  double sum = 0.0;
  for (const MovePlay& m : r[1].moves) sum += m.residual_m;
  EXPECT_DOUBLE_EQ(r[1].total_residual_m, sum);
  EXPECT_GT(r[0].total_residual_m, 1e-5);  // the unshaped moves ring
  EXPECT_GT(r[1].improvement, 0.9) << r[0].total_residual_m << " → " << r[1].total_residual_m;
  for (const MovePlay& m : r[0].moves) EXPECT_EQ(m.contact_onsets, 0);
}

TEST(ArmBenchmark, StartPlacesAreCheckedPerJoint) {
  const ArmModel arm = builtin_arm("scara-2");
  MovePlayOptions o;
  o.limits = kLimits;
  const auto moves = pick_and_place_moves(arm, 1, 1);
  o.start_play_fraction = Eigen::Vector3d(0.0, 0.0, 0.0);
  EXPECT_THROW(play_move(arm, moves[0], {}, o), InvalidArgument);
  o.start_play_fraction = Eigen::Vector2d(1.5, 0.0);
  EXPECT_THROW(play_move(arm, moves[0], {}, o), InvalidArgument);
  o.start_play_fraction = Eigen::Vector2d(-1.0, 1.0);
  EXPECT_GE(play_move(arm, moves[0], {}, o).contact_onsets, 1);
}

}  // namespace
}  // namespace clearshape::arm
