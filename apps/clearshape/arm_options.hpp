#pragma once
// Options shared by the `clearshape arm` subcommands (cmd_arm.cpp, cmd_arm_modes.cpp): which arm
// (built-in or URDF + TOML, with an optional play for every joint), angle lists, output files.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Dense>

#include "clearshape/arm/arm.hpp"

namespace clearshape::cli {

struct ArmSource {
  std::string name = "scara-2";
  std::string urdf, config;
  double play_deg = 0.0;
  CLI::Option* play_option = nullptr;
};

/// --arm, --urdf, --config, --play-deg on `app`.
void add_arm_options(CLI::App& app, ArmSource& source);
/// A subcommand of `parent` with the arm options.
CLI::App* add_arm_subcommand(CLI::App& parent, const std::string& name, const std::string& description,
                             ArmSource& source);
/// The arm named by the options (InvalidArgument naming the option; InputError naming the file).
arm::ArmModel load_arm(const ArmSource& source);

/// "a,b,…" → one angle per joint (rad). InvalidArgument naming `option` and the joints.
Eigen::VectorXd parse_angles(const std::string& text, const std::string& option, const arm::ArmModel& arm);
/// "v" (every joint) or "v1,v2,…" (one per joint) → one value per joint, each in [lo, hi].
/// InvalidArgument naming `option`, the joints, the unit and the range.
std::vector<double> parse_joint_values(const std::string& text, const std::string& option, const arm::ArmModel& arm,
                                       const std::string& unit, double lo, double hi);
std::string format_angles(const Eigen::VectorXd& q);

/// ".json" or ".csv" (lower case) of `-o`; InvalidArgument naming -o otherwise.
std::string output_kind(const std::filesystem::path& path);

}  // namespace clearshape::cli

#include "clearshape/arm/clearance_aware.hpp"
#include "clearshape/arm/trajectory.hpp"

namespace clearshape::cli {

/// A synchronised jerk-limited move, optionally shaped (arm move, arm simulate).
struct MoveRequest {
  std::string from, to;
  std::string shaper = "none";  ///< none | fixed | scheduled | clearance-aware
  std::string method = "zvd";
  bool every_mode = false;
  /// Limits at the link: one value for every joint or one per joint, comma-separated.
  std::string velocity = "2", acceleration = "20", jerk = "400";
  double sample_time_s = 1e-3;
  // clearance-aware (arm/clearance_aware.hpp): the design's search and its start places
  int evaluations = 40;      ///< of the objective, 10-100000
  int slots = 8;             ///< impulse slots, 2-32
  double grid_s = 0.0;       ///< slot spacing (s, 0-1; 0: a quarter period of the end pose's lowest mode)
  std::string start_places;  ///< "f1,f2;f1,f2;…" (φ/β per joint in [-1, 1]); empty: the library's five
  double design_settle_s = 1.5;  ///< simulated after the shaped command in each trial (s, 0.1-10)
  int threads = 2;           ///< parallel simulations, 1-64
  // the flank-keeping stop (arm/benchmark.hpp flank_keeping_limits; docs/arm.md §7)
  double flank_margin = 0.0;  ///< 0: off, [0, 1]
  double flank_floor = 0.05;  ///< (0, 1]
};
/// --from, --to (required when `required`), --shaper, --method, --every-mode, --velocity,
/// --acceleration, --jerk, --sample-time, --flank-margin, --flank-floor.
void add_move_options(CLI::App& app, MoveRequest& move, bool required);
/// Each joint's limits from --velocity, --acceleration, --jerk (InvalidArgument naming the option).
std::vector<signal::AxisLimits> joint_limits(const arm::ArmModel& arm, const MoveRequest& move);
/// joint_limits within flank_keeping_limits at `end_pose_rad` (--flank-margin, --flank-floor;
/// InvalidArgument naming the option); `summary` receives one line with the lowered limits when on.
std::vector<signal::AxisLimits> move_limits(const arm::ArmModel& arm, const MoveRequest& move,
                                            const Eigen::VectorXd& end_pose_rad, std::string& summary);
/// The (shaped) move; `summary` receives one line per joint on its design, `applied` (when given)
/// the shaper of each joint (empty for none).
arm::JointTrajectory build_move(const arm::ArmModel& arm, const MoveRequest& move, std::string& summary,
                                std::vector<shaping::Shaper>* applied = nullptr);

/// --start-places "f1,f2;…" → one vector per start place (φ_i/β_i, each in [-1, 1]);
/// InvalidArgument naming --start-places and the allowed values.
std::vector<Eigen::VectorXd> parse_start_places(const std::string& text, const arm::ArmModel& arm);
/// The clearance-aware design's options from the request (arm_clearance_aware.cpp).
arm::ArmClearanceAwareOptions clearance_aware_options(const arm::ArmModel& arm, const MoveRequest& move);
/// The move shaped by design_clearance_aware_move (one shaper on every joint); `summary` receives
/// the design: its shaper, per start place the tool residual unshaped and shaped, the worst ratio
/// (WORSE than unshaped flagged), the evaluations and the design's wall time.
arm::JointTrajectory clearance_aware_move(const arm::ArmModel& arm, const MoveRequest& move,
                                          const arm::JointTrajectory& unshaped, std::string& summary,
                                          std::vector<shaping::Shaper>& applied);

/// Registers `arm modes` under `arm` (cmd_arm_modes.cpp).
void setup_arm_modes(CLI::App& arm);
/// Registers `arm study` under `arm` (cmd_arm_study.cpp).
void setup_arm_study(CLI::App& arm);

}  // namespace clearshape::cli
