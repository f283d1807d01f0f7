#pragma once
// `clearshape shape --method clearance-aware --model FIT.json --moves 5,10,20`: a positive shaper
// optimized on the identified nonlinear model (study/clearance_aware.hpp; docs/large-play.md).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace clearshape::cli {

struct ClearanceAwareOptions {
  std::string model;
  std::vector<double> moves;
  double max_duration_s = 0.0;
  int max_evaluations = 80;
  int threads = 0;
  CLI::Option* model_option = nullptr;
  CLI::Option* moves_option = nullptr;
  CLI::Option* max_duration_option = nullptr;
  CLI::Option* max_evaluations_option = nullptr;
  CLI::Option* threads_option = nullptr;
};

/// Adds --model, --moves, --max-duration-s, --max-evaluations, --threads to `shape`.
void add_clearance_aware_options(CLI::App& sub, ClearanceAwareOptions& options);
/// True if any of them was given (they need --method clearance-aware).
bool clearance_aware_options_given(const ClearanceAwareOptions& options);
/// Designs and prints (table, or JSON with `json`). The duration bound: --max-duration-s, else
/// the ZVDD duration of --frequency-hz/--zeta (`frequency_hz` > 0), else of the model file's
/// link mode. Throws InvalidArgument/InputError on bad input.
void run_clearance_aware(const ClearanceAwareOptions& options, double frequency_hz, double zeta, bool json);

}  // namespace clearshape::cli
