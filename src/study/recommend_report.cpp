#include "clearshape/study/recommend_report.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/shaping/grid.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/study/clearance_model_json.hpp"

namespace clearshape::study {
namespace {

using ojson = nlohmann::ordered_json;

ojson number_or_null(double v) { return std::isfinite(v) ? ojson(v) : ojson(nullptr); }

ojson impulses_json(const shaping::Shaper& s) {
  ojson impulses = ojson::array();
  for (const auto& i : s.impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
  return impulses;
}

ojson mode_json(const advise::ModeEstimate& m) {
  return {{"frequency_hz", m.frequency_hz},           {"frequency_std_hz", m.frequency_std_hz},
          {"damping_ratio", m.damping_ratio},         {"damping_ratio_std", m.damping_ratio_std},
          {"source", m.source},                       {"peak_power", m.peak_power},
          {"prominence", m.prominence},
          {"damping_ratio_range", m.damping_ratio_range ? ojson({m.damping_ratio_range->first, m.damping_ratio_range->second})
                                                        : ojson(nullptr)},
          {"note", m.note},
          {"half_power_low_hz", m.half_power_low_hz}, {"half_power_high_hz", m.half_power_high_hz}};
}

// Every candidate as the JSON lists it: the linear ones (with their predicted MD given a model),
// then the clearance-aware design when it was asked for.
ojson candidates_json(const advise::Recommendation& r, const std::optional<MovePrediction>& pred,
                                       const std::optional<ClearanceAwareCandidate>& ca, double grid_hz) {
  ojson cands = ojson::array();
  for (const auto& c : r.candidates) {
    ojson j{{"name", c.name}, {"available", c.available}, {"note", c.note}};
    if (c.available) {
      ojson impulses = ojson::array();
      for (const auto& i : c.shaper->impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
      j["design_frequency_hz"] = c.design_frequency_hz;
      j["design_damping"] = c.design_damping;
      j["duration_s"] = c.duration_s;
      j["remaining_worst"] = c.remaining_worst;
      j["remaining_nominal"] = c.remaining_nominal;
      j["least_remaining"] = c.least_remaining;
      j["least_remaining_frequency_hz"] = c.least_remaining_frequency_hz;
      j["within_budget"] = c.within_budget;
      j["leaves_too_much"] = c.leaves_too_much;
      j["impulses"] = impulses;
      if (r.printer_figures) {  // Klipper's figures for printer data (advise/smoothing.hpp)
        j["smoothing_mm"] = c.smoothing_mm;
        j["max_accel_mm_s2"] = number_or_null(c.max_accel_mm_s2);
        j["klipper_score"] = c.klipper_score;
      }
      if (grid_hz > 0.0) {  // the impulses above are the applied ones, on the drive's update grid
        j["update_grid_hz"] = grid_hz;
        j["duplicate_of"] = c.duplicate_of ? ojson(*c.duplicate_of) : ojson(nullptr);
        j["designed_impulses"] = impulses_json(*c.designed);
        j["remaining_worst_designed"] = c.remaining_worst_designed;
      }
    }
    if (pred) {
      const auto& md = pred->md[&c - r.candidates.data()];
      j["predicted_md"] = md ? ojson(*md) : ojson(nullptr);
      j["worse_than_unshaped"] = md && *md > pred->unshaped_md;  // issue 19: never offered unmarked
    }
    cands.push_back(j);
  }
  if (ca) {  // beside the linear candidates: designed on the model, not from a mode
    ojson impulses = ojson::array();
    for (const auto& i : ca->shaper.impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
    cands.push_back({{"name", "clearance-aware"},
                     {"available", true},
                     {"note", "designed by simulation on the model for the move (not ranked by remaining vibration)"},
                     {"duration_s", ca->shaper.duration_s()},
                     {"max_duration_s", ca->max_duration_s},
                     {"bound_source", ca->bound_source},
                     {"impulses", impulses},
                     {"predicted_md", ca->predicted_md},
                     {"worse_than_unshaped", pred && ca->predicted_md > pred->unshaped_md},
                     {"design_worst_md", ca->design_worst_md_deg},
                     {"evaluations", ca->evaluations},
                     {"design_time_s", ca->design_time_s}});
  }
  return cands;
}

ojson inputs_json(const std::vector<advise::MeasuredSpectrum>& spectra) {
  ojson inputs = ojson::array();
  for (const auto& s : spectra) {
    inputs.push_back({{"file", s.source},
                      {"format", std::string(advise::to_string(s.format))},
                      {"column", s.column},
                      {"samples", s.series ? ojson(s.series->size()) : ojson(nullptr)},
                      {"sample_rate_hz", s.series ? ojson(1.0 / s.series->sample_time_s) : ojson(nullptr)},
                      {"window_s", s.series ? ojson({s.series->start_s, s.series->end_s()}) : ojson(nullptr)},
                      {"segments", s.segments},
                      {"resolution_hz", s.resolution_hz},
                      {"bins", s.frequency_hz.size()},
                      {"power_unit", s.power_unit}});
  }
  return inputs;
}

// Which bins each band of test damping ratios covers and why (advise::DampingBand); the rest band first.
ojson damping_bands_json(const advise::Recommendation& r) {
  ojson bands = ojson::array();
  for (const auto& b : r.damping_bands) {
    bands.push_back({{"mode", b.mode ? ojson(*b.mode + 1) : ojson(nullptr)},
                     {"low_hz", b.low_hz},
                     {"high_hz", number_or_null(b.high_hz)},
                     {"test_damping_ratios", b.ratios},
                     {"reason", b.reason}});
  }
  return bands;
}

ojson scoring_json(const advise::Recommendation& r, const advise::RecommendOptions& o) {
  ojson scoring = {{"measure", "remaining = sum(max(V*P - thr, 0)) / sum(max(P - thr, 0)), thr = threshold_fraction * max P"},
                   {"threshold_fraction", o.threshold_fraction},
                   {"design_damping", r.design_damping},
                   {"design_damping_reason", r.design_damping_reason},
                   {"test_damping_ratios", r.test_damping_ratios},
                   {"damping_bands", damping_bands_json(r)},
                   {"frequency_scales", r.frequency_scales},
                   {"max_delay_s", number_or_null(o.max_delay_s)},
                   {"vibration_tolerance", o.vibration_tolerance},
                   {"max_remaining", o.max_remaining},
                   {"scan", o.scan_step_hz ? fmt::format("linear, {:g} Hz steps", *o.scan_step_hz)
                                           : fmt::format("log-spaced, x{:g} per step", 1.0 + o.scan_step_ratio)}};
  if (o.update_grid_hz > 0.0) scoring["update_grid_hz"] = o.update_grid_hz;
  if (r.klipper_normalized) scoring["psd"] = "P / (f + 0.1 Hz), as Klipper's calibrate_shaper normalises a TEST_RESONANCES PSD";
  if (r.printer_figures) {
    scoring["smoothing"] = {{"accel_mm_s2", o.smoothing.accel_mm_s2},
                            {"square_corner_velocity_mm_s", o.smoothing.square_corner_velocity_mm_s},
                            {"target_smoothing_mm", o.smoothing.target_smoothing_mm},
                            {"weighed", r.weighed_smoothing ? "klipper" : "none"}};
  }
  return scoring;
}

ojson model_json(const RecommendRequest& request, const std::optional<MovePrediction>& pred) {
  if (!pred || !request.model) return nullptr;
  return {{"file", request.model->model.string()},
          {"move", request.model->move_type},
          {"move_parameters", ojson::parse(pred->move_parameters)},
          {"md_signal", pred->signal_name},
          {"duration_s", pred->duration_s},
          {"sample_time_s", pred->sample_time_s},
          {"initial_play_fraction", pred->initial_play_fraction},
          {"unshaped_md", pred->unshaped_md}};
}

ojson design_offsets_json(const std::vector<advise::DesignOffset>& offsets) {
  ojson out = ojson::array();
  for (const auto& d : offsets) {
    out.push_back({{"factor", d.factor},
                   {"design_frequency_hz", d.design_frequency_hz},
                   {"mode_frequency_hz", d.mode_frequency_hz},
                   {"mode_frequency_std_hz", d.mode_frequency_std_hz},
                   {"offset_sigmas", number_or_null(d.offset_sigmas)},
                   {"spectrum_hz", d.spectrum_hz},
                   {"near_best_hz", d.near_best_hz},
                   {"worst_case_hz", d.worst_case_hz},
                   {"selection_hz", d.selection_hz},
                   {"cause", d.cause},
                   {"reason", d.reason}});
  }
  return out;
}

// One measured spectrum for the figure, up to f_max: its curve, its unit, a Klipper file's axes
// and, with a pick, the PSD the pick leaves (advise::power_after_shaper).
ojson plot_spectrum(const advise::MeasuredSpectrum& s, const advise::Recommendation& r, double f_max) {
  std::size_t n = 0;
  while (n < s.frequency_hz.size() && s.frequency_hz[n] <= f_max) ++n;
  const std::vector<double> f(s.frequency_hz.begin(), s.frequency_hz.begin() + static_cast<std::ptrdiff_t>(n));
  const auto head = [n](const std::vector<double>& v) { return std::vector<double>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n)); };
  ojson axes = ojson::array();
  for (const auto& a : s.axes) axes.push_back({{"column", a.column}, {"power", head(a.power)}});
  ojson after = nullptr;
  if (r.chosen) {
    after = advise::power_after_shaper(*r.candidates[*r.chosen].shaper, f, head(s.power), r);
  }
  return {{"label", std::filesystem::path(s.source).filename().string() + " (" + s.column + ")"},
          {"column", s.column},
          {"power_unit", s.power_unit.empty() ? advise::psd_unit_of_column(s.column) : s.power_unit},
          {"frequency_hz", f},
          {"power", head(s.power)},
          {"axes", axes},
          {"power_after_shaper", after}};
}

ojson recommendation_json(const advise::Recommendation& r, const std::optional<MovePrediction>& pred, double grid_hz) {
  if (!r.chosen) return nullptr;
  const auto& c = r.candidates[*r.chosen];
  ojson j = {{"name", c.name},
          {"design_frequency_hz", c.design_frequency_hz},
          {"design_damping", c.design_damping},
          {"duration_s", c.duration_s},
          {"remaining_worst", c.remaining_worst},
          {"warning", r.warning.empty() ? ojson(nullptr) : ojson(r.warning)},
          {"predicted_md", pred ? ojson(*pred->md[*r.chosen]) : ojson(nullptr)},
          {"shape_command", shape_command(c, r, grid_hz)},
          {"design_offsets", design_offsets_json(r.design_offsets)}};
  if (r.printer_figures) {
    j["smoothing_mm"] = c.smoothing_mm;
    j["max_accel_mm_s2"] = number_or_null(c.max_accel_mm_s2);
  }
  return j;
}

// The move's parameters as JSON text (signal/parameters.hpp), for the output.
std::string move_parameters_json(const signal::Signal& move) {
  ojson parameters = ojson::object();
  for (const auto& [key, value] : signal::parameters_of(move)) {
    parameters[key] = std::visit([](const auto& x) { return ojson(x); }, value);
  }
  return parameters.dump();
}

// The ranges `clearshape recommend` allows for the move (its --move-… flags).
void check_move(const MoveRequest& m) {
  if (!(m.duration_s > 0.0 && m.duration_s <= 60.0)) throw_invalid("move duration_s", m.duration_s, "(0, 60] s");
  if (!(m.sample_time_s >= 1e-5 && m.sample_time_s <= 0.1)) {
    throw_invalid("move sample_time_s", m.sample_time_s, "[1e-5, 0.1] s (a rate of 10 Hz … 100 kHz)");
  }
  require_in_closed("initial_play_fraction", m.initial_play_fraction, -1.0, 1.0, "φ(0)/β");
}

}  // namespace

std::string shape_command(const advise::CandidateResult& c, const advise::Recommendation& r, double grid_hz) {
  const auto star = c.name.find('*');
  const std::string method = c.name.substr(0, star);
  std::string s = fmt::format("clearshape shape --method {} --frequency-hz {:.6g} --zeta {:.6g}", method, c.design_frequency_hz[0],
                              c.design_damping);
  if (method == "si") {
    const double u = (r.frequency_scales.size() > 1 ? r.frequency_scales.back() - 1.0 : 0.0);
    const double half = std::max(u, 0.02);
    s += fmt::format(" --band-low-hz {:.6g} --band-high-hz {:.6g}", c.design_frequency_hz[0] * (1.0 - half),
                     c.design_frequency_hz[0] * (1.0 + half));
  }
  if (star != std::string::npos && c.design_frequency_hz.size() > 1) {
    s += fmt::format(" --second-frequency-hz {:.6g} --second-zeta {:.6g}", c.design_frequency_hz[1],
                     std::clamp(r.modes[1].damping_ratio, 0.0, 0.9));
  }
  if (grid_hz > 0.0) s += fmt::format(" --grid-hz {:g}", grid_hz);
  return s;
}


RecommendReport recommend_from_spectra(const RecommendRequest& request) {
  RecommendReport report;
  for (const auto& r : request.data) report.spectra.push_back(advise::load_spectrum(r));
  report.estimation = advise::estimate_modes(report.spectra, request.modes);
  report.recommendation = advise::recommend(report.spectra, report.estimation.modes, request.options);
  return report;
}

void add_model_predictions(const RecommendRequest& request, RecommendReport& report) {
  if (request.model) add_model_predictions(request, read_clearance_model_json(request.model->model), report);
}

void add_model_predictions(const RecommendRequest& request, const IdentifiedClearanceModel& model, RecommendReport& report) {
  if (!request.model) return;
  const MoveRequest& m = *request.model;
  check_move(m);
  const advise::RecommendOptions& o = request.options;
  advise::Recommendation& r = report.recommendation;
  auto& pred = report.prediction;
  pred = predict_mean_deviations(model.model, m.move, m.duration_s, m.sample_time_s, m.initial_play_fraction, r);
  pred->move = m.move_type;
  pred->move_parameters = move_parameters_json(m.move);
  apply_predicted_md(r, *pred, o.vibration_tolerance);
  if (!m.clearance_aware) return;
  auto& ca = report.clearance_aware;
  ca = design_for_move(model.model, m.move, *pred, r, o.max_delay_s);
  if (o.update_grid_hz > 0.0) {  // as the drive applies it, like the linear candidates
    ca->shaper = shaping::on_update_grid(ca->shaper, 1.0 / o.update_grid_hz);
    ca->predicted_md = predict_shaped_md(model.model, m.move, *pred, ca->shaper);
  }
}

RecommendReport recommend(const RecommendRequest& request) {
  RecommendReport report = recommend_from_spectra(request);
  add_model_predictions(request, report);
  return report;
}

ojson recommend_document(const RecommendRequest& request, const RecommendReport& report) {
  const auto& r = report.recommendation;
  const auto& o = request.options;
  const auto& pred = report.prediction;
  auto doc = io::make_document();
  doc["command"] = "recommend";
  doc["inputs"] = inputs_json(report.spectra);
  ojson modes = ojson::array(), spectral = ojson::array();
  for (const auto& m : r.modes) modes.push_back(mode_json(m));
  for (const auto& m : report.estimation.spectral_modes) spectral.push_back(mode_json(m));
  doc["modes"] = modes;
  doc["spectral_modes"] = spectral;
  const auto& est = report.estimation;
  doc["free_decay"] = {{"used", est.free_decay_used}, {"fit_percent", est.free_decay_fit_percent}, {"note", est.note}};
  doc["scoring"] = scoring_json(r, o);
  doc["candidates"] = candidates_json(r, pred, report.clearance_aware, o.update_grid_hz);
  doc["model"] = model_json(request, pred);
  doc["recommendation"] = recommendation_json(r, pred, o.update_grid_hz);
  doc["reason"] = r.reason;
  doc["plot"] = request.plot.empty() ? ojson(nullptr) : ojson(request.plot);
  return doc;
}

ojson recommend_plot_data(const RecommendReport& report) {
  const auto& r = report.recommendation;
  double top = 0.0, f_max = 0.0;
  for (const auto& m : r.modes) top = std::max(top, m.frequency_hz);
  for (const auto& s : report.spectra) f_max = std::max(f_max, s.frequency_hz.back());
  f_max = std::min(f_max, 3.0 * top);
  ojson doc;
  ojson spectra = ojson::array();
  for (const auto& s : report.spectra) spectra.push_back(plot_spectrum(s, r, f_max));
  doc["spectra"] = spectra;
  doc["after_shaper"] = "P(f) * V(f)^2, V the recommended shaper's worst case over the test damping ratios and frequency scales";
  std::vector<double> grid;
  for (int k = 0; k <= 600; ++k) grid.push_back(f_max * k / 600.0);
  doc["frequency_hz"] = grid;
  ojson cands = ojson::array();
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    const auto& c = r.candidates[i];
    if (!c.available || !c.shaper) continue;
    cands.push_back({{"name", c.name},
                     {"design_frequency_hz", c.design_frequency_hz},
                     {"remaining_worst", c.remaining_worst},
                     {"duration_s", c.duration_s},
                     {"chosen", r.chosen && *r.chosen == i},
                     {"response", advise::worst_response(*c.shaper, grid, r)}});
    if (r.printer_figures) {  // Klipper's legend: smoothing and max acceleration (advise/smoothing.hpp)
      cands.back()["smoothing_mm"] = c.smoothing_mm;
      cands.back()["max_accel_mm_s2"] = number_or_null(c.max_accel_mm_s2);
    }
  }
  doc["candidates"] = cands;
  ojson modes = ojson::array();
  for (const auto& m : r.modes) modes.push_back({{"frequency_hz", m.frequency_hz}, {"frequency_std_hz", m.frequency_std_hz}});
  doc["modes"] = modes;
  doc["design_offsets"] = design_offsets_json(r.design_offsets);
  doc["reason"] = r.reason;
  return doc;
}

}  // namespace clearshape::study
