// clearshape identify: fit a MATLAB-style process model (thesis §4.2, Eq. 4.2: P3UZ) to one or
// several recorded runs by simulation error, with parameter uncertainties, ωn = 1/Tw and ζ = Zeta;
// with --crossval, the thesis's cross-validation over input types (each run identified alone,
// simulated on every other, the matrix of fits and the best model).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/butterworth.hpp"
#include "clearshape/dsp/differentiate.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/ident/cross_validation.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/trust.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "command.hpp"
#include "identify_residuals.hpp"
#include "io_columns.hpp"

namespace clearshape::cli {

namespace {

struct IdentifyState {
  std::string model = "P3UZ";
  std::vector<std::string> data;
  std::string input_column, output_column, time_column;
  double sample_time_s = 0.0;
  CLI::Option* sample_time_option = nullptr;
  std::vector<std::string> fix, initial, bound;
  std::string initial_state = "auto";
  std::string hold = "zoh";
  bool output_offset = false;
  bool input_offset = false;
  double max_delay_s = 0.0;
  std::size_t starts = 3;
  bool crossval = false;
  bool json = false;
  std::string simulated_csv;
  double from_s = 0.0;      ///< window start, s from the record's first sample
  double to_s = 0.0;        ///< window end, s (0 = the end of the record)
  bool derivative = false;  ///< differentiate the output (backward difference)
  std::string butterworth;  ///< low-pass the output: 4th-order Butterworth, "30rad/s" or "5Hz"
  std::size_t resid_lags = 25;     ///< residual tests: lags M (MATLAB resid's default)
  double resid_confidence = 0.99;  ///< residual tests: confidence of the bands and verdicts
  mutable std::string output_name;  ///< the output column's name, set by load (guard rails)
  mutable std::string input_name;
  mutable double sample_time_used_s = 0.0;  ///< the largest sample time of the runs (aliasing check)
};

// --from-s/--to-s: keep [from, to) of the record (after the derivative and the filter, so the
// filter has settled on the part before the window).
void cut_window(ident::Experiment& e, const IdentifyState& st, const std::string& path) {
  if (st.from_s == 0.0 && st.to_s == 0.0) return;
  const std::size_t n = e.output.size();
  const auto from = static_cast<std::size_t>(std::llround(std::max(0.0, st.from_s) / e.sample_time_s));
  const std::size_t end = st.to_s > 0.0 ? static_cast<std::size_t>(std::llround(st.to_s / e.sample_time_s)) : n;
  if (!(from < end && end <= n)) {
    throw InvalidArgument(fmt::format("identify: window --from-s {} --to-s {} is outside {} ({} s long)", st.from_s, st.to_s, path,
                                      e.sample_time_s * static_cast<double>(n)));
  }
  const auto a = static_cast<std::ptrdiff_t>(from), b = static_cast<std::ptrdiff_t>(end);
  e.input = std::vector<double>(e.input.begin() + a, e.input.begin() + b);
  e.output = std::vector<double>(e.output.begin() + a, e.output.begin() + b);
}

// The number `text` starts with (std::stod); `used` = the characters it took, 0 when none.
double leading_number(const std::string& text, std::size_t& used) {
  used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  return v;
}

// "30rad/s" or "5Hz" → rad/s.
double parse_cutoff_rad_s(const std::string& text) {
  std::size_t used = 0;
  const double v = leading_number(text, used);
  const std::string unit = lower(text.substr(used));
  if (used == 0 || !(v > 0.0) || (unit != "rad/s" && unit != "hz")) {
    throw InvalidArgument(fmt::format("--butterworth '{}': expected a cutoff > 0 with its unit, e.g. 30rad/s or 5Hz", text));
  }
  return unit == "hz" ? 2.0 * kPi * v : v;
}

ident::Experiment load(const std::string& path, const IdentifyState& st) {
  const io::Table t = io::read_table(path);
  const bool have_ts = st.sample_time_option != nullptr && st.sample_time_option->count() > 0;
  const IoColumns c = choose_io_columns(t, st.input_column, st.output_column, st.time_column, have_ts, true);
  ident::Experiment e;
  e.name = std::filesystem::path(path).stem().string();
  if (c.time) {
    e.sample_time_s = io::uniform_sample_time(t, t.names[*c.time]);
  } else if (have_ts) {
    require_positive("--sample-time", st.sample_time_s, "Give the sample time of the records in seconds.");
    e.sample_time_s = st.sample_time_s;
  } else {
    throw InputError(path, 0, "", "has no time column (time_s, time or t); process models are continuous-time, so "
                                  "give --time-column NAME or --sample-time SECONDS");
  }
  e.input = t.columns[c.input];
  e.output = t.columns[c.output];
  st.input_name = t.names[c.input];
  st.output_name = t.names[c.output];
  st.sample_time_used_s = std::max(st.sample_time_used_s, e.sample_time_s);
  // Say which columns were used (the defaults guess: command…/input…/u…, then the next column).
  fmt::print(stderr, "clearshape identify: {}: {}\n", path, describe_io_columns(t, c, e.sample_time_s));
  refuse_converted_copy(t, c, e.sample_time_s, "identify");
  if (st.derivative) e.output = dsp::backward_difference(e.output, e.sample_time_s);
  if (!st.butterworth.empty()) {
    e.output = dsp::sosfilt(dsp::butter_lowpass_rad_s(4, parse_cutoff_rad_s(st.butterworth), 1.0 / e.sample_time_s), e.output);
  }
  cut_window(e, st, path);
  return e;
}

// The guard rails (ident/trust.hpp) plus one only the command sees: a speed-mode model (input
// in V) fitted to an angle (output in deg, rad or counts) — the study fits the speed instead.
std::vector<std::string> identify_warnings(const ident::ProcessEstimate& est, const IdentifyState& st) {
  ident::TrustOptions trust;
  trust.sample_time_s = st.sample_time_used_s;
  auto w = ident::assess(est, trust).warnings;
  const auto ends = [](const std::string& s, const char* tail) {
    const std::string t = tail;
    return s.size() >= t.size() && lower(s).compare(s.size() - t.size(), t.size(), t) == 0;
  };
  const bool speed_input = ends(st.input_name, "_v");
  const bool angle_output = ends(st.output_name, "_deg") || ends(st.output_name, "_rad") || ends(st.output_name, "counts");
  if (speed_input && angle_output && !st.derivative) {
    w.push_back(fmt::format("a speed-mode model (input '{}' in V) is fitted to an angle ('{}'): fit the speed "
                            "instead, e.g. --derivative --butterworth 30rad/s (the thesis's §3.3 chain)",
                            st.input_name, st.output_name));
  }
  return w;
}

void report_warnings(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) fmt::print(stderr, "clearshape identify: warning: {}\n", w);
  if (!warnings.empty()) fmt::print(stderr, "clearshape identify: the model is NOT to be trusted (\"trusted\": false)\n");
}

double parse_value(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  const double v = leading_number(text, used);
  if (used != text.size() || !std::isfinite(v)) {
    throw InvalidArgument(fmt::format("{}: '{}' is not a finite number", option, text));
  }
  return v;
}

std::pair<std::string, std::string> split_assignment(const std::string& text, const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InvalidArgument(fmt::format("{} '{}': expected NAME=VALUE, e.g. {} Tz=-0.04", option, text, option));
  }
  return {text.substr(0, eq), text.substr(eq + 1)};
}

