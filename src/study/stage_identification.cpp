// Stages 1–3: repeatability (Eq. 4.1, Tables 4.1/4.2), drive identification (Eq. 4.2, §4.2)
// with cross-validation, and the link's residual mode (docs/design.md §2).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/trust.hpp"
#include "clearshape/metrics/consistency.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

namespace {

bool speed_mode(const Context& c) { return c.p.mode == rig::CommandMode::speed; }

// The encoder signal of a run: angle (position mode) or speed through the §3.3 chain.
std::vector<double> encoder_signal(const Context& c, const Record& r) {
  if (speed_mode(c)) return motor_speed_deg_s(r, c.p.identification.speed_chain == "zero-phase");
  return r.motor_angle_deg;
}

std::string encoder_unit(const Context& c) { return speed_mode(c) ? "deg/s" : "deg"; }

json column(const std::string& key, const std::string& label, const std::vector<double>& ours,
            const ThesisColumn* thesis) {
  json col;
  col["key"] = key;
  col["label"] = label;
  col["ours"] = ours;
  const MeanStd ms = mean_std(ours);
  col["ours_mean"] = ms.mean;
  col["ours_std"] = ms.std;
  if (thesis) {
    col["thesis"] = thesis->values;
    col["thesis_mean"] = thesis->mean ? json(*thesis->mean) : json(nullptr);
  } else {
    col["thesis"] = json::array();
    col["thesis_mean"] = nullptr;
  }
  return col;
}

}  // namespace

void stage_consistency(Context& c) {
  const auto& cs = c.p.consistency;
  if (cs.inputs.empty()) {
    c.log("consistency: no inputs in the protocol, skipped");
    return;
  }
  json table = make_table(cs.table, "consistency",
                          fmt::format("Eq. 4.1 error of each of {} repeated runs ({})", c.p.repetitions,
                                      speed_mode(c) ? "encoder speed through the §3.3 chain" : "encoder angle"),
                          "dimensionless");
  json rows = json::array();
  for (int r = 1; r <= c.p.repetitions; ++r) rows.push_back(std::to_string(r));
  table["row_labels"] = rows;
  json cols = json::array();
  json headline = json::object();
  for (const auto& name : cs.inputs) {
    const auto& runs = c.unshaped_runs(name);
    std::vector<std::vector<double>> signals;
    for (const auto& r : runs) signals.push_back(encoder_signal(c, r));
    std::vector<double> errors;
    std::string note;
    try {
      const metrics::ConsistencyResult res = metrics::consistency_errors(signals);
      errors = res.errors;
    } catch (const InvalidArgument& e) {
      note = e.what();
    }
    const auto th = cs.thesis.find(name);
    json col = column(name, c.p.input(name).label, errors, th == cs.thesis.end() ? nullptr : &th->second);
    if (!note.empty()) col["note"] = note;
    headline[name] = {{"ours_mean", col["ours_mean"]}, {"thesis_mean", col["thesis_mean"]}};
    cols.push_back(col);

    // Figure data: every run's encoder signal (Figures 4.2–4.5, 4.7–4.8).
    std::vector<std::string> names{"time_s"};
    std::vector<const std::vector<double>*> data{&runs.front().time_s};
    for (std::size_t i = 0; i < signals.size(); ++i) {
      names.push_back(fmt::format("run{:02d}_{}", i + 1, speed_mode(c) ? "motor_speed_deg_s" : "motor_angle_deg"));
      data.push_back(&signals[i]);
    }
    const std::string file = fmt::format("consistency_{}.csv", name);
    write_data_csv(c, file, names, data);
    json series = json::array();
    for (std::size_t i = 1; i < names.size(); ++i) series.push_back({{"column", names[i]}, {"label", fmt::format("run {}", i)}});
    const bool position = !speed_mode(c);
    const std::string thesis_fig = position ? (name.find("double") != std::string::npos ? "4.8" : "4.7")
                                            : [&] {
                                                const std::string type(c.p.input(name).signal.type());
                                                return type == "step" ? "4.2" : type == "ramp" ? "4.3"
                                                     : type == "sine" ? "4.4" : "4.5";
                                              }();
    c.figures.push_back({{"id", fmt::format("consistency-{}", name)},
                         {"thesis_figure", thesis_fig},
                         {"kind", "time-series"},
                         {"title", fmt::format("{} runs of the {} (encoder, {})", runs.size(),
                                               c.p.input(name).label, encoder_unit(c))},
                         {"file", c.data_file(file)},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", speed_mode(c) ? "motor speed (deg/s)" : "motor angle (deg)"},
                         {"series", series}});
  }
  table["columns"] = cols;
  table["headline"] = headline;
  table["note"] = std::string(
      "Eq. 4.1: E_i = RMS(m − t_i)/r over the record, m the mean of the runs, r its range. The "
      "simulated rig's runs differ only by what its truth models (rig/variation.hpp), drawn afresh "
      "for every run from the run's seed: ") +
      (speed_mode(c)
           ? "a scatter of the drive gain Kp, a start latency of the D/A updates (uniform, under one "
             "sample) and the D/A's offset (per run) and white output noise (per sample)"
           : "a scatter of the drive gain Kp (small: the servo's encoder loop holds the position) "
             "and the phase of the 30 Hz pulse-update clock relative to the command (a start "
             "latency drawn uniformly per run)") +
      ", besides the link's initial position in the play, the flank damping and the gyro noise, "
      "which the encoder does not see. Their sizes were calibrated (clearshape calibrate-rig, "
      "studies/sim-rig-truth.toml) so that the mean E of this table and the trials' spread of the "
      "unshaped Eq. 5.1 come near the thesis's. Where we differ: the thesis does not say what made "
      "its runs differ, so the per-input pattern is ours only as far as these mechanisms reproduce "
      "it, and the encoder's 0.03° counts make a small variation read as whole-count flips." +
      std::string(speed_mode(c)
                      ? ""
                      : " The thesis's double step repeats 20 times worse than its step; none of the "
                        "modelled causes singles out a second move, so ours stays near the step's.");
  c.tables.push_back(table);
}

