// Simulated rig, one whole run per iteration (rig::simulate_run: command path, CVODE plant with
// the clearance joint, sensors): 10 s of the thesis position-mode step (20°, Table B.1) and a
// speed-mode step (2 V), the built-in (calibrated thesis) rig truth, 1 kHz output.
// Counters: simulated seconds per wall second (the real-time factor) and contact events per
// run. bench/simulate_peer.py compares with SciPy's solve_ivp on the same model.
// Beside them, the design loops' fixed-step path (plant/fixed_step.hpp) on the worn-coupling rig:
// four 3 s runs of the 20° step (the link at four places in the play) one after the other
// (simulate_fixed_step) and stepped together (simulate_fixed_steps) — the same responses to the bit;
// the ratio of the two times is what interleaving buys.
#include <benchmark/benchmark.h>

#include "clearshape/core/series.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/fixed_step.hpp"
#include "clearshape/rig/builtin_truths.hpp"
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

// The worn-coupling rig's plant under a 20° step at 0.5 s, 3 s, from the flank at `fraction`.
struct FixedStepCase {
  cs::plant::PlantModel model;
  cs::UniformSeries input;
  std::vector<cs::plant::FixedStepJob> jobs;
};

FixedStepCase fixed_step_case() {
  const rig::RigTruth t = rig::builtin_truth("worn-coupling");
  FixedStepCase c{rig::plant_model(t, rig::CommandMode::position), {}, {}};
  c.input.sample_time_s = 1e-3;
  for (std::size_t k = 0; k <= 3000; ++k) c.input.values.push_back(k >= 500 ? cs::deg_to_rad(20.0) : 0.0);
  for (const double fraction : {-1.0, -0.5, 0.5, 1.0}) {
    cs::plant::FixedStepOptions o;
    o.initial_relative_angle_rad = fraction * t.half_play_rad();
    c.jobs.push_back({&c.model, &c.input, o});
  }
  return c;
}

void BM_FixedStepFourRunsOneByOne(benchmark::State& state) {
  const FixedStepCase c = fixed_step_case();
  for (auto _ : state) {
    for (const auto& j : c.jobs) benchmark::DoNotOptimize(cs::plant::simulate_fixed_step(*j.model, *j.drive_input, j.options));
  }
}

void BM_FixedStepFourRunsTogether(benchmark::State& state) {
  const FixedStepCase c = fixed_step_case();
  for (auto _ : state) benchmark::DoNotOptimize(cs::plant::simulate_fixed_steps(c.jobs));
}

}  // namespace

BENCHMARK(BM_FixedStepFourRunsOneByOne)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FixedStepFourRunsTogether)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulatePositionStep20deg)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateSpeedStep2V)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
