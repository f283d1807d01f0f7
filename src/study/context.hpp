#pragma once
// Shared state of one study run (internal): the protocol, the run cache, the stage results
// and the JSON being assembled.
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/ident/process_fit.hpp"
#include "clearshape/shaping/shaper.hpp"
#include "clearshape/study/model.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"
#include "clearshape/study/runner.hpp"

namespace clearshape::study::detail {

using json = nlohmann::ordered_json;

struct ModeResult {
  bool available = false;
  shaping::Mode mode{};
  std::string note;  ///< why it is unavailable, or how it was obtained
};

struct Context {
  Context(const Protocol& protocol, const StudyOptions& options);

  const Protocol& p;
  const StudyOptions& options;
  std::shared_ptr<const RunSource> source;  ///< where the runs come from
  std::string hash;
  std::filesystem::path out;
  std::filesystem::path runs_dir;
  std::filesystem::path data_dir;
  std::chrono::steady_clock::time_point start;
  std::mutex progress_mutex;
  int threads = 1;

  // Stage results.
  std::map<std::string, std::vector<Record>> unshaped;  ///< by input name
  std::optional<ident::ProcessEstimate> drive;          ///< the selected drive model
  std::string drive_input;
  ModeResult drive_mode;
  ModeResult link_mode;
  std::optional<ClearanceModel> model;
  /// The relative 1σ of the model's play, K and Coulomb torque (stage_clearance: from the fit that
  /// gave `model`), for the design stage's uncertainty set; nullopt when not fitted.
  std::optional<ClearanceModelSigma> model_sigma;
  /// The clearance-aware shaper (designed once on `model`, ensure_clearance_aware), or why not.
  std::optional<shaping::Shaper> clearance_aware;
  std::string clearance_aware_note;
  bool clearance_aware_tried = false;

  // Output assembly.
  json tables = json::array();
  json figures = json::array();
  json sections = json::object();  ///< per-stage detail (identification, link_mode, …)
  std::vector<StageTiming> timing;
  json skipped = json::array();  ///< stages skipped for want of runs (results.json "skipped_stages")
  /// Files this study wrote under <out>/data/ (names), for the outputs manifest.
  mutable std::mutex written_mutex;
  mutable std::vector<std::string> data_written;

  void log(const std::string& line);
  double elapsed_s() const;
  /// Runs (or reads back) the requests, in parallel; results in request order.
  std::vector<Record> run_all(const std::vector<RunRequest>& requests, const std::string& stage);
  /// Unshaped runs of an input (repetitions of them), cached.
  const std::vector<Record>& unshaped_runs(const std::string& input);
  /// The command of an input sampled at the protocol's rate over the record.
  UniformSeries command_of(const InputSpec& input, double record_s) const;
  /// A data file under <out>/data/ (relative name for figures.json).
  std::string data_file(const std::string& name) const { return "data/" + name; }
  StageTiming& begin_stage(const std::string& name);
};

void stage_consistency(Context& c);
void stage_identification(Context& c);
void stage_link_mode(Context& c);
void stage_clearance(Context& c);
void stage_simulation(Context& c);
void stage_rig_tests(Context& c);
/// The measurement floor (rest trials) and "what a command can reach here"; after the rig tests.
void stage_measurement_floor(Context& c);

/// Designs the clearance-aware shaper once, if a rig-test column or the simulation stage asks
/// for it: on the fitted clearance model, for the amplitudes of the protocol's step and
/// double-step inputs, at most as long as ZVDD for the link mode (results.json
/// sections.clearance_aware).
void ensure_clearance_aware(Context& c);

/// The take-up profile (study/take_up.hpp) for a rig table's input — a step or double step — on
/// the fitted clearance model, no longer than ZVDD for the link mode on the update grid
/// (results.json sections.take_up.<input>); nullopt + reason when it cannot be designed, else
/// `reason` describes the design.
std::optional<shaping::Shaper> take_up_for(Context& c, const InputSpec& in, std::string& reason);

/// Designs `method` for a mode source; nullopt + reason when it cannot be designed.
std::optional<shaping::Shaper> design_for(const Context& c, const std::string& method,
                                          const std::string& mode_source, std::string& reason);

/// A uniform table record for results.json.
json make_table(const std::string& id, const std::string& kind, const std::string& title,
                const std::string& unit);

/// True (logged, recorded in c.skipped) when the source lacks a run `stage` needs.
bool skip_for_missing_runs(Context& c, const std::vector<StagePlan>& plan, const std::string& stage);

/// Writes a CSV under <out>/data/.
void write_data_csv(const Context& c, const std::string& name, const std::vector<std::string>& columns,
                    const std::vector<const std::vector<double>*>& data);

/// Every ambiguity the study settles (results.json "ambiguities", tables.md).
/// `rig_kind` (RunSource::kind) decides what the rig-truth entry says: a simulated rig's truth,
/// or measurements on a physical or recorded rig.
json ambiguities(const Protocol& p, std::string_view rig_kind);

/// results.json "rig": what the rig is, in words the report prints as they are — kind, description,
/// summary (one sentence on what it is), calibrated_to_thesis (its truth was fitted to the thesis's
/// unshaped measurements: only the built-in thesis rig), scored_against_thesis (its numbers get
/// verdicts: the thesis rig, or a physical/recorded rig repeating the experiment) and, for a
/// built-in what-if rig, documented {contact_exponent, play_deg} (its documented joint, so the
/// report can say when a fit misses it).
json rig_document(std::string_view kind, std::string_view description);

/// Every table column's thesis numbers as the thesis printed them (thesis_printed,
/// thesis_mean_printed, thesis_improvement_printed): a column of trials keeps its common number of
/// decimals (0.270, 0.0009), numbers below 10⁻³ keep the thesis's ×10ⁿ form (1.56×10⁻⁴).
void add_thesis_printed(json& tables);

/// tables.md from results.json.
std::string render_tables_markdown(const json& results);

}  // namespace clearshape::study::detail
