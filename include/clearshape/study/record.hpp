#pragma once
// One recorded run of the study: a command executed on a rig (rig::Rig lifecycle + real-time
// read/write loop), its measurements, and its files — <id>.csv (one row per sample) and
// <id>.json (the sidecar: protocol hash, seed, shaper, units, rig counters).
//
// CSV columns (docs/study-outputs.md): time_s, command_<u>, command_applied_<u>,
// encoder_counts, motor_angle_deg, gyro_raw, link_rate_deg_s, flags — u = deg (position mode)
// or v (speed mode). Values are written in the shortest round-trip form, so a run read back is
// bit-identical to the run recorded (a resumed study gives the same bytes as a fresh one).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/core/series.hpp"
#include "clearshape/rig/rig.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::study {

/// How the study obtains a rig for one run (the default is the simulated thesis rig).
struct RigFactory {
  /// Recorded in every sidecar and in the protocol hash ("sim", "sim:<config hash>", …).
  std::string description = "sim";
  /// What the rig is, for results.json "rig": "simulated-thesis" | "simulated-config" |
  /// "physical" (study/run_source.hpp).
  std::string kind = "simulated-thesis";
  /// Runs that may execute at the same time (1 for hardware; the simulated rig allows more).
  int parallel_runs = 1;
  /// A configured-or-unconfigured rig for `mode` sampling at `sample_rate_hz`; `seed` seeds
  /// whatever the rig randomizes (the simulated rig's noise and initial play).
  std::function<std::unique_ptr<rig::Rig>(rig::CommandMode mode, double sample_rate_hz,
                                          std::uint64_t seed)>
      make;
};

/// What to run.
struct RunRequest {
  std::string id;              ///< unique within a study: "<stage>/<input>/<column>/rNN"
  std::string stage;           ///< "unshaped", "rig-tests"
  std::string input;           ///< input name
  std::string column = "none"; ///< "none" or "<shaper>@<mode source>"
  int repetition = 1;          ///< 1-based
  std::uint64_t seed = 1;
  std::optional<shaping::Shaper> shaper;  ///< recorded in the sidecar
  UniformSeries command;       ///< command units (deg or V), at the rig's sample time
  double record_s = 5.0;
};

/// The primary recorded columns of one run (everything else is derived from them).
struct Record {
  std::string id;
  rig::CommandMode mode = rig::CommandMode::position;
  double sample_time_s = 1e-3;
  std::vector<double> time_s;
  std::vector<double> command;          ///< requested, command units
  std::vector<double> command_applied;  ///< what the driver received, command units
  std::vector<double> encoder_counts;
  std::vector<double> motor_angle_deg;
  std::vector<double> gyro_raw;
  std::vector<double> link_rate_deg_s;
  std::vector<double> flags;
  std::size_t size() const noexcept { return time_s.size(); }
};

/// Seed of a run: SplitMix64 of the study seed and the FNV-1a hash of the run id.
std::uint64_t run_seed(std::uint64_t study_seed, std::string_view run_id) noexcept;

/// Runs `request` on `rig` (configure if needed → activate → read/write loop → deactivate).
/// The command is held between samples and after its end. Throws RuntimeError when the rig
/// refuses a lifecycle step or a read fails (naming the sample), InvalidArgument when the
/// rig's sample time differs from the command's.
Record execute_run(rig::Rig& rig, const RunRequest& request);

/// <dir>/<id with '/' → '__'>.csv and .json.
std::filesystem::path record_csv_path(const std::filesystem::path& runs_dir, std::string_view id);
std::filesystem::path record_sidecar_path(const std::filesystem::path& runs_dir, std::string_view id);

/// Writes the CSV, then the sidecar (each atomically; the sidecar last, so a sidecar means a
/// complete run).
void write_record(const std::filesystem::path& runs_dir, const Record& record,
                  const RunRequest& request, std::string_view protocol_hash,
                  std::string_view rig_description, const nlohmann::ordered_json& rig_counters);
/// Reads a run back if its sidecar exists and carries `protocol_hash` (and the CSV parses);
/// nullopt otherwise.
std::optional<Record> read_record(const std::filesystem::path& runs_dir, const RunRequest& request,
                                  rig::CommandMode mode, std::string_view protocol_hash);

/// CSV column names for a mode (command unit suffix).
std::vector<std::string> record_columns(rig::CommandMode mode);

}  // namespace clearshape::study
