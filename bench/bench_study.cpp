// Wall time of the quick study and of its stages (the full studies run in `make run`; their
// stage timings are in out/<study>/timing.json). One iteration = the whole quick study from a
// fresh output folder; the stage times are reported as counters (seconds).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/runner.hpp"

namespace st = clearshape::study;

namespace {

std::filesystem::path studies_dir() {
  // The protocols are in <source>/studies; this file is <source>/bench/bench_study.cpp.
  if (std::filesystem::exists("studies/thesis-position.toml")) return "studies";
  return std::filesystem::path(__FILE__).parent_path().parent_path() / "studies";
}

void run_quick(benchmark::State& state, const std::string& protocol_file, bool quick) {
  const st::Protocol base = st::load_protocol(studies_dir() / protocol_file);
  const st::Protocol protocol = quick ? st::quick_variant(base) : base;
  const auto out = std::filesystem::temp_directory_path() / ("clearshape_bench_" + protocol.name);
  std::vector<st::StageTiming> last;
  for (auto _ : state) {
    st::StudyOptions options;
    options.out_dir = out;
    options.fresh = true;
    const st::StudyResult r = st::run_study(protocol, options);
    last = r.timing;
    benchmark::DoNotOptimize(r.results);
  }
  for (const auto& t : last) state.counters[t.stage + "_s"] = t.seconds;
  std::filesystem::remove_all(out);
}

void BM_QuickStudyPosition(benchmark::State& state) { run_quick(state, "thesis-position.toml", true); }
void BM_QuickStudySpeed(benchmark::State& state) { run_quick(state, "thesis-speed.toml", true); }
void BM_FullStudyPosition(benchmark::State& state) { run_quick(state, "thesis-position.toml", false); }
void BM_FullStudySpeed(benchmark::State& state) { run_quick(state, "thesis-speed.toml", false); }

}  // namespace

BENCHMARK(BM_QuickStudyPosition)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_QuickStudySpeed)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_FullStudyPosition)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_FullStudySpeed)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
