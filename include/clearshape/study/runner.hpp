#pragma once
// The study runner: executes a protocol against a rig and writes its outputs.
//
//   const auto protocol = study::load_protocol("studies/thesis-position.toml");
//   study::StudyOptions options;
//   options.out_dir = "out/thesis-position";
//   const study::StudyResult result = study::run_study(protocol, options);
//
// Stages, in the thesis's order (each prints one line per stage and per run on `progress`):
//   1. unshaped runs + consistency   Eq. 4.1 per run and mean (Tables 4.1 / 4.2)
//   2. identification                Eq. 4.2 per input from the encoder (speed mode through the
//                                    §3.3 chain), cross-validation, the best model → ωn, ζ
//   3. link mode                     the link's residual mode from the gyro's free response
//   4. clearance                     Eq. 4.3 contact parameters fitted so that the model's link
//                                    rate matches the gyro record; Eq. 4.1 agreement
//   5. simulation                    every input, unshaped and shaped (each shaper × mode source)
//   6. rig tests                     repeated trials per table column (Tables 5.1, B.1–B.5),
//                                    summaries (5.2, B.6)
//   7. measurement floor             rig_tests.floor_trials rest trials: Eq. 5.1 when nothing
//                                    moves, and what a command can reach above it (only when
//                                    the protocol asks for rest trials)
// The runner only ever sees measurements: the rig comes from a RigFactory (the default builds
// the simulated thesis rig, whose true parameters stay hidden inside it).
//
// Resumable: each finished run is written atomically under <out>/runs/ (CSV + JSON sidecar);
// on restart a run whose sidecar carries the same protocol hash is read back instead of run.
// Deterministic: the same protocol and seed give the same bytes in every output except
// timing.json (wall-clock times). Outputs: results.json, tables.md, figures.json, data/*.csv,
// runs/*, timing.json — formats in docs/study-outputs.md.
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"
#include "clearshape/study/run_source.hpp"

namespace clearshape::rig {
struct RigTruth;
}  // namespace clearshape::rig

namespace clearshape::study {

inline constexpr int kResultsSchemaVersion = 2;

/// The simulated thesis rig: a rig::SimRig with its built-in (calibrated) truth, rig/truth.hpp;
/// any number of parallel runs.
RigFactory sim_rig_factory();
/// The simulated rig with a built-in truth by name (rig/builtin_truths.hpp): "thesis" is
/// sim_rig_factory(); others have kind "simulated-<name>". Throws InvalidArgument for others.
RigFactory sim_rig_factory(std::string_view truth_name);
/// A RigFactory::make for a rig::SimRig with `truth` (shared by every rig it makes).
decltype(RigFactory::make) sim_rig_maker(std::shared_ptr<const rig::RigTruth> truth);

struct StudyOptions {
  std::filesystem::path out_dir = "out/study";
  bool fresh = false;        ///< discard finished runs (<out>/runs) before starting
  RigFactory rig = sim_rig_factory();
  /// Where the runs come from; nullptr = rig_run_source(rig, …) (a recordings folder:
  /// study/recordings.hpp). Stages whose runs the source lacks are skipped and listed in
  /// results.json "skipped_stages".
  std::shared_ptr<const RunSource> source;
  int threads = 0;           ///< parallel runs; 0 = min(rig.parallel_runs, hardware threads)
  std::ostream* progress = nullptr;  ///< one line per stage and run (nullptr: silent)
};

struct StageTiming {
  std::string stage;
  double seconds = 0.0;
  int runs_executed = 0;
  int runs_reused = 0;
};

struct StudyResult {
  nlohmann::ordered_json results;  ///< the content of results.json
  std::string tables_markdown;     ///< tables.md
  nlohmann::ordered_json figures;  ///< figures.json
  std::vector<StageTiming> timing;
  /// A short summary for `clearshape study --json`: name, out_dir, key numbers, timing.
  nlohmann::ordered_json summary() const;
  /// One table of results["tables"] by id; throws InvalidArgument when absent.
  const nlohmann::ordered_json& table(std::string_view id) const;
};

/// Runs the study and writes its outputs. Throws InvalidArgument for a protocol the rig
/// cannot run, RuntimeError when a run or a stage fails.
StudyResult run_study(const Protocol& protocol, const StudyOptions& options);

}  // namespace clearshape::study
