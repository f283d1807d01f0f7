#include "clearshape/study/fit_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "clearshape/plant/gyroscope.hpp"

namespace clearshape::study {
namespace {

using json = nlohmann::ordered_json;

// The samples before the command first leaves its initial value: the rest, whose gyro scatter is noise.
std::size_t rest_samples(const std::vector<double>& command) {
  std::size_t k = 0;
  while (k < command.size() && command[k] == command.front()) ++k;
  return k;
}

// The drive command of the first record and the link rate averaged over the records (as the
// study); with an envelope window, the mean of the records' envelopes too.
}  // namespace

void read_link_records(const LinkRecordsRequest& o, rig::CommandMode mode, ClearanceFitProblem& fp) {
  const std::string unit = mode == rig::CommandMode::position ? "deg" : "v";
  std::vector<double> sum;
  std::vector<std::vector<double>> records;
  for (const auto& file : o.files) {
    const io::Table t = io::read_table(file);
    const std::string time = io::require_time_column(t, o.time_column);
    const double ts = io::uniform_sample_time(t, time);
    std::string cmd = o.command_column;
    if (cmd.empty()) cmd = t.find("command_applied_" + unit) ? "command_applied_" + unit : "command_" + unit;
    const auto& rate = t.column(o.gyro_column);
    const double scale = o.gyro_scale_deg_s;
    const std::size_t n = std::min(t.rows(), sample_count(o.window_s, ts));
    if (sum.empty()) {
      fp.drive_command.sample_time_s = ts;
      fp.drive_command.values.assign(t.column(cmd).begin(), t.column(cmd).begin() + static_cast<std::ptrdiff_t>(n));
      fp.duration_s = static_cast<double>(n - 1) * ts;
      sum.assign(n, 0.0);
    } else if (n != sum.size() || std::abs(ts - fp.drive_command.sample_time_s) > 1e-9) {
      throw InputError(file.string(), 0, time, "every --data record must have the first one's sample time and length");
    }
    for (std::size_t k = 0; k < n; ++k) sum[k] += scale * rate[k] / static_cast<double>(o.files.size());
    records.emplace_back(n);
    for (std::size_t k = 0; k < n; ++k) records.back()[k] = scale * rate[k];
  }
  fp.measured_link_rate_deg_s = sum;
  if (o.envelope_window_s > 0.0) {
    fp.envelope_window_s = o.envelope_window_s;
    fp.measured_link_rate_envelope_deg_s = mean_rate_envelope_deg_s(
        records, sum.size(), o.envelope_window_s, fp.drive_command.sample_time_s, rest_samples(fp.drive_command.values));
  }
}

std::vector<ClearanceRunRecord> read_link_runs(const LinkRecordsRequest& o, rig::CommandMode mode) {
  std::vector<ClearanceRunRecord> runs;
  for (const auto& file : o.files) {
    LinkRecordsRequest one = o;
    one.files = {file};
    one.envelope_window_s = 0.0;
    ClearanceFitProblem fp;
    read_link_records(one, mode, fp);
    if (!runs.empty() && (fp.drive_command.values.size() != runs.front().drive_command.values.size() ||
                          std::abs(fp.drive_command.sample_time_s - runs.front().drive_command.sample_time_s) > 1e-9)) {
      throw InputError(file.string(), 0, o.time_column.empty() ? "time" : o.time_column,
                       "every --data record must have the first one's sample time and length");
    }
    runs.push_back({file.filename().string(), fp.drive_command, fp.measured_link_rate_deg_s});
  }
  return runs;
}

lti::ProcessModel read_identified_drive(const std::filesystem::path& path) {
  const std::string file = path.string();
  const std::string text = io::read_text_file(path);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(file, 0, "", fmt::format("not JSON: {}", e.what()));
  }
  if (doc.contains("models") && doc.contains("best")) doc = doc["models"].at(doc["best"].at("index").get<std::size_t>());
  if (!doc.contains("model") || !doc.contains("parameters")) {
    throw InputError(file, 0, "model", "expected the output of `clearshape identify --json` (keys model, parameters)");
  }
  lti::ProcessParameters p;
  for (const auto& [name, v] : doc["parameters"].items()) p.set(name, v.at("value").get<double>());
  return lti::ProcessModel(doc["model"].get<std::string>(), p);
}

