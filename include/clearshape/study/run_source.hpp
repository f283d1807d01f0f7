#pragma once
// Where a study's runs come from — the one seam between the thesis's programme and the rig:
// a simulated rig, a physical rig (both through study::RigFactory and execute_run) or a folder
// of recordings made elsewhere (study/recordings.hpp).
//
//   plan:    plan_runs(protocol)           every run each stage needs, by id (no rig involved)
//   obtain:  RunSource::obtain(request)    one run's records
//   tabulate: the stages (src/study/stage_*.cpp) turn the records into tables
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {

/// One run a stage needs (what `--print-manifest` lists and a recordings folder must hold).
struct PlannedRun {
  std::string id;               ///< "unshaped/<input>/rNN", "rig/<table>/<column>/rNN", "rest/rNN"
  std::string stage;            ///< the run's kind: "unshaped" | "rig-tests" | "rest"
  std::string input;            ///< empty for a rest trial (zero command)
  std::string column = "none";  ///< "none", "<shaper>@<mode source>" or "rest"
  int repetition = 1;
};

/// The runs of one study stage ("consistency", "identification", "link-mode", "clearance",
/// "simulation", "rig-tests", "measurement-floor"), in the order the stage requests them.
struct StagePlan {
  std::string stage;
  std::vector<PlannedRun> runs;
};

/// The run ids (the one place they are spelled): "unshaped/<input>/rNN", "rig/<table>/<column>/rNN",
/// "rest/rNN" (a rest trial of the measurement floor: zero command, study/measurement_floor.hpp).
std::string unshaped_run_id(std::string_view input, int repetition);
std::string rig_test_run_id(std::string_view table, std::string_view column, int repetition);
std::string rest_run_id(int repetition);

/// Every stage of the protocol with the runs it needs (a run shared by stages appears in each).
std::vector<StagePlan> plan_runs(const Protocol& protocol);
/// The distinct runs of the protocol, in first-use order.
std::vector<PlannedRun> distinct_runs(const Protocol& protocol);

/// A run's records and what the source reports about obtaining them (the rig's counters).
struct ObtainedRun {
  Record record;
  nlohmann::ordered_json counters = nlohmann::ordered_json::object();
};

class RunSource {
 public:
  virtual ~RunSource() = default;
  /// "simulated-thesis" | "simulated-config" | "physical" | "recordings" (results.json "rig").
  virtual std::string kind() const = 0;
  /// Recorded in results.json, every sidecar and the protocol hash.
  virtual std::string description() const = 0;
  /// Runs that may be obtained at the same time.
  virtual int parallel_runs() const = 0;
  /// Whether the source can give this run (a recordings folder may lack some).
  virtual bool has(const PlannedRun& run) const = 0;
  /// The run's records. Throws RuntimeError when obtaining fails, InputError for a bad file.
  virtual ObtainedRun obtain(const RunRequest& request) const = 0;
  /// Whether finished runs under <out>/runs may be read back instead of obtained again (a
  /// recording is cheaper to read again than to trust a copy of it).
  virtual bool reuse_finished_runs() const { return true; }
};

/// The rig-backed source: a rig from `factory` per run, executed by execute_run.
std::shared_ptr<const RunSource> rig_run_source(RigFactory factory, rig::CommandMode mode,
                                                double sample_rate_hz);

}  // namespace clearshape::study
