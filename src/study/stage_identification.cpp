// Stage 2: drive identification (thesis Eq. 4.2, §4.2): the model structure fitted to each
// identification input's unshaped record, cross-validated on every other record; the selected
// model gives the drive-model mode for shaping (ωn = 1/Tw, ζ = Zeta).
#include <algorithm>

#include <fmt/format.h>

#include "identification.hpp"

namespace clearshape::study::detail {

namespace {

// Plan: one experiment per input, from its first unshaped run (input = what the driver received).
std::vector<ident::Experiment> identification_experiments(Context& c) {
  std::vector<ident::Experiment> experiments;
  for (const auto& name : c.p.identification.inputs) {
    const Record& r = c.unshaped_runs(name).front();
    ident::Experiment e;
    e.name = name;
    e.sample_time_s = r.sample_time_s;
    e.input = r.command_applied;  // what the driver received (the 30 Hz ramp / the D/A output)
    e.output = encoder_signal(c, r);
    experiments.push_back(std::move(e));
  }
  return experiments;
}

// Cross-validation (§4.2): every model simulated on every input's record; score = mean fit on the
// other records (on its own when there is only one).
void cross_validate(DriveFits& f) {
  const std::size_t m = f.estimates.size();
  f.fit.assign(m, std::vector<double>(m, 0.0));
  f.score.assign(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t j = 0; j < m; ++j) {
      ident::CompareOptions co;
      co.initial_state = ident::InitialState::zero;
      f.fit[i][j] = ident::compare(f.estimates[i].model, f.experiments[j], co).fit_percent;
      if (i != j || m == 1) {
        sum += f.fit[i][j];
        ++count;
      }
    }
    f.score[i] = sum / count;
  }
}

// The guard rails (ident/trust.hpp): an untrusted model is selected only when no model is trusted.
void select_model(Context& c, DriveFits& f) {
  for (const auto& e : f.estimates) f.trust.push_back(ident::assess(e));
  const bool any_trusted = std::any_of(f.trust.begin(), f.trust.end(), [](const auto& t) { return t.trusted; });
  f.best = 0;
  for (std::size_t i = 0; i < f.estimates.size(); ++i) {
    const bool eligible = f.trust[i].trusted || !any_trusted;
    const bool best_eligible = f.trust[f.best].trusted || !any_trusted;
    if (eligible && (!best_eligible || f.score[i] > f.score[f.best])) f.best = i;
  }
  for (std::size_t i = 0; i < f.estimates.size(); ++i) {
    for (const auto& w : f.trust[i].warnings) {
      c.log(fmt::format("identification: the {} model is not trusted: {}", c.p.identification.inputs[i], w));
    }
  }
}

// Run: fit every experiment, cross-validate, select.
DriveFits fit_drive_models(Context& c, const lti::ProcessStructure& structure,
                           std::vector<ident::Experiment> experiments) {
  const auto& id = c.p.identification;
  DriveFits f;
  f.experiments = std::move(experiments);
  for (const auto& e : f.experiments) {
    c.log(fmt::format("identification: fitting {} to the {} record ({} samples)", id.structure, e.name, e.size()));
    ident::ProcessFitOptions options;
    f.estimates.push_back(ident::estimate_process_model(structure, std::span(&e, 1), options));
  }
  cross_validate(f);
  select_model(c, f);
  return f;
}

using ParameterRows = std::vector<std::pair<std::string, std::string>>;  // name, unit

// One input's column of the 4.2-model table: the parameters with their 1σ, ωn, the fits.
json model_column(const Context& c, const DriveFits& f, std::size_t i, const ParameterRows& params) {
  const auto& est = f.estimates[i];
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
  values.push_back(f.fit[i][i]);
  stds.push_back(nullptr);
  values.push_back(f.score[i]);
  stds.push_back(nullptr);
  const std::string& input = c.p.identification.inputs[i];
  json col;
  col["key"] = input;
  col["label"] = fmt::format("{}{}", c.p.input(input).label, i == f.best ? " (selected)" : "");
  col["ours"] = values;
  col["ours_std"] = stds;
  return col;
}

// Tabulate: Eq. 4.2 parameters next to the thesis's (table 4.2-model).
void tabulate_drive_models(Context& c, const DriveFits& f) {
  const auto& id = c.p.identification;
  json table = make_table("4.2-model", "parameters",
                          fmt::format("Identified drive model, Eq. 4.2 ({}), per input; selected: {}",
                                      id.structure, c.drive_input), "");
  const ParameterRows params{
      {"Kp", speed_mode(c) ? "(deg/s)/V" : "deg/deg"}, {"Tz", "s"}, {"Zeta", "-"}, {"Tw", "s"}, {"Tp3", "s"}};
  json rows = json::array();
  for (const auto& [name, unit] : params) rows.push_back(fmt::format("{} ({})", name, unit));
  rows.push_back("ωn = 1/Tw (rad/s)");
  rows.push_back("fit on own record (%)");
  rows.push_back("mean cross-validation fit (%)");
  table["row_labels"] = rows;
  json cols = json::array();
  for (std::size_t i = 0; i < f.estimates.size(); ++i) cols.push_back(model_column(c, f, i, params));
  const auto& t = id.thesis;
  if (t.kp != 0.0 || t.tw_s > 0.0) {  // a protocol without the thesis's model (another rig) gets no column of zeros
    json thesis_col;
    thesis_col["key"] = "thesis";
    thesis_col["label"] = fmt::format("thesis ({} model)", t.selected_input.empty() ? "selected" : t.selected_input);
    if (!t.selected_input.empty()) thesis_col["input"] = t.selected_input;  // compared with ours from that input
    // ωn: the thesis prints the formula (1/Tw), not a number; a recomputation is not the thesis's number.
    thesis_col["thesis"] = {t.kp, t.tz_s, t.zeta, t.tw_s, t.tp3_s, nullptr, nullptr, nullptr};
    cols.push_back(thesis_col);
  }
  table["columns"] = cols;
  const auto& ours = c.drive->model.parameters();
  table["headline"] = {{"selected_input", c.drive_input},
                       {"ours", {{"kp", ours.kp}, {"tz_s", ours.tz}, {"zeta", ours.zeta}, {"tw_s", ours.tw}, {"tp3_s", ours.tp3}}},
                       {"thesis", {{"kp", t.kp}, {"tz_s", t.tz_s}, {"zeta", t.zeta}, {"tw_s", t.tw_s}, {"tp3_s", t.tp3_s}}}};
  table["note"] = speed_mode(c)
      ? "Speed mode: the output is the encoder angle differentiated and low-passed by the 4th-order "
        "30 rad/s Butterworth (§3.3), so the identified model contains the filter (§4.2) — its ωn "
        "and ζ are those of drive × filter, not of the drive alone."
      : "Position mode: input = the position the driver received (the 30 Hz pulse train, a ramp "
        "for a step), output = the encoder angle.";
  c.tables.push_back(table);
}

// Tabulate: the cross-validation matrix (table 4.2-cross-validation).
void tabulate_cross_validation(Context& c, const DriveFits& f) {
  const auto& inputs = c.p.identification.inputs;
  const std::size_t m = f.estimates.size();
  json xv = make_table("4.2-cross-validation", "matrix",
                       "Cross-validation: fit % (NRMSE, zero initial state) of each input's model on each input's record", "%");
  json xrows = json::array();
  for (const auto& name : inputs) xrows.push_back(fmt::format("model from {}", name));
  xv["row_labels"] = xrows;
  json xcols = json::array();
  for (std::size_t j = 0; j < m; ++j) {
    std::vector<double> v(m);
    for (std::size_t i = 0; i < m; ++i) v[i] = f.fit[i][j];
    xcols.push_back({{"key", inputs[j]}, {"label", fmt::format("on {} record", inputs[j])}, {"ours", v}});
  }
  xv["columns"] = xcols;
  xv["note"] = "The thesis tested every input's transfer function on every input and selected the "
               "step model (§4.2); we select the model with the best mean fit on the other records.";
  c.tables.push_back(xv);
}

// Drive-model mode for shaping (ωn = 1/Tw, ζ = Zeta, §4.2).
ModeResult drive_mode_of(const ident::ProcessEstimate& drive) {
  const auto wn = drive.natural_frequency_rad_s();
  const auto zeta = drive.damping_ratio();
  if (wn && zeta && *zeta < 1.0) {
    return {true, shaping::Mode{*wn, *zeta}, "ωn = 1/Tw, ζ = Zeta of the selected model (§4.2)"};
  }
  if (wn && zeta) {
    return {false, shaping::Mode{*wn, *zeta},
            fmt::format("ζ = {:.4f} ≥ 1: the drive model has no oscillatory mode; a shaper designed "
                        "from it is the identity (docs/design.md §2)", *zeta)};
  }
  return {false, {}, "the model structure has no underdamped pair (U)"};
}

// results.json sections.identification: the selection, the drive mode and every fitted model.
void record_identification_section(Context& c, const DriveFits& f) {
  json section;
  section["selected_input"] = c.drive_input;
  section["drive_mode"] = {{"available", c.drive_mode.available},
                           {"natural_frequency_rad_s", c.drive_mode.mode.natural_frequency_rad_s},
                           {"damping_ratio", c.drive_mode.mode.damping_ratio},
                           {"note", c.drive_mode.note}};
  json models = json::array();
  for (std::size_t i = 0; i < f.estimates.size(); ++i) {
    const auto& est = f.estimates[i];
    json fitted = json::object();
    for (const auto& pe : est.parameters) fitted[pe.name] = {{"value", pe.value}, {"std", pe.std_dev}};
    models.push_back({{"input", c.p.identification.inputs[i]}, {"structure", est.model.code()},
                      {"parameters", fitted}, {"fit_percent", f.fit[i][i]}, {"loss", est.loss},
                      {"converged", est.converged}, {"trusted", f.trust[i].trusted},
                      {"warnings", f.trust[i].warnings}});
  }
  section["models"] = models;
  c.sections["identification"] = section;
}

// Figures 4.16/4.17: the selected model against each record (data/identification_<input>.csv).
void write_identification_figures(Context& c, const DriveFits& f) {
  const auto& inputs = c.p.identification.inputs;
  const std::string unit = speed_mode(c) ? "deg_s" : "deg";
  for (std::size_t j = 0; j < f.experiments.size(); ++j) {
    const auto cmp = ident::compare(c.drive->model, f.experiments[j], ident::CompareOptions{});
    const auto time = c.unshaped_runs(inputs[j]).front().time_s;
    const std::string file = fmt::format("identification_{}.csv", inputs[j]);
    write_data_csv(c, file,
                   {"time_s", speed_mode(c) ? "input_v" : "input_deg", fmt::format("measured_{}", unit),
                    fmt::format("model_{}", unit)},
                   {&time, &f.experiments[j].input, &f.experiments[j].output, &cmp.simulated.values});
    c.figures.push_back({{"id", fmt::format("identification-{}", inputs[j])},
                         {"thesis_figure", speed_mode(c) ? "4.16" : "4.17"},
                         {"kind", "time-series"},
                         {"title", fmt::format("Identified model ({}) and experiment, {} (fit {:.1f} %)",
                                               c.drive_input, c.p.input(inputs[j]).label, cmp.fit_percent)},
                         {"file", c.data_file(file)},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", speed_mode(c) ? "motor speed (deg/s)" : "motor angle (deg)"},
                         {"series", {{{"column", fmt::format("measured_{}", unit)}, {"label", "experiment (simulated rig)"}},
                                     {{"column", fmt::format("model_{}", unit)}, {"label", "identified model"}}}}});
  }
}

}  // namespace

void stage_identification(Context& c) {
  const auto& id = c.p.identification;
  if (id.inputs.empty()) {
    c.log("identification: no inputs in the protocol, skipped");
    return;
  }
  const lti::ProcessStructure structure = lti::ProcessStructure::parse(id.structure);
  const DriveFits fits = fit_drive_models(c, structure, identification_experiments(c));
  c.drive = fits.estimates[fits.best];
  c.drive_input = id.inputs[fits.best];
  c.log(fmt::format("identification: selected the {} model (mean cross-validation fit {:.1f} %)",
                    c.drive_input, fits.score[fits.best]));
  tabulate_drive_models(c, fits);
  tabulate_cross_validation(c, fits);
  c.drive_mode = drive_mode_of(*c.drive);
  record_identification_section(c, fits);
  write_identification_figures(c, fits);
}

}  // namespace clearshape::study::detail
