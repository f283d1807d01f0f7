// clearshape recommend: recorded vibration in, a recommended input shaper out — after Klipper's
// calibrate_shaper (remaining vibration against 5 % of the PSD's maximum, worst over test damping
// ratios, design frequency fitted by a scan) and beyond it: modes with their 1σ (spectrum, or the
// free-decay fit), the frequency uncertainty in the worst case, ZVD…ZVDDD, EI2/EI3, SI and
// two-mode convolutions, and a delay budget instead of printer smoothing (docs/recommend.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/study/recommend_report.hpp"
#include "command.hpp"
#include "option_checks.hpp"
#include "recommend_plot.hpp"
#include "signal_options.hpp"

namespace clearshape::cli {

namespace {

struct RecommendState {
  std::vector<std::string> data;
  std::string column, time_column, plot;
  CLI::Option* from_option = nullptr;
  CLI::Option* to_option = nullptr;
  CLI::Option* delay_option = nullptr;
  CLI::Option* design_damping_option = nullptr;
  CLI::Option* min_frequency_option = nullptr;
  double from_s = 0.0, to_s = 0.0, segment_s = 0.0, max_delay_s = 0.0, design_damping = 0.0, min_frequency_hz = 0.0;
  std::string damping_range, candidates;
  std::size_t modes = 2;
  double frequency_sigmas = 2.0, vibration_tolerance = 0.01, threshold = 0.05, scan_step = 0.005, scan_step_hz = 0.0;
  double max_remaining = 0.2;
  CLI::Option* scan_step_hz_option = nullptr;
  bool no_fit = false, json = false;
  // --model: the predicted Eq. 5.1 mean deviation of each candidate for the user's move.
  std::string model, move = "step";
  SignalOptions move_options;
  CLI::Option* move_option = nullptr;
  double move_duration_s = 4.0, move_rate_hz = 1000.0, initial_play = 0.0;
  CLI::Option* move_duration_option = nullptr;
  CLI::Option* move_rate_option = nullptr;
  CLI::Option* initial_play_option = nullptr;
  bool clearance_aware = false;  // --clearance-aware: also design on the model (study/clearance_aware.hpp)
  double grid_hz = 0.0;          // --grid-hz: the drive's update rate (0: off)
  std::string weigh_smoothing = "none";  // --weigh-smoothing klipper: pick by Klipper's score
  double square_corner_velocity = 5.0, smoothing_accel = 5000.0;  // Klipper's smoothing figures, mm/s and mm/s²
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i <= text.size()) {
    const std::size_t j = std::min(text.find(',', i), text.size());
    std::string item = text.substr(i, j - i);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    out.push_back(item);
    i = j + 1;
  }
  return out;
}

std::pair<double, double> damping_range(const std::string& text) {
  const auto parts = split(text);
  double lo = 0.0, hi = 0.0;
  try {
    if (parts.size() != 2) throw std::invalid_argument("two values");
    std::size_t used = 0;
    lo = std::stod(parts[0], &used);
    if (used != parts[0].size()) throw std::invalid_argument("lo");
    hi = std::stod(parts[1], &used);
    if (used != parts[1].size()) throw std::invalid_argument("hi");
  } catch (const std::exception&) {
    throw InvalidArgument(fmt::format("--damping-range {}: give two damping ratios 'low,high' with 0 < low ≤ high < 1, e.g. 0.05,0.15", text));
  }
  if (!(lo > 0.0 && lo <= hi && hi < 1.0)) {
    throw InvalidArgument(fmt::format("--damping-range {}: allowed 0 < low ≤ high < 1", text));
  }
  return {lo, hi};
}

advise::RecommendOptions options(const RecommendState& st) {
  advise::RecommendOptions o;
  if (!st.candidates.empty()) o.candidates = split(st.candidates);
  if (!st.damping_range.empty()) {
    const auto [lo, hi] = damping_range(st.damping_range);
    o.damping_low = lo;
    o.damping_high = hi;
  }
  if (st.design_damping_option->count() > 0) {
    if (!(st.design_damping >= 0.0 && st.design_damping < 1.0)) throw_invalid("--design-damping", st.design_damping, "[0, 1)");
    o.design_damping = st.design_damping;
  }
  if (st.delay_option->count() > 0) {
    if (!(st.max_delay_s > 0.0)) throw_invalid("--max-delay-s", st.max_delay_s, "> 0 s");
    o.max_delay_s = st.max_delay_s;
  }
  if (!(st.frequency_sigmas >= 0.0 && st.frequency_sigmas <= 5.0)) throw_invalid("--frequency-sigmas", st.frequency_sigmas, "[0, 5]");
  o.frequency_sigmas = st.frequency_sigmas;
  if (!(st.vibration_tolerance >= 0.0 && st.vibration_tolerance < 1.0)) {
    throw_invalid("--vibration-tolerance", st.vibration_tolerance, "[0, 1) (a fraction: 0.01 = 1 point)");
  }
  o.vibration_tolerance = st.vibration_tolerance;
  if (!(st.threshold > 0.0 && st.threshold < 1.0)) throw_invalid("--threshold", st.threshold, "(0, 1) (Klipper: 0.05)");
  o.threshold_fraction = st.threshold;
  if (!(st.scan_step > 0.0 && st.scan_step < 1.0)) throw_invalid("--scan-step", st.scan_step, "(0, 1) (a fraction: 0.005 = 0.5 %)");
  o.scan_step_ratio = st.scan_step;
  if (st.scan_step_hz_option->count() > 0) {
    if (!(st.scan_step_hz > 0.0)) throw_invalid("--scan-step-hz", st.scan_step_hz, "> 0 Hz");
    o.scan_step_hz = st.scan_step_hz;
  }
  if (!(st.max_remaining > 0.0 && st.max_remaining <= 1.0)) {
    throw_invalid("--max-remaining", st.max_remaining, "(0, 1] (a fraction: 0.2 = 20 %)");
  }
  o.max_remaining = st.max_remaining;
  if (st.min_frequency_option->count() > 0) {
    if (!(st.min_frequency_hz >= 0.0)) throw_invalid("--min-frequency-hz", st.min_frequency_hz, ">= 0 Hz");
    o.min_frequency_hz = st.min_frequency_hz;
  }
  o.update_grid_hz = st.grid_hz;
  o.weigh_smoothing = st.weigh_smoothing == "klipper";
  if (!(st.square_corner_velocity >= 0.0 && st.square_corner_velocity <= 1000.0)) {
    throw_invalid("--square-corner-velocity", st.square_corner_velocity, "[0, 1000] mm/s (Klipper's default: 5)");
  }
  if (!(st.smoothing_accel > 0.0 && st.smoothing_accel <= 1e6)) {
    throw_invalid("--smoothing-accel", st.smoothing_accel, "(0, 1e6] mm/s² (Klipper: 5000)");
  }
  o.smoothing.square_corner_velocity_mm_s = st.square_corner_velocity;
  o.smoothing.accel_mm_s2 = st.smoothing_accel;
  return o;
}

// "0 ms 0.6031, 33.33 ms 0.3969": the impulses the drive applies, for the table.
std::string impulses_text(const shaping::Shaper& s) {
  std::string out;
  for (const auto& i : s.impulses()) out += fmt::format("{}{:.2f} ms {:.4f}", out.empty() ? "" : ", ", 1000.0 * i.time_s, i.amplitude);
  return out;
}

void print_table(const std::vector<advise::MeasuredSpectrum>& spectra, const advise::ModeEstimation& est,
                 const advise::Recommendation& r, const std::optional<study::MovePrediction>& pred,
                 const std::optional<study::ClearanceAwareCandidate>& ca, double grid_hz) {
  for (const auto& s : spectra) {
    fmt::print("input  {} ({}, {}): {} bins, resolution {:.3g} Hz{}\n", s.source, advise::to_string(s.format), s.column,
               s.frequency_hz.size(), s.resolution_hz, s.segments > 0 ? fmt::format(", {} Welch segments", s.segments) : "");
  }
  std::size_t i = 0;
  for (const auto& m : r.modes) {
    fmt::print("mode {} {:.4f} Hz ± {:.3g} (1σ), ζ {:.4f} ± {:.3g} ({})\n", ++i, m.frequency_hz, m.frequency_std_hz, m.damping_ratio,
               m.damping_ratio_std, m.source);
    if (!m.note.empty()) fmt::print("       {}\n", m.note);
  }
  fmt::print("       {}\n", est.note);
  fmt::print("worst case over ζ {:.4g} and frequency × {:.4g}{}\n", fmt::join(r.test_damping_ratios, ", "),
             fmt::join(r.frequency_scales, ", "), r.klipper_normalized ? ", on the PSD ÷ (f + 0.1 Hz) as Klipper scores it" : "");
  for (const auto& b : r.damping_bands) {
    fmt::print("       {}{}\n", b.mode ? fmt::format("ζ {:.4g} on {:.4g}–{:.4g} Hz: ", fmt::join(b.ratios, ", "), b.low_hz, b.high_hz) : "",
               b.reason);
  }
  fmt::print("design damping ζ {:.4g}: {}\n\n", r.design_damping, r.design_damping_reason);
  if (pred) {
    fmt::print("predicted Eq. 5.1 MD of the {} on the model for the move {} {}, {:.4g} s at {:.4g} Hz: unshaped {:.4g}\n\n",
               pred->signal_name, pred->move, pred->move_parameters, pred->duration_s, 1.0 / pred->sample_time_s, pred->unshaped_md);
  }
  if (grid_hz > 0.0) {
    fmt::print("on the drive's {:g} Hz update grid: every candidate's impulses rounded to the nearest update ({:.2f} ms), those on\n"
               "the same update merged; delay, remaining and predicted MD are the applied shaper's, designed_% the off-grid design's\n\n",
               grid_hz, 1000.0 / grid_hz);
  }
  const bool printer = r.printer_figures;
  fmt::print("{:<10} {:>18} {:>10} {:>12} {:>12} {:>10}{}{}{}\n", "shaper", "design_hz", "delay_ms", "remaining_%", "nominal_%", "budget",
             printer ? fmt::format(" {:>12} {:>16}", "smoothing_mm", "max_accel_mm_s2") : "",
             pred ? fmt::format(" {:>13}", "predicted_md") : std::string(), grid_hz > 0.0 ? fmt::format(" {:>10}", "designed_%") : "");
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    const auto& c = r.candidates[k];
    const std::string mark = r.chosen && *r.chosen == k ? " <" : "";
    if (!c.available) {
      fmt::print("{:<10} unavailable: {}\n", c.name, c.note);
      continue;
    }
    std::string f = fmt::format("{:.3f}", c.design_frequency_hz[0]);
    if (c.design_frequency_hz.size() > 1) f += fmt::format("+{:.3f}", c.design_frequency_hz[1]);
    fmt::print("{:<10} {:>18} {:>10.2f} {:>12} {:>12.2f} {:>10}{}{}{}{}\n", c.name, f, 1000.0 * c.duration_s,
               fmt::format("{}{:.2f}", c.leaves_too_much ? "!" : "", 100.0 * c.remaining_worst), 100.0 * c.remaining_nominal,
               c.within_budget ? "ok" : "over",
               printer ? fmt::format(" {:>12.4f} {:>16.0f}", c.smoothing_mm, c.max_accel_mm_s2) : "", pred ? fmt::format(" {:>13.5g}", *pred->md[k]) : std::string(),
               grid_hz > 0.0 ? fmt::format(" {:>10.2f}", 100.0 * c.remaining_worst_designed) : "",
               mark + (pred && pred->md[k] && *pred->md[k] > pred->unshaped_md ? " WORSE than unshaped" : ""));
    if (grid_hz > 0.0) {
      fmt::print("           applied: {}{}\n", impulses_text(*c.shaper),
                 c.duplicate_of ? fmt::format(" (the same as {}: not chosen)", *c.duplicate_of) : "");
    }
  }
  if (ca) {
    fmt::print("{:<10} {:>18} {:>10.2f} {:>12} {:>12} {:>10} {:>13.5g}{}\n", "clearance-aware", "(model)", 1000.0 * ca->shaper.duration_s(),
               "-", "-", "-", ca->predicted_md, pred && ca->predicted_md > pred->unshaped_md ? " WORSE than unshaped" : "");
    fmt::print("           designed on the model for the move ({} evaluations, {:.2f} s; bound {:.4g} s: {})\n", ca->evaluations,
               ca->design_time_s, ca->max_duration_s, ca->bound_source);
  }
  if (std::any_of(r.candidates.begin(), r.candidates.end(), [](const auto& c) { return c.leaves_too_much; })) {
    fmt::print("(!: leaves more than the --max-remaining limit)\n");
  }
  fmt::print("\nrecommended: {}\n", r.chosen ? r.candidates[*r.chosen].name : std::string("none"));
  fmt::print("reason: {}\n", r.reason);
  if (!r.warning.empty()) fmt::print("warning: {}\n", r.warning);
  if (r.chosen) fmt::print("shaper: {}\n", study::shape_command(r.candidates[*r.chosen], r, grid_hz));
}