std::vector<double> gyro_low_pass_settings_hz() {
  std::vector<double> g{0.0};
  for (auto lp : {plant::GyroLowPass::hz256, plant::GyroLowPass::hz188, plant::GyroLowPass::hz98, plant::GyroLowPass::hz42,
                  plant::GyroLowPass::hz20, plant::GyroLowPass::hz10, plant::GyroLowPass::hz5}) {
    g.push_back(plant::bandwidth_hz(lp));
  }
  return g;
}

namespace {

// The rest of the identified nonlinear model, so that a document alone describes it
// (`clearshape shape --method clearance-aware --model`): the drive as `identify --json` writes it,
// the fixed link inertia, the mode, v_t of the Coulomb term.
void add_model_rest(json& doc, const ClearanceModel& start, double friction_regularization_rad_s) {
  json drive_parameters = json::object();
  const auto names = start.drive.structure().parameter_names();
  const auto values = start.drive.to_vector();
  for (std::size_t i = 0; i < names.size(); ++i) drive_parameters[std::string(names[i])] = {{"value", values[i]}};
  doc["friction_regularization_rad_s"] = friction_regularization_rad_s;
  doc["mode"] = rig::to_string(start.mode);
  doc["link_inertia_kg_m2"] = start.link_inertia_kg_m2;
  doc["drive"] = {{"model", start.drive.code()}, {"parameters", drive_parameters}};
}

}  // namespace

nlohmann::ordered_json exponent_check_json(const ClearanceRunsFitResult& fit) {
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return {{"exponent_free", fit.exponent_free_value}, {"exponent_free_std", num(fit.exponent_free_std)},
          {"chi2", fit.exponent_chi2}, {"significantly_better", fit.exponent_free_better}};
}

namespace {

// One fitted parameter in a fit-clearance document (the play in degrees).
json parameter_entry(const ClearanceParameter& q, json std_value, const char* std_kind) {
  const bool angle = q.name == "play";
  return {{"value", angle ? rad_to_deg(q.value) : q.value},
          {"unit", clearance_parameter_unit(q.name)},
          {"start", angle ? rad_to_deg(q.start) : q.start},
          {"free", q.free},
          {"std", std::move(std_value)},
          {"std_kind", std_kind},
          {"identifiable", q.identifiable},
          {"at_bound", q.at_bound}};
}

}  // namespace

json fit_clearance_document(const ClearanceFitProblem& fp, const ClearanceFitResult& fit) {
  json doc = io::make_document();
  doc["command"] = "fit-clearance";
  json params = json::object();
  json warnings = json::array();
  for (const auto& q : fit.parameters) {
    params[q.name] = parameter_entry(q, std::isfinite(q.std_error) ? json(q.std_error) : json(nullptr),
                                     q.name == "exponent" ? "absolute"
                                     : q.name == "coulomb" || q.name == "viscous" || q.name == "restitution"
                                         ? "relative (of the value)"
                                         : "relative (of log value)");
    if (q.free && q.at_bound) warnings.push_back(fmt::format("{} ended on its bound", q.name));
    if (q.free && !q.identifiable) warnings.push_back(fmt::format("{} is not identifiable from this record (1σ too large or not finite)", q.name));
  }
  if (!fit.converged) warnings.push_back(fmt::format("the search did not converge ({})", fit.termination));
  doc["parameters"] = params;
  if (fit.model.contact_law == ContactLawChoice::flores) doc["contact_law"] = "flores";  // dashpot: no key
  doc["agreement"] = fit.agreement;  // Eq. 4.1: RMS(model − measured) / range(measured)
  doc["start_agreement"] = clearance_agreement(
      fp.measured_link_rate_deg_s,
      sensed_link_rate_deg_s(fp, simulate_drive_command(fit.start_model, fp.drive_command, fp.duration_s), fit.sensor_low_pass_hz));
  doc["rms_error_deg_s"] = fit.rms_error_deg_s;
  doc["envelope_window_s"] = fp.measured_link_rate_envelope_deg_s.empty() ? 0.0 : fp.envelope_window_s;
  doc["envelope_rms_error_deg_s"] = fit.envelope_rms_error_deg_s;
  doc["sensor_low_pass_hz"] = fit.sensor_low_pass_hz;
  doc["evaluations"] = fit.evaluations;
  doc["termination"] = fit.termination;
  doc["converged"] = fit.converged;
  doc["trusted"] = warnings.empty();
  doc["warnings"] = warnings;
  add_model_rest(doc, fp.start, fit.model.friction_regularization_rad_s);
  return doc;
}

