#pragma once
// A mode map identified from runs (issue 24 item 3; docs/arm.md §7): at each pose of a grid the
// arm is simulated with play (simulate_arm) under a small jerk-limited step of one joint at a
// time, or a slow ramp of all joints that keeps the flanks loaded (ModeMapExcitation); once the
// drives have settled, the links ring at the arm's residual modes, and the free
// response of each link's rate (a gyro on that link) is identified with the stabilisation-diagram
// mode estimate of ident/modes.hpp (ERA + least squares, 1σ from the fit's covariance). The
// estimates of the same mode from the runs at one pose (within `merge_tolerance` in frequency)
// are combined by inverse-variance weighting. Each identified mode is set beside the nearest of
// the linearised modes (arm/modes.hpp, joint_modes) at the pose: with play 0 they agree closely;
// with play the link rattles in its play and the identified frequency depends on the amplitude.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/arm.hpp"
#include "clearshape/arm/modes.hpp"
#include "clearshape/arm/simulation.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/signal/jerk_limited.hpp"

namespace clearshape::arm {

/// How the runs excite the arm's modes.
enum class ModeMapExcitation {
  /// one run per joint: a small jerk-limited step of that joint (step_deg, limits); the links
  /// ring freely after it. With play the free response is a mode only where gravity keeps the
  /// flanks loaded through the swing; elsewhere the links rattle in their play.
  step,
  /// one run: every joint ramps at ramp_velocity_rad_s, reached gently (ramp_acceleration_rad_s2);
  /// each link starts on its trailing flank (or on its gravity flank) and the bearing's friction
  /// keeps it there, so the links ring at the locked-play modes while the joints cruise through
  /// the pose (it is passed in the middle of the window). Needs
  /// Coulomb friction ≥ K·(swing): the swing ≈ a/ω² must stay below F_c/K.
  loaded_ramp,
};

/// What the identification reads: every link's rate (a gyro on each link), or only the last
/// link's 3-axis gyroscope (ArmTrace::gyro_rad_s, the arm's [imu]), its axes that turn in the window.
enum class ModeMapSensor { link_rates, last_link_gyro };

struct ModeMapOptions {
  ModeMapExcitation excitation = ModeMapExcitation::step;
  ModeMapSensor sensor = ModeMapSensor::link_rates;
  double step_deg = 1.0;  ///< each run's step of one joint at the link (deg), > 0
  /// Limits of that step per joint (rad/s, rad/s², rad/s³); empty: 2 rad/s, 40 rad/s², 4000 rad/s³.
  std::vector<signal::AxisLimits> limits;
  double ramp_velocity_rad_s = 0.02;       ///< loaded_ramp: every joint's cruise rate, > 0
  double ramp_acceleration_rad_s2 = 0.1;   ///< loaded_ramp: reached at this acceleration (jerk 100×), > 0
  double settle_s = 0.15;           ///< after the step ends, before the window (the drives settle), >= 0
  double window_s = 0.6;            ///< the free-response window identified (s), > 0
  double output_rate_hz = 1000.0;   ///< samples of the link rates, > 0
  double merge_tolerance = 0.05;    ///< relative frequency within which two runs' estimates are one mode, (0, 1)
  double harmonic_tolerance = 0.003;  ///< relative, for MapMode::harmonic, [0, merge_tolerance)
  /// modes = 0: the arm's number of joints; residual modes worth shaping are lightly damped:
  /// max_damping_ratio 0.05 (a heavier "mode" is the rattle of a link in its play, or friction's)
  ident::ModeOptions identification = [] {
    ident::ModeOptions o;
    o.modes = 0;
    o.max_damping_ratio = 0.05;
    return o;
  }();
  ArmSolverOptions solver{};
  JointModeOptions linearisation{};
  void validate(int dof) const;
};

/// One identified mode at a pose, with its nearest linearised mode.
struct MapMode {
  double natural_frequency_hz = 0.0;
  double natural_frequency_std_hz = 0.0;  ///< 1σ
  double damping_ratio = 0.0;
  double damping_ratio_std = 0.0;         ///< 1σ
  int runs = 0;                 ///< how many runs' estimates were combined
  int linear_mode = 0;          ///< the nearest of joint_modes' modes (index, ascending frequency)
  double linear_frequency_hz = 0.0;
  double linear_damping_ratio = 0.0;
  double relative_frequency_error = 0.0;  ///< (f − f_lin) / f_lin
  /// k ≥ 2 when f is within `harmonic_tolerance` of k times a lower identified mode's frequency
  /// (2 ≤ k ≤ 9): a harmonic of that mode from a nonlinearity (the play's contact, the regularised
  /// Coulomb friction), not a mode of its own; 0 otherwise.
  int harmonic = 0;
};

struct ModeMapPoint {
  Eigen::VectorXd pose_rad;
  std::vector<MapMode> modes;        ///< ascending frequency
  ArmModes linearised;               ///< joint_modes at the pose
  std::vector<std::string> failures; ///< runs that gave no mode ("joint shoulder: reason")
};

struct ModeMap {
  std::string arm_name;
  std::vector<std::string> joint_names;
  std::vector<ModeMapPoint> points;
};

/// One run's rate signals in its free-response window, sampled uniformly from start_s (rows:
/// time): every link's rate (samples × joints) and the last link's 3-axis gyro (samples × 3, its
/// frame). Either may be empty (not recorded); ModeMapOptions::sensor says which one is read.
struct RunRecord {
  std::string name;  ///< the excitation, in failures: "loaded ramp", "step of shoulder"
  double start_s = 0.0;
  double sample_time_s = 1e-3;
  Eigen::MatrixXd link_rate_rad_s;
  Eigen::MatrixXd gyro_rad_s;
};

/// The runs at one pose, and the runs that gave no record (a failed simulation).
struct PoseRuns {
  Eigen::VectorXd pose_rad;
  std::vector<RunRecord> runs;
  std::vector<std::string> failures;
};

/// A simulated run of identify_mode_map: its excitation, the whole trace and the window's start.
struct SimulatedRun {
  ModeMapExcitation excitation = ModeMapExcitation::step;
  int joint = -1;              ///< the stepped joint (step), −1 (loaded_ramp)
  std::string name;            ///< "loaded ramp", "step of shoulder"
  double window_start_s = 0.0;
  ArmTrace trace;
};

struct SimulatedPose {
  Eigen::VectorXd pose_rad;
  std::vector<SimulatedRun> runs;
  std::vector<std::string> failures;  ///< runs whose simulation failed ("step of elbow: reason")
};

/// A grid of poses: `points_per_joint` values per joint at the centres of equal cells of its URDF
/// range, lower + (k + ½)(upper − lower)/N (a continuous joint: of [−π, π)); the first joint
/// varies slowest. Throws InvalidArgument for points_per_joint < 1 or a grid above 10 000 poses.
std::vector<Eigen::VectorXd> pose_grid(const ArmModel& arm, int points_per_joint);

/// The mode map of `arm` at `poses` (one angle per joint each): simulate_mode_runs, then
/// mode_map_from_runs on their windows. Throws InvalidArgument for bad options or poses; a run
/// whose identification fails is listed in the point's failures.
ModeMap identify_mode_map(const ArmModel& arm, const std::vector<Eigen::VectorXd>& poses,
                          const ModeMapOptions& options = {});

/// The runs identify_mode_map simulates at `poses` (options.excitation), whole traces kept.
std::vector<SimulatedPose> simulate_mode_runs(const ArmModel& arm, const std::vector<Eigen::VectorXd>& poses,
                                              const ModeMapOptions& options = {});

/// The window of each simulated run (window_start_s to the trace's end) as a RunRecord.
std::vector<PoseRuns> simulated_windows(const std::vector<SimulatedPose>& simulated);

/// The mode map from runs at poses, simulated or recorded (the one identification of the map):
/// each record of options.sensor — every link's rate, or each gyro axis that turns (peak above
/// 1e-9 rad/s) — is identified, the estimates of a pose merged, set beside joint_modes at the
/// pose and harmonics marked. Throws InvalidArgument for bad options, a pose of the wrong size,
/// or a run without the records options.sensor reads.
ModeMap mode_map_from_runs(const ArmModel& arm, const std::vector<PoseRuns>& poses,
                           const ModeMapOptions& options = {});

}  // namespace clearshape::arm
