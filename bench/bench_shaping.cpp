// Shaping benchmarks: StreamingShaper ns/sample (mean, and per-call p50/p99.9/max), and offline
// shaping of a 10^6-sample signal. bench/shaping_peer.py compares the offline case with
// numpy.convolve / scipy.signal.lfilter on the same signal and shaper.
//
//   bench_shaping [google-benchmark flags]
//   bench_shaping --dump-offline=PREFIX   writes PREFIX_input.f64 and PREFIX_output.f64 (raw
//                                         little-endian doubles) for the peer script, then exits
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "clearshape/core/series.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/streaming.hpp"
#include "benchmark_main.hpp"

namespace sh = clearshape::shaping;

namespace {

constexpr double kSampleTimeS = 1e-3;           // 1 kHz servo loop (thesis §4 logging rate)
constexpr std::size_t kOfflineSamples = 1000000;

// ZV family with `impulses` impulses (Singer & Seering 1990): C(n,k)·K^k/(1+K)^n at k·π/ωd;
// 10 Hz, ζ = 0.1, so at 1 ms every impulse after the first falls between samples (2n−1 taps).
sh::Shaper zv_family(int impulses) {
  const sh::Mode mode = sh::Mode::from_hz(10.0, 0.1);
  const double zeta = mode.damping_ratio;
  const double k = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
  const int n = impulses - 1;
  std::vector<sh::Impulse> list;
  double binomial = 1.0;
  for (int i = 0; i <= n; ++i) {
    list.push_back({i * std::numbers::pi / mode.damped_frequency_rad_s(), binomial * std::pow(k, i)});
    binomial = binomial * (n - i) / (i + 1);
  }
  return sh::Shaper("zv" + std::string(static_cast<std::size_t>(n - 1), 'd'), list);
}

// A deterministic test command: a sine plus a staircase of steps (no RNG needed to reproduce).
std::vector<double> test_signal(std::size_t n) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * kSampleTimeS;
    u[k] = std::sin(2.0 * std::numbers::pi * 0.37 * t) + static_cast<double>((k / 1234) % 5);
  }
  return u;
}

void BM_StreamingStep(benchmark::State& state) {
  const int impulses = static_cast<int>(state.range(0));
  sh::StreamingShaper shaper(zv_family(impulses), kSampleTimeS);
  const std::vector<double> input = test_signal(4096);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(shaper.step(input[k]));
    k = (k + 1) & 4095;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["taps"] = static_cast<double>(shaper.tap_count());
}
BENCHMARK(BM_StreamingStep)->DenseRange(2, 5)->ArgName("impulses");

// Worst case: every call timed on its own (steady_clock) over 10^6 samples. The counters
// include the clock's own cost, reported as clock_overhead_ns (median of an empty timing);
// calls_over_1us counts calls hit by preemption or interrupts (the max is usually one of them).
void BM_StreamingStepLatency(benchmark::State& state) {
  constexpr std::size_t kCalls = 1000000;
  using Clock = std::chrono::steady_clock;
  const int impulses = static_cast<int>(state.range(0));
  sh::StreamingShaper shaper(zv_family(impulses), kSampleTimeS);
  const std::vector<double> input = test_signal(4096);
  std::vector<double> call_ns(kCalls), empty_ns(kCalls);
  for (auto _ : state) {
    for (std::size_t k = 0; k < kCalls; ++k) {
      const auto t0 = Clock::now();
      benchmark::DoNotOptimize(shaper.step(input[k & 4095]));
      const auto t1 = Clock::now();
      call_ns[k] = std::chrono::duration<double, std::nano>(t1 - t0).count();
    }
    for (std::size_t k = 0; k < kCalls; ++k) {
      const auto t0 = Clock::now();
      benchmark::ClobberMemory();
      const auto t1 = Clock::now();
      empty_ns[k] = std::chrono::duration<double, std::nano>(t1 - t0).count();
    }
  }
  auto quantile = [](std::vector<double>& v, double q) {
    const auto idx = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(idx), v.end());
    return v[idx];
  };
  state.counters["call_p50_ns"] = quantile(call_ns, 0.5);
  state.counters["call_p99.9_ns"] = quantile(call_ns, 0.999);
  state.counters["call_max_ns"] = *std::max_element(call_ns.begin(), call_ns.end());
  state.counters["calls_over_1us"] =
      static_cast<double>(std::count_if(call_ns.begin(), call_ns.end(), [](double t) { return t > 1e3; }));
  state.counters["clock_overhead_ns"] = quantile(empty_ns, 0.5);
  state.counters["taps"] = static_cast<double>(shaper.tap_count());
}
BENCHMARK(BM_StreamingStepLatency)->DenseRange(2, 5)->ArgName("impulses")->Iterations(1)
    ->Unit(benchmark::kMillisecond);

void BM_ShapeOffline(benchmark::State& state) {
  const sh::Shaper shaper = zv_family(static_cast<int>(state.range(0)));
  const clearshape::UniformSeries input{0.0, kSampleTimeS, test_signal(kOfflineSamples)};
  for (auto _ : state) {
    clearshape::UniformSeries y = sh::shape_offline(shaper, input);
    benchmark::DoNotOptimize(y.values.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kOfflineSamples));
}
BENCHMARK(BM_ShapeOffline)->DenseRange(2, 5)->ArgName("impulses")->Unit(benchmark::kMillisecond);

bool write_doubles(const std::string& path, const std::vector<double>& v) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(v.data(), sizeof(double), v.size(), f) == v.size();
  return std::fclose(f) == 0 && ok;
}

// The offline case's input and ZVD-shaped output, for bench/shaping_peer.py to check against.
int dump_offline(const std::string& prefix) {
  const clearshape::UniformSeries input{0.0, kSampleTimeS, test_signal(kOfflineSamples)};
  const clearshape::UniformSeries y = sh::shape_offline(zv_family(3), input);
  if (!write_doubles(prefix + "_input.f64", input.values) ||
      !write_doubles(prefix + "_output.f64", y.values)) {
    std::fprintf(stderr, "bench_shaping: cannot write %s_*.f64\n", prefix.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  constexpr std::string_view kDump = "--dump-offline=";
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with(kDump)) return dump_offline(std::string(arg.substr(kDump.size())));
  }
  return run_google_benchmarks(argc, argv);
}
