#pragma once
// One recorded run on the physical rig's board (docs/hardware.md "Host side"): a command series
// played through rig::SerialRig by the real-time runner, every cycle's sample collected by the
// logging thread, and the verdict on the record — complete, or degraded and why. What
// `clearshape rig run|stream` and `rig calibrate` (study/axis_calibration.hpp) record.
//
//   rig::SerialRig board(options);                  // STOP from its destructor on any exit
//   rig::BoardRunOptions o;  o.command = values;    // one value per cycle (deg or V)
//   rig::BoardRecord record;
//   const rig::BoardRunOutcome out = rig::run_on_board(board, o, record);
//   io::write_text_atomic(path, io::format_csv(...record_table(record, ...)...));
//
// The record's sidecar JSON (units, statistics, flagged samples) is built here too, so every
// command that records a run writes the same one.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::rig {

/// The columns of a run, one row per sample read (the CSV `rig run` writes).
struct BoardRecord {
  std::vector<double> time_s, command, shaped, applied, counts, motor_deg, gyro_raw, gyro_deg_s, flags, latency_s;
  Measurement last{};  ///< the newest sample (for progress lines)

  void reserve(std::size_t samples);
  /// Appends a logged cycle (skipped when its read failed); `applied` in deg (position) or V.
  void add(const LogRecord& record, bool position);
  std::size_t size() const noexcept { return time_s.size(); }
};

struct BoardRunOptions {
  std::vector<double> command;            ///< one value per cycle (position: deg, speed: V)
  std::optional<shaping::Shaper> shaper;  ///< shaped online (StreamingShaper) when set
  bool write_commands = true;             ///< false: sensors only (`rig stream`)
  bool realtime_scheduling = true;        ///< SCHED_FIFO and mlockall for the loop
  const std::atomic<bool>* stop_flag = nullptr;  ///< polled every cycle (io::interrupt_requested())
  /// Each warning once, as it is found (also kept in BoardRunOutcome::warnings).
  std::function<void(const std::string&)> warn;
  /// Called once the board has answered CONFIGURE, before the first cycle (e.g. to print its firmware).
  std::function<void(const SerialRig&)> configured;
  /// Progress about 5 times a second (the runner's status callback) with the record so far.
  std::function<void(const RunStatistics&, const BoardRecord&)> progress;
};

struct BoardRunOutcome {
  RunStatistics stats;
  SerialRigStats link;
  std::string stop_problem;            ///< empty when the board confirmed STOP
  std::vector<std::string> warnings;
  std::optional<BoardStats> board_during_run;  ///< the board's counters over the run (STATS after − before)
  std::vector<std::string> degraded;  ///< why the record is not complete; empty: complete
  int interrupted_by = 0;             ///< the signal that ended the run (io::pending_interrupt), 0: none
  bool complete() const noexcept { return degraded.empty(); }
};

/// Configures the board (SerialRig::configure), runs options.command through the real-time
/// runner (one cycle per value), collects every sample into `record`, and cleans the rig up (STOP,
/// servo off). Warns (options.warn) when the board's watchdog held the command or the board rejected
/// host frames; a stop, an interrupt or the rig's degradation() make the record degraded. Throws
/// what SerialRig and RealtimeRunner throw (the rig's destructor still sends STOP).
BoardRunOutcome run_on_board(SerialRig& rig, const BoardRunOptions& options, BoardRecord& record);

/// The record's columns and their names, in the order `rig run` writes them: time_s,
/// command_<u> (runs), command_shaped_<u> (shaped runs), command_applied_<u>, encoder_counts,
/// motor_deg, gyro_raw, gyro_deg_s, flags, latency_s; <u> = deg (position) or v (speed).
struct RecordColumns {
  std::vector<std::string> names;
  std::vector<const std::vector<double>*> columns;
};
RecordColumns record_columns(const BoardRecord& record, CommandMode mode, bool with_command, bool shaped);

/// The sidecar's parts: the columns' units, the run's statistics (loop, link, flagged samples,
/// the board's counters), the board's identity and the configuration sent to it.
nlohmann::ordered_json record_units_json(const SerialRigOptions& options);
nlohmann::ordered_json run_statistics_json(const BoardRunOutcome& outcome, const BoardRecord& record,
                                           const SerialRigOptions& options);
nlohmann::ordered_json board_json(const SerialRig& rig);
nlohmann::ordered_json board_stats_json(const BoardStats& stats);
nlohmann::ordered_json board_configuration_json(const SerialRigOptions& options);
/// "encoder-quadrature, pulse-ab, …" for the board's capability bits ("none" for 0).
std::string capability_names(std::uint32_t capabilities);

/// Where a record goes: `requested` when complete; otherwise `<stem>.incomplete<ext>` beside it,
/// so a failed run never replaces a previous good record of the same name.
std::string record_path_for(const std::string& requested, bool complete);

}  // namespace clearshape::rig
