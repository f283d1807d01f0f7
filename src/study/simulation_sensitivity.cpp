// Stage 5's shaper sensitivity curves (Eq. 2.19) of every designed shaper, all evaluated on the
// vibration that matters — the link's identified residual mode (ω_link, ζ_link) — against
// r = ω/ω_link: a drive-model shaper is designed for ζ ≈ 1 (position) and its own-ζ curve says
// nothing about the link. Where the drive's 30 Hz update grid moved or merged impulses
// (design_for), the curve as applied is drawn and, beside it, the curve as designed: the grid is
// real (the driver applies the position at its updates), so the as-applied curve is what the rig
// sees; e.g. an MZV for a 15 Hz mode needs impulses 22 and 45 ms apart, the grid gives 33 and
// 67 ms, and its V(1) is far from 0. Without an identified link mode every shaper is drawn at its
// own mode.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/shaping/residual.hpp"
#include "simulation.hpp"

namespace clearshape::study::detail {

namespace {

constexpr std::size_t kPoints = 251;     // samples of r = ω/ω_ref
constexpr double kMaxRatio = 2.5;        // r from 0 to this
// The as-designed curve is drawn only where the grid changes V by more than this (in V, a
// fraction): a shift of a fraction of a millisecond is not worth a second line.
constexpr double kGridEffect = 0.02;

bool same_impulses(const shaping::Shaper& a, const shaping::Shaper& b) {
  const auto& x = a.impulses();
  const auto& y = b.impulses();
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i].time_s - y[i].time_s) > 1e-9 || std::abs(x[i].amplitude - y[i].amplitude) > 1e-12) return false;
  }
  return true;
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0.0;
  for (std::size_t k = 0; k < kPoints; ++k) diff = std::max(diff, std::abs(a[k] - b[k]));
  return diff;
}

// V(r) of a shaper on a reference mode (Eq. 2.19). Eq. 2.19 compares the residual after the last
// impulse t_N with one impulse applied at t_N, so an impulse of no consequence (a drive-model ZV
// for ζ ≈ 1 ends with one of 1e-10) would let the unshaped vibration decay until t_N and read as
// cancelled: impulses below 1e-9 of the sum are left out of the curves (the shaper is then the
// single impulse it is, V = 1).
std::vector<double> residual_curve(const shaping::Shaper& full, const shaping::Mode& reference) {
  double total = 0.0;
  for (const auto& i : full.impulses()) total += std::abs(i.amplitude);
  std::vector<shaping::Impulse> kept;
  for (const auto& i : full.impulses()) {
    if (std::abs(i.amplitude) >= 1e-9 * total) kept.push_back(i);
  }
  const shaping::Shaper shaper(full.method(), std::move(kept), shaping::Shaper::Normalize::no);
  const auto curve = shaping::sensitivity_curve(shaper, reference, reference.damping_ratio, 0.0, kMaxRatio, kPoints);
  std::vector<double> v(kPoints);
  for (std::size_t k = 0; k < kPoints; ++k) v[k] = curve[k].residual;
  return v;
}

// The curves drawn so far: CSV columns and figure series, one per distinct curve.
struct SensitivityCurves {
  std::vector<std::string> names{"frequency_ratio"};
  std::vector<std::vector<double>> curves;
  json series = json::array();

  // A curve identical to one already drawn (the drive-model ZV family for ζ ≈ 1: one impulse
  // each, V ≡ 1) joins it: one line, both names.
  void add(std::vector<double> v, const std::string& column, const std::string& label, const char* variant) {
    for (std::size_t i = 0; i < curves.size(); ++i) {
      if (series[i].at("variant") != variant) continue;
      if (max_abs_difference(curves[i], v) < 1e-12) {
        series[i]["label"] = merged_label(series[i].at("label").get<std::string>(), label);
        return;
      }
    }
    curves.push_back(std::move(v));
    names.push_back(column);
    series.push_back({{"column", column}, {"label", label}, {"variant", variant}});
  }

  // "zv (drive-model)" + "zvd (drive-model)" → "zv = zvd (drive-model)"
  static std::string merged_label(const std::string& merged, const std::string& label) {
    const auto paren = label.find(" (");
    const auto tail = paren == std::string::npos ? std::string() : label.substr(paren);
    if (!tail.empty() && merged.size() > tail.size() && merged.ends_with(tail)) {
      return fmt::format("{} = {}{}", merged.substr(0, merged.size() - tail.size()), label.substr(0, paren), tail);
    }
    return fmt::format("{} = {}", merged, label);
  }
};

