#pragma once
// The end of every benchmark program's main (after its own --report/--dump options): Google
// Benchmark over the remaining options; an option it does not know is exit 1.
#include <benchmark/benchmark.h>

inline int run_google_benchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