ident::ProcessFitOptions fit_options(const IdentifyState& st) {
  ident::ProcessFitOptions o;
  const std::string ic = lower(st.initial_state);
  if (ic == "zero") {
    o.initial_state = ident::InitialState::zero;
  } else if (ic == "estimate") {
    o.initial_state = ident::InitialState::estimate;
  } else if (ic == "auto") {
    o.initial_state = ident::InitialState::automatic;
  } else {
    throw InvalidArgument(fmt::format("--initial-state = '{}' is not valid; allowed: auto, zero, estimate", st.initial_state));
  }
  const std::string hold = lower(st.hold);
  if (hold == "zoh") {
    o.hold = lti::Hold::zoh;
  } else if (hold == "foh") {
    o.hold = lti::Hold::foh;
  } else {
    throw InvalidArgument(fmt::format("--hold = '{}' is not valid; allowed: zoh, foh", st.hold));
  }
  o.estimate_output_offset = st.output_offset;
  o.estimate_input_offset = st.input_offset;
  if (st.max_delay_s != 0.0) require_positive("--max-delay", st.max_delay_s);
  o.max_delay_s = st.max_delay_s;
  if (st.starts < 1) throw_invalid("--starts", 0.0, ">= 1");
  o.starts = st.starts;
  for (const auto& f : st.fix) {
    const auto [name, value] = split_assignment(f, "--fix");
    o.parameters[name].fixed = parse_value(value, "--fix " + name);
  }
  for (const auto& f : st.initial) {
    const auto [name, value] = split_assignment(f, "--initial");
    o.parameters[name].initial = parse_value(value, "--initial " + name);
  }
  for (const auto& f : st.bound) {
    const auto [name, range] = split_assignment(f, "--bound");
    const auto colon = range.find(':');
    if (colon == std::string::npos) {
      throw InvalidArgument(fmt::format("--bound '{}': expected NAME=LOW:HIGH (either side may be empty)", f));
    }
    const std::string lo = range.substr(0, colon), hi = range.substr(colon + 1);
    if (!lo.empty()) o.parameters[name].lower = parse_value(lo, "--bound " + name);
    if (!hi.empty()) o.parameters[name].upper = parse_value(hi, "--bound " + name);
  }
  return o;
}