// A record of a whole move (rest, move, free decay) read without --from-s: its spectrum is the
// move's, not the mode's (a 20° step's gyro gives 10.7 ± 1.4 Hz for a 14.9 Hz mode). Names the
// largest swing, when it stands out as a move does, and the window that starts after it.
void print_window_hints(const std::vector<advise::MeasuredSpectrum>& spectra) {
  for (const auto& s : spectra) {
    if (s.format != advise::InputFormat::table || !s.series || s.series->size() < 16) continue;
    const auto& v = s.series->values;
    double mean = 0.0;
    for (const double x : v) mean += x / static_cast<double>(v.size());
    std::size_t peak = 0;
    for (std::size_t k = 1; k < v.size(); ++k) {
      if (std::abs(v[k] - mean) > std::abs(v[peak] - mean)) peak = k;
    }
    double ms = 0.0;
    for (const double x : v) ms += (x - mean) * (x - mean) / static_cast<double>(v.size());
    // An isolated swing: noise or a sweep peaks at about 4 RMS over 10^4 samples (Gaussian), a move at 7–10.
    if (!(std::abs(v[peak] - mean) > 6.0 * std::sqrt(ms))) continue;
    const double t_peak_s = static_cast<double>(peak) * s.series->sample_time_s;
    const double length_s = static_cast<double>(v.size() - 1) * s.series->sample_time_s;
    if (t_peak_s > 0.7 * length_s) continue;
    const double from_s = std::ceil((t_peak_s + 0.05) * 10.0) / 10.0;
    fmt::print(stderr,
               "clearshape recommend: hint: {}: the largest swing of {} is at {:.3g} s and this is not a free decay; if the record "
               "holds a move, analyse the decay after it: --from-s {:.3g}\n",
               s.source, s.column, t_peak_s, from_s);
  }
}