// Every designed column's curve as applied and, where the grid matters, as designed.
SensitivityCurves sensitivity_curves(const Context& c, const SimulationPlan& plan) {
  SensitivityCurves out;
  const bool on_link = c.link_mode.available;
  for (std::size_t j = 1; j < plan.columns.size(); ++j) {
    const SimulationColumn& col = plan.columns[j];
    if (!col.shaper) continue;
    const std::string src = col.mode_source();
    const shaping::Mode& own = src == "drive-model" ? c.drive_mode.mode : c.link_mode.mode;
    const shaping::Mode& reference = on_link ? c.link_mode.mode : own;
    std::vector<double> applied = residual_curve(*col.shaper, reference);
    std::string ignored;
    const auto designed = design_off_grid(c, col.method(), src, ignored);
    std::vector<double> as_designed;
    if (designed && !same_impulses(*designed, *col.shaper)) {
      as_designed = residual_curve(*designed, reference);
      if (!(max_abs_difference(as_designed, applied) > kGridEffect)) as_designed.clear();
    }
    out.add(std::move(applied), fmt::format("residual_{}", col.key),
            as_designed.empty() ? col.label : fmt::format("{}, on the {:g} Hz grid", col.label, c.p.shaping.grid_hz),
            "applied");
    if (!as_designed.empty()) {
      out.add(std::move(as_designed), fmt::format("residual_{}_designed", col.key),
              fmt::format("{}, as designed (off the grid)", col.label), "designed");
    }
  }
  return out;
}

// The modes marked on the r axis: the link mode at r = 1 and the drive model's beside it.
json sensitivity_markers(const Context& c) {
  json markers = json::array();
  if (!c.link_mode.available) return markers;
  const double link_rad_s = c.link_mode.mode.natural_frequency_rad_s;
  markers.push_back({{"x", 1.0},
                     {"label", fmt::format("link mode {:.3g} Hz, ζ {:.2g}", link_rad_s / (2.0 * std::numbers::pi),
                                           c.link_mode.mode.damping_ratio)}});
  if (c.drive_mode.available) {
    markers.push_back({{"x", c.drive_mode.mode.natural_frequency_rad_s / link_rad_s},
                       {"label", fmt::format("drive model {:.3g} Hz, ζ {:.2g}",
                                             c.drive_mode.mode.natural_frequency_rad_s / (2.0 * std::numbers::pi),
                                             c.drive_mode.mode.damping_ratio)}});
  }
  return markers;
}

std::string sensitivity_title(const Context& c) {
  if (!c.link_mode.available) {
    return "Shaper sensitivity: residual vibration V vs frequency ratio ω/ωm (Eq. 2.19)";
  }
  return fmt::format("Shaper sensitivity on the link's residual mode (ζ = {:.2g}): residual "
                     "vibration V (Eq. 2.19) vs ω/ω_link, every shaper as applied{}",
                     c.link_mode.mode.damping_ratio,
                     c.p.shaping.grid_hz > 0.0 ? fmt::format(" on the {:g} Hz update grid", c.p.shaping.grid_hz)
                                               : std::string());
}

}  // namespace

void write_sensitivity_figure(Context& c, const SimulationPlan& plan) {
  const bool on_link = c.link_mode.available;
  std::vector<double> ratio(kPoints);
  for (std::size_t k = 0; k < kPoints; ++k) {
    ratio[k] = kMaxRatio * static_cast<double>(k) / static_cast<double>(kPoints - 1);
  }
  const SensitivityCurves curves = sensitivity_curves(c, plan);
  const json markers = sensitivity_markers(c);
  if (curves.curves.empty()) return;
  std::vector<const std::vector<double>*> data{&ratio};
  for (const auto& v : curves.curves) data.push_back(&v);
  write_data_csv(c, "sensitivity.csv", curves.names, data);
  c.figures.push_back({{"id", "shaper-sensitivity"},
                       {"thesis_figure", nullptr},
                       {"kind", "sensitivity"},
                       {"title", sensitivity_title(c)},
                       {"file", c.data_file("sensitivity.csv")},
                       {"x", {{"column", "frequency_ratio"}, {"label", on_link ? "ω / ω_link" : "ω / ωm"}}},
                       {"y_label", "residual vibration V"},
                       {"series", curves.series},
                       {"markers", markers},
                       {"reference_mode", on_link ? "link-mode" : "own"}});
}

}  // namespace clearshape::study::detail
