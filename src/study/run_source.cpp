// The plan of a study's runs and the rig-backed run source (study/run_source.hpp).
#include "clearshape/study/run_source.hpp"

#include <set>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::study {

std::string unshaped_run_id(std::string_view input, int repetition) {
  return fmt::format("unshaped/{}/r{:02d}", input, repetition);
}

std::string rig_test_run_id(std::string_view table, std::string_view column, int repetition) {
  return fmt::format("rig/{}/{}/r{:02d}", table, column, repetition);
}

std::string rest_run_id(int repetition) { return fmt::format("rest/r{:02d}", repetition); }

namespace {

std::vector<PlannedRun> unshaped(const Protocol& p, const std::vector<std::string>& inputs) {
  std::vector<PlannedRun> runs;
  for (const auto& input : inputs) {
    if (input.empty()) continue;
    for (int r = 1; r <= p.repetitions; ++r) {
      runs.push_back({unshaped_run_id(input, r), "unshaped", input, "none", r});
    }
  }
  return runs;
}

std::vector<PlannedRun> rig_tests(const Protocol& p) {
  std::vector<PlannedRun> runs;
  for (const auto& table : p.rig_tests.tables) {
    for (const auto& col : table.columns) {
      for (int r = 1; r <= p.repetitions; ++r) {
        runs.push_back({rig_test_run_id(table.id, col.key(), r), "rig-tests", table.input, col.key(), r});
      }
    }
  }
  return runs;
}

std::vector<PlannedRun> rest_trials(const Protocol& p) {
  std::vector<PlannedRun> runs;
  for (int r = 1; r <= p.rig_tests.floor_trials; ++r) runs.push_back({rest_run_id(r), "rest", "", "rest", r});
  return runs;
}

class RigRunSource final : public RunSource {
 public:
  RigRunSource(RigFactory factory, rig::CommandMode mode, double sample_rate_hz)
      : factory_(std::move(factory)), mode_(mode), sample_rate_hz_(sample_rate_hz) {}
  std::string kind() const override { return factory_.kind; }
  std::string description() const override { return factory_.description; }
  int parallel_runs() const override { return factory_.parallel_runs; }
  bool has(const PlannedRun&) const override { return true; }
  ObtainedRun obtain(const RunRequest& request) const override {
    std::unique_ptr<rig::Rig> rig = factory_.make(mode_, sample_rate_hz_, request.seed);
    ObtainedRun out{execute_run(*rig, request), {}};
    const auto& cnt = rig->counters();
    out.counters = {{"reads", cnt.reads},
                    {"writes", cnt.writes},
                    {"failed_reads", cnt.failed_reads},
                    {"failed_writes", cnt.failed_writes}};
    // A rig with a link (the serial rig) also records what the link saw.
    const rig::LinkCounters link = rig->link_counters();
    if (link.samples > 0) {
      out.counters["samples_received"] = link.samples;
      out.counters["samples_lost"] = link.samples_lost;
      out.counters["frames_corrupted"] = link.frames_corrupted;
      out.counters["samples_late"] = link.samples_late;
    }
    return out;
  }

 private:
  RigFactory factory_;
  rig::CommandMode mode_;
  double sample_rate_hz_;
};

}  // namespace

std::vector<StagePlan> plan_runs(const Protocol& p) {
  return {
      {"consistency", unshaped(p, p.consistency.inputs)},
      {"identification", unshaped(p, p.identification.inputs)},
      {"link-mode", unshaped(p, {p.link_mode.input})},
      {"clearance", unshaped(p, {p.clearance.input})},
      {"simulation", {}},
      {"rig-tests", rig_tests(p)},
      {"measurement-floor", rest_trials(p)},
  };
}

std::vector<PlannedRun> distinct_runs(const Protocol& p) {
  std::vector<PlannedRun> out;
  std::set<std::string> seen;
  for (const auto& stage : plan_runs(p)) {
    for (const auto& run : stage.runs) {
      if (seen.insert(run.id).second) out.push_back(run);
    }
  }
  return out;
}

std::shared_ptr<const RunSource> rig_run_source(RigFactory factory, rig::CommandMode mode, double sample_rate_hz) {
  if (!factory.make) throw InvalidArgument("rig_run_source: the rig factory's make is empty");
  return std::make_shared<RigRunSource>(std::move(factory), mode, sample_rate_hz);
}

}  // namespace clearshape::study
