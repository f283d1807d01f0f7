// Stage 3: the link's residual mode (clearshape; docs/design.md §2): the gyro's free response
// after the link-mode input's last move, one damped mode per unshaped run (ident/modes.hpp), the
// median over the runs as the link mode for shaping.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "identification.hpp"

namespace clearshape::study::detail {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// Plan: the free-response window of a run — from the settling (or the command) after the last
// move plus settle_after_move_s, window_s long; nullopt when the record leaves 50 samples or fewer.
std::optional<UniformSeries> free_response_window(const Context& c, const InputSpec& in, const Record& r) {
  const auto& lm = c.p.link_mode;
  const std::vector<double> motor = speed_mode(c) ? motor_speed_deg_s(r, true) : r.motor_angle_deg;
  const double t0 = (lm.start == "after-command" ? in.last_move_start_s
                                                 : settle_time_s(motor, r.sample_time_s, in.last_move_start_s)) +
                    lm.settle_after_move_s;
  const auto k0 = static_cast<std::size_t>(std::llround(t0 / r.sample_time_s));
  const auto k1 = std::min(r.size(), k0 + static_cast<std::size_t>(std::llround(lm.window_s / r.sample_time_s)));
  if (k1 <= k0 + 50) return std::nullopt;
  UniformSeries window;
  window.start_s = r.time_s[k0];
  window.sample_time_s = r.sample_time_s;
  window.values.assign(r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(k0),
                       r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(k1));
  return window;
}

// Run: one mode from each run's window.
LinkModeRuns identify_link_modes(const Context& c, const InputSpec& in, const std::vector<Record>& runs) {
  LinkModeRuns out;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto window = free_response_window(c, in, runs[i]);
    if (!window) continue;
    try {
      ident::ModeOptions mo;
      mo.modes = 1;
      mo.max_damping_ratio = c.p.link_mode.max_damping_ratio;
      auto res = ident::identify_free_response_modes(*window, mo);
      if (res.modes.empty()) continue;
      out.wn_rad_s.push_back(res.modes.front().natural_frequency_rad_s);
      out.zeta.push_back(res.modes.front().damping_ratio);
      out.fit_percent.push_back(res.fit_percent);
      out.per_run.push_back({{"run", i + 1}, {"window_start_s", window->start_s},
                             {"natural_frequency_hz", res.modes.front().natural_frequency_hz()},
                             {"damping_ratio", res.modes.front().damping_ratio}, {"fit_percent", res.fit_percent}});
      if (!out.example) out.example.emplace(i, std::move(res));
    } catch (const std::exception& e) {
      out.per_run.push_back({{"run", i + 1}, {"error", e.what()}});
    }
  }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Tabulate: the link mode next to the drive model's (table link-mode).
void tabulate_link_mode(Context& c, const LinkModeRuns& runs, const MeanStd& ws, const MeanStd& zs) {
  const double w = c.link_mode.mode.natural_frequency_rad_s;
  const double z = c.link_mode.mode.damping_ratio;
  json table = make_table("link-mode", "parameters", "The link's residual mode, identified from the gyro (clearshape; docs/design.md §2)", "");
  table["row_labels"] = {"natural frequency (Hz)", "damping ratio", "runs used"};
  table["columns"] = {{{"key", "link-mode"}, {"label", "link mode (gyro)"},
                       {"ours", {w / kTwoPi, z, static_cast<double>(runs.wn_rad_s.size())}},
                       {"ours_std", {ws.std / kTwoPi, zs.std, nullptr}}},
                      {{"key", "drive-model"}, {"label", "drive model (Eq. 4.2)"},
                       {"ours", {c.drive_mode.mode.natural_frequency_rad_s / kTwoPi,
                                 c.drive_mode.mode.damping_ratio, nullptr}}}};
  table["note"] = "The thesis designs its shapers from the drive model's ωn and ζ (§3.3). In position "
                  "mode that model has ζ ≈ 1 and cannot give the published improvement, so clearshape "
                  "also identifies the link's own residual mode and reports both.";
  c.tables.push_back(table);
}

// The first identified run's gyro free response and its fitted mode (data/link_mode_fit.csv).
void write_link_mode_figure(Context& c, const std::vector<Record>& records, const LinkModeRuns& runs) {
  if (!runs.example) return;
  const auto& [i, res] = *runs.example;
  const Record& r = records[i];
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
                                             c.link_mode.mode.natural_frequency_rad_s / kTwoPi,
                                             c.link_mode.mode.damping_ratio)},
                       {"file", c.data_file("link_mode_fit.csv")},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", "link rate (deg/s)"},
                       {"series", {{{"column", "gyro_deg_s"}, {"label", "gyro"}},
                                   {{"column", "fitted_deg_s"}, {"label", "fitted mode"}}}}});
}

}  // namespace

void stage_link_mode(Context& c) {
  const auto& lm = c.p.link_mode;
  if (lm.input.empty()) {
    c.link_mode = {false, {}, "no [link_mode] in the protocol"};
    return;
  }
  const InputSpec& in = c.p.input(lm.input);
  const auto& records = c.unshaped_runs(lm.input);
  const LinkModeRuns runs = identify_link_modes(c, in, records);
  json section;
  section["input"] = lm.input;
  section["runs"] = runs.per_run;
  if (runs.wn_rad_s.empty()) {
    c.link_mode = {false, {}, "no oscillatory mode found in the gyro's free response"};
    section["available"] = false;
    section["note"] = c.link_mode.note;
    c.sections["link_mode"] = section;
    c.log("link-mode: " + c.link_mode.note);
    return;
  }
  const double w = median(runs.wn_rad_s);
  const double z = median(runs.zeta);
  c.link_mode = {true, shaping::Mode{w, z},
                 fmt::format("median over {} runs of the gyro's free response after the {}", runs.wn_rad_s.size(),
                             in.label)};
  const MeanStd ws = mean_std(runs.wn_rad_s), zs = mean_std(runs.zeta);
  section["available"] = true;
  section["natural_frequency_rad_s"] = w;
  section["natural_frequency_hz"] = w / (2.0 * 3.14159265358979323846);
  section["damping_ratio"] = z;
  section["natural_frequency_std_rad_s"] = ws.std;
  section["damping_ratio_std"] = zs.std;
  section["note"] = c.link_mode.note;
  c.sections["link_mode"] = section;
  c.log(fmt::format("link-mode: {:.3f} Hz, ζ = {:.4f} (median of {} runs)", w / kTwoPi, z, runs.wn_rad_s.size()));
  tabulate_link_mode(c, runs, ws, zs);
  write_link_mode_figure(c, records, runs);
}

}  // namespace clearshape::study::detail