json fit_clearance_runs_document(const ClearanceRunsFitProblem& rp, const ClearanceRunsFitResult& fit) {
  json doc = io::make_document();
  doc["command"] = "fit-clearance";
  doc["method"] = "per-run: each run its own start place φ(0)/β and flank damping (nuisances); K, play and the "
                  "friction shared; n held at 1 (docs/worn-coupling.md)";
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  json params = json::object();
  json warnings = json::array();
  for (const auto& q : fit.parameters) {
    params[q.name] = parameter_entry(q, q.free ? num(q.std_error) : json(nullptr),
                                     q.name == "exponent" ? "absolute" : "relative (1σ / value)");
    if (q.free && !q.identifiable) warnings.push_back(fmt::format("{} is not identifiable from these runs (1σ too large or not finite)", q.name));
  }
  if (!fit.converged) warnings.push_back(fmt::format("the search did not converge ({})", fit.termination));
  if (fit.exponent_free_better) {
    warnings.push_back(fmt::format("n free fits significantly better (χ²₁ {:.3g} > 3.84, n {:.3g}): the flank is not linear",
                                   fit.exponent_chi2, fit.exponent_free_value));
  }
  if (fit.run_ids.size() < 3) warnings.push_back("fewer than 3 runs: the flank damping's run spread is not known");
  doc["parameters"] = params;
  json runs = json::array();
  for (std::size_t i = 0; i < fit.run_ids.size(); ++i) {
    runs.push_back({{"id", fit.run_ids[i]}, {"start_fraction", fit.start_fraction[i]},
                    {"start_fraction_std", num(fit.start_fraction_std[i])}, {"damping_n_m_s_per_rad", fit.run_damping[i]},
                    {"rms_error_deg_s", fit.run_rms_error_deg_s[i]}});
  }
  doc["runs"] = runs;
  const ClearanceModelSigma sg = fit.sigma();
  doc["model_sigma"] = {{"play_rel_sigma", num(sg.play_rel_sigma)}, {"stiffness_rel_sigma", num(sg.stiffness_rel_sigma)},
                        {"coulomb_rel_sigma", num(sg.coulomb_rel_sigma)}, {"damping_spread", num(sg.damping_spread)}};
  doc["exponent_check"] = exponent_check_json(fit);
  doc["rms_error_deg_s"] = fit.rms_error_deg_s;
  doc["cvode_check_rms_error_deg_s"] = fit.check_rms_error_deg_s;
  doc["sensor_low_pass_hz"] = fit.sensor_low_pass_hz;
  doc["iterations"] = fit.iterations;
  doc["simulations"] = fit.simulations;
  doc["termination"] = fit.termination;
  doc["converged"] = fit.converged;
  doc["trusted"] = warnings.empty();
  doc["warnings"] = warnings;
  add_model_rest(doc, rp.start, fit.model.friction_regularization_rad_s);
  return doc;
}

}  // namespace clearshape::study
