#pragma once
// A study protocol: the thesis's experimental programme (Chapters 4–5, Appendix B) as data,
// read from a TOML file (studies/thesis-position.toml, studies/thesis-speed.toml).
//
// The file (every value carries its unit in its key; command units are deg in position mode
// and V in speed mode, written as the key suffix _deg / _v):
//   format = "clearshape-study-protocol/1"
//   [study]            name, title, mode ("position" | "speed"), seed, sample_rate_hz, record_s,
//                      repetitions
//   [measure]          md_signal ("link_angle_deg" | "link_rate_deg_s"), bias_window_s,
//                      md_final_window_fraction
//   [shaping]          grid_hz (round impulse times to the drive's update grid; 0 = off),
//                      clearance_aware_max_duration_s (0: ZVDD's duration for the link mode),
//                      clearance_aware_max_evaluations (the design's search budget, 300)
//   [[input]]          name, label, type (signal::signal_types()) and the signal's parameters:
//                      amplitude_deg, second_amplitude_deg, offset_deg, limit_deg, levels_deg,
//                      slope_deg_per_s, acceleration_deg_per_s2 (…_v… in speed mode), start_s,
//                      rise_s, hold_s, fall_s, dwell_s, second_start_s, bit_period_s,
//                      frequency_hz, phase_rad, order, seed, rise_shape, repeat
//   [consistency]      table, inputs, signal ("motor_angle_deg" | "motor_speed_deg_s");
//                      [consistency.thesis.<input>] label, values, mean   (Eq. 4.1 columns)
//   [identification]   structure, inputs, speed_chain ("causal" | "zero-phase");
//                      [identification.thesis] selected_input, kp, tz_s, zeta, tw_s, tp3_s
//   [link_mode]        input, start ("after-settling" | "after-command"), settle_after_move_s,
//                      window_s, max_damping_ratio
//   [clearance]        input, exponent, link_inertia_kg_m2, play_deg,
//                      stiffness_n_m_per_rad_pow_n, damping_n_m_s_per_rad, fit, filter_gyro,
//                      window_s, max_evaluations, contact_law ("dashpot" | "flores"),
//                      restitution; [clearance.thesis] stiffness, damping, agreement
//   [simulation]       inputs, shapers, mode_sources ("drive-model" | "link-mode"), record_s
//   [rig_tests]        [[rig_tests.table]] id, title, input, [[rig_tests.table.column]]
//                      shaper ("none" | a shaping method), mode_source, label, thesis,
//                      thesis_mean; [[rig_tests.summary]] id, title, kind ("combine" |
//                      "improvement"), tables, column, thesis; floor_trials (0 … 1000 rest
//                      trials: the Eq. 5.1 measurement floor, study/measurement_floor.hpp)
//   [quick]            repetitions, record_s, simulation_inputs, simulation_shapers,
//                      clearance_max_evaluations   (the reduced variant used by --quick)
// Unknown tables or keys, wrong types and values out of range are InputErrors naming the file,
// the line and the key. References between sections (an input name, a table id) are checked.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/rig/types.hpp"
#include "clearshape/signal/signal.hpp"

