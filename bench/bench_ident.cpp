// Identification benchmarks: the thesis P3UZ model (Eq. 4.2, speed mode) on 5 s records at 1 kHz
// (5001 samples each, 1 % noise), one experiment (PRBS) and four (step, ramp, sine, PRBS):
//   BM_FitP3UZ/experiments:N     the full procest-like fit (candidates ranked + multi-start LM)
//   BM_RefineP3UZ/experiments:N  one Levenberg–Marquardt run from the truth × 1.15 (the problem
//                                bench/ident_peer.py gives scipy.optimize.least_squares)
//   BM_FreeDecayModes            two modes of a 2.5 s gyro free decay (ERA + LS)
//
//   bench_ident [google-benchmark flags]
//   bench_ident --dump=PREFIX    writes PREFIX_u<e>.f64 / PREFIX_y<e>.f64 (raw little-endian
//                                doubles) for e = 0..3 and PREFIX_fit<N>.json (our refined
//                                parameters) for the peer script, then exits
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/lti/simulate.hpp"
#include "benchmark_main.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;

namespace {

constexpr double kDt = 1e-3;
constexpr std::size_t kSamples = 5001;  // 5 s at 1 kHz (thesis Eq. 4.1 note)

std::vector<double> input(int kind) {
  std::vector<double> u(kSamples);
  std::mt19937_64 rng(77);
  double level = 1.0;
  for (std::size_t k = 0; k < kSamples; ++k) {
    const double t = static_cast<double>(k) * kDt;
    switch (kind) {
      case 0:  // PRBS, 20 ms hold
        if (k % 20 == 0 && (rng() & 1U)) level = -level;
        u[k] = level;
        break;
      case 1: u[k] = 1.0; break;                                    // step
      case 2: u[k] = 0.4 * t; break;                                // ramp
      default: u[k] = std::sin(2.0 * 3.141592653589793 * 2.0 * t);  // sine 2 Hz
    }
  }
  return u;
}

// Runs of the speed-mode model with 1 % white noise (seeded): PRBS first.
std::vector<ident::Experiment> experiments(int count) {
  const auto model = lti::thesis_speed_mode_model();
  std::vector<ident::Experiment> out;
  for (int e = 0; e < count; ++e) {
    const auto u = input(e == 0 ? 0 : e);
    auto y = lti::simulate(model, clearshape::UniformSeries{0.0, kDt, u}).values;
    double rms = 0.0;
    for (double v : y) rms += v * v;
    rms = std::sqrt(rms / static_cast<double>(y.size()));
    std::mt19937_64 rng(100 + static_cast<std::uint64_t>(e));
    std::normal_distribution<double> nd;
    for (double& v : y) v += 0.01 * rms * nd(rng);
    out.push_back({"run" + std::to_string(e), kDt, u, y});
  }
  return out;
}

ident::ProcessFitOptions refine_options() {
  ident::ProcessFitOptions o;
  o.search = false;
  o.initial_state = ident::InitialState::zero;
  const auto truth = lti::thesis_speed_mode_model();
  for (auto name : truth.structure().parameter_names()) {
    o.parameters[std::string(name)].initial = 1.15 * truth.parameters().get(name);
  }
  return o;
}

void BM_FitP3UZ(benchmark::State& state) {
  const auto data = experiments(static_cast<int>(state.range(0)));
  const auto structure = lti::thesis_speed_mode_model().structure();
  for (auto _ : state) {
    auto est = ident::estimate_process_model(structure, data);
    benchmark::DoNotOptimize(est);
  }
}
BENCHMARK(BM_FitP3UZ)->ArgName("experiments")->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_RefineP3UZ(benchmark::State& state) {
  const auto data = experiments(static_cast<int>(state.range(0)));
  const auto structure = lti::thesis_speed_mode_model().structure();
  const auto options = refine_options();
  for (auto _ : state) {
    auto est = ident::estimate_process_model(structure, data, options);
    benchmark::DoNotOptimize(est);
  }
}
BENCHMARK(BM_RefineP3UZ)->ArgName("experiments")->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_FreeDecayModes(benchmark::State& state) {
  clearshape::UniformSeries y{0.0, kDt, std::vector<double>(2500)};
  std::mt19937_64 rng(5);
  std::normal_distribution<double> nd;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double t = static_cast<double>(k) * kDt;
    y.values[k] = 0.3 + 40 * std::exp(-0.03 * 38.96 * t) * std::cos(38.94 * t + 0.4) +
                  15 * std::exp(-0.012 * 109.96 * t) * std::cos(109.95 * t - 1.0) + 2.0 * nd(rng);
  }
  ident::ModeOptions o;
  o.modes = 2;
  for (auto _ : state) {
    auto r = ident::identify_free_response_modes(y, o);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_FreeDecayModes)->Unit(benchmark::kMillisecond);

void write_f64(const std::string& path, const std::vector<double>& v) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(double)));
}

int dump(const std::string& prefix) {
  const auto data = experiments(4);
  for (std::size_t e = 0; e < data.size(); ++e) {
    write_f64(prefix + "_u" + std::to_string(e) + ".f64", data[e].input);
    write_f64(prefix + "_y" + std::to_string(e) + ".f64", data[e].output);
  }
  const auto structure = lti::thesis_speed_mode_model().structure();
  for (int count : {1, 4}) {
    const auto est = ident::estimate_process_model(structure, std::span(data).first(static_cast<std::size_t>(count)),
                                                   refine_options());
    std::ofstream f(prefix + "_fit" + std::to_string(count) + ".json");
    f.precision(17);
    f << "{";
    for (std::size_t i = 0; i < est.parameters.size(); ++i) {
      f << (i ? ", " : "") << "\"" << est.parameters[i].name << "\": " << est.parameters[i].value;
    }
    f << ", \"weighted_cost\": " << est.weighted_cost << "}\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a.rfind("--dump=", 0) == 0) return dump(std::string(a.substr(7)));
  }
  return run_google_benchmarks(argc, argv);
}
