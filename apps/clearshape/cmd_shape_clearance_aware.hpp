#pragma once
// `clearshape shape --method clearance-aware --model FIT.json --moves 5,10,20`: a positive shaper
// optimized on the identified nonlinear model (study/clearance_aware.hpp; docs/large-play.md), and
// `--method take-up` (study/take_up.hpp), designed on the same model with the same options.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include "clearshape/study/clearance_model_json.hpp"
#include "clearshape/shaping/shaper.hpp"

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

/// The model file of --model (and --moves given) for a model-designed `method`; throws
/// InvalidArgument naming the missing option, InputError on a bad file.
study::IdentifiedClearanceModel read_design_model(const ClearanceAwareOptions& options, const std::string& method);
/// The longest shaper: --max-duration-s, else ZVDD's duration for --frequency-hz/--zeta
/// (`frequency_hz` > 0), else for the model file's link mode; `source` says which.
double design_duration_bound(const ClearanceAwareOptions& options, const study::IdentifiedClearanceModel& identified,
                             double frequency_hz, double zeta, const std::string& method, std::string& source);

/// One impulse of `shape --json`: {"time_s", "amplitude"} (schema 1 wrote `t`/`a` beside them;
/// docs/cli.md, `shape --json`).
nlohmann::ordered_json impulse_json(double time_s, double amplitude);
/// A shaper's impulses as a list of impulse_json.
nlohmann::ordered_json impulses_json(const shaping::Shaper& shaper);
/// `units` of the impulses (`amplitude_unit` for the amplitude).
nlohmann::ordered_json impulse_units_json(const std::string& amplitude_unit);
/// `shape --method custom --impulses` text of a shaper: "t1:a1,t2:a2,…".
std::string custom_impulses_argument(const shaping::Shaper& shaper);
/// The head of a model-designed shaper's --json document: command, method, model file, moves,
/// the duration bound and its source.
nlohmann::ordered_json design_document(const ClearanceAwareOptions& options, const std::string& method,
                                       double max_duration_s, const std::string& bound_source);

/// `shape --method take-up` (study/take_up.hpp): one profile per --moves amplitude, within the
/// same duration bound; --max-evaluations and --threads do not apply (a closed form, no search).
void run_take_up(const ClearanceAwareOptions& options, double frequency_hz, double zeta, bool json);

}  // namespace clearshape::cli