std::string unit_of(const std::string& name) {
  if (name == "Kp") return "output units per command unit";
  if (name == "Zeta") return "1";
  return "s";
}

nlohmann::ordered_json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

// `model` is the structure as the user wrote it (upper case: "P3UZ", the thesis's spelling);
// model_canonical is lti's letter order ("P3ZU").
nlohmann::ordered_json estimate_json(const ident::ProcessEstimate& est, const std::vector<std::string>& files,
                                     const std::string& model) {
  nlohmann::ordered_json j;
  j["model"] = model;
  j["model_canonical"] = est.model.code();
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& p : est.parameters) {
    params[p.name] = {{"value", p.value}, {"std", number_or_null(p.std_dev)}, {"fixed", p.fixed}, {"unit", unit_of(p.name)}};
  }
  j["parameters"] = params;
  j["fit_percent"] = est.fit_percent();
  if (est.natural_frequency_rad_s()) {
    j["wn_rad_s"] = *est.natural_frequency_rad_s();
    j["wn_std_rad_s"] = number_or_null(*est.natural_frequency_std_rad_s());
    j["natural_frequency_hz"] = rad_s_to_hz(*est.natural_frequency_rad_s());
    j["zeta"] = *est.damping_ratio();
    j["zeta_std"] = number_or_null(*est.damping_ratio_std());
  } else {
    j["wn_rad_s"] = nullptr;
    j["zeta"] = nullptr;
  }
  nlohmann::ordered_json zeros = nlohmann::ordered_json::array();
  for (const auto& z : est.model.zeros()) zeros.push_back({{"re", z.real()}, {"im", z.imag()}});
  nlohmann::ordered_json poles = nlohmann::ordered_json::array();
  for (const auto& p : est.model.poles()) poles.push_back({{"re", p.real()}, {"im", p.imag()}});
  j["poles_rad_s"] = poles;
  j["zeros_rad_s"] = zeros;
  j["loss"] = est.loss;
  j["fpe"] = est.fpe;
  j["aic"] = est.aic;
  j["bic"] = est.bic;
  j["samples"] = est.samples;
  j["free_parameters"] = est.free_parameters;
  j["converged"] = est.converged;
  j["iterations"] = est.iterations;
  j["candidates"] = est.candidates;
  nlohmann::ordered_json exps = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < est.experiments.size(); ++i) {
    const auto& e = est.experiments[i];
    nlohmann::ordered_json x0 = nlohmann::ordered_json::array();
    for (Eigen::Index k = 0; k < e.initial_state.size(); ++k) x0.push_back(e.initial_state(k));
    exps.push_back({{"name", e.name},
                    {"file", i < files.size() ? files[i] : ""},
                    {"samples", e.simulated.size()},
                    {"sample_time_s", e.simulated.sample_time_s},
                    {"fit_percent", e.fit_percent},
                    {"fit_percent_zero_ic", e.fit_percent_zero_ic},
                    {"fit_percent_estimated_ic", e.fit_percent_estimated_ic},
                    {"rmse", e.rmse},
                    {"output_offset", e.output_offset},
                    {"input_offset", e.input_offset},
                    {"initial_state", x0}});
  }
  j["experiments"] = exps;
  return j;
}

