// Clearance-aware design time (study/clearance_aware.hpp; docs/worn-coupling.md, issue 19): the
// issue's design problem — 4 moves (10°, 20°, 56° low jerk, 16° + 16°) × 5 start places in the
// play × 3 model points (nominal and ±1σ corners) = 60 cases per evaluation, 6 slots of the 30 Hz
// grid (≤ 0.2 s) — on the worn-coupling rig's true model (1° play, linear flank, bearing Coulomb
// 0.01 N·m), 2 threads. Goal: under 10 s on two cores.
// Beside it, one case simulated both ways in the same run: the fixed-step path
// (plant/fixed_step.hpp) the design uses and CVODE (plant::simulate) — the ratio is the speed-up
// the design owes to the fixed-step path; bench/clearance_aware_peer.py times SciPy on the case.
// Counters: design_s, goal_ratio = design_s / 10 s (< 1 meets the goal), evaluations,
// worst_kept_pct (the worst case's shaped/unshaped MD on the model, %).
#include <benchmark/benchmark.h>

#include <chrono>

#include "clearshape/core/units.hpp"
#include "clearshape/rig/worn_coupling.hpp"
#include "clearshape/shaping/shaper.hpp"
#include "clearshape/signal/generators.hpp"
#include "clearshape/study/clearance_aware.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;
namespace sg = clearshape::signal;

namespace {

st::ClearanceModel worn_model() {
  const cs::rig::RigTruth t = cs::rig::worn_coupling_rig_truth();
  st::ClearanceModel m;
  m.mode = cs::rig::CommandMode::position;
  m.drive = cs::lti::thesis_position_mode_model();
  m.link_inertia_kg_m2 = t.link.inertia_kg_m2;
  m.play_rad = t.clearance_rad;
  m.stiffness = t.position_contact.stiffness;
  m.exponent = 1.0;
  m.damping = t.position_contact.damping;
  m.coulomb_n_m = t.joint_friction.coulomb;
  m.viscous_n_m_s_per_rad = t.joint_friction.viscous;
  return m;
}

st::ClearanceAwareRequest request() {
  st::ClearanceAwareRequest r;
  r.model = worn_model();
  const auto add = [&](const char* name, const sg::Signal& s) {
    r.profiles.push_back(*st::design_move(name, s, 1000.0, 3.0, 1.0 / 30.0));  // cut on the 30 Hz update grid
  };
  add("step-10", sg::Step{10.0, 0.5});
  add("step-20", sg::Step{20.0, 0.5});
  add("step-56-low-jerk", sg::Step{56.0, 0.5, 0.1});
  add("double-step-16", sg::DoubleStep{16.0, 0.5, 16.0, 1.0});
  r.uncertainty = st::uncertainty_set(0.05, 0.05, 0.15);
  r.max_duration_s = 0.2;
  r.max_evaluations = 300;
  r.threads = 2;
  return r;
}

void BM_ClearanceAwareDesign4Moves5Starts3Points(benchmark::State& state) {
  const st::ClearanceAwareRequest r = request();
  st::ClearanceAwareResult result;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto begin = std::chrono::steady_clock::now();
    result = st::design_clearance_aware(r);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    benchmark::DoNotOptimize(result.worst_md_deg);
  }
  state.counters["design_s"] = seconds;
  state.counters["goal_ratio"] = seconds / 10.0;
  state.counters["evaluations"] = result.evaluations;
  state.counters["worst_kept_pct"] = 100.0 * result.worst_ratio;
}

// One design case (20°, the link on the rear flank): the design's fixed-step path vs CVODE.
void simulate_case(benchmark::State& state, bool fixed_step) {
  const st::ClearanceAwareRequest r = request();
  const st::DesignMove move = r.profiles.at(1);
  const double duration_s = static_cast<double>(move.command.values.size() - 1) * 1e-3 + r.max_duration_s + r.settle_s;
  cs::UniformSeries command = move.command;
  command.values.resize(static_cast<std::size_t>(duration_s * 1000.0) + 1, command.values.back());
  for (auto _ : state) {
    const auto response = st::simulate_command(r.model, command, duration_s, -1.0, fixed_step);
    benchmark::DoNotOptimize(response.link_angle_deg.back());
  }
}

void BM_DesignCaseFixedStep(benchmark::State& state) { simulate_case(state, true); }
void BM_DesignCaseCvode(benchmark::State& state) { simulate_case(state, false); }

}  // namespace

BENCHMARK(BM_ClearanceAwareDesign4Moves5Starts3Points)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_DesignCaseFixedStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DesignCaseCvode)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
