// Simulated rig, one whole run per iteration (rig::simulate_run: command path, CVODE plant with
// the clearance joint, sensors): 10 s of the thesis position-mode step (20°, Table B.1) and a
// speed-mode step (2 V), the built-in (calibrated thesis) rig truth, 1 kHz output.
// Counters: simulated seconds per wall second (the real-time factor) and contact events per
// run. bench/simulate_peer.py compares with SciPy's solve_ivp on the same model.
#include <benchmark/benchmark.h>

#include "clearshape/core/series.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/offline.hpp"
#include "clearshape/rig/truth.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;

namespace {

constexpr double kDuration_s = 10.0;
constexpr double kStepAt_s = 0.5;

cs::UniformSeries step(double amplitude) {
  cs::UniformSeries s;
  s.sample_time_s = 1e-3;
  const std::size_t n = cs::sample_count(kDuration_s, s.sample_time_s);
  for (std::size_t k = 0; k < n; ++k) s.values.push_back(static_cast<double>(k) * 1e-3 >= kStepAt_s ? amplitude : 0.0);
  return s;
}

void run(benchmark::State& state, rig::CommandMode mode, double amplitude) {
  const rig::RigTruth truth = rig::thesis_rig_truth();
  const cs::UniformSeries command = step(amplitude);
  rig::RunOptions options;
  options.duration_s = kDuration_s;
  long events = 0;
  for (auto _ : state) {
    const rig::RunRecord record = rig::simulate_run(truth, mode, command, options);
    events = record.simulation.stats.events;
    benchmark::DoNotOptimize(record.simulation.link_angle_rad.data());
  }
  state.counters["events_per_run"] = static_cast<double>(events);
  state.counters["real_time_factor"] =
      benchmark::Counter(kDuration_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SimulatePositionStep20deg(benchmark::State& state) {
  run(state, rig::CommandMode::position, cs::deg_to_rad(20.0));
}
void BM_SimulateSpeedStep2V(benchmark::State& state) {
  run(state, rig::CommandMode::speed, 2.0);
}

}  // namespace

BENCHMARK(BM_SimulatePositionStep20deg)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateSpeedStep2V)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
