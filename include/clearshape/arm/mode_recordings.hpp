#pragma once
// The mode map from recorded runs (issue 24 item 3; docs/arm.md §7, "From recorded runs"): an
// engineer records the map's excitation (the loaded ramp, or a step of each joint) at every pose
// of a grid on their own arm, lists the files in a manifest, and the map is identified from them
// by the same identification as the simulated runs (mode_map_from_runs). The manifest (TOML):
//
//   format = "clearshape-arm-recordings-1"
//   arm = "scara-2"                 # optional: refused when it is not the arm the map is for
//   description = "…"              # optional
//   [columns]                       # optional; these are the defaults
//   time = "time_s"                 # seconds, strictly increasing, uniform
//   link_rates = ["shoulder_link_rate_rad_s", "elbow_link_rate_rad_s"]  # <joint>_link_rate_rad_s
//   gyro = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"]            # the last link's gyro;
//                                   # "" for an axis not read (one that only carries the gyro's noise)
//   rate_unit = "rad/s"             # or "deg/s", for every rate column
//   [[run]]
//   file = "pose01-loaded-ramp.csv" # relative to the manifest's folder
//   pose_rad = [-1.733, -1.733]     # one angle per joint, within the URDF's limits
//   excitation = "loaded-ramp"      # or "step", with joint = "<joint>" (the stepped joint)
//   window_start_s = 0.351          # optional: the free response from here (default: first sample)
//   window_s = 0.6                  # optional: this long (default: to the file's end)
//
// Runs with the same pose (within 1e-9 rad) are one point of the map, in the manifest's order.
// A column is read only when options.sensor needs it (link_rates or gyro).
// `write_mode_recordings` writes simulated runs in this form: the template of a recording.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/mode_map.hpp"

namespace clearshape::arm {

inline constexpr const char* kModeRecordingsFormat = "clearshape-arm-recordings-1";

struct ModeRecordingColumns {
  std::string time = "time_s";
  std::vector<std::string> link_rates;  ///< one per joint; empty: <joint>_link_rate_rad_s
  std::vector<std::string> gyro{"gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s"};  ///< "": axis not read
  double rate_scale = 1.0;              ///< rad/s per unit of the rate columns (rate_unit)
};

struct RecordedRun {
  std::filesystem::path file;
  std::size_t manifest_line = 0;
  Eigen::VectorXd pose_rad;
  ModeMapExcitation excitation = ModeMapExcitation::loaded_ramp;
  int joint = -1;                    ///< the stepped joint (step)
  double window_start_s = -1.0;      ///< < 0: the file's first sample
  double window_s = 0.0;             ///< 0: to the file's end
};

struct ModeRecordings {
  std::filesystem::path manifest;
  std::string description;
  ModeRecordingColumns columns;
  std::vector<RecordedRun> runs;
};

/// Reads the manifest for `arm`. Throws InputError naming the manifest, the line and the key, with
/// the allowed values: a wrong format, another arm, a missing file, a pose of the wrong size or
/// outside a joint's limits, an excitation not step / loaded-ramp, a step without its joint, a
/// link_rates list not one per joint, no [[run]].
ModeRecordings read_mode_recordings(const std::filesystem::path& manifest, const ArmModel& arm);

/// One recorded run's window as a RunRecord (the columns options.sensor reads, in rad/s). Throws
/// InputError naming the file (and line) for a missing column (listing those present), a time
/// column not strictly increasing and uniform (0.1 % of the mean step), a non-finite value, or a
/// window with fewer than 50 samples.
RunRecord read_recorded_run(const RecordedRun& run, const ModeRecordingColumns& columns, const ArmModel& arm,
                            ModeMapSensor sensor);

/// The mode map from the recordings (mode_map_from_runs on their windows).
ModeMap mode_map_from_recordings(const ArmModel& arm, const ModeRecordings& recordings,
                                 const ModeMapOptions& options = {});

/// Writes the simulated runs to `folder` as recordings: per run a CSV (time_s, every
/// <joint>_link_rate_rad_s, gyro_x|y|z_rad_s; shortest round-trip digits) named
/// pose<NN>-loaded-ramp.csv or pose<NN>-step-<joint>.csv, and manifest.toml listing them with
/// their poses, excitations and window starts; all files appear together or not at all
/// (io::AtomicBatch). Returns the manifest's path.
std::filesystem::path write_mode_recordings(const std::filesystem::path& folder, const ArmModel& arm,
                                            const std::vector<SimulatedPose>& simulated);

}  // namespace clearshape::arm
