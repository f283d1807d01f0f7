// The built-in scara-2 (docs/arm.md), 10 s per iteration: both joints move every second between
// ±20° (shoulder) and ±30° (elbow) at the link, so both plays close, rattle and reopen all run
// long (contact in both joints). CVODE BDF with the default tolerances, 1 kHz output.
// Counters: simulated seconds per wall second, contact onsets and CVODE steps per run.
// bench/arm_peer.py times SciPy's solve_ivp on the same model; `bench_arm --trajectory=PATH`
// writes the run's trajectory (CSV) for it and exits.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "clearshape/arm/simulation.hpp"
#include "benchmark_main.hpp"

namespace arm = clearshape::arm;
namespace plant = clearshape::plant;

namespace {

constexpr double kDuration_s = 10.0;

// Link-side targets ±amplitude (degrees), one move per second from 0.5 s on, each a 0.4 s
// cosine blend (peak acceleration π²/2·A/T²: 11 rad/s² for 20°), sampled at 1 ms and
// interpolated linearly; times the gear ratio, as a Kp = 1 position drive takes motor degrees.
plant::Command moves(double amplitude_deg, double gear_ratio) {
  clearshape::UniformSeries s;
  s.sample_time_s = 1e-3;
  const int n = static_cast<int>(kDuration_s / s.sample_time_s) + 1;
  const double pattern[] = {0.0, 1.0, 0.0, -1.0};
  for (int k = 0; k < n; ++k) {
    const double t = k * s.sample_time_s;
    const int move = t < 0.5 ? 0 : static_cast<int>(t - 0.5) + 1;
    const double from = move == 0 ? 0.0 : pattern[(move - 1) % 4];
    const double to = pattern[move % 4];
    const double blend = move == 0 ? 1.0 : std::min((t - 0.5 - (move - 1)) / 0.4, 1.0);
    const double w = 0.5 - 0.5 * std::cos(std::numbers::pi * blend);
    s.values.push_back((from + (to - from) * w) * amplitude_deg * gear_ratio);
  }
  return plant::Command(s, plant::Interpolation::linear);
}

struct Run {
  arm::ArmModel model = arm::builtin_arm("scara-2");
  std::vector<plant::Command> commands;
  arm::ArmSimulationOptions options;
  Run() {
    commands = {moves(20.0, model.joints[0].gear_ratio), moves(30.0, model.joints[1].gear_ratio)};
    options.duration_s = kDuration_s;
    options.output_rate_hz = 1000.0;
  }
};

void BM_ArmScara2Moves10s(benchmark::State& state) {
  const Run run;
  long onsets = 0, steps = 0, rhs = 0;
  for (auto _ : state) {
    const arm::ArmTrace tr = arm::simulate_arm(run.model, run.commands, run.options);
    onsets = 0;
    for (const arm::ArmEvent& e : tr.events) onsets += e.onset ? 1 : 0;
    steps = tr.steps;
    rhs = tr.rhs_evaluations;
    benchmark::DoNotOptimize(tr.link_angle_rad.data());
  }
  state.counters["onsets_per_run"] = static_cast<double>(onsets);
  state.counters["steps_per_run"] = static_cast<double>(steps);
  state.counters["rhs_per_run"] = static_cast<double>(rhs);
  state.counters["real_time_factor"] =
      benchmark::Counter(kDuration_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ArmScara2Moves10s)->Unit(benchmark::kMillisecond);

void write_trajectory(const std::string& path) {
  const Run run;
  const arm::ArmTrace tr = arm::simulate_arm(run.model, run.commands, run.options);
  std::ofstream out(path);
  out.precision(17);
  out << "time_s,motor1_rad,motor2_rad,link1_rad,link2_rad,rate1_rad_s,rate2_rad_s\n";
  for (Eigen::Index k = 0; k < tr.link_angle_rad.rows(); ++k) {
    out << tr.time_s[static_cast<std::size_t>(k)] << ',' << tr.motor_angle_rad(k, 0) << ',' << tr.motor_angle_rad(k, 1)
        << ',' << tr.link_angle_rad(k, 0) << ',' << tr.link_angle_rad(k, 1) << ',' << tr.link_rate_rad_s(k, 0) << ','
        << tr.link_rate_rad_s(k, 1) << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  constexpr const char* kFlag = "--trajectory=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], kFlag, std::strlen(kFlag)) == 0) {
      write_trajectory(argv[i] + std::strlen(kFlag));
      return 0;
    }
  }
  return run_google_benchmarks(argc, argv);
}