void stage_identification(Context& c) {
  const auto& id = c.p.identification;
  if (id.inputs.empty()) {
    c.log("identification: no inputs in the protocol, skipped");
    return;
  }
  const lti::ProcessStructure structure = lti::ProcessStructure::parse(id.structure);
  std::vector<ident::Experiment> experiments;
  for (const auto& name : id.inputs) {
    const Record& r = c.unshaped_runs(name).front();
    ident::Experiment e;
    e.name = name;
    e.sample_time_s = r.sample_time_s;
    e.input = r.command_applied;  // what the driver received (the 30 Hz ramp / the D/A output)
    e.output = encoder_signal(c, r);
    experiments.push_back(std::move(e));
  }
  std::vector<ident::ProcessEstimate> estimates;
  for (const auto& e : experiments) {
    c.log(fmt::format("identification: fitting {} to the {} record ({} samples)", id.structure, e.name, e.size()));
    ident::ProcessFitOptions options;
    estimates.push_back(ident::estimate_process_model(structure, std::span(&e, 1), options));
  }
  // Cross-validation (§4.2): every model simulated on every input's record.
  const std::size_t m = estimates.size();
  std::vector<std::vector<double>> fit(m, std::vector<double>(m, 0.0));
  std::vector<double> score(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t j = 0; j < m; ++j) {
      ident::CompareOptions co;
      co.initial_state = ident::InitialState::zero;
      fit[i][j] = ident::compare(estimates[i].model, experiments[j], co).fit_percent;
      if (i != j || m == 1) {
        sum += fit[i][j];
        ++count;
      }
    }
    score[i] = sum / count;
  }
  // The guard rails (ident/trust.hpp): an untrusted model is selected only when no model is trusted.
  std::vector<ident::TrustAssessment> trust;
  for (const auto& e : estimates) trust.push_back(ident::assess(e));
  const bool any_trusted = std::any_of(trust.begin(), trust.end(), [](const auto& t) { return t.trusted; });
  std::size_t best = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const bool eligible = trust[i].trusted || !any_trusted;
    const bool best_eligible = trust[best].trusted || !any_trusted;
    if (eligible && (!best_eligible || score[i] > score[best])) best = i;
  }
  for (std::size_t i = 0; i < m; ++i) {
    for (const auto& w : trust[i].warnings) c.log(fmt::format("identification: the {} model is not trusted: {}", id.inputs[i], w));
  }
  c.drive = estimates[best];
  c.drive_input = id.inputs[best];
  c.log(fmt::format("identification: selected the {} model (mean cross-validation fit {:.1f} %)",
                    c.drive_input, score[best]));

  // Eq. 4.2 parameters next to the thesis's.
  json table = make_table("4.2-model", "parameters",
                          fmt::format("Identified drive model, Eq. 4.2 ({}), per input; selected: {}",
                                      id.structure, c.drive_input), "");
  const std::vector<std::pair<std::string, std::string>> params{
      {"Kp", speed_mode(c) ? "(deg/s)/V" : "deg/deg"}, {"Tz", "s"}, {"Zeta", "-"}, {"Tw", "s"}, {"Tp3", "s"}};
  json rows = json::array();
  for (const auto& [name, unit] : params) rows.push_back(fmt::format("{} ({})", name, unit));
  rows.push_back("ωn = 1/Tw (rad/s)");
  rows.push_back("fit on own record (%)");
  rows.push_back("mean cross-validation fit (%)");
  table["row_labels"] = rows;
  json cols = json::array();
  for (std::size_t i = 0; i < m; ++i) {
    const auto& est = estimates[i];
    json values = json::array();
    json stds = json::array();
    for (const auto& [name, unit] : params) {
      if (est.model.structure().has_parameter(name)) {
        values.push_back(est.parameter(name).value);
        stds.push_back(est.parameter(name).std_dev);
      } else {
        values.push_back(nullptr);
        stds.push_back(nullptr);
      }
    }
    const auto wn = est.natural_frequency_rad_s();
    values.push_back(wn ? json(*wn) : json(nullptr));
    stds.push_back(est.natural_frequency_std_rad_s() ? json(*est.natural_frequency_std_rad_s()) : json(nullptr));
    values.push_back(fit[i][i]);
    stds.push_back(nullptr);
    values.push_back(score[i]);
    stds.push_back(nullptr);
    json col;
    col["key"] = id.inputs[i];
    col["label"] = fmt::format("{}{}", c.p.input(id.inputs[i]).label, i == best ? " (selected)" : "");
    col["ours"] = values;
    col["ours_std"] = stds;
    cols.push_back(col);
  }
  const auto& t = id.thesis;
  if (t.kp != 0.0 || t.tw_s > 0.0) {  // a protocol without the thesis's model (another rig) gets no column of zeros
    json thesis_col;
    thesis_col["key"] = "thesis";
    thesis_col["label"] = fmt::format("thesis ({} model)", t.selected_input.empty() ? "selected" : t.selected_input);
    thesis_col["thesis"] = {t.kp, t.tz_s, t.zeta, t.tw_s, t.tp3_s, t.tw_s > 0 ? 1.0 / t.tw_s : 0.0, nullptr, nullptr};
    cols.push_back(thesis_col);
  }
  table["columns"] = cols;
  table["headline"] = {{"selected_input", c.drive_input},
                       {"ours", {{"kp", c.drive->model.parameters().kp},
                                 {"tz_s", c.drive->model.parameters().tz},
                                 {"zeta", c.drive->model.parameters().zeta},
                                 {"tw_s", c.drive->model.parameters().tw},
                                 {"tp3_s", c.drive->model.parameters().tp3}}},
                       {"thesis", {{"kp", t.kp}, {"tz_s", t.tz_s}, {"zeta", t.zeta}, {"tw_s", t.tw_s}, {"tp3_s", t.tp3_s}}}};
  table["note"] = speed_mode(c)
      ? "Speed mode: the output is the encoder angle differentiated and low-passed by the 4th-order "
        "30 rad/s Butterworth (§3.3), so the identified model contains the filter (§4.2) — its ωn "
        "and ζ are those of drive × filter, not of the drive alone."
      : "Position mode: input = the position the driver received (the 30 Hz pulse train, a ramp "
        "for a step), output = the encoder angle.";
  c.tables.push_back(table);

  json xv = make_table("4.2-cross-validation", "matrix",
                       "Cross-validation: fit % (NRMSE, zero initial state) of each input's model on each input's record", "%");
  json xrows = json::array();
  for (const auto& name : id.inputs) xrows.push_back(fmt::format("model from {}", name));
  xv["row_labels"] = xrows;
  json xcols = json::array();
  for (std::size_t j = 0; j < m; ++j) {
    std::vector<double> v(m);
    for (std::size_t i = 0; i < m; ++i) v[i] = fit[i][j];
    xcols.push_back({{"key", id.inputs[j]}, {"label", fmt::format("on {} record", id.inputs[j])}, {"ours", v}});
  }
  xv["columns"] = xcols;
  xv["note"] = "The thesis tested every input's transfer function on every input and selected the "
               "step model (§4.2); we select the model with the best mean fit on the other records.";
  c.tables.push_back(xv);

  // Drive-model mode for shaping (ωn = 1/Tw, ζ = Zeta, §4.2).
  const auto wn = c.drive->natural_frequency_rad_s();
  const auto zeta = c.drive->damping_ratio();
  if (wn && zeta && *zeta < 1.0) {
    c.drive_mode = {true, shaping::Mode{*wn, *zeta}, "ωn = 1/Tw, ζ = Zeta of the selected model (§4.2)"};
  } else if (wn && zeta) {
    c.drive_mode = {false, shaping::Mode{*wn, *zeta},
                    fmt::format("ζ = {:.4f} ≥ 1: the drive model has no oscillatory mode; a shaper designed "
                                "from it is the identity (docs/design.md §2)", *zeta)};
  } else {
    c.drive_mode = {false, {}, "the model structure has no underdamped pair (U)"};
  }

  json section;
  section["selected_input"] = c.drive_input;
  section["drive_mode"] = {{"available", c.drive_mode.available},
                           {"natural_frequency_rad_s", c.drive_mode.mode.natural_frequency_rad_s},
                           {"damping_ratio", c.drive_mode.mode.damping_ratio},
                           {"note", c.drive_mode.note}};
  json models = json::array();
  for (std::size_t i = 0; i < m; ++i) {
    json fitted = json::object();
    for (const auto& pe : estimates[i].parameters) fitted[pe.name] = {{"value", pe.value}, {"std", pe.std_dev}};
    models.push_back({{"input", id.inputs[i]}, {"structure", estimates[i].model.code()},
                      {"parameters", fitted}, {"fit_percent", fit[i][i]}, {"loss", estimates[i].loss},
                      {"converged", estimates[i].converged}, {"trusted", trust[i].trusted},
                      {"warnings", trust[i].warnings}});
  }
  section["models"] = models;
  c.sections["identification"] = section;

  // Figures 4.16/4.17: the selected model against each record.
  for (std::size_t j = 0; j < m; ++j) {
    const auto cmp = ident::compare(c.drive->model, experiments[j], ident::CompareOptions{});
    const auto time = c.unshaped_runs(id.inputs[j]).front().time_s;
    const std::string file = fmt::format("identification_{}.csv", id.inputs[j]);
    const std::string unit = speed_mode(c) ? "deg_s" : "deg";
    write_data_csv(c, file,
                   {"time_s", speed_mode(c) ? "input_v" : "input_deg", fmt::format("measured_{}", unit),
                    fmt::format("model_{}", unit)},
                   {&time, &experiments[j].input, &experiments[j].output, &cmp.simulated.values});
    c.figures.push_back({{"id", fmt::format("identification-{}", id.inputs[j])},
                         {"thesis_figure", speed_mode(c) ? "4.16" : "4.17"},
                         {"kind", "time-series"},
                         {"title", fmt::format("Identified model ({}) and experiment, {} (fit {:.1f} %)",
                                               c.drive_input, c.p.input(id.inputs[j]).label, cmp.fit_percent)},
                         {"file", c.data_file(file)},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", speed_mode(c) ? "motor speed (deg/s)" : "motor angle (deg)"},
                         {"series", {{{"column", fmt::format("measured_{}", unit)}, {"label", "experiment (simulated rig)"}},
                                     {{"column", fmt::format("model_{}", unit)}, {"label", "identified model"}}}}});
  }
}

