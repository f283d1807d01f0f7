// The run-source seam (study/run_source.hpp): the plan lists exactly the runs the study asks its
// source for (so --print-manifest and a recordings folder cover the whole programme), a source
// that lacks runs makes the stages needing them skip, by name, in results.json, and the rig
// kind is recorded. Cost: one quick position study (≈ 3 s) and one with two stages skipped.
#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include <unistd.h>

#include "clearshape/core/error.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/run_source.hpp"
#include "clearshape/study/runner.hpp"
#include "study_paths.hpp"

namespace st = clearshape::study;
using clearshape::testing::studies_path;

namespace {

// The simulated rig, remembering what it was asked for; `lacking` runs it does not have.
class CountingSource final : public st::RunSource {
 public:
  CountingSource(std::shared_ptr<const st::RunSource> inner, std::set<std::string> lacking)
      : inner_(std::move(inner)), lacking_(std::move(lacking)) {}
  std::string kind() const override { return inner_->kind(); }
  std::string description() const override { return inner_->description() + " (counted)"; }
  int parallel_runs() const override { return inner_->parallel_runs(); }
  bool has(const st::PlannedRun& run) const override { return lacking_.count(run.id) == 0; }
  bool reuse_finished_runs() const override { return false; }
  st::ObtainedRun obtain(const st::RunRequest& request) const override {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      asked_.insert(request.id);
    }
    return inner_->obtain(request);
  }
  std::set<std::string> asked() const { return asked_; }

 private:
  std::shared_ptr<const st::RunSource> inner_;
  std::set<std::string> lacking_;
  mutable std::mutex mutex_;
  mutable std::set<std::string> asked_;
};

// A rig whose every run fails; the first repetition of each input fails last (after 0.2 s).
class FailingSource final : public st::RunSource {
 public:
  std::string kind() const override { return "failing"; }
  std::string description() const override { return "a rig that fails every run"; }
  int parallel_runs() const override { return 4; }
  bool has(const st::PlannedRun&) const override { return true; }
  bool reuse_finished_runs() const override { return false; }
  st::ObtainedRun obtain(const st::RunRequest& request) const override {
    if (request.id.ends_with("/r01")) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    throw clearshape::InvalidArgument("run " + request.id + " failed");
  }
};

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace

TEST(RunSource, ThePlanIsExactlyWhatTheStudyAsksFor) {
  const auto p = st::quick_variant(st::load_protocol(studies_path("thesis-position.toml")));
  st::StudyOptions o;
  o.out_dir = temp_dir("clearshape_run_source_plan");
  auto source = std::make_shared<CountingSource>(st::rig_run_source(o.rig, p.mode, p.sample_rate_hz), std::set<std::string>{});
  o.source = source;
  const auto result = st::run_study(p, o);
  std::set<std::string> planned;
  for (const auto& r : st::distinct_runs(p)) planned.insert(r.id);
  EXPECT_EQ(source->asked(), planned);
  EXPECT_EQ(result.results.at("rig").at("kind"), "simulated-thesis");
  EXPECT_TRUE(result.results.at("skipped_stages").empty());
  std::filesystem::remove_all(o.out_dir);
}

TEST(RunSource, MissingRunsSkipTheirStagesByName) {
  const auto p = st::quick_variant(st::load_protocol(studies_path("thesis-position.toml")));
  st::StudyOptions o;
  o.out_dir = temp_dir("clearshape_run_source_missing");
  const std::string gone = st::rig_test_run_id("B.3", "zvdd@link-mode", 2);
  auto source = std::make_shared<CountingSource>(st::rig_run_source(o.rig, p.mode, p.sample_rate_hz), std::set<std::string>{gone});
  o.source = source;
  const auto result = st::run_study(p, o);
  const auto& skipped = result.results.at("skipped_stages");
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0].at("stage"), "rig-tests");
  EXPECT_EQ(skipped[0].at("missing_runs"), nlohmann::ordered_json::array({gone}));
  EXPECT_EQ(source->asked().count(gone), 0u);
  for (const auto& id : source->asked()) EXPECT_EQ(id.rfind("unshaped/", 0), 0u) << id;  // no rig test ran
  EXPECT_NO_THROW(result.table("4.3-clearance"));
  EXPECT_THROW(result.table("B.1"), clearshape::InvalidArgument);
  std::filesystem::remove_all(o.out_dir);
}

// Runs go in parallel, yet the error a study reports is the first failing run in request order,
// not the first to fail in time (a CLI test once named r02 where it expected r01).
TEST(RunSource, TheErrorNamesTheFirstFailingRunWhateverTheTiming) {
  const auto p = st::quick_variant(st::load_protocol(studies_path("thesis-position.toml")));
  st::StudyOptions o;
  o.out_dir = temp_dir("clearshape_run_source_failing");
  o.threads = 3;
  o.source = std::make_shared<FailingSource>();
  try {
    st::run_study(p, o);
    ADD_FAILURE() << "a study on a rig that fails every run returned";
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("/r01 failed"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(o.out_dir);
}
