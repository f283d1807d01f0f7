#pragma once
// The arm's pick-and-place benchmark (issue 24 item 5; docs/arm.md §7): chained point-to-point
// moves across the workspace, each played through the arm's drives with its joints' commands
// shaped one way or another, and judged by the tool tip's residual vibration — Eq. 5.1 (the
// thesis's mean deviation, metrics/mean_deviation.hpp) on each tool coordinate after the command
// ends, combined as √(MD_x² + MD_y² + MD_z²) (a horizontal arm's z, a vertical arm's y stay still).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/arm.hpp"
#include "clearshape/arm/simulation.hpp"
#include "clearshape/arm/trajectory.hpp"
#include "clearshape/signal/jerk_limited.hpp"

namespace clearshape::arm {

/// A rest-to-rest move of every joint.
struct PointToPoint {
  Eigen::VectorXd from_rad;
  Eigen::VectorXd to_rad;
};

/// `count` moves chained across the workspace (each starts where the one before ended, the first
/// at the workspace centre), their end poses drawn uniformly over each joint's range narrowed by
/// `margin` of it at both ends (a continuous joint: ±π), from std::mt19937_64 seeded with `seed`:
/// the same arguments give the same moves. Throws InvalidArgument for count 0 or margin outside
/// [0, 0.45].
std::vector<PointToPoint> pick_and_place_moves(const ArmModel& arm, std::size_t count, std::uint64_t seed = 1,
                                               double margin = 0.1);

/// Eq. 5.1 of the tool's x, y and z from `from_s` on, combined √(MD_x² + MD_y² + MD_z²) (m).
double tool_residual_m(const ArmTrace& trace, double from_s);

struct MovePlayOptions {
  std::vector<signal::AxisLimits> limits;  ///< one per joint (link rad/s, rad/s², rad/s³)
  double sample_time_s = 1e-3;
  double settle_s = 1.5;                   ///< simulated after the shaped command ends
  /// Where each link starts in its play, φ_i(0)/β_i in [−1, 1] (empty: the centre).
  Eigen::VectorXd start_play_fraction;
  /// The flank-keeping stop (flank_keeping_limits): > 0 plans each move with the acceleration
  /// limits lowered to flank_margin × the bound at its end pose; 0: the limits as given. [0, 1].
  double flank_margin = 0.0;
  /// flank_keeping_limits' floor: no limit is lowered below this share of its own. (0, 1].
  double flank_floor = 0.05;
};

/// The flank-keeping limits of a move ending at `end_pose_rad` (docs/arm.md §7, "The
/// flank-keeping stop"). Joint i's link stays on the flank gravity loads while the contact torque
/// M_ii q̈_i + g_i keeps g_i's sign (M(q) q̈ + g(q) = τ, arm/chain.hpp, coupling left out), i.e. for
/// |q̈_i| < |g_i(q)| / M_ii(q); an acceleration step at the stop's end swings that torque by
/// M_ii |Δq̈_i| both ways, so the bound holds in either direction of the move. Each joint's
/// acceleration limit becomes max(floor · a_i, min(a_i, margin · |g_i| / M_ii)): near the pose
/// where g_i crosses zero no reachable deceleration keeps the flank loaded and the floor caps the
/// cost; a joint without gravity (|g_i| / M_ii ≤ 1e-9 a_i, e.g. a horizontal arm) keeps a_i.
/// Throws InvalidArgument naming flank_margin ([0, 1]), flank_floor ((0, 1]) or the pose's and
/// limits' size (one per joint).
std::vector<signal::AxisLimits> flank_keeping_limits(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                                     std::span<const signal::AxisLimits> limits, double margin,
                                                     double floor);

struct MovePlay {
  double residual_m = 0.0;      ///< tool_residual_m from the end of the shaped command
  double command_end_s = 0.0;   ///< where the shaped command ends
  double shaper_duration_s = 0.0;  ///< the longest joint shaper
  long contact_onsets = 0;      ///< flank contacts over the run
};

/// Plans `move` (plan_move; within flank_keeping_limits when options.flank_margin > 0), shapes
/// each joint with its shaper (shape_trajectory), and simulates the arm through its drives
/// (drive_commands, simulate_arm).
MovePlay play_move_with(const ArmModel& arm, const PointToPoint& move, std::span<const shaping::Shaper> shapers,
                        const MovePlayOptions& options);

/// play_move_with the shapers of `shaping` (joint_shapers at the move's end pose).
MovePlay play_move(const ArmModel& arm, const PointToPoint& move, const MoveShaping& shaping,
                   const MovePlayOptions& options);

/// The benchmark's result for one way of shaping: the residual of every move, and over the
/// benchmark 1 − Σ residual / Σ residual unshaped.
struct BenchmarkDesign {
  std::string name;  ///< e.g. "zvd fixed", "zvd end_pose every-mode", "clearance-aware"
  MoveShaping shaping;
  std::vector<MovePlay> moves;
  double total_residual_m = 0.0;
  double improvement = 0.0;  ///< against the first design of run_benchmark (unshaped)
};

/// Every move with each of `designs`; the improvement of each is judged against designs[0].
std::vector<BenchmarkDesign> run_benchmark(const ArmModel& arm, std::span<const PointToPoint> moves,
                                           std::span<const MoveShaping> designs, const MovePlayOptions& options);

}  // namespace clearshape::arm
