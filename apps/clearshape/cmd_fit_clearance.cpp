// `clearshape fit-clearance`: the clearance fit of thesis §4.2 (Eq. 4.3 contact parameters, with
// the Eq. 4.1 agreement) as its own command — a drive model (identify --json, or Eq. 4.2
// parameters) and one or more link records (command the drive received + link gyro) in; the
// contact parameters with their 1σ, identifiability and the agreement out (study::fit_clearance).
// Untrustworthy results (not converged, a parameter at its bound or not identifiable) are marked
// `trusted: false` with `warnings`, printed on stderr; the exit status stays 0 (docs/recordings.md).
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/atomic_file.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/rig/types.hpp"
#include "clearshape/study/fit_clearance.hpp"
#include "clearshape/study/model.hpp"
#include "command.hpp"

namespace clearshape::cli {
namespace {

using json = nlohmann::ordered_json;

struct FitClearanceOptions {
  std::string drive_json, model, mode = "position";
  std::vector<std::string> params, data, fit{"stiffness", "damping", "play", "exponent"};
  std::string time_column, command_column, gyro_column = "link_rate_deg_s", gyro_unit = "deg/s";
  double link_inertia_kg_m2 = 5e-3, play_deg = 0.1, stiffness = 300.0, exponent = 1.5, damping = 0.1;
  double window_s = 2.0, link_wn_rad_s = 0.0, link_zeta = 0.0;
  double envelope_window_s = 0.0;  // 0: the mean record alone
  std::string low_pass = "auto";
  std::string contact_law = "dashpot";  // Eq. 4.3, or "flores" (restitution e instead of D)
  double restitution = 0.6;
  int max_evaluations = 150;
  bool json = false;
  bool per_run = false;  // each record its own run (study::fit_clearance_runs), never averaged
  double rest_s = 0.4;   // per-run: the gyro's rest window before the move, its mean removed
};

// The drive: `identify --json` (a fit, or cross-validation's best model) or --model + --param.
lti::ProcessModel read_drive(const FitClearanceOptions& o) {
  if (!o.drive_json.empty()) return study::read_identified_drive(o.drive_json);
  lti::ProcessParameters p;
  if (o.model.empty()) throw InvalidArgument("fit-clearance: give --drive FILE (identify --json) or --model CODE with --param");
  for (const auto& kv : o.params) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw InvalidArgument(fmt::format("--param '{}': expected NAME=VALUE, e.g. Kp=0.99", kv));
    p.set(kv.substr(0, eq), std::stod(kv.substr(eq + 1)));
  }
  return lti::ProcessModel(o.model, p);
}

double gyro_scale(const std::string& unit) {
  if (unit == "deg/s") return 1.0;
  if (unit == "rad/s") return rad_to_deg(1.0);
  if (unit == "lsb") return 1.0 / 14.375;  // ITG-3205 sensitivity, LSB per deg/s
  throw InvalidArgument(fmt::format("--gyro-unit '{}': allowed deg/s, rad/s, lsb", unit));
}

// The records as the library reads them (study/fit_clearance.hpp).
study::LinkRecordsRequest records_request(const FitClearanceOptions& o) {
  study::LinkRecordsRequest r;
  r.files.assign(o.data.begin(), o.data.end());
  r.time_column = o.time_column;
  r.command_column = o.command_column;
  r.gyro_column = o.gyro_column;
  r.gyro_scale_deg_s = gyro_scale(o.gyro_unit);
  r.window_s = o.window_s;
  r.envelope_window_s = o.envelope_window_s;
  return r;
}

std::vector<double> low_pass_grid(const std::string& spec) {
  if (spec == "none") return {0.0};
  if (spec == "auto") return study::gyro_low_pass_settings_hz();
  const double hz = std::stod(spec);
  if (!(hz > 0.0)) throw InvalidArgument(fmt::format("--sensor-low-pass '{}': allowed auto, none or a bandwidth > 0 Hz", spec));
  return {hz};
}

void print_text(const json& doc) {
  fmt::print("clearance fit (thesis §4.2, {}; joint friction Eq. 2.9 c·tanh(φ̇/v_t) + b·φ̇)\n\n",
             doc.contains("contact_law") ? "Flores law F = K·δ^n·(1 + 8(1−e)/(5e)·δ̇/δ̇⁻)" : "Eq. 4.3 F = K·δ^n + D·δ̇");
  fmt::print("  {:<10} {:>14} {:<10} {:>12} {:>10} {:>13} {:>9}\n", "parameter", "value", "unit", "start", "1σ", "identifiable", "at bound");
  for (const auto& [name, p] : doc["parameters"].items()) {
    std::string sigma = "fixed";
    if (p["free"].get<bool>()) {
      sigma = p["std"].is_null() ? "n/a"
              : name == "exponent" ? fmt::format("{:.2g}", p["std"].get<double>())
                                   : fmt::format("{:.2g} %", 100.0 * p["std"].get<double>());
    }
    fmt::print("  {:<10} {:>14.6g} {:<10} {:>12.4g} {:>10} {:>13} {:>9}\n", name, p["value"].get<double>(),
               p["unit"].get<std::string>(), p["start"].get<double>(), sigma, p["identifiable"].get<bool>() ? "yes" : "no",
               p["at_bound"].get<bool>() ? "yes" : "no");
  }
  fmt::print("\n  Eq. 4.1 agreement {:.4g} (start {:.4g}), RMS {:.4g} deg/s, sensor low-pass {} Hz\n",
             doc["agreement"].get<double>(), doc["start_agreement"].get<double>(), doc["rms_error_deg_s"].get<double>(),
             doc["sensor_low_pass_hz"].get<double>());
  fmt::print("  {} after {} evaluations: {}\n", doc["termination"].get<std::string>(), doc["evaluations"].get<int>(),
             doc["converged"].get<bool>() ? "converged" : "NOT converged");
  fmt::print("  trusted: {}\n", doc["trusted"].get<bool>() ? "yes" : "no (see the warnings on stderr)");
}

void print_runs_text(const json& doc) {
  fmt::print("clearance fit, per run ({})\n\n", doc["method"].get<std::string>());
  fmt::print("  {:<10} {:>14} {:<10} {:>10} {:>13}\n", "parameter", "value", "unit", "1σ", "identifiable");
  for (const auto& [name, p] : doc["parameters"].items()) {
    const std::string sigma = !p["free"].get<bool>() ? "fixed"
                              : p["std"].is_null()  ? "n/a"
                                                    : fmt::format("{:.2g} %", 100.0 * p["std"].get<double>());
    fmt::print("  {:<10} {:>14.6g} {:<10} {:>10} {:>13}\n", name, p["value"].get<double>(), p["unit"].get<std::string>(),
               sigma, p["identifiable"].get<bool>() ? "yes" : "no");
  }
  fmt::print("\n  {:<28} {:>12} {:>10} {:>14}\n", "run", "φ(0)/β", "D", "RMS (deg/s)");
  for (const auto& r : doc["runs"]) {
    fmt::print("  {:<28} {:>12.4g} {:>10.4g} {:>14.4g}\n", r["id"].get<std::string>(), r["start_fraction"].get<double>(),
               r["damping_n_m_s_per_rad"].get<double>(), r["rms_error_deg_s"].get<double>());
  }
  const auto& spread = doc["model_sigma"]["damping_spread"];
  fmt::print("\n  flank damping's run spread (1σ of ln D, 90 % upper bound): {}\n",
             spread.is_null() ? std::string("n/a") : fmt::format("{:.3g}", spread.get<double>()));
  fmt::print("  RMS {:.4g} deg/s (CVODE check {:.4g}), sensor low-pass {:.4g} Hz, {}: {}\n",
             doc["rms_error_deg_s"].get<double>(), doc["cvode_check_rms_error_deg_s"].get<double>(),
             doc["sensor_low_pass_hz"].get<double>(), doc["termination"].get<std::string>(),
             doc["converged"].get<bool>() ? "converged" : "NOT converged");
  fmt::print("  trusted: {}\n", doc["trusted"].get<bool>() ? "yes" : "no (see the warnings on stderr)");
}

// The fit's start model from the options: the drive, the fixed inertia, the start values.
study::ClearanceModel start_model(const FitClearanceOptions& o, rig::CommandMode mode) {
  study::ClearanceModel m;
  m.mode = mode;
  m.drive = read_drive(o);
  m.link_inertia_kg_m2 = o.link_inertia_kg_m2;
  m.play_rad = deg_to_rad(o.play_deg);
  m.stiffness = o.stiffness;
  m.exponent = o.exponent;
  m.damping = o.damping;
  m.contact_law = study::contact_law_from_string(o.contact_law);
  m.restitution = o.restitution;
  return m;
}

// --per-run: the per-run fit (study::fit_clearance_runs), position mode and the dashpot law with
// n held at 1, as the study's per-run fit.
json run_per_run(const FitClearanceOptions& o, rig::CommandMode mode) {
  if (mode != rig::CommandMode::position) throw InvalidArgument("--per-run: fits position-mode records (--mode position)");
  if (o.contact_law != "dashpot") throw InvalidArgument("--per-run: fits the dashpot law (--contact-law dashpot)");
  if (o.envelope_window_s > 0.0) throw InvalidArgument("--per-run: --envelope-window-s is for the averaged fit; leave it out");
  if (!(o.rest_s > 0.0 && o.rest_s < o.window_s)) throw_invalid("--rest-s", o.rest_s, "(0, --window-s)");
  study::ClearanceRunsFitProblem rp;
  rp.start = start_model(o, mode);
  rp.start.exponent = 1.0;  // a linear flank held; n free is the checked alternative
  rp.free.clear();
  for (const auto& f : o.fit) {
    if (f != "exponent") rp.free.push_back(f);
  }
  rp.runs = study::read_link_runs(records_request(o), mode);
  rp.duration_s = static_cast<double>(rp.runs.front().drive_command.values.size() - 1) * rp.runs.front().drive_command.sample_time_s;
  rp.rest_s = o.rest_s;
  rp.link_natural_frequency_rad_s = o.link_wn_rad_s;
  rp.link_damping_ratio = o.link_zeta;
  rp.sensor_low_pass_grid_hz = low_pass_grid(o.low_pass);
  std::cerr << fmt::format("clearshape fit-clearance: per-run fit, drive {}, {} run(s), {:.3g} s, fitting {} (n held at 1)\n",
                           rp.start.drive.code(), rp.runs.size(), rp.duration_s, fmt::join(rp.free, ", "));
  return study::fit_clearance_runs_document(rp, study::fit_clearance_runs(rp));
}

void run(const FitClearanceOptions& o) {
  const rig::CommandMode mode = rig::command_mode_from_string(o.mode);
  if (o.per_run) {
    const json doc = run_per_run(o, mode);
    for (const auto& w : doc["warnings"]) std::cerr << "clearshape fit-clearance: warning: " << w.get<std::string>() << "\n";
    if (o.json) {
      print_json(doc);
    } else {
      print_runs_text(doc);
    }
    return;
  }
  study::ClearanceFitProblem fp;
  fp.start = start_model(o, mode);
  fp.free = o.fit;
  fp.link_natural_frequency_rad_s = o.link_wn_rad_s;
  fp.link_damping_ratio = o.link_zeta;
  fp.max_evaluations = o.max_evaluations;
  fp.sensor_low_pass_grid_hz = low_pass_grid(o.low_pass);
  study::read_link_records(records_request(o), mode, fp);
  std::cerr << fmt::format("clearshape fit-clearance: {} drive {}, {} record(s), {:.3g} s, fitting {}\n", o.mode,
                           fp.start.drive.code(), o.data.size(), fp.duration_s, fmt::join(fp.free, ", "));
  const json doc = study::fit_clearance_document(fp, study::fit_clearance(fp));
  for (const auto& w : doc["warnings"]) std::cerr << "clearshape fit-clearance: warning: " << w.get<std::string>() << "\n";
  if (o.json) {
    print_json(doc);
  } else {
    print_text(doc);
  }
}

const bool fit_clearance_registered = register_command(
    {"fit-clearance", "Fit the Eq. 4.3 contact parameters to a link record, given a drive model", 55,
     [](CLI::App& sub) {
       auto o = std::make_shared<FitClearanceOptions>();
       sub.add_option("--drive", o->drive_json, "Drive model: the output of `clearshape identify --json`");
       sub.add_option("--model", o->model, "Drive model structure instead of --drive (Eq. 4.2: P3UZ)");
       sub.add_option("--param", o->params, "A drive parameter with --model, e.g. --param Kp=0.99 (repeatable)");
       sub.add_option("--mode", o->mode, "Command mode of the record: position (deg) or speed (V)")->capture_default_str();
       sub.add_option("--data", o->data, "Link record(s) (CSV); several are averaged (--per-run: each its own run)")->required();
       sub.add_flag("--per-run", o->per_run,
                    "Fit each record as its own run (its own start place in the play and flank damping), never "
                    "averaged: records of a joint whose link starts anywhere in the play (docs/worn-coupling.md); "
                    "position mode, dashpot law, n held at 1");
       sub.add_option("--rest-s", o->rest_s, "--per-run: the rest before the move, s (the gyro's mean there is removed)")
           ->capture_default_str();
       sub.add_option("--time-column", o->time_column, "Time column in s (default: time_s, time or t)");
       sub.add_option("--command-column", o->command_column,
                      "What the drive received (default: command_applied_deg|v, else command_deg|v)");
       sub.add_option("--gyro-column", o->gyro_column, "Link gyroscope column")->capture_default_str();
       sub.add_option("--gyro-unit", o->gyro_unit, "deg/s, rad/s or lsb (14.375 LSB per deg/s)")->capture_default_str();
       sub.add_option("--window-s", o->window_s, "Record length compared, from t = 0, s")->capture_default_str()->check(CLI::PositiveNumber);
       sub.add_option("--link-inertia", o->link_inertia_kg_m2, "Link inertia J, kg·m² (held fixed)")->capture_default_str()->check(CLI::PositiveNumber);
       sub.add_option("--play-deg", o->play_deg, "Total play 2β, deg (start value when fitted)")->capture_default_str();
       sub.add_option("--stiffness", o->stiffness, "K, N·m/rad^n (start value when fitted)")->capture_default_str();
       sub.add_option("--exponent", o->exponent, "n (start value when fitted)")->capture_default_str();
       sub.add_option("--damping", o->damping, "D, N·m·s/rad (start value when fitted)")->capture_default_str();
       sub.add_option("--contact-law", o->contact_law,
                      "Contact law: dashpot (Eq. 4.3, K·δ^n + D·δ̇) or flores (K·δ^n·(1 + 8(1−e)/(5e)·δ̇/δ̇⁻); "
                      "`damping` in --fit then fits the restitution e)")
           ->capture_default_str()
           ->check(CLI::IsMember({"dashpot", "flores"}));
       sub.add_option("--restitution", o->restitution, "e of the flores law (start value when fitted; the link mode's ζ "
                      "sets it when --link-zeta is given)")
           ->capture_default_str()
           ->check(CLI::Range(0.05, 1.0));
       sub.add_option("--fit", o->fit, "Free parameters: of stiffness, damping, play, exponent, coulomb, viscous (the joint's friction)")
           ->capture_default_str();
       sub.add_option("--envelope-window-s", o->envelope_window_s,
                      "Also fit the records' mean link-rate envelope (moving RMS over this window, s, e.g. 0.05; "
                      "0: off)")
           ->check(CLI::Range(0.0, 10.0));
       sub.add_option("--link-wn", o->link_wn_rad_s, "The link's residual mode ωn, rad/s (start of K/J; `modes`)");
       sub.add_option("--link-zeta", o->link_zeta, "The link's residual mode ζ (start of D/J)");
       sub.add_option("--sensor-low-pass", o->low_pass, "Gyro low-pass: auto (ITG-3205 settings), none, or Hz")->capture_default_str();
       sub.add_option("--max-evaluations", o->max_evaluations, "Per local search")->capture_default_str()->check(CLI::Range(5, 100000));
       sub.add_flag("--json", o->json, "Print the result as JSON");
       sub.callback([o] { run(*o); });
     }});

}  // namespace
}  // namespace clearshape::cli