void stage_link_mode(Context& c) {
  const auto& lm = c.p.link_mode;
  if (lm.input.empty()) {
    c.link_mode = {false, {}, "no [link_mode] in the protocol"};
    return;
  }
  const InputSpec& in = c.p.input(lm.input);
  const auto& runs = c.unshaped_runs(lm.input);
  std::vector<double> wn, zeta, fits;
  json per_run = json::array();
  std::optional<std::pair<std::size_t, ident::ModeIdentification>> example;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Record& r = runs[i];
    const std::vector<double> motor = speed_mode(c) ? motor_speed_deg_s(r, true) : r.motor_angle_deg;
    const double t0 = (lm.start == "after-command" ? in.last_move_start_s
                                                   : settle_time_s(motor, r.sample_time_s, in.last_move_start_s)) +
                      lm.settle_after_move_s;
    const auto k0 = static_cast<std::size_t>(std::llround(t0 / r.sample_time_s));
    const auto k1 = std::min(r.size(), k0 + static_cast<std::size_t>(std::llround(lm.window_s / r.sample_time_s)));
    if (k1 <= k0 + 50) continue;
    UniformSeries window;
    window.start_s = r.time_s[k0];
    window.sample_time_s = r.sample_time_s;
    window.values.assign(r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(k0),
                         r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(k1));
    try {
      ident::ModeOptions mo;
      mo.modes = 1;
      mo.max_damping_ratio = lm.max_damping_ratio;
      auto res = ident::identify_free_response_modes(window, mo);
      if (res.modes.empty()) continue;
      wn.push_back(res.modes.front().natural_frequency_rad_s);
      zeta.push_back(res.modes.front().damping_ratio);
      fits.push_back(res.fit_percent);
      per_run.push_back({{"run", i + 1}, {"window_start_s", window.start_s},
                         {"natural_frequency_hz", res.modes.front().natural_frequency_hz()},
                         {"damping_ratio", res.modes.front().damping_ratio}, {"fit_percent", res.fit_percent}});
      if (!example) example.emplace(i, std::move(res));
    } catch (const std::exception& e) {
      per_run.push_back({{"run", i + 1}, {"error", e.what()}});
    }
  }
  json section;
  section["input"] = lm.input;
  section["runs"] = per_run;
  if (wn.empty()) {
    c.link_mode = {false, {}, "no oscillatory mode found in the gyro's free response"};
    section["available"] = false;
    section["note"] = c.link_mode.note;
    c.sections["link_mode"] = section;
    c.log("link-mode: " + c.link_mode.note);
    return;
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  const double w = median(wn);
  const double z = median(zeta);
  c.link_mode = {true, shaping::Mode{w, z},
                 fmt::format("median over {} runs of the gyro's free response after the {}", wn.size(), in.label)};
  const MeanStd ws = mean_std(wn), zs = mean_std(zeta);
  section["available"] = true;
  section["natural_frequency_rad_s"] = w;
  section["natural_frequency_hz"] = w / (2.0 * 3.14159265358979323846);
  section["damping_ratio"] = z;
  section["natural_frequency_std_rad_s"] = ws.std;
  section["damping_ratio_std"] = zs.std;
  section["note"] = c.link_mode.note;
  c.sections["link_mode"] = section;
  c.log(fmt::format("link-mode: {:.3f} Hz, ζ = {:.4f} (median of {} runs)", w / 6.283185307179586, z, wn.size()));

  json table = make_table("link-mode", "parameters", "The link's residual mode, identified from the gyro (clearshape; docs/design.md §2)", "");
  table["row_labels"] = {"natural frequency (Hz)", "damping ratio", "runs used"};
  table["columns"] = {{{"key", "link-mode"}, {"label", "link mode (gyro)"},
                       {"ours", {w / 6.283185307179586, z, static_cast<double>(wn.size())}},
                       {"ours_std", {ws.std / 6.283185307179586, zs.std, nullptr}}},
                      {{"key", "drive-model"}, {"label", "drive model (Eq. 4.2)"},
                       {"ours", {c.drive_mode.mode.natural_frequency_rad_s / 6.283185307179586,
                                 c.drive_mode.mode.damping_ratio, nullptr}}}};
  table["note"] = "The thesis designs its shapers from the drive model's ωn and ζ (§3.3). In position "
                  "mode that model has ζ ≈ 1 and cannot give the published improvement, so clearshape "
                  "also identifies the link's own residual mode and reports both.";
  c.tables.push_back(table);

  if (example) {
    const auto& [i, res] = *example;
    const Record& r = runs[i];
    std::vector<double> t(res.fitted.values.size()), y(res.fitted.values.size());
    const auto k0 = static_cast<std::size_t>(std::llround(res.fitted.start_s / r.sample_time_s));
    for (std::size_t k = 0; k < t.size(); ++k) {
      t[k] = res.fitted.start_s + static_cast<double>(k) * r.sample_time_s;
      y[k] = r.link_rate_deg_s[std::min(k0 + k, r.size() - 1)];
    }
    write_data_csv(c, "link_mode_fit.csv", {"time_s", "gyro_deg_s", "fitted_deg_s"}, {&t, &y, &res.fitted.values});
    c.figures.push_back({{"id", "link-mode-fit"},
                         {"thesis_figure", nullptr},
                         {"kind", "time-series"},
                         {"title", fmt::format("Link residual mode: gyro free response and damped-sinusoid fit ({:.2f} Hz, ζ = {:.3f})",
                                               w / 6.283185307179586, z)},
                         {"file", c.data_file("link_mode_fit.csv")},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", "link rate (deg/s)"},
                         {"series", {{{"column", "gyro_deg_s"}, {"label", "gyro"}},
                                     {{"column", "fitted_deg_s"}, {"label", "fitted mode"}}}}});
  }
}

}  // namespace clearshape::study::detail
