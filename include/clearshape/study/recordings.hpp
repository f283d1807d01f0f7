#pragma once
// A study on runs recorded elsewhere: a folder of CSVs and a manifest (DIR/manifest.toml) that
// maps each run of the protocol to a file and names its columns and units (docs/recordings.md).
//
//   format = "clearshape-recordings/1"
//   description = "axis 2, belt drive, 2026-11-20"      # optional, shown in results.json
//   [columns]                    # defaults of every run (each [[run]] may override any key)
//   time = "time_s"              # default: the first of time_s, time, t; time_unit: s | ms
//   command = "command_deg"      # command_unit: deg | rad (position mode), V (speed mode)
//   command_applied = "command_applied_deg"   # optional; default: the command
//   motor_angle = "motor_angle_deg"           # motor_angle_unit: deg | rad | counts
//   counts_per_rev = 12000                    # with motor_angle_unit = "counts"
//   link_rate = "link_rate_deg_s"             # link_rate_unit: deg/s | rad/s | lsb
//   lsb_per_deg_s = 14.375                    # with link_rate_unit = "lsb"
//   gyro_full_scale_deg_s = 2000              # the gyroscope's range (ITG-3205: ±2000 °/s)
//   [[run]]
//   id = "unshaped/step-20/r01"  # a run of the protocol (--print-manifest lists them all)
//   file = "step20-1.csv"        # relative to DIR
//
// The defaults are the columns of the study's own runs/*.csv, so a study's runs folder is a
// recordings folder as it stands. Runs the protocol expects but the manifest does not list are
// missing (the stages needing them are skipped and say so); a listed run the protocol does not
// have, a missing file, an unknown key or unit is an InputError naming the manifest's line.
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/run_source.hpp"

namespace clearshape::study {

inline constexpr const char* kRecordingsFormat = "clearshape-recordings/1";

/// How one recording's columns map onto a run's records.
struct RecordingColumns {
  std::string time;                   ///< "" = the first of time_s, time, t
  std::string time_unit = "s";        ///< s | ms
  std::string command;
  std::string command_unit;           ///< deg | rad | V
  std::string command_applied;        ///< "" = the command
  std::string motor_angle = "motor_angle_deg";
  std::string motor_angle_unit = "deg";  ///< deg | rad | counts
  double counts_per_rev = 12000.0;
  std::string link_rate = "link_rate_deg_s";
  std::string link_rate_unit = "deg/s";  ///< deg/s | rad/s | lsb
  double lsb_per_deg_s = 14.375;
  double gyro_full_scale_deg_s = 2000.0;  ///< the ITG-3205's ±2000 °/s; a rate beyond it is refused
};

struct RecordingEntry {
  std::string id;
  std::filesystem::path file;  ///< absolute (DIR / file)
  std::size_t manifest_line = 0;
  RecordingColumns columns;
};

struct RecordingsManifest {
  std::filesystem::path dir;
  std::filesystem::path path;  ///< DIR/manifest.toml
  std::string description;
  std::string hash;            ///< FNV-1a of the manifest text, 16 hex digits
  std::map<std::string, RecordingEntry> runs;  ///< by run id
};

/// Reads DIR/manifest.toml and checks it against the protocol (ids, files, units).
RecordingsManifest load_recordings_manifest(const std::filesystem::path& dir, const Protocol& protocol);
/// The template for `study --print-manifest`: every run the protocol expects, with the study's
/// own run file names and columns as defaults.
std::string recordings_manifest_template(const Protocol& protocol);
/// A recording converted to a run's records (`sample_time_s` of the protocol; the record is
/// cut to `record_s`). Throws InputError naming the file and the column.
Record read_recording(const RecordingEntry& entry, const Protocol& protocol, double record_s);

/// The recordings-backed run source.
std::shared_ptr<const RunSource> recordings_run_source(RecordingsManifest manifest, const Protocol& protocol);

}  // namespace clearshape::study
