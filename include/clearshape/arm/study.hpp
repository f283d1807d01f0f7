#pragma once
// The arm study (issue 24 item 5; docs/arm.md §7 "The arm study"): a study TOML names an arm
// (built-in, or URDF + TOML), its play, a pick-and-place benchmark (arm/benchmark.hpp: move count,
// seed, limits per joint) and the designs to compare — unshaped (always, the reference), one
// fixed shaper per joint at the workspace centre, shapers scheduled at each move's end pose, and
// the clearance-aware command designed per move (arm/clearance_aware.hpp), and the move re-planned
// to keep the gravity-loaded flanks (flank_keeping_limits) unshaped or scheduled — plus a grid of poses
// for the workspace map of the linearised modes (arm/modes.hpp, joint_modes: the map is the
// linearised model's, not identified from runs). run_arm_study plays every move with every design
// (moves spread over threads; the result does not depend on their number) and
// write_arm_study writes results.json and tables.md into one folder, both or neither.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "clearshape/arm/benchmark.hpp"
#include "clearshape/arm/clearance_aware.hpp"
#include "clearshape/shaping/design.hpp"

namespace clearshape::arm {

/// What a study TOML holds (docs/arm.md, "The arm study").
struct ArmStudySpec {
  std::string name;
  std::string file;               ///< the study file, for errors and the report
  std::string arm = "scara-2";    ///< a built-in arm, or "" with urdf + config
  std::filesystem::path urdf, config;  ///< relative paths are taken from the study file's folder
  std::vector<double> play_deg;   ///< total play per joint (empty: the arm's own)
  std::size_t moves = 20;         ///< [20, 1000] in a file; --quick plays fewer
  std::uint64_t seed = 1;
  double margin = 0.1;            ///< the moves' end poses avoid this share of each joint's range
  std::vector<signal::AxisLimits> limits;  ///< per joint (link rad/s, rad/s², rad/s³)
  double sample_time_s = 1e-3;
  double settle_s = 1.5;
  shaping::Method method = shaping::Method::zvd;
  bool every_mode = false;
  /// After unshaped: fixed, scheduled, clearance-aware, and on the flank-keeping stop
  /// (MovePlayOptions::flank_margin) flank-unshaped and flank-scheduled.
  std::vector<std::string> designs{"fixed", "scheduled", "clearance-aware"};
  double flank_margin = 0.5;      ///< the flank designs' MovePlayOptions::flank_margin, (0, 1]
  double flank_floor = 0.05;      ///< their MovePlayOptions::flank_floor, (0, 1]
  int evaluations = 100;          ///< clearance-aware: evaluations of J per move
  int slots = 8;                  ///< clearance-aware: impulse slots
  int threads = 2;                ///< moves played in parallel
  int map_points = 9;             ///< poses per joint of the mode map (first two joints)
  bool quick = false;
};

/// Reads a study TOML; errors are InputError naming the file, line, key and the allowed values.
ArmStudySpec read_arm_study(const std::filesystem::path& file);
/// The same from text; `file` names it in errors and relative URDF/TOML paths are taken from its folder.
ArmStudySpec parse_arm_study(std::string_view text, const std::string& file);
/// A few seconds' version for tests: 3 moves, 10 evaluations per clearance-aware design, 3×3 poses.
void make_quick(ArmStudySpec& spec);

/// The arm of the study, with its play set.
ArmModel study_arm(const ArmStudySpec& spec);

struct ArmStudyResult {
  std::vector<PointToPoint> moves;
  std::vector<BenchmarkDesign> designs;  ///< designs[0] is unshaped
  /// Per move, when the study has the clearance-aware design: its design (start places, ratios).
  std::vector<ArmClearanceAwareResult> clearance_aware;
  nlohmann::ordered_json mode_map;       ///< the grid and the modes at every pose
  nlohmann::ordered_json drawing;        ///< the arm's joints and tool at the workspace centre
};

/// Plays the study. Throws InvalidArgument for a spec that does not fit the arm (the limits' count).
ArmStudyResult run_arm_study(const ArmStudySpec& spec, const ArmModel& arm);

/// results.json (docs/arm.md) and tables.md of a study.
nlohmann::ordered_json arm_study_json(const ArmStudySpec& spec, const ArmModel& arm, const ArmStudyResult& result);
std::string arm_study_tables(const ArmStudySpec& spec, const ArmStudyResult& result);
/// Writes both into `folder` (io::AtomicBatch: both or neither).
void write_arm_study(const std::filesystem::path& folder, const ArmStudySpec& spec, const ArmModel& arm,
                     const ArmStudyResult& result);

/// The points of the arm drawn at `pose_rad`: the base, every joint's origin, the tool (m, root frame).
std::vector<Eigen::Vector3d> arm_points_m(const ArmModel& arm, const Eigen::VectorXd& pose_rad);

}  // namespace clearshape::arm
