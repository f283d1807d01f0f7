#pragma once
// Commands for the arm (issue 24 item 4; docs/arm.md §7): a synchronised jerk-limited
// point-to-point move of the joints (signal/jerk_limited.hpp), each joint's command shaped by a
// shaper designed from the arm's linearised modes (arm/modes.hpp) — one fixed shaper per joint
// designed at the workspace centre, or one designed at the move's end pose — and written as a
// joint trajectory a controller can play: CSV (time_s, one angle per joint in rad) and JSON in
// the shape of a ROS trajectory_msgs/JointTrajectory (joint_names; points with positions,
// velocities, accelerations and time_from_start {sec, nanosec}).
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "clearshape/arm/arm.hpp"
#include "clearshape/arm/modes.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/jerk_limited.hpp"

namespace clearshape::arm {

/// Joint angles, rates and accelerations at increasing times (rows: samples, columns: joints).
struct JointTrajectory {
  std::vector<std::string> joint_names;
  std::vector<double> time_s;            ///< from 0, strictly increasing
  Eigen::MatrixXd position_rad;
  Eigen::MatrixXd velocity_rad_s;
  Eigen::MatrixXd acceleration_rad_s2;
  /// Throws InvalidArgument naming the field: names and columns agree, times from 0 strictly
  /// increasing, all values finite.
  void validate() const;
};

/// The synchronised jerk-limited move of every joint of `arm` from `start_rad` to `end_rad`
/// (one limit per joint, in rad/s, rad/s², rad/s³), sampled every `sample_time_s`.
JointTrajectory plan_move(const ArmModel& arm, const Eigen::VectorXd& start_rad, const Eigen::VectorXd& end_rad,
                          std::span<const signal::AxisLimits> limits, double sample_time_s);

/// Where each joint's shaper is designed.
enum class ShaperSchedule {
  none,      ///< no shaping
  fixed,     ///< at the workspace centre (workspace_centre): the same shapers for every move
  end_pose,  ///< at the move's end pose (pose-scheduled)
};
std::string_view to_string(ShaperSchedule schedule) noexcept;

struct MoveShaping {
  ShaperSchedule schedule = ShaperSchedule::end_pose;
  shaping::Method method = shaping::Method::zvd;  ///< zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3
  double vtol = 0.05;                              ///< for the EI family
  /// false: each joint's shaper cancels its dominant mode; true: every mode of the pose (the
  /// shapers of all modes convolved, Crain, Singhose & Seering 1996), the same for all joints.
  bool every_mode = false;
  JointModeOptions modes{};
};

/// One shaper per joint, designed by `shaping.method` at the dominant mode of that joint
/// (ArmModes::joint_mode) at the design pose, or at every mode (`every_mode`); schedule none
/// gives single unit impulses.
std::vector<shaping::Shaper> joint_shapers(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                           const MoveShaping& shaping);

/// Each joint's positions, rates and accelerations convolved with its shaper (the same impulses
/// for all three: convolution commutes with differentiation); the trajectory is lengthened by the
/// longest shaper, every joint held at rest after its own end. Needs uniform samples.
JointTrajectory shape_trajectory(const JointTrajectory& trajectory, std::span<const shaping::Shaper> shapers);

/// The position-drive commands that play `trajectory` on `arm`: u_i = N_i q_i / (the drive's
/// steady-state motor angle per command unit), linear between samples. Throws InvalidArgument for
/// a speed-mode drive, other joint names, or non-uniform samples.
std::vector<plant::Command> drive_commands(const ArmModel& arm, const JointTrajectory& trajectory);

/// CSV: time_s, then <joint>_rad per joint (shortest round-trip number format).
std::string trajectory_csv(const JointTrajectory& trajectory);
void write_trajectory_csv(const std::filesystem::path& path, const JointTrajectory& trajectory);
/// Reads a CSV written by write_trajectory_csv (positions; rates and accelerations zero).
JointTrajectory read_trajectory_csv(const std::filesystem::path& path);

/// The ROS JointTrajectory shape (plus clearshape's schema_version and clearshape_version).
nlohmann::ordered_json trajectory_json(const JointTrajectory& trajectory);
void write_trajectory_json(const std::filesystem::path& path, const JointTrajectory& trajectory);
/// Parses that shape; InputError naming `source` and the field (e.g. points[3].positions).
JointTrajectory trajectory_from_json(const nlohmann::json& document, const std::string& source);
JointTrajectory read_trajectory_json(const std::filesystem::path& path);

}  // namespace clearshape::arm