// The library's request from the options (checked here, named by their flags).
study::RecommendRequest request(const RecommendState& st) {
  study::RecommendRequest q;
  q.options = options(st);
  for (const auto& path : st.data) {
    advise::SpectrumRequest req;
    req.path = path;
    req.column = st.column;
    req.time_column = st.time_column;
    if (st.from_option->count() > 0) req.from_s = st.from_s;
    if (st.to_option->count() > 0) req.to_s = st.to_s;
    req.segment_s = st.segment_s;
    q.data.push_back(req);
  }
  q.modes.max_modes = st.modes;
  q.modes.free_decay_fit = !st.no_fit;
  q.modes.min_frequency_hz = q.options.min_frequency_hz;
  q.plot = st.plot;
  return q;
}

void check_move_options(const RecommendState& st) {
  const bool move_given = st.move_option->count() > 0 || st.move_duration_option->count() > 0 || st.move_rate_option->count() > 0 ||
                          st.initial_play_option->count() > 0;
  if (st.clearance_aware && st.model.empty()) {
    throw InvalidArgument("--clearance-aware needs --model FIT.json and a --move step (the design runs on the model)");
  }
  if (st.model.empty() && move_given) {
    throw InvalidArgument("--move, --move-duration-s, --move-rate-hz and --initial-play need --model FIT.json");
  }
  if (!st.model.empty()) {
    if (!(st.move_duration_s > 0.0 && st.move_duration_s <= 60.0)) throw_invalid("--move-duration-s", st.move_duration_s, "(0, 60] s");
    if (!(st.move_rate_hz >= 10.0 && st.move_rate_hz <= 1e5)) throw_invalid("--move-rate-hz", st.move_rate_hz, "[10, 1e5] Hz");
    if (!(st.initial_play >= -1.0 && st.initial_play <= 1.0)) throw_invalid("--initial-play", st.initial_play, "[-1, 1] (φ(0)/β)");
  }
}

