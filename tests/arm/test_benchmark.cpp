// The arm's pick-and-place benchmark (arm/benchmark.hpp): the moves are reproducible and stay
// in the workspace; the tool residual is Eq. 5.1, an RMS about the settled mean (a steady sine of
// amplitude A gives A/√2, an identity); a stiff arm without play driven by shapers at its
// own modes keeps almost none of its unshaped residual (linear theory, Singer & Seering 1990);
// within the flank-keeping limits the contact torque of vertical-2's plays keeps the sign gravity
// gives it through the stop (M q̈ + g = τ: the link never leaves its loaded flank), without them
// it crosses.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "clearshape/arm/benchmark.hpp"
#include "clearshape/arm/chain.hpp"
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

// The least contact torque of each joint from the middle of `move` (planned within `limits`,
// unshaped) to the end of the settle, over |g_i| and signed so that > 0 is gravity's flank.
Eigen::VectorXd least_loaded_contact(const ArmModel& arm, const PointToPoint& move,
                                     const std::vector<signal::AxisLimits>& limits) {
  const JointTrajectory t = plan_move(arm, move.from_rad, move.to_rad, limits, 1e-3);
  ArmSimulationOptions o;
  o.duration_s = t.time_s.back() + 1.5;
  const ArmTrace trace = simulate_arm(arm, drive_commands(arm, t), o);
  ChainWorkspace ws(arm.chain);
  Eigen::VectorXd g;
  ws.gravity_torque(move.to_rad, g);  // at rest τ = g(q): the loaded flank's torque has g's sign
  Eigen::VectorXd least = Eigen::VectorXd::Constant(arm.dof(), std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < trace.time_s.size(); ++k) {
    if (trace.time_s[k] < 0.5 * t.time_s.back()) continue;
    for (int i = 0; i < arm.dof(); ++i) {
      least(i) = std::min(least(i), trace.contact_torque_n_m(static_cast<Eigen::Index>(k), i) / g(i));
    }
  }
  return least;
}

TEST(ArmBenchmark, FlankKeepingStopKeepsGravitysFlankLoadedThroughTheStop) {
  const ArmModel arm = builtin_arm("vertical-2");  // 0.5° play per joint
  const std::vector<signal::AxisLimits> limits{{2.0, 20.0, 18000.0}, {3.0, 30.0, 27000.0}};  // the study's
  const PointToPoint move = pick_and_place_moves(arm, 20, 1, 0.1)[17];  // the study's move 17
  const auto kept = flank_keeping_limits(arm, move.to_rad, limits, 0.5, 0.05);
  EXPECT_LT(kept[0].acceleration, 0.5 * limits[0].acceleration);  // the shoulder's |g| / M_ii = 9.4 rad/s²
  const Eigen::VectorXd with = least_loaded_contact(arm, move, kept);
  const Eigen::VectorXd without = least_loaded_contact(arm, move, limits);
  for (int i = 0; i < arm.dof(); ++i) EXPECT_GT(with(i), 0.0) << "joint " << i << " leaves its loaded flank";
  EXPECT_LT(without(0), 0.0) << "the shoulder keeps its flank without the bound: the test shows nothing";
  MovePlayOptions o;
  o.limits = limits;
  const MovePlay plain = play_move(arm, move, {.schedule = ShaperSchedule::none}, o);
  o.flank_margin = 0.5;
  const MovePlay flank = play_move(arm, move, {.schedule = ShaperSchedule::none}, o);
  EXPECT_GT(flank.command_end_s, plain.command_end_s);  // the price: a longer move
  EXPECT_LT(flank.residual_m, 0.1 * plain.residual_m);  // no strike after the command's end
}

TEST(ArmBenchmark, FlankKeepingLimitsLeaveAGravityFreeArmAndCheckTheirRange) {
  const ArmModel scara = builtin_arm("scara-2");  // gravity along the joint axes: g(q) = 0
  const Eigen::VectorXd pose = pick_and_place_moves(scara, 1, 1)[0].to_rad;
  const auto same = flank_keeping_limits(scara, pose, kLimits, 0.5, 0.05);
  for (std::size_t i = 0; i < kLimits.size(); ++i) EXPECT_EQ(same[i].acceleration, kLimits[i].acceleration);
  const auto message = [&](double margin, double floor) {
    try {
      (void)flank_keeping_limits(scara, pose, kLimits, margin, floor);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(1.5, 0.05).find("flank_margin"), std::string::npos);
  EXPECT_NE(message(-0.1, 0.05).find("flank_margin"), std::string::npos);
  EXPECT_NE(message(0.5, 0.0).find("flank_floor = 0 is out of range; allowed: (0, 1]"), std::string::npos)
      << message(0.5, 0.0);
  MovePlayOptions o;
  o.limits = kLimits;
  o.flank_margin = 2.0;
  EXPECT_THROW(play_move(scara, pick_and_place_moves(scara, 1, 1)[0], {}, o), InvalidArgument);
}

}  // namespace
}  // namespace clearshape::arm
