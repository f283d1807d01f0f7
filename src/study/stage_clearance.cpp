// Stage 4: the clearance model (thesis §4.2, Fig. 4.18–4.20): the identified drive plus a link on
// a torsional play with the Eq. 4.3 contact law and the joint's friction (Eq. 2.9, regularized),
// whose parameters are fitted (clearance_fit.cpp) so that the model's link rate matches the mean
// gyro record; the agreement is reported with Eq. 4.1 as in the thesis (0.0067 speed / 0.0042
// position). In three steps: plan the fit problem from the protocol and the runs → run the fit
// and its reference models → tabulate (log, table 4.3-clearance, results section, figure).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/study/fit_clearance.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"
#include "rig_tests.hpp"  // opt()

namespace clearshape::study {

namespace detail {

namespace {

// A torque for the report's text: 3 significant digits in N·m, mN·m or µN·m, never "4.92e-05 N·m".
std::string torque_text(double n_m) {
  const double a = std::abs(n_m);
  if (a >= 1.0 || a == 0.0 || !std::isfinite(a)) return fmt::format("{:.3g} N·m", n_m);
  if (a >= 1e-3) return fmt::format("{:.3g} mN·m", 1e3 * n_m);
  return fmt::format("{:.3g} µN·m", 1e6 * n_m);
}

// --- Plan: the fit problem (start model, the drive's command, the mean gyro record).
struct ClearancePlan {
  ClearanceFitProblem fp;
  std::vector<double> measured;  ///< the mean gyro record (filtered with filter_gyro)
};

// The mean gyro record of the input's unshaped runs and the command the drive received (first run).
void plan_records(Context& c, ClearancePlan& plan) {
  const auto& cl = c.p.clearance;
  const auto& runs = c.unshaped_runs(cl.input);
  const Record& first = runs.front();
  ClearanceFitProblem& fp = plan.fp;
  fp.duration_s = std::min(cl.window_s, first.time_s.back());
  const std::size_t n = sample_count(fp.duration_s, first.sample_time_s);
  fp.drive_command.sample_time_s = first.sample_time_s;
  fp.drive_command.values.assign(first.command_applied.begin(),
                                 first.command_applied.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<double> measured(n, 0.0);
  for (const auto& r : runs) {
    for (std::size_t k = 0; k < n; ++k) measured[k] += r.link_rate_deg_s[k] / static_cast<double>(runs.size());
  }
  // With filter_gyro the measurement is filtered: the identified speed drive already contains the
  // §3.3 filter (§4.2), so the model's link rate is compared with a filtered gyro.
  if (cl.filter_gyro) {
    measured = dsp::sosfilt(dsp::thesis_speed_filter(first.sample_time_s), measured);
  }
  fp.measured_link_rate_deg_s = measured;
  plan.measured = std::move(measured);
}

ClearancePlan plan_clearance(Context& c) {
  const auto& cl = c.p.clearance;
  ClearancePlan plan;
  ClearanceFitProblem& fp = plan.fp;
  fp.start.mode = c.p.mode;
  fp.start.drive = c.drive->model;
  fp.start.link_inertia_kg_m2 = cl.link_inertia_kg_m2;
  fp.start.play_rad = deg_to_rad(cl.play_deg);
  fp.start.stiffness = cl.stiffness_n_m_per_rad_pow_n;
  fp.start.exponent = cl.exponent;
  fp.start.damping = cl.damping_n_m_s_per_rad;
  fp.start.contact_law = contact_law_from_string(cl.contact_law);
  fp.start.restitution = cl.restitution;
  const bool flores = fp.start.contact_law == ContactLawChoice::flores;
  plan_records(c, plan);
  for (const auto& f : cl.fit) {
    if (f == "damping" && !flores && !(cl.damping_n_m_s_per_rad > 0.0)) continue;  // log-parametrised
    fp.free.push_back(f);
  }
  // A fitted play comes with the joint's friction (Eq. 2.9): it decides how a link that leaves its
  // flank crosses the play and where it stops.
  if (std::find(fp.free.begin(), fp.free.end(), "play") != fp.free.end()) {
    fp.free.insert(fp.free.end(), {"coulomb", "viscous"});
  }
  std::sort(fp.free.begin(), fp.free.end());
  fp.free.erase(std::unique(fp.free.begin(), fp.free.end()), fp.free.end());
  if (c.link_mode.available) {
    fp.link_natural_frequency_rad_s = c.link_mode.mode.natural_frequency_rad_s;
    fp.link_damping_ratio = c.link_mode.mode.damping_ratio;
  }
  fp.max_evaluations = cl.max_evaluations;
  // The gyroscope's digital low-pass: the thesis does not say which ITG-3205 DLPF setting it
  // used, so the record chooses among the chip's settings (and none).
  fp.sensor_low_pass_grid_hz = {0.0};
  for (auto lp : {plant::GyroLowPass::hz256, plant::GyroLowPass::hz188, plant::GyroLowPass::hz98,
                  plant::GyroLowPass::hz42, plant::GyroLowPass::hz20, plant::GyroLowPass::hz10, plant::GyroLowPass::hz5}) {
    fp.sensor_low_pass_grid_hz.push_back(plant::bandwidth_hz(lp));
  }
  return plan;
}

// --- Run: the fit, the agreement of its start and of a rigid link, and their descriptions.
struct ClearanceRun {
  ClearanceFitResult fit;
  double rigid_agreement = 0.0;  ///< a rigid link (no play: link = motor), the reference to beat
  double start_agreement = 0.0;
  bool friction_fitted = false;        ///< the fit's free parameters included the joint's friction
  bool friction_dropped = false;       ///< fitted, not determined by the record, refitted without
  double dropped_coulomb_n_m = 0.0;    ///< the undetermined fit's Coulomb torque, its relative 1σ
  double dropped_coulomb_std = 0.0;    ///< and its RMS error
  double dropped_rms_deg_s = 0.0;
  std::string status, grid_text, fitted_names, identifiable, weak;
};

void describe_run(const ClearanceFitProblem& fp, ClearanceRun& run) {
  const ClearanceFitResult& fit = run.fit;
  for (const auto& st : fit.starts) {
    run.grid_text += fmt::format("{}n {} {:.3g}: RMS {:.4g} deg/s, {} ({} evaluations)", run.grid_text.empty() ? "" : "; ",
                                 st.exponent_free ? "free →" : "=", st.exponent, st.rms_error_deg_s, st.termination,
                                 st.evaluations);
  }
  run.status = fp.free.empty()
                   ? std::string("not fitted (no free parameters)")
                   : fmt::format("NLopt BOBYQA: {} after {} model evaluations ({}){}", fit.termination, fit.evaluations,
                                 fit.converged ? "converged: step/function tolerance met" : "NOT converged",
                                 fit.starts.size() > 1 ? "; multi-start over the exponent" : "");
  run.fitted_names = fp.free.empty() ? std::string("nothing") : fmt::format("{}", fmt::join(fp.free, ", "));
  for (const auto& q : fit.parameters) {
    if (!q.free) continue;
    const std::string item = q.name == "exponent" ? fmt::format("n ± {:.2g}", q.std_error)
                                                  : fmt::format("{} ± {:.2g} %", q.name, 100.0 * q.std_error);
    std::string& list = q.identifiable ? run.identifiable : run.weak;
    list += fmt::format("{}{}{}", list.empty() ? "" : ", ", item, q.at_bound ? " (at its bound)" : "");
  }
}

// The joint's friction is kept only where the record determines it: a Coulomb torque whose 1σ
// exceeds its value is not told apart from 0 by the record, and the fit without friction (fewer
// parameters, the same record) is the model.
bool friction_determined(const ClearanceFitResult& fit) {
  for (const auto& q : fit.parameters) {
    if (q.name == "coulomb") return q.free && q.value > 0.0 && std::isfinite(q.std_error) && q.std_error < 1.0;
  }
  return false;
}

ClearanceRun run_clearance(ClearancePlan& plan) {
  ClearanceFitProblem& fp = plan.fp;
  ClearanceRun run;
  run.fit = fit_clearance(fp);
  run.friction_fitted = std::find(fp.free.begin(), fp.free.end(), "coulomb") != fp.free.end();
  if (run.friction_fitted && !friction_determined(run.fit)) {
    run.friction_dropped = true;
    run.dropped_coulomb_n_m = run.fit.model.coulomb_n_m;
    for (const auto& q : run.fit.parameters) {
      if (q.name == "coulomb") run.dropped_coulomb_std = q.std_error;
    }
    run.dropped_rms_deg_s = run.fit.rms_error_deg_s;
    std::erase_if(fp.free, [](const std::string& f) { return f == "coulomb" || f == "viscous"; });
    run.fit = fit_clearance(fp);
  }
  ClearanceModel rigid = run.fit.model;
  rigid.play_rad = 0.0;
  const auto sensed_rate = [&](const ClearanceModel& m) {
    return sensed_link_rate_deg_s(fp, simulate_drive_command(m, fp.drive_command, fp.duration_s), run.fit.sensor_low_pass_hz);
  };
  run.rigid_agreement = clearance_agreement(plan.measured, sensed_rate(rigid));
  run.start_agreement = clearance_agreement(plan.measured, sensed_rate(run.fit.start_model));
  describe_run(fp, run);
  return run;
}

// --- Tabulate.
void log_clearance(Context& c, const ClearancePlan& plan, const ClearanceRun& run) {
  const ClearanceModel& fitted = run.fit.model;
  const bool friction = fitted.coulomb_n_m > 0.0 || fitted.viscous_n_m_s_per_rad > 0.0 ||
                        std::find(plan.fp.free.begin(), plan.fp.free.end(), "coulomb") != plan.fp.free.end();
  const bool flores = fitted.contact_law == ContactLawChoice::flores;
  c.log(fmt::format("clearance: K = {:.4g}, {} = {:.4g}, play = {:.4g}°, n = {:.3g}{}, Eq. 4.1 agreement {:.4f} ({})",
                    fitted.stiffness, flores ? "e" : "D", flores ? fitted.restitution : fitted.damping,
                    rad_to_deg(fitted.play_rad), fitted.exponent,
                    friction ? fmt::format(", friction c = {:.3g} N·m, b = {:.3g} N·m·s/rad", fitted.coulomb_n_m,
                                           fitted.viscous_n_m_s_per_rad)
                             : std::string(),
                    run.fit.agreement, run.status));
  if (!run.fit.converged && !plan.fp.free.empty()) {
    c.log(fmt::format("clearance: warning: the contact fit did not converge ({}); raise [clearance] max_evaluations",
                      run.fit.termination));
  }
}

json clearance_table(const Context& c, const ClearanceRun& run) {
  const auto& cl = c.p.clearance;
  const ClearanceFitResult& fit = run.fit;
  const ClearanceModel& fitted = fit.model;
  const ClearanceModel& start = fit.start_model;
  json table = make_table("4.3-clearance", "parameters",
                          fmt::format("Clearance model ({}) calibrated to the gyro record of the {}",
                                      fit.model.contact_law == ContactLawChoice::flores ? "Flores restitution law" : "Eq. 4.3",
                                      c.p.input(cl.input).label), "");
  const double J = fitted.link_inertia_kg_m2;
  const bool flores = fitted.contact_law == ContactLawChoice::flores;  // e in D's row, no D/J
  const auto dissipation = [flores](const ClearanceModel& m) { return flores ? m.restitution : m.damping; };
  const json null;
  const auto per_inertia = [flores, J, &null](const ClearanceModel& m) { return flores ? null : json(m.damping / J); };
  table["row_labels"] = {"K (N·m/rad^n)", flores ? "restitution e (Flores law)" : "D (N·m·s/rad)", "exponent n", "total play (deg)",
                         "link inertia (kg·m²)", "Eq. 4.1 agreement", "RMS error (deg/s)",
                         "K/J (rad^(1−n)/s²)", flores ? "D/J (1/s; none: Flores law)" : "D/J (1/s)", "gyro low-pass (Hz, 0 = none)", "model evaluations",
                         "converged (1 = yes)"};
  table["columns"] = {
      {{"key", "ours"}, {"label", "clearshape (fitted)"},
       {"ours", {fitted.stiffness, dissipation(fitted), fitted.exponent, rad_to_deg(fitted.play_rad), J, fit.agreement,
                 fit.rms_error_deg_s, fitted.stiffness / J, per_inertia(fitted), fit.sensor_low_pass_hz,
                 fit.evaluations, fit.converged ? 1 : 0}}},
      {{"key", "start"}, {"label", c.link_mode.available ? "start (link mode, then K–D pre-fit and play scan)" : "start (protocol values, then K–D pre-fit and play scan)"},
       {"ours", {start.stiffness, dissipation(start), start.exponent, rad_to_deg(start.play_rad), J, run.start_agreement,
                 fit.start_rms_error_deg_s, start.stiffness / J, per_inertia(start), fit.sensor_low_pass_hz, null,
                 null}}},
      {{"key", "rigid"}, {"label", "rigid link (no play), for reference"},
       {"ours", {null, null, null, 0.0, J, run.rigid_agreement, null, null, null, fit.sensor_low_pass_hz, null, null}}},
      {{"key", "thesis"}, {"label", "thesis (units unstated)"},
       {"thesis", {opt(cl.thesis_stiffness), opt(cl.thesis_damping), cl.thesis_stiffness ? json(1.5) : null, null, null,
                   opt(cl.thesis_agreement), null, null, null, null, null, null}}}};
  table["headline"] = {{"agreement_ours", fit.agreement}, {"agreement_thesis", opt(cl.thesis_agreement)}};
  table["note"] = fmt::format(
      "Fitted: {}; {}. Searches: {}. Identifiable at the optimum (local 1σ below 10 %, from σ²(JᵀJ)⁻¹ with the "
      "residual's autocorrelation): {}{}.{} The thesis states K and D without units and with a link of unknown "
      "inertia, so only the agreement is comparable; our model fixes the link inertia at {} kg·m² (only K/J and D/J "
      "are identifiable from the gyro). The start is the identified link mode read as a linear flank "
      "(K/J = ω², D/J = 2ζω); for n ≠ 1 the stiffness is carried at the reference deflection {:.3g}° "
      "(K·δ_ref^(n−1) held). The model's link rate passes through the gyroscope's first-order low-pass at the "
      "ITG-3205 DLPF setting that explains the record best ({}; the thesis does not state its setting).",
      run.fitted_names, run.status, run.grid_text.empty() ? std::string("none") : run.grid_text,
      run.identifiable.empty() ? std::string("none") : run.identifiable, run.weak.empty() ? "" : "; weakly determined: " + run.weak,
      cl.filter_gyro ? " The gyro record passes through the 30 rad/s filter of §3.3 before the comparison: the "
                       "identified speed model contains that filter (§4.2), so its link rate is a filtered one; "
                       "the link's own oscillation is filtered in the record but not in the model, so K and D "
                       "here are effective values of that comparison, not the joint's (the link-mode start is)."
                     : "",
      J, rad_to_deg(fit.reference_deflection_rad),
      fit.sensor_low_pass_hz > 0.0 ? fmt::format("{:g} Hz", fit.sensor_low_pass_hz) : std::string("none"));
  if (run.friction_dropped) {
    table["note"] = table["note"].get<std::string>() +
                    fmt::format(" The joint's friction (Eq. 2.9) was fitted too (Coulomb {} ± {:.0f} %, RMS {:.4g} "
                                "deg/s), but its 1σ exceeds its value: this record does not determine it, so the model "
                                "has none.",
                                torque_text(run.dropped_coulomb_n_m), 100.0 * run.dropped_coulomb_std,
                                run.dropped_rms_deg_s);
  }
  return table;
}

json parameters_json(const ClearanceFitResult& fit) {
  json parameters = json::array();
  for (const auto& q : fit.parameters) {
    const bool deg = q.name == "play";
    parameters.push_back({{"name", q.name},
                          {"value", deg ? rad_to_deg(q.value) : q.value},
                          {"start", deg ? rad_to_deg(q.start) : q.start},
                          {"unit", clearance_parameter_unit(q.name)},
                          {"free", q.free},
                          {"at_bound", q.at_bound},
                          {"std_error", std::isfinite(q.std_error) ? json(q.std_error) : json()},
                          {"std_error_kind", q.name == "exponent" ? "absolute"
                                             : q.name == "coulomb" || q.name == "viscous" || q.name == "restitution"
                                                 ? "relative (1σ / value)"
                                                                                          : "relative (1σ of the log)"},
                          {"identifiable", q.identifiable}});
  }
  return parameters;
}

json clearance_section(const Context& c, const ClearanceRun& run) {
  const ClearanceFitResult& fit = run.fit;
  const ClearanceModel& fitted = fit.model;
  const double J = fitted.link_inertia_kg_m2;
  json starts = json::array();
  for (const auto& st : fit.starts) {
    starts.push_back({{"exponent", st.exponent}, {"exponent_free", st.exponent_free},
                      {"rms_error_deg_s", st.rms_error_deg_s}, {"evaluations", st.evaluations},
                      {"termination", st.termination}});
  }
  json low_pass_scan = json::array();
  for (const auto& [hz, e] : fit.sensor_low_pass_scan) low_pass_scan.push_back({{"hz", hz}, {"rms_error_deg_s", e}});
  json section = {{"stiffness_n_m_per_rad_pow_n", fitted.stiffness},
          {"damping_n_m_s_per_rad", fitted.damping},
          {"exponent", fitted.exponent},
          {"gyro_filtered", c.p.clearance.filter_gyro},
          {"play_deg", rad_to_deg(fitted.play_rad)},
          {"coulomb_n_m", fitted.coulomb_n_m},
          {"viscous_n_m_s_per_rad", fitted.viscous_n_m_s_per_rad},
          {"friction_regularization_rad_s", fitted.friction_regularization_rad_s},
          {"friction_fit", {{"fitted", run.friction_fitted},
                            {"kept", !run.friction_dropped},
                            {"dropped_coulomb_n_m", run.friction_dropped ? json(run.dropped_coulomb_n_m) : json()},
                            {"dropped_coulomb_rel_std", run.friction_dropped && std::isfinite(run.dropped_coulomb_std)
                                                            ? json(run.dropped_coulomb_std) : json()},
                            {"dropped_rms_error_deg_s", run.friction_dropped ? json(run.dropped_rms_deg_s) : json()}}},
          {"link_inertia_kg_m2", J},
          {"stiffness_over_inertia", fitted.stiffness / J},
          {"damping_over_inertia_1_s", fitted.damping / J},
          {"agreement", fit.agreement},
          {"start_agreement", run.start_agreement},
          {"rigid_agreement", run.rigid_agreement},
          {"rms_error_deg_s", fit.rms_error_deg_s},
          {"reference_deflection_deg", rad_to_deg(fit.reference_deflection_rad)},
          {"gyro_low_pass_hz", fit.sensor_low_pass_hz},
          {"gyro_low_pass_scan", low_pass_scan},
          {"evaluations", fit.evaluations},
          {"termination", fit.termination},
          {"converged", fit.converged},
          {"status", run.status},
          {"starts", starts},
          {"parameters", parameters_json(fit)}};
  if (fitted.contact_law == ContactLawChoice::flores) {  // the default writes nothing: byte-identical
    section["contact_law"] = to_string(fitted.contact_law);
    section["restitution"] = fitted.restitution;
  }
  return section;
}

// Figures 4.19/4.20: the model's link rate (through the gyro's low-pass) against the mean gyro.
void clearance_figure(Context& c, const ClearancePlan& plan, const ClearanceRun& run) {
  const auto& cl = c.p.clearance;
  const ClearanceFitResult& fit = run.fit;
  const ModelResponse r = simulate_drive_command(fit.model, plan.fp.drive_command, plan.fp.duration_s);
  std::vector<double> time(r.time_s.begin(), r.time_s.end());
  std::vector<double> model_rate_deg_s = sensed_link_rate_deg_s(plan.fp, r, fit.sensor_low_pass_hz);
  std::vector<double> measured = plan.measured;
  const std::size_t m = std::min({time.size(), model_rate_deg_s.size(), measured.size()});
  time.resize(m);
  model_rate_deg_s.resize(m);
  measured.resize(m);
  write_data_csv(c, "clearance_fit.csv", {"time_s", "gyro_mean_deg_s", "model_link_rate_deg_s"},
                 {&time, &measured, &model_rate_deg_s});
  c.figures.push_back({{"id", "clearance-fit"},
                       {"thesis_figure", c.p.mode == rig::CommandMode::speed ? "4.19" : "4.20"},
                       {"kind", "time-series"},
                       {"title", fmt::format("Model with clearance vs gyro, {} (Eq. 4.1 agreement {:.4f}; thesis {})",
                                             c.p.input(cl.input).label, fit.agreement,
                                             cl.thesis_agreement ? fmt::format("{:g}", *cl.thesis_agreement) : "—")},
                       {"file", c.data_file("clearance_fit.csv")},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", "link rate (deg/s)"},
                       {"series", {{{"column", "gyro_mean_deg_s"}, {"label", "experiment (mean gyro)"}},
                                   {{"column", "model_link_rate_deg_s"}, {"label", "model with clearance (through the gyro's low-pass)"}}}}});
}

// --- The per-run joint fit (study/model.hpp fit_clearance_runs, issue 19): the input's runs one
// by one, each with its own start place in the play and flank damping, never their average. In
// position mode with the dashpot law, whenever the play is fitted; its model replaces the
// averaged fit's where it determines the joint: play and K to 10 %, the Coulomb torque told apart
// from 0 (1σ below its value, the averaged fit's own rule for friction), n = 1 not rejected.
struct PerRunFit {
  bool tried = false;
  bool adopted = false;
  std::string reason;  ///< why it was not tried or not adopted
  ClearanceRunsFitResult fit;
};

PerRunFit run_per_run_fit(Context& c, const ClearancePlan& plan) {
  const auto& cl = c.p.clearance;
  PerRunFit out;
  const bool play_free = std::find(cl.fit.begin(), cl.fit.end(), "play") != cl.fit.end();
  if (c.p.mode != rig::CommandMode::position || cl.filter_gyro || !play_free ||
      plan.fp.start.contact_law != ContactLawChoice::dashpot) {
    out.reason = "not tried: it fits a position-mode record with the dashpot law (Eq. 4.3) when the play is fitted";
    return out;
  }
  ClearanceRunsFitProblem rp;
  rp.start = plan.fp.start;
  rp.start.exponent = 1.0;  // a linear flank held; n free is the checked alternative
  rp.start.coulomb_n_m = 0.0;
  rp.start.viscous_n_m_s_per_rad = 0.0;
  if (!(rp.start.damping > 0.0)) rp.start.damping = 0.1;
  rp.duration_s = plan.fp.duration_s;
  rp.rest_s = c.p.measure.bias_window_s;
  rp.link_natural_frequency_rad_s = plan.fp.link_natural_frequency_rad_s;
  rp.link_damping_ratio = plan.fp.link_damping_ratio;
  rp.sensor_low_pass_grid_hz = plan.fp.sensor_low_pass_grid_hz;
  rp.threads = std::max(1, c.threads);
  for (const Record& r : c.unshaped_runs(cl.input)) {
    const std::size_t n = std::min(r.size(), sample_count(rp.duration_s, r.sample_time_s));
    ClearanceRunRecord run;
    run.id = r.id;
    run.drive_command.sample_time_s = r.sample_time_s;
    run.drive_command.values.assign(r.command_applied.begin(), r.command_applied.begin() + static_cast<std::ptrdiff_t>(n));
    run.link_rate_deg_s.assign(r.link_rate_deg_s.begin(), r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(n));
    rp.runs.push_back(std::move(run));
  }
  out.tried = true;
  out.fit = fit_clearance_runs(rp);
  const ClearanceModelSigma s = out.fit.sigma();
  const bool determined = std::isfinite(s.play_rel_sigma) && s.play_rel_sigma < 0.1 && std::isfinite(s.stiffness_rel_sigma) &&
                          s.stiffness_rel_sigma < 0.1;
  const bool friction = std::isfinite(s.coulomb_rel_sigma) && s.coulomb_rel_sigma < 1.0;
  out.adopted = determined && friction && !out.fit.exponent_free_better;
  out.reason = out.adopted ? "adopted: play and K determined to 10 %, the Coulomb torque told apart from 0, n = 1 not rejected"
               : !determined ? fmt::format("not adopted: play ± {:.3g} %, K ± {:.3g} % (both must be below 10 %)",
                                           100.0 * s.play_rel_sigma, 100.0 * s.stiffness_rel_sigma)
               : !friction   ? fmt::format("not adopted: the Coulomb torque ± {:.3g} % is not told apart from 0",
                                           100.0 * s.coulomb_rel_sigma)
                             : fmt::format("not adopted: n free fits significantly better (χ²₁ {:.3g} > 3.84, n {:.3g})",
                                           out.fit.exponent_chi2, out.fit.exponent_free_value);
  return out;
}

// The truth of a built-in simulated rig, for scoring (null for any other rig: its truth is hidden).
json simulated_truth(const Context& c) {
  const std::string kind = c.source ? c.source->kind() : std::string();
  const std::string prefix = "simulated-";
  if (kind.rfind(prefix, 0) != 0 || !rig::is_builtin_truth(kind.substr(prefix.size()))) return json();
  const rig::RigTruth t = rig::builtin_truth(kind.substr(prefix.size()));
  const auto& contact = t.contact(c.p.mode);
  return {{"rig", kind.substr(prefix.size())},
          {"play_deg", rad_to_deg(t.clearance_rad)},
          {"stiffness_n_m_per_rad_pow_n", contact.stiffness},
          {"exponent", contact.exponent},
          {"damping_n_m_s_per_rad", contact.damping},
          {"coulomb_n_m", t.joint_friction.coulomb},
          {"viscous_n_m_s_per_rad", t.joint_friction.viscous}};
}

json sigma_json(const ClearanceModelSigma& s) {
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(); };
  return {{"play_rel_sigma", num(s.play_rel_sigma)},
          {"stiffness_rel_sigma", num(s.stiffness_rel_sigma)},
          {"coulomb_rel_sigma", num(s.coulomb_rel_sigma)},
          {"damping_spread", num(s.damping_spread)}};
}

// The fit's scalars (per_run_fit) and its two lists, kept at the section's top level
// (per_run_parameters, per_run_starts) so that the report's all-numbers view nests no table twice.
json per_run_json(const PerRunFit& pr, json& parameters, json& runs) {
  json out = {{"tried", pr.tried}, {"adopted", pr.adopted}, {"status", pr.reason}};
  if (!pr.tried) return out;
  const ClearanceRunsFitResult& f = pr.fit;
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(); };
  parameters = json::array();
  for (const auto& q : f.parameters) {
    const bool deg = q.name == "play";
    parameters.push_back({{"name", q.name}, {"value", deg ? rad_to_deg(q.value) : q.value},
                          {"unit", clearance_parameter_unit(q.name)}, {"free", q.free},
                          {"std_error", num(q.std_error)},
                          {"std_error_kind", q.name == "exponent" ? "absolute" : "relative (1σ / value)"},
                          {"identifiable", q.identifiable}});
  }
  runs = json::array();
  for (std::size_t i = 0; i < f.run_ids.size(); ++i) {
    runs.push_back({{"id", f.run_ids[i]}, {"start_fraction", f.start_fraction[i]},
                    {"start_fraction_std", num(f.start_fraction_std[i])}, {"damping_n_m_s_per_rad", f.run_damping[i]},
                    {"rms_error_deg_s", f.run_rms_error_deg_s[i]}});
  }
  out["method"] = "each run with its own start place φ(0)/β and flank damping (nuisances), K, play, Coulomb and "
                  "viscous friction shared, n held at 1; Levenberg–Marquardt on the gyro records (docs/worn-coupling.md)";
  out["model_sigma"] = sigma_json(f.sigma());
  out["rms_error_deg_s"] = f.rms_error_deg_s;
  out["cvode_check_rms_error_deg_s"] = f.check_rms_error_deg_s;
  out["gyro_low_pass_hz"] = f.sensor_low_pass_hz;
  out["exponent_check"] = exponent_check_json(f);
  out["iterations"] = f.iterations;
  out["simulations"] = f.simulations;
  out["converged"] = f.converged;
  out["termination"] = f.termination;
  return out;
}

// The relative 1σ of the averaged fit's play, K and Coulomb torque (NaN where not fitted).
ClearanceModelSigma averaged_sigma(const ClearanceFitResult& fit) {
  ClearanceModelSigma s{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::quiet_NaN()};
  for (const auto& q : fit.parameters) {
    if (q.name == "play" && q.free) s.play_rel_sigma = q.std_error;
    if (q.name == "stiffness" && q.free) s.stiffness_rel_sigma = q.std_error;
    if (q.name == "coulomb" && q.free) s.coulomb_rel_sigma = q.std_error;
  }
  return s;
}

}  // namespace

void stage_clearance(Context& c) {
  if (c.p.clearance.input.empty() || !c.drive) {
    c.log("clearance: skipped (no [clearance] or no identified drive)");
    return;
  }
  ClearancePlan plan = plan_clearance(c);
  const ClearanceRun run = run_clearance(plan);
  log_clearance(c, plan, run);
  c.tables.push_back(clearance_table(c, run));
  c.sections["clearance"] = clearance_section(c, run);
  clearance_figure(c, plan, run);
  c.model = run.fit.model;  // the model of the simulated tests (stage 5)
  c.model_sigma = averaged_sigma(run.fit);
  const PerRunFit per_run = run_per_run_fit(c, plan);
  if (per_run.tried) {
    const ClearanceModel& m = per_run.fit.model;
    c.log(fmt::format("clearance: per-run fit over {} runs: play = {:.4g}° ± {:.2g} %, K = {:.4g} ± {:.2g} %, c = {:.3g} N·m ± "
                      "{:.2g} %, D = {:.4g} (geometric mean), RMS {:.4g} deg/s; {}",
                      per_run.fit.run_ids.size(), rad_to_deg(m.play_rad), 100.0 * per_run.fit.sigma().play_rel_sigma,
                      m.stiffness, 100.0 * per_run.fit.sigma().stiffness_rel_sigma, m.coulomb_n_m,
                      100.0 * per_run.fit.sigma().coulomb_rel_sigma, m.damping, per_run.fit.rms_error_deg_s, per_run.reason));
  }
  if (per_run.adopted) {
    c.model = per_run.fit.model;
    c.model_sigma = per_run.fit.sigma();
  }
  json per_run_parameters, per_run_starts;
  c.sections["clearance"]["per_run_fit"] = per_run_json(per_run, per_run_parameters, per_run_starts);
  if (per_run.tried) {
    c.sections["clearance"]["per_run_parameters"] = per_run_parameters;
    c.sections["clearance"]["per_run_starts"] = per_run_starts;
  }
  // The built-in simulated rig's truth, for scoring, beside the section: the clearance section
  // holds only what the runs determine (runs read back from recordings reproduce it exactly).
  if (const json truth = simulated_truth(c); !truth.is_null()) c.sections["clearance_truth"] = truth;
  c.sections["clearance"]["model_source"] = per_run.adopted ? "per-run fit" : "averaged-record fit";
  c.sections["clearance"]["model_sigma"] = sigma_json(*c.model_sigma);
}

}  // namespace detail

}  // namespace clearshape::study
