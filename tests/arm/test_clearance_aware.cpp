// The arm's clearance-aware command (arm/clearance_aware.hpp): simulations of one arm on several
// threads agree with one thread to the last bit (each has its own KDL chain); the design is the
// same for any thread count; it never leaves a start place worse than unshaped without saying
// so; and on a move where scara-2's links rattle through their plays it removes far more than
// the linear both-mode ZVD from every start place.
#include <gtest/gtest.h>

#include <thread>

#include "clearshape/arm/clearance_aware.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {
namespace {

const std::vector<signal::AxisLimits> kLimits{{2.0, 20.0, 400.0}, {3.0, 30.0, 600.0}};

MovePlayOptions play_options() {
  MovePlayOptions o;
  o.limits = kLimits;
  return o;
}

TEST(ArmClearanceAware, SimulationsOnSeveralThreadsAgreeWithOne) {
  const ArmModel arm = builtin_arm("scara-2");
  const PointToPoint move = pick_and_place_moves(arm, 12, 1)[9];
  MovePlayOptions o = play_options();
  o.start_play_fraction = Eigen::Vector2d(-1.0, 1.0);
  const double serial = play_move(arm, move, {.schedule = ShaperSchedule::none}, o).residual_m;
  std::vector<double> parallel(8, 0.0);
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < 2; ++t) {
    pool.emplace_back([&, t] {
      for (std::size_t k = t; k < parallel.size(); k += 2) {
        parallel[k] = play_move(arm, move, {.schedule = ShaperSchedule::none}, o).residual_m;
      }
    });
  }
  for (auto& t : pool) t.join();
  for (const double r : parallel) EXPECT_EQ(r, serial);
}

TEST(ArmClearanceAware, BeatsTheLinearShaperFromEveryStartPlaceAndIsTheSameOnAnyThreadCount) {
  const ArmModel arm = builtin_arm("scara-2");
  const PointToPoint move = pick_and_place_moves(arm, 12, 1)[9];  // unshaped 0.15–0.43 mm
  ArmClearanceAwareOptions o;
  o.play = play_options();
  o.max_evaluations = 40;
  o.threads = 2;
  const ArmClearanceAwareResult d = design_clearance_aware_move(arm, move, o);
  ASSERT_EQ(d.start_places.size(), 5u);
  EXPECT_TRUE(d.shaper.is_positive());
  EXPECT_LE(d.shaper.duration_s(), 7.0 * 0.25 / 15.0);  // 8 slots a quarter period of a ≥ 15 Hz mode apart
  double unshaped = 0.0, shaped = 0.0, linear = 0.0;
  for (std::size_t s = 0; s < d.start_places.size(); ++s) {
    unshaped += d.unshaped_residual_m[s];
    shaped += d.shaped_residual_m[s];
    MovePlayOptions p = o.play;
    p.start_play_fraction = d.start_places[s];
    linear += play_move(arm, move, {.schedule = ShaperSchedule::end_pose, .every_mode = true}, p).residual_m;
  }
  EXPECT_LT(shaped, 0.1 * unshaped) << shaped << " of " << unshaped;
  EXPECT_LT(shaped, 0.5 * linear) << shaped << " against the both-mode ZVD's " << linear;
  EXPECT_EQ(d.worse_than_unshaped, d.worst_ratio > 1.0);
  o.threads = 1;
  const ArmClearanceAwareResult one = design_clearance_aware_move(arm, move, o);
  ASSERT_EQ(one.shaper.impulses().size(), d.shaper.impulses().size());
  for (std::size_t k = 0; k < d.shaper.impulses().size(); ++k) {
    EXPECT_EQ(one.shaper.impulses()[k].time_s, d.shaper.impulses()[k].time_s);
    EXPECT_EQ(one.shaper.impulses()[k].amplitude, d.shaper.impulses()[k].amplitude);
  }
  EXPECT_EQ(one.shaped_residual_m, d.shaped_residual_m);
}

TEST(ArmClearanceAware, BadOptionsAreNamed) {
  const ArmModel arm = builtin_arm("scara-2");
  const PointToPoint move = pick_and_place_moves(arm, 1, 1)[0];
  ArmClearanceAwareOptions o;
  o.play = play_options();
  o.slots = 1;
  EXPECT_THROW(design_clearance_aware_move(arm, move, o), InvalidArgument);
  o.slots = 8;
  o.start_places = {Eigen::Vector3d(0.0, 0.0, 0.0)};
  EXPECT_THROW(design_clearance_aware_move(arm, move, o), InvalidArgument);
  o.start_places = {Eigen::Vector2d(0.0, 2.0)};
  EXPECT_THROW(design_clearance_aware_move(arm, move, o), InvalidArgument);
}

}  // namespace
}  // namespace clearshape::arm