study::MoveRequest move_request(const RecommendState& st) {
  study::MoveRequest m;
  m.model = st.model;
  m.move_type = st.move;
  m.move = st.move_options.build(st.move);
  m.duration_s = st.move_duration_s;
  m.sample_time_s = 1.0 / st.move_rate_hz;
  m.initial_play_fraction = st.initial_play;
  m.clearance_aware = st.clearance_aware;
  return m;
}

void run_recommend(const RecommendState& st) {
  if (!st.plot.empty() && std::filesystem::path(st.plot).extension() != ".png") {
    throw InvalidArgument(fmt::format("--plot {}: the figure is a PNG; give a path ending in .png", st.plot));
  }
  if (!(st.segment_s >= 0.0)) throw_invalid("--segment-s", st.segment_s, ">= 0 s (0: automatic)");
  if (st.modes < 1 || st.modes > 2) throw_invalid("--modes", static_cast<double>(st.modes), "1 or 2");
  study::RecommendRequest q = request(st);
  check_move_options(st);
  study::RecommendReport report = study::recommend_from_spectra(q);
  if (st.from_option->count() == 0 && !report.estimation.free_decay_used) print_window_hints(report.spectra);
  if (!st.model.empty()) {
    const study::IdentifiedClearanceModel model = study::read_clearance_model_json(st.model);
    q.model = move_request(st);  // the move is built after the model is read, as before
    study::add_model_predictions(q, model, report);
  }
  const auto& r = report.recommendation;
  if (!r.chosen) fmt::print(stderr, "clearshape recommend: warning: no recommendation: {}\n", r.reason);
  if (!r.warning.empty()) fmt::print(stderr, "clearshape recommend: warning: {}\n", r.warning);
  if (!st.plot.empty()) write_recommend_plot(st.plot, report);
  if (st.json) {
    print_json(study::recommend_document(q, report));
  } else {
    print_table(report.spectra, report.estimation, r, report.prediction, report.clearance_aware, q.options.update_grid_hz);
    if (!st.plot.empty()) fmt::print("plot: {}\n", st.plot);
  }
}