namespace clearshape::study {

inline constexpr const char* kProtocolFormat = "clearshape-study-protocol/1";

/// One command input of the programme (in command units: deg or V).
struct InputSpec {
  std::string name;   ///< identifier used by the stages ("step-20")
  std::string label;  ///< human label ("20° step")
  signal::Signal signal = signal::Step{};
  /// The keys as written in the file (with units), for the effective protocol in results.json.
  nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
  /// Time of the last change of the command (start of the last move), s: Eq. 5.1 searches for
  /// the steady-state start after it.
  double last_move_start_s = 0.0;
};

/// A column of published numbers (Tables 4.1, 4.2, 5.1, B.1–B.6).
struct ThesisColumn {
  std::string label;
  std::vector<double> values;
  std::optional<double> mean;
};

enum class MdSignal { link_angle_deg, link_rate_deg_s };
std::string_view to_string(MdSignal signal) noexcept;

struct MeasureSpec {
  /// What Eq. 5.1 is computed on (the thesis does not say; see docs/design.md §2 and the study's
  /// ambiguities): position mode the link angle (gyro integrated), speed mode the link rate.
  MdSignal md_signal = MdSignal::link_angle_deg;
  /// The gyro bias is estimated on [0, bias_window_s) (before any move) and removed.
  double bias_window_s = 0.4;
  double md_final_window_fraction = 0.2;  ///< metrics::MeanDeviationOptions
};

struct ShapingSpec {
  /// Position mode: the driver takes a new velocity only at its pulse-train updates (§3.2,
  /// 30 Hz), so impulse times are rounded to that grid (nearest update; impulses falling on the
  /// same update are merged). 0 = keep the designed times.
  double grid_hz = 0.0;
  /// The clearance-aware shaper's duration bound (s); 0: ZVDD's for the link mode (it never adds
  /// more delay than ZVDD).
  double clearance_aware_max_duration_s = 0.0;
  /// The clearance-aware search's budget of objective evaluations (--quick: 40).
  int clearance_aware_max_evaluations = 300;
};

struct ConsistencyStage {
  std::string table = "4.2";
  std::vector<std::string> inputs;
  /// "motor_angle_deg" (position mode) or "motor_speed_deg_s" (speed mode, thesis chain).
  std::string signal = "motor_angle_deg";
  std::map<std::string, ThesisColumn> thesis;  ///< by input name
};

struct ThesisProcessModel {
  std::string selected_input;
  double kp = 0.0, tz_s = 0.0, zeta = 0.0, tw_s = 0.0, tp3_s = 0.0;
};

struct IdentificationStage {
  std::string structure = "P3UZ";
  std::vector<std::string> inputs;
  std::string speed_chain = "causal";  ///< "causal" | "zero-phase" (dsp::Phase)
  ThesisProcessModel thesis;
};

struct LinkModeStage {
  std::string input;
  /// Where the free-response window starts: "after-settling" (the motor within 2 % of its final
  /// value — position mode) or "after-command" (the last command change — speed mode, where the
  /// drive's own oscillation is part of the free response).
  std::string start = "after-settling";
  double settle_after_move_s = 0.05;  ///< skipped after that instant
  double window_s = 1.5;              ///< length of the free-response window
  double max_damping_ratio = 0.7;
};

struct ClearanceStage {
  std::string input;
  double exponent = 1.5;                 ///< n of Eq. 4.3
  double link_inertia_kg_m2 = 5e-3;      ///< the model's nominal link inertia
  double play_deg = 0.1;                 ///< total play 2β (start value when fitted)
  double stiffness_n_m_per_rad_pow_n = 1e4;  ///< K (start value when fitted)
  double damping_n_m_s_per_rad = 300.0;      ///< D (start value when fitted)
  /// "dashpot" (Eq. 4.3) or "flores" (restitution law; "damping" in `fit` then fits e).
  std::string contact_law = "dashpot";
  double restitution = 0.6;                  ///< e (flores; start value without a link mode)
  std::vector<std::string> fit{"stiffness", "damping"};  ///< of stiffness, damping, play, exponent
  /// Compare the model with the gyro passed through the §3.3 filter (speed mode: the identified
  /// drive contains that filter, §4.2, so the measurement is filtered alike).
  bool filter_gyro = false;
  double window_s = 2.0;                 ///< record length compared (from the input's start)
  int max_evaluations = 150;
  /// Thesis §4.2 (units unstated); absent (null in results.json) for a protocol that gives none.
  std::optional<double> thesis_stiffness;
  std::optional<double> thesis_damping;
  std::optional<double> thesis_agreement;  ///< Eq. 4.1 agreement the thesis reached
};

struct SimulationStage {
  std::vector<std::string> inputs;
  std::vector<std::string> shapers;       ///< shaping::method_names()
  std::vector<std::string> mode_sources;  ///< "drive-model", "link-mode"
  double record_s = 5.0;
};

/// The shaper name of clearance-aware design (study/clearance_aware.hpp): designed on the study's
/// fitted clearance model (mode source "clearance-model") for the amplitudes of the protocol's
/// rig-test steps, at most as long as ZVDD for the link mode.
inline constexpr std::string_view kClearanceAwareShaper = "clearance-aware";
/// The shaper name of a take-up profile (study/take_up.hpp), rig tests only: designed on the
/// fitted clearance model (mode source "clearance-model") for each table's input move, at most
/// as long as ZVDD for the link mode on the update grid.
inline constexpr std::string_view kTakeUpShaper = "take-up";

struct RigColumn {
  std::string shaper = "none";  ///< "none", a shaping method name, "clearance-aware" or "take-up"
  std::string mode_source;      ///< "drive-model" | "link-mode" | "clearance-model" (empty for none)
  std::string label;
  ThesisColumn thesis;          ///< empty values when the thesis has no such column
  /// The improvement % the thesis printed for this column (Appendix B, §5.1.2), verbatim; absent
  /// when it printed none (results.json then gives only the value recomputed from its means).
  std::optional<double> thesis_improvement;
  /// "none", or "<shaper>@<mode_source>" (e.g. "zvdd@link-mode").
  std::string key() const;
};

struct RigTable {
  std::string id;     ///< "5.1", "B.1", …
  std::string title;
  std::string input;
  std::vector<RigColumn> columns;
};

struct RigSummary {
  std::string id;     ///< "5.2", "B.6"
  std::string title;
  std::string kind;   ///< "combine" (tables side by side) | "improvement" (mean improvements)
  std::vector<std::string> tables;
  std::string column;           ///< improvement: the shaped column key
  std::vector<double> thesis;   ///< improvement: the thesis's %, one per table
};

struct RigTestStage {
  std::vector<RigTable> tables;
  std::vector<RigSummary> summaries;
  /// Rest trials (a zero command of the record's length) whose Eq. 5.1 in each table's input
  /// window is the measurement floor (study/measurement_floor.hpp); 0 = none.
  int floor_trials = 0;
};

struct QuickReduction {
  int repetitions = 3;
  double record_s = 3.0;
  std::vector<std::string> simulation_inputs;   ///< empty = keep
  std::vector<std::string> simulation_shapers;  ///< empty = keep
  int clearance_max_evaluations = 40;
  // floor_trials: at most `repetitions` rest trials (not a key of its own).
};

struct Protocol {
  std::filesystem::path source;
  std::string name;
  std::string title;
  rig::CommandMode mode = rig::CommandMode::position;
  std::uint64_t seed = 1;
  double sample_rate_hz = 1000.0;
  double record_s = 5.0;
  int repetitions = 10;
  /// [study] rig: the built-in simulated truth the study runs on by default ("thesis",
  /// "large-play"; rig/builtin_truths.hpp). `study --rig/--rig-config/--recordings` override it.
  std::string rig = "thesis";
  bool quick = false;  ///< the [quick] reduction has been applied
  MeasureSpec measure;
  ShapingSpec shaping;
  std::vector<InputSpec> inputs;
  ConsistencyStage consistency;
  IdentificationStage identification;
  LinkModeStage link_mode;
  ClearanceStage clearance;
  SimulationStage simulation;
  RigTestStage rig_tests;
  QuickReduction quick_reduction;

  const InputSpec& input(std::string_view name) const;  ///< throws InvalidArgument
  const RigTable& table(std::string_view id) const;     ///< throws InvalidArgument
  double sample_time_s() const noexcept { return 1.0 / sample_rate_hz; }
  /// "deg" (position) or "V" (speed): the command unit.
  std::string_view command_unit() const noexcept;
};

/// Reads and validates a protocol. Throws InputError (file, line, key).
Protocol load_protocol(const std::filesystem::path& path);
/// Parses protocol text (`source` names it in errors).
Protocol parse_protocol(std::string_view text, const std::filesystem::path& source);
/// The protocol with its [quick] reduction applied (fewer repetitions, shorter records).
Protocol quick_variant(const Protocol& protocol);

/// The effective protocol as JSON (what results.json records).
nlohmann::ordered_json to_json(const Protocol& protocol);
/// FNV-1a 64-bit hash of to_json(protocol) and `rig_description`, as 16 hex digits: a run
/// is reused on restart only when its sidecar carries the same hash.
std::string protocol_hash(const Protocol& protocol, std::string_view rig_description);

}  // namespace clearshape::study