void print_estimate(const ident::ProcessEstimate& est, const std::string& model) {
  fmt::print("model {}: {} experiment(s), {} samples; {} candidates ranked, {} LM iterations, {}\n\n",
             model, est.experiments.size(), est.samples, est.candidates, est.iterations,
             est.converged ? "converged" : "NOT converged (iteration limit)");
  fmt::print("  {:<6} {:>14} {:>12}  {}\n", "param", "value", "std", "unit");
  for (const auto& p : est.parameters) {
    const std::string sd = p.fixed ? "fixed" : (std::isfinite(p.std_dev) ? fmt::format("{:.4g}", p.std_dev) : "n/a");
    fmt::print("  {:<6} {:>14.7g} {:>12}  {}\n", p.name, p.value, sd, unit_of(p.name));
  }
  if (est.natural_frequency_rad_s()) {
    fmt::print("\n  wn = 1/Tw  {:.6g} rad/s ({:.6g} Hz), std {:.3g} rad/s\n", *est.natural_frequency_rad_s(),
               rad_s_to_hz(*est.natural_frequency_rad_s()), *est.natural_frequency_std_rad_s());
    fmt::print("  zeta       {:.6g}, std {:.3g}\n", *est.damping_ratio(), *est.damping_ratio_std());
  }
  fmt::print("\n  {:<20} {:>9} {:>12} {:>14} {:>12}\n", "experiment", "fit %", "fit % x0=0", "fit % x0 est.", "RMSE");
  for (const auto& e : est.experiments) {
    fmt::print("  {:<20} {:>9.3f} {:>12.3f} {:>14.3f} {:>12.5g}\n", e.name, e.fit_percent, e.fit_percent_zero_ic,
               e.fit_percent_estimated_ic, e.rmse);
  }
  fmt::print("\n  loss V {:.6g}, FPE {:.6g}, AIC {:.6g}, BIC {:.6g} (p = {}, N = {})\n", est.loss, est.fpe, est.aic,
             est.bic, est.free_parameters, est.samples);
}

void write_simulated(const std::string& path, const ident::Experiment& e, const ident::ExperimentFit& f) {
  const std::vector<double> time = f.simulated.times_s();
  io::write_csv(path, {"time_s", "input", "measured", "simulated"}, {&time, &e.input, &e.output, &f.simulated.values});
  fmt::print(stderr, "clearshape identify: wrote {} ({} rows)\n", path, time.size());
}

// --- plan: the structure, the runs and the fit options ------------------------------------------

struct IdentifyPlan {
  lti::ProcessStructure structure;
  std::string model;  ///< as the user wrote it, upper case ("P3UZ", the thesis's spelling)
  std::vector<ident::Experiment> experiments;
  ident::ProcessFitOptions options;
};

IdentifyPlan plan(const IdentifyState& st) {
  if (st.data.empty()) throw InvalidArgument("identify: give at least one --data FILE");
  lti::ProcessStructure structure = lti::ProcessStructure::parse(st.model);
  std::string model = st.model;
  for (char& c : model) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::vector<ident::Experiment> experiments;
  for (const auto& path : st.data) experiments.push_back(load(path, st));
  ident::ProcessFitOptions options = fit_options(st);
  return {std::move(structure), std::move(model), std::move(experiments), std::move(options)};
}

// --- crossval: each run identified alone, simulated on every other -------------------------------

using ModelWarnings = std::vector<std::vector<std::string>>;  // per model of the cross-validation

nlohmann::ordered_json matrix_json(const Eigen::MatrixXd& fit_percent) {
  nlohmann::ordered_json m = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < fit_percent.rows(); ++i) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (Eigen::Index j = 0; j < fit_percent.cols(); ++j) row.push_back(fit_percent(i, j));
    m.push_back(row);
  }
  return m;
}

nlohmann::ordered_json crossval_json(const IdentifyState& st, const IdentifyPlan& p, const ident::CrossValidation& cv,
                                     const ModelWarnings& warnings) {
  auto doc = io::make_document();
  doc["command"] = "identify";
  doc["mode"] = "crossval";
  doc["model"] = p.model;
  doc["model_canonical"] = p.structure.code();
  doc["experiments"] = cv.names;
  doc["fit_percent_matrix"] = matrix_json(cv.fit_percent);
  doc["matrix_layout"] = "row i: model identified on experiment i; column j: simulated on experiment j (NRMSE fit %)";
  nlohmann::ordered_json models = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < cv.estimates.size(); ++i) {
    auto j = estimate_json(cv.estimates[i], {st.data[i]}, p.model);
    j["identified_on"] = cv.names[i];
    j["mean_validation_fit_percent"] = cv.mean_validation_fit_percent[i];
    j["trusted"] = warnings[i].empty();
    j["warnings"] = warnings[i];
    models.push_back(j);
  }
  doc["models"] = models;
  doc["best"] = {{"index", cv.best}, {"identified_on", cv.names[cv.best]},
                 {"mean_validation_fit_percent", cv.mean_validation_fit_percent[cv.best]},
                 {"trusted", warnings[cv.best].empty()}};
  if (cv.joint) doc["joint"] = estimate_json(*cv.joint, st.data, p.model);
  return doc;
}