void setup_recommend(CLI::App& sub) {
  auto st = std::make_shared<RecommendState>();
  sub.add_option("--data", st->data,
                 "Recording: a clearshape CSV, Klipper's raw accelerometer CSV (#time,accel_x,…) or its PSD CSV (freq,psd_x,…); "
                 "repeat for several (worst case over them)")
      ->required();
  sub.add_option("--column", st->column,
                 "Column to analyse: a table's column (e.g. gyro_deg_s; required for tables); Klipper: accel_x|accel_y|accel_z|xyz "
                 "or psd_x|…|psd_xyz (default xyz)");
  sub.add_option("--time-column", st->time_column, "Time column of a table, s (default: time_s, time or t)");
  st->from_option = sub.add_option("--from-s", st->from_s, "Window start, s from the record's first sample (e.g. the end of the move)");
  st->to_option = sub.add_option("--to-s", st->to_s, "Window end, s from the record's first sample");
  sub.add_option("--segment-s", st->segment_s, "Welch segment length, s (0: the largest power of two ≤ a quarter of the record)")
      ->capture_default_str();
  sub.add_option("--modes", st->modes, "Modes to look for: 1, or 2 (a second when a second peak stands out)")->capture_default_str();
  st->delay_option = sub.add_option("--max-delay-s", st->max_delay_s, "Delay budget: candidates longer than this are not recommended, s");
  sub.add_option("--damping-range", st->damping_range,
                 "Test damping ratios 'low,high' (three evenly spaced; default: the mode's ζ ± max(2σ, ζ/4))");
  st->design_damping_option = sub.add_option("--design-damping", st->design_damping, "Design damping ratio (default: the mode's ζ)");
  sub.add_option("--candidates", st->candidates, "Comma-separated candidates (default: zv,mzv,zvd,zvdd,zvddd,ei,ei2,ei3,si and, for two "
                                                 "modes, zv*zv,mzv*mzv,zvd*zvd,ei*ei)");
  sub.add_option("--frequency-sigmas", st->frequency_sigmas, "Frequency uncertainty in the worst case: ± this many σ (0: none)")
      ->capture_default_str();
  sub.add_option("--vibration-tolerance", st->vibration_tolerance,
                 "Recommend the shortest candidate within this of the least remaining vibration (fraction)")
      ->capture_default_str();
  sub.add_option("--threshold", st->threshold, "PSD threshold as a fraction of its maximum (Klipper: 0.05)")->capture_default_str();
  sub.add_option("--scan-step", st->scan_step,
                 "Relative step of the design-frequency scan: each scanned frequency is (1 + this) × the one before")
      ->capture_default_str();
  st->scan_step_hz_option = sub.add_option("--scan-step-hz", st->scan_step_hz,
                                           "A linear scan in steps of this many Hz instead (ties the design to the unit of time)");
  sub.add_option("--max-remaining", st->max_remaining,
                 "Flag candidates leaving more than this fraction of the vibration; a pick beyond it is warned about")
      ->capture_default_str();
  st->min_frequency_option = sub.add_option("--min-frequency-hz", st->min_frequency_hz, "Ignore the spectrum below this, Hz "
                                                                                       "(default: two resolution bins)");
  sub.add_flag("--no-free-decay-fit", st->no_fit, "Use the spectral mode estimate only");
  sub.add_option("--plot", st->plot, "Write the spectrum and every candidate's remaining-vibration curve to this PNG");
  sub.add_flag("--json", st->json, "Print the result as JSON");
  sub.add_option("--model", st->model,
                 "Identified nonlinear model (`fit-clearance --json` or a study's results.json): add each candidate's predicted "
                 "Eq. 5.1 mean deviation for --move; less predicted MD wins ties");
  st->move_option = sub.add_option("--move", st->move, "The move, with the signal options below (e.g. --amplitude 20 --rise-s 0.05): " +
                                                           SignalOptions::type_list())
                        ->check(SignalOptions::type_check())
                        ->capture_default_str();
  st->move_options.add_to(sub, "--move");
  st->move_duration_option = sub.add_option("--move-duration-s", st->move_duration_s, "Simulated length of the move, s")->capture_default_str();
  st->move_rate_option = sub.add_option("--move-rate-hz", st->move_rate_hz, "Sample rate of the move's simulation, Hz")->capture_default_str();
  st->initial_play_option = sub.add_option("--initial-play", st->initial_play, "Where the link rests in the play at the start, φ(0)/β in [-1, 1]")
                                ->capture_default_str();
  sub.add_option("--grid-hz", st->grid_hz,
                 "The drive takes a new command only at updates of this rate (Hz; the thesis's pulse-train drive: 30): every "
                 "candidate is snapped to that grid before it is fitted and scored; omit for none")
      ->check(positive_at_most(1e6, "Hz", "--grid-hz"));
  sub.add_option("--weigh-smoothing", st->weigh_smoothing,
                 "klipper: pick as Klipper's calibrate_shaper does, weighing remaining vibration against printer smoothing "
                 "(score smoothing·(v^1.5 + 0.2v + 0.01)); none: the shortest candidate within the tolerance")
      ->check(CLI::IsMember({"none", "klipper"}))
      ->capture_default_str();
  sub.add_option("--square-corner-velocity", st->square_corner_velocity,
                 "Printer's square-corner velocity for the smoothing figures, mm/s (Klipper's default)")
      ->capture_default_str();
  sub.add_option("--smoothing-accel", st->smoothing_accel, "Acceleration the smoothing figure is quoted at, mm/s² (Klipper: 5000)")
      ->capture_default_str();
  sub.add_flag("--clearance-aware", st->clearance_aware,
               "With --model and a --move step: also design the clearance-aware shaper on the model (study/clearance_aware.hpp, "
               "no longer than ZVDD for the first mode) and predict its MD; about 1–3 s");
  sub.callback([st] { run_recommend(*st); });
}

const bool recommend_registered = register_command(
    {"recommend", "Recommend an input shaper from recorded vibration (after Klipper's calibrate_shaper)", 32, setup_recommend});

}  // namespace

}  // namespace clearshape::cli
