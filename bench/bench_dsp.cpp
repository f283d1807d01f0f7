// dsp benchmarks: the thesis speed filter (4th-order Butterworth, 30 rad/s, 1 kHz) per sample in
// real time, causal and zero-phase filtering of a 10^6-sample signal, Butterworth design, and a
// Welch PSD. bench/dsp_peer.py times scipy.signal on the same work and prints the ratios.
//
//   bench_dsp [google-benchmark flags]
//   bench_dsp --dump=PREFIX   writes PREFIX_{input,sosfilt,sosfiltfilt,welch}.f64 (raw
//                             little-endian doubles) for the peer script's agreement check
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "clearshape/dsp/butterworth.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/dsp/welch.hpp"
#include "benchmark_main.hpp"

namespace dsp = clearshape::dsp;

namespace {

constexpr std::size_t kSamples = 1000000;
constexpr std::size_t kWelchSegment = 1024;

// Deterministic test signal: two sines and a staircase (no RNG needed to reproduce).
std::vector<double> test_signal(std::size_t n) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * 1e-3;
    u[k] = std::sin(2.0 * std::numbers::pi * 0.37 * t) + 0.2 * std::sin(2.0 * std::numbers::pi * 91.0 * t) +
           static_cast<double>((k / 1234) % 5);
  }
  return u;
}

dsp::WelchOptions welch_options() {
  dsp::WelchOptions o;
  o.segment_length = kWelchSegment;
  return o;
}

void BM_StreamingStep(benchmark::State& state) {
  dsp::StreamingSosFilter filter(dsp::thesis_speed_filter(1e-3));
  const std::vector<double> input = test_signal(4096);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(filter.step(input[k]));
    k = (k + 1) & 4095;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StreamingStep);

void BM_Sosfilt(benchmark::State& state) {
  const auto design = dsp::thesis_speed_filter(1e-3);
  const std::vector<double> input = test_signal(kSamples);
  for (auto _ : state) benchmark::DoNotOptimize(dsp::sosfilt(design, input).data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSamples));
}
BENCHMARK(BM_Sosfilt)->Unit(benchmark::kMillisecond);

void BM_Sosfiltfilt(benchmark::State& state) {
  const auto design = dsp::thesis_speed_filter(1e-3);
  const std::vector<double> input = test_signal(kSamples);
  for (auto _ : state) benchmark::DoNotOptimize(dsp::sosfiltfilt(design, input).data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSamples));
}
BENCHMARK(BM_Sosfiltfilt)->Unit(benchmark::kMillisecond);

void BM_ButterDesign(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(dsp::butter_lowpass(order, 4.77, 1000.0));
}
BENCHMARK(BM_ButterDesign)->Arg(4)->Arg(16)->Unit(benchmark::kMicrosecond);

void BM_Welch(benchmark::State& state) {
  const std::vector<double> input = test_signal(kSamples);
  for (auto _ : state) benchmark::DoNotOptimize(dsp::welch(input, 1000.0, welch_options()).power.data());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kSamples));
}
BENCHMARK(BM_Welch)->Unit(benchmark::kMillisecond);

bool write_f64(const std::string& path, const std::vector<double>& v) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(v.data(), sizeof(double), v.size(), f) == v.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with("--dump=")) {
      const std::string prefix(arg.substr(7));
      const auto design = dsp::thesis_speed_filter(1e-3);
      const auto input = test_signal(kSamples);
      const bool ok = write_f64(prefix + "_input.f64", input) &&
                      write_f64(prefix + "_sosfilt.f64", dsp::sosfilt(design, input)) &&
                      write_f64(prefix + "_sosfiltfilt.f64", dsp::sosfiltfilt(design, input)) &&
                      write_f64(prefix + "_welch.f64", dsp::welch(input, 1000.0, welch_options()).power);
      return ok ? 0 : 1;
    }
  }
  return run_google_benchmarks(argc, argv);
}