void print_crossval(const IdentifyPlan& p, const ident::CrossValidation& cv, const ModelWarnings& warnings) {
  fmt::print("cross-validation of {} (thesis §4.2): NRMSE fit %, row = identified on, column = simulated on\n\n",
             p.model);
  fmt::print("  {:<16}", "");
  for (const auto& n : cv.names) fmt::print(" {:>12.12}", n);
  fmt::print(" {:>12}\n", "mean other");
  for (std::size_t i = 0; i < cv.names.size(); ++i) {
    fmt::print("  {:<16.16}", cv.names[i]);
    for (std::size_t j = 0; j < cv.names.size(); ++j) {
      fmt::print(" {:>12.3f}", cv.fit_percent(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    }
    fmt::print(" {:>12.3f}{}{}\n", cv.mean_validation_fit_percent[i], i == cv.best ? "  <- best" : "",
               warnings[i].empty() ? "" : "  (not trusted)");
  }
  if (cv.joint) {
    fmt::print("  {:<16}", "joint (all)");
    for (double f : cv.joint_fit_percent) fmt::print(" {:>12.3f}", f);
    fmt::print("\n");
  }
  fmt::print("\nbest: identified on {}\n", cv.names[cv.best]);
  print_estimate(cv.estimates[cv.best], p.model);
}

void run_crossval(const IdentifyState& st, const IdentifyPlan& p) {
  if (!st.simulated_csv.empty()) throw InvalidArgument("identify: --simulated applies without --crossval");
  ident::CrossValidationOptions co;
  co.fit = p.options;
  fmt::print(stderr, "clearshape identify: cross-validating {} on {} runs\n", p.model, p.experiments.size());
  const auto cv = ident::cross_validate(p.structure, p.experiments, co);
  ModelWarnings warnings;
  for (const auto& e : cv.estimates) warnings.push_back(identify_warnings(e, st));
  for (std::size_t i = 0; i < warnings.size(); ++i) {
    for (const auto& w : warnings[i]) fmt::print(stderr, "clearshape identify: warning: model from {}: {}\n", cv.names[i], w);
  }
  if (!cv.best_trusted) {
    fmt::print(stderr, "clearshape identify: the best model by validation fit (identified on {}) is not to be trusted (its warnings above)\n",
               cv.names[cv.best]);
  }
  if (st.json) {
    print_json(crossval_json(st, p, cv, warnings));
  } else {
    print_crossval(p, cv, warnings);
  }
}

// --- fit: one model for all runs -------------------------------------------------------------------

nlohmann::ordered_json fit_json(const IdentifyState& st, const IdentifyPlan& p, const ident::ProcessEstimate& est,
                                const std::vector<std::string>& warnings, const std::vector<ExperimentResiduals>& residuals) {
  auto doc = io::make_document();
  doc["command"] = "identify";
  doc["mode"] = "fit";
  const nlohmann::ordered_json result = estimate_json(est, st.data, p.model);
  for (const auto& [k, v] : result.items()) doc[k] = v;
  doc["trusted"] = warnings.empty();
  doc["warnings"] = warnings;
  doc["residual_tests"] = residuals_json(residuals, st.resid_lags);
  doc["residual_warnings"] = residual_warnings(residuals);
  doc["configuration"] = {{"initial_state", st.initial_state},
                          {"hold", st.hold},
                          {"output_offset", st.output_offset},
                          {"input_offset", st.input_offset},
                          {"starts", st.starts},
                          {"fix", st.fix},
                          {"bound", st.bound},
                          {"initial", st.initial},
                          {"focus", "simulation"}};
  return doc;
}

void run_fit(const IdentifyState& st, const IdentifyPlan& p) {
  fmt::print(stderr, "clearshape identify: fitting {} to {} run(s)\n", p.model, p.experiments.size());
  const auto est = ident::estimate_process_model(p.structure, p.experiments, p.options);
  if (!st.simulated_csv.empty()) {
    if (p.experiments.size() != 1) throw InvalidArgument("identify: --simulated needs exactly one --data file");
    write_simulated(st.simulated_csv, p.experiments[0], est.experiments[0]);
  }
  const auto warnings = identify_warnings(est, st);
  report_warnings(warnings);
  const auto residuals = test_residuals(p.experiments, est, st.resid_lags, st.resid_confidence);
  for (const auto& w : residual_warnings(residuals)) fmt::print(stderr, "clearshape identify: warning: {}\n", w);
  if (st.json) {
    print_json(fit_json(st, p, est, warnings, residuals));
  } else {
    print_estimate(est, p.model);
    print_residuals(residuals, st.resid_lags);
  }
}

void run_identify(const IdentifyState& st) {
  const IdentifyPlan p = plan(st);
  if (st.crossval) {
    run_crossval(st, p);
  } else {
    run_fit(st, p);
  }
}

void setup_identify(CLI::App& sub) {
  auto st = std::make_shared<IdentifyState>();
  sub.add_option("--model", st->model, "Process model structure: P + poles 0-3 + D/Z/U/I (thesis Eq. 4.2: P3UZ)")
      ->capture_default_str();
  sub.add_option("--data", st->data, "Recorded run (CSV or whitespace columns, header optional); repeat for several")
      ->required();
  sub.add_option("--input-column", st->input_column, "Input (command) column: name or 1-based index");
  sub.add_option("--output-column", st->output_column, "Output (response) column: name or 1-based index");
  sub.add_option("--time-column", st->time_column, "Time column in seconds (default: time_s, time or t if present)");
  st->sample_time_option = sub.add_option("--sample-time", st->sample_time_s, "Sample time in s when there is no time column");
  sub.add_option("--fix", st->fix, "Hold a parameter, e.g. --fix Tz=-0.04 (repeatable)");
  sub.add_option("--initial", st->initial, "Also start the search from this value, e.g. --initial Tw=0.05 (repeatable)");
  sub.add_option("--bound", st->bound, "Bound a parameter, e.g. --bound Zeta=0:1 (repeatable; a side may be empty)");
  sub.add_option("--initial-state", st->initial_state, "Initial state per run: auto, zero, estimate")->capture_default_str();
  sub.add_option("--hold", st->hold, "Input between samples: zoh, foh")->capture_default_str();
  sub.add_flag("--output-offset", st->output_offset, "Estimate a constant output offset per run");
  sub.add_flag("--input-offset", st->input_offset, "Estimate a constant input offset per run");
  sub.add_option("--max-delay", st->max_delay_s, "Upper bound of Td in s (default: a quarter of the shortest run)");
  sub.add_option("--starts", st->starts, "Levenberg-Marquardt runs from the best-ranked starting points")->capture_default_str();
  sub.add_flag("--crossval", st->crossval, "Thesis §4.2 cross-validation: identify on each run, simulate on every other");
  sub.add_option("--simulated", st->simulated_csv, "Write time_s, input, measured, simulated to this CSV (one --data)");
  sub.add_flag("--json", st->json, "Print the result as JSON (with \"trusted\" and \"warnings\"; docs/recordings.md)");
  sub.add_option("--from-s", st->from_s, "Fit only from this time on, s from the record's start");
  sub.add_option("--to-s", st->to_s, "Fit only up to this time, s (default: the end of the record)");
  sub.add_flag("--derivative", st->derivative, "Differentiate the output (backward difference): fit a speed to an angle record");
  sub.add_option("--butterworth", st->butterworth,
                 "Low-pass the output, 4th-order Butterworth at this cutoff (30rad/s = the thesis's §3.3 chain)");
  sub.add_option("--resid-lags", st->resid_lags, "Residual tests (MATLAB resid): correlations up to this lag, samples")
      ->capture_default_str();
  sub.add_option("--resid-confidence", st->resid_confidence, "Residual tests: confidence of the bands and verdicts, in (0, 1)")
      ->capture_default_str();
  sub.callback([st] { run_identify(*st); });
}

const bool identify_registered = register_command(
    {"identify", "Identify a process model (thesis Eq. 4.2, P3UZ) from recorded runs; --crossval over input types", 30,
     setup_identify});

}  // namespace

}  // namespace clearshape::cli
