// Stage 5: simulated tests (thesis §5.1.1, §5.2.1): every input on the study's calibrated model,
// unshaped and with each shaper designed from each mode source; Eq. 5.1, the delay each shaper
// adds, and the shapers' sensitivity curves.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/residual.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

namespace {

// The shaper as designed for a mode source, before the update grid (nullopt with a reason).
std::optional<shaping::Shaper> design_off_grid(const Context& c, const std::string& method,
                                               const std::string& mode_source, std::string& reason) {
  if ((method == kClearanceAwareShaper) != (mode_source == "clearance-model")) {
    reason = "clearance-aware is designed on the clearance model, the linear shapers on a mode";
    return std::nullopt;
  }
  if (method == kClearanceAwareShaper) {
    if (!c.clearance_aware) reason = c.clearance_aware_note;
    return c.clearance_aware;
  }
  const ModeResult& m = mode_source == "drive-model" ? c.drive_mode : c.link_mode;
  if (!m.available) {
    reason = m.note.empty() ? fmt::format("no {} mode", mode_source) : m.note;
    return std::nullopt;
  }
  try {
    shaping::DesignRequest request;
    request.method = shaping::method_from_string(method);
    request.mode = m.mode;
    if (request.method == shaping::Method::si) {  // a protocol's SI: V <= 5 % over ±20 % of the mode
      shaping::SiOptions si;
      si.frequency_low_rad_s = 0.8 * m.mode.natural_frequency_rad_s;
      si.frequency_high_rad_s = 1.2 * m.mode.natural_frequency_rad_s;
      request.si = si;
    }
    return shaping::design(request);
  } catch (const std::exception& e) {
    reason = e.what();
    return std::nullopt;
  }
}

bool same_impulses(const shaping::Shaper& a, const shaping::Shaper& b) {
  const auto& x = a.impulses();
  const auto& y = b.impulses();
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i].time_s - y[i].time_s) > 1e-9 || std::abs(x[i].amplitude - y[i].amplitude) > 1e-12) return false;
  }
  return true;
}

}  // namespace

std::optional<shaping::Shaper> design_for(const Context& c, const std::string& method,
                                          const std::string& mode_source, std::string& reason) {
  auto off_grid = design_off_grid(c, method, mode_source, reason);
  if (!off_grid) return std::nullopt;
  try {
    const shaping::Shaper& designed = *off_grid;
    if (!(c.p.shaping.grid_hz > 0.0)) return designed;
    // The drive's update grid (§3.2): nearest update instant, coincident impulses merged.
    const double t_u = 1.0 / c.p.shaping.grid_hz;
    std::vector<shaping::Impulse> on_grid;
    for (const auto& i : designed.impulses()) {
      const double t = std::round(i.time_s / t_u) * t_u;
      if (!on_grid.empty() && std::abs(on_grid.back().time_s - t) < 0.5 * t_u) {
        on_grid.back().amplitude += i.amplitude;
      } else {
        on_grid.push_back({t, i.amplitude});
      }
    }
    return shaping::Shaper(designed.method(), std::move(on_grid), shaping::Shaper::Normalize::no);
  } catch (const std::exception& e) {
    reason = e.what();
    return std::nullopt;
  }
}

namespace {

std::string figure_for(const Context& c, const InputSpec& in) {
  const std::string type(in.signal.type());
  if (c.p.mode == rig::CommandMode::speed) {
    return type == "step" ? "5.4" : type == "ramp" ? "5.5" : type == "sine" ? "5.6" : type == "prbs" ? "5.7" : "";
  }
  if (type == "step") return "5.12";
  if (type == "ramp") return "5.13";
  if (type == "stacked-steps") return "5.14";
  if (type == "double-step") return "5.15";
  if (type == "parabolic") return "5.16";
  if (type == "trapezoid") return "5.17";
  return "";
}

// Eq. 5.1 needs a steady state: a sine, a PRBS, a parabola, an unbounded ramp or a repeating
// staircase never settles.
bool settles(const signal::Signal& s) {
  const std::string type(s.type());
  if (type == "sine" || type == "prbs" || type == "parabolic") return false;
  if (const auto* r = s.get_if<signal::Ramp>()) return r->limit.has_value();
  if (const auto* st = s.get_if<signal::StackedSteps>()) return !st->repeat;
  return true;
}

std::vector<double> md_values(const Context& c, const ModelResponse& r) {
  return c.p.measure.md_signal == MdSignal::link_angle_deg ? r.link_angle_deg : r.link_rate_deg_s;
}

}  // namespace

void stage_simulation(Context& c) {
  const auto& sim = c.p.simulation;
  if (sim.inputs.empty() || !c.model) {
    c.log("simulation: skipped (no inputs or no calibrated model)");
    return;
  }
  ensure_clearance_aware(c);
  const bool position = c.p.mode == rig::CommandMode::position;
  const std::string md_unit = c.p.measure.md_signal == MdSignal::link_angle_deg ? "deg" : "deg/s";
  const std::string md_name = c.p.measure.md_signal == MdSignal::link_angle_deg ? "link_angle_deg" : "link_rate_deg_s";
  const std::string u = position ? "deg" : "v";

  // Column keys: none, then shaper@source for every source and shaper.
  struct Col {
    std::string key, label;
    std::optional<shaping::Shaper> shaper;
    std::string reason;
  };
  std::vector<Col> cols{{"none", "unshaped", std::nullopt, ""}};
  for (const auto& src : sim.mode_sources) {
    for (const auto& method : sim.shapers) {
      Col col;
      col.key = fmt::format("{}@{}", method, src);
      col.label = fmt::format("{} ({})", method, src);
      col.shaper = design_for(c, method, src, col.reason);
      cols.push_back(std::move(col));
    }
  }

  std::vector<std::vector<double>> md(cols.size()), delay(cols.size());
  std::vector<std::vector<double>> unshaped_motor, unshaped_link;
  std::vector<double> unshaped_time;
  for (const auto& name : sim.inputs) {
    const InputSpec& in = c.p.input(name);
    const UniformSeries command = c.command_of(in, sim.record_s);
    std::vector<std::string> names{"time_s", fmt::format("command_{}", u)};
    std::vector<std::vector<double>> columns;
    ModelResponse base;
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const Col& col = cols[j];
      if (j > 0 && !col.shaper) {
        md[j].push_back(std::numeric_limits<double>::quiet_NaN());
        delay[j].push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      const UniformSeries shaped = j == 0 ? command : shaping::shape_offline(*col.shaper, command, false);
      const ModelResponse r = simulate_command(*c.model, shaped, sim.record_s);
      UniformSeries s;
      s.sample_time_s = r.sample_time_s;
      s.values = md_values(c, r);
      md[j].push_back(settles(in.signal) ? series_mean_deviation(s, c.p.measure, in.last_move_start_s).mean_deviation
                                         : std::numeric_limits<double>::quiet_NaN());
      if (j == 0) {
        base = r;
        delay[j].push_back(0.0);
        columns.push_back(r.time_s);
        columns.push_back(command.values);
        columns.back().resize(r.time_s.size(), command.values.back());
        unshaped_time = r.time_s;
        unshaped_motor.push_back(position ? r.motor_angle_deg : r.motor_rate_deg_s);
        unshaped_link.push_back(r.link_rate_deg_s);
      } else {
        UniformSeries a, b;
        a.sample_time_s = b.sample_time_s = r.sample_time_s;
        a.values = md_values(c, base);
        b.values = s.values;
        const double d = metrics::shaping_delay_s(a, b, 0.5, 0.0);
        delay[j].push_back(d);
        std::vector<double> sc = shaped.values;
        sc.resize(r.time_s.size(), shaped.values.back());
        names.push_back(fmt::format("command_{}_{}", u, col.key));
        columns.push_back(std::move(sc));
      }
      names.push_back(fmt::format("{}_{}", md_name, col.key));
      columns.push_back(s.values);
    }
    std::vector<const std::vector<double>*> data;
    for (const auto& v : columns) data.push_back(&v);
    const std::string file = fmt::format("simulation_{}.csv", name);
    write_data_csv(c, file, names, data);
    // The thesis's figure per input: unshaped and the shapers it used (ZV/ZVD/ZVDD from the drive
    // model in speed mode; ZVDD in position mode, here from the link mode).
    json series = json::array();
    series.push_back({{"column", fmt::format("{}_none", md_name)}, {"label", "unshaped"}});
    for (std::size_t j = 1; j < cols.size(); ++j) {
      if (!cols[j].shaper) continue;
      const bool thesis_like = position ? cols[j].key == "zvdd@link-mode"
                                        : (cols[j].key == "zv@drive-model" || cols[j].key == "zvd@drive-model" ||
                                           cols[j].key == "zvdd@drive-model");
      if (thesis_like) series.push_back({{"column", fmt::format("{}_{}", md_name, cols[j].key)}, {"label", cols[j].label}});
    }
    c.figures.push_back({{"id", fmt::format("simulation-{}", name)},
                         {"thesis_figure", figure_for(c, in)},
                         {"kind", "time-series"},
                         {"title", fmt::format("Simulation with clearance, {}: unshaped and shaped", in.label)},
                         {"file", c.data_file(file)},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", position ? "link angle (deg)" : "link rate (deg/s)"},
                         {"series", series},
                         {"all_columns_prefix", md_name + "_"}});
  }

  // Figures 5.1/5.2 (speed) and 5.10/5.11 (position): every input unshaped, encoder and gyro.
  {
    std::vector<std::string> names{"time_s"};
    std::vector<const std::vector<double>*> data{&unshaped_time};
    json motor_series = json::array(), link_series = json::array();
    for (std::size_t i = 0; i < sim.inputs.size(); ++i) {
      unshaped_motor[i].resize(unshaped_time.size());
      unshaped_link[i].resize(unshaped_time.size());
      names.push_back(fmt::format("motor_{}_{}", position ? "angle_deg" : "speed_deg_s", sim.inputs[i]));
      data.push_back(&unshaped_motor[i]);
      motor_series.push_back({{"column", names.back()}, {"label", c.p.input(sim.inputs[i]).label}});
    }
    for (std::size_t i = 0; i < sim.inputs.size(); ++i) {
      names.push_back(fmt::format("link_rate_deg_s_{}", sim.inputs[i]));
      data.push_back(&unshaped_link[i]);
      link_series.push_back({{"column", names.back()}, {"label", c.p.input(sim.inputs[i]).label}});
    }
    write_data_csv(c, "simulation_unshaped.csv", names, data);
    c.figures.push_back({{"id", "simulation-unshaped-encoder"},
                         {"thesis_figure", position ? "5.10" : "5.1"},
                         {"kind", "time-series"},
                         {"title", "Simulation with clearance, unshaped inputs, motor (encoder)"},
                         {"file", c.data_file("simulation_unshaped.csv")},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", position ? "motor angle (deg)" : "motor speed (deg/s)"},
                         {"series", motor_series}});
    c.figures.push_back({{"id", "simulation-unshaped-gyro"},
                         {"thesis_figure", position ? "5.11" : "5.2"},
                         {"kind", "time-series"},
                         {"title", "Simulation with clearance, unshaped inputs, link (gyroscope)"},
                         {"file", c.data_file("simulation_unshaped.csv")},
                         {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                         {"y_label", "link rate (deg/s)"},
                         {"series", link_series}});
  }

  json table = make_table(position ? "5.2-simulation" : "5.1-simulation", "mean-deviation",
                          "Simulated tests on the calibrated model: Eq. 5.1 per input, unshaped and shaped", md_unit);
  json rows = json::array();
  for (const auto& name : sim.inputs) rows.push_back(c.p.input(name).label);
  table["row_labels"] = rows;
  json tcols = json::array();
  for (std::size_t j = 0; j < cols.size(); ++j) {
    json col = {{"key", cols[j].key}, {"label", cols[j].label}, {"ours", md[j]}, {"delay_s", delay[j]}};
    if (!cols[j].shaper && j > 0) col["note"] = cols[j].reason;
    if (cols[j].shaper) col["shaper_duration_s"] = cols[j].shaper->duration_s();
    tcols.push_back(col);
  }
  table["columns"] = tcols;
  {
    std::string unsettled;
    for (const auto& name : sim.inputs) {
      if (!settles(c.p.input(name).signal)) unsettled += (unsettled.empty() ? "" : ", ") + c.p.input(name).label;
    }
    table["note"] = fmt::format(
        "Model predictions on the study's calibrated model (no sensor noise). The thesis shows these tests as "
        "figures only (Fig. 5.4–5.7, 5.12–5.17). A shaper designed from a mode of this very model cancels it "
        "exactly here; the rig tests show what is left on the rig. The delay (delay_s in results.json) is the "
        "extra time to reach half of the unshaped response's final value.{}",
        unsettled.empty() ? std::string()
                          : fmt::format(" No steady state, so no Eq. 5.1 (—): {} — see their figures.", unsettled));
  }
  c.tables.push_back(table);

  // Shaper sensitivity curves (Eq. 2.19) of every designed shaper, all evaluated on the vibration
  // that matters — the link's identified residual mode (ω_link, ζ_link) — against r = ω/ω_link:
  // a drive-model shaper is designed for ζ ≈ 1 (position) and its own-ζ curve says nothing about
  // the link. Where the drive's 30 Hz update grid moved or merged impulses (design_for), the curve
  // as applied is drawn and, beside it, the curve as designed: the grid is real (the driver
  // applies the position at its updates), so the as-applied curve is what the rig sees; e.g. an
  // MZV for a 15 Hz mode needs impulses 22 and 45 ms apart, the grid gives 33 and 67 ms, and its
  // V(1) is far from 0. Without an identified link mode every shaper is drawn at its own mode.
  const bool on_link = c.link_mode.available;
  std::vector<std::string> names{"frequency_ratio"};
  std::vector<std::vector<double>> curves;
  json series = json::array();
  const std::size_t points = 251;
  std::vector<double> ratio(points);
  for (std::size_t k = 0; k < points; ++k) ratio[k] = 2.5 * static_cast<double>(k) / static_cast<double>(points - 1);
  // Eq. 2.19 compares the residual after the last impulse t_N with one impulse applied at t_N, so
  // an impulse of no consequence (a drive-model ZV for ζ ≈ 1 ends with one of 1e-10) would let the
  // unshaped vibration decay until t_N and read as cancelled: impulses below 1e-9 of the sum are
  // left out of the curves (the shaper is then the single impulse it is, V = 1).
  auto curve_of = [&](const shaping::Shaper& full, const shaping::Mode& reference) {
    double total = 0.0;
    for (const auto& i : full.impulses()) total += std::abs(i.amplitude);
    std::vector<shaping::Impulse> kept;
    for (const auto& i : full.impulses()) {
      if (std::abs(i.amplitude) >= 1e-9 * total) kept.push_back(i);
    }
    const shaping::Shaper shaper(full.method(), std::move(kept), shaping::Shaper::Normalize::no);
    const auto curve = shaping::sensitivity_curve(shaper, reference, reference.damping_ratio, 0.0, 2.5, points);
    std::vector<double> v(points);
    for (std::size_t k = 0; k < points; ++k) v[k] = curve[k].residual;
    return v;
  };
  auto add_curve = [&](std::vector<double> v, const std::string& column, const std::string& label,
                       const char* variant) {
    // A curve identical to one already drawn (the drive-model ZV family for ζ ≈ 1: one impulse
    // each, V ≡ 1) joins it: one line, both names.
    for (std::size_t i = 0; i < curves.size(); ++i) {
      if (series[i].at("variant") != variant) continue;
      double diff = 0.0;
      for (std::size_t k = 0; k < points; ++k) diff = std::max(diff, std::abs(curves[i][k] - v[k]));
      if (diff < 1e-12) {
        // "zv (drive-model)" + "zvd (drive-model)" → "zv = zvd (drive-model)"
        std::string merged = series[i].at("label").get<std::string>();
        const auto paren = label.find(" (");
        const auto tail = paren == std::string::npos ? std::string() : label.substr(paren);
        if (!tail.empty() && merged.size() > tail.size() && merged.ends_with(tail)) {
          merged = fmt::format("{} = {}{}", merged.substr(0, merged.size() - tail.size()), label.substr(0, paren), tail);
        } else {
          merged = fmt::format("{} = {}", merged, label);
        }
        series[i]["label"] = merged;
        return;
      }
    }
    curves.push_back(std::move(v));
    names.push_back(column);
    series.push_back({{"column", column}, {"label", label}, {"variant", variant}});
  };
  // The as-designed curve is drawn only where the grid changes V by more than this (in V, a
  // fraction): a shift of a fraction of a millisecond is not worth a second line.
  constexpr double kGridEffect = 0.02;
  json markers = json::array();
  for (std::size_t j = 1; j < cols.size(); ++j) {
    if (!cols[j].shaper) continue;
    const std::string src = cols[j].key.substr(cols[j].key.find('@') + 1);
    const shaping::Mode& own = src == "drive-model" ? c.drive_mode.mode : c.link_mode.mode;
    const shaping::Mode& reference = on_link ? c.link_mode.mode : own;
    std::vector<double> applied = curve_of(*cols[j].shaper, reference);
    std::string ignored;
    const auto designed = design_off_grid(c, cols[j].key.substr(0, cols[j].key.find('@')), src, ignored);
    std::vector<double> as_designed;
    if (designed && !same_impulses(*designed, *cols[j].shaper)) {
      as_designed = curve_of(*designed, reference);
      double effect = 0.0;
      for (std::size_t k = 0; k < points; ++k) effect = std::max(effect, std::abs(as_designed[k] - applied[k]));
      if (!(effect > kGridEffect)) as_designed.clear();
    }
    add_curve(std::move(applied), fmt::format("residual_{}", cols[j].key),
              as_designed.empty() ? cols[j].label : fmt::format("{}, on the {:g} Hz grid", cols[j].label, c.p.shaping.grid_hz),
              "applied");
    if (!as_designed.empty()) {
      add_curve(std::move(as_designed), fmt::format("residual_{}_designed", cols[j].key),
                fmt::format("{}, as designed (off the grid)", cols[j].label), "designed");
    }
  }
  if (on_link) {
    markers.push_back({{"x", 1.0},
                       {"label", fmt::format("link mode {:.3g} Hz, ζ {:.2g}",
                                             c.link_mode.mode.natural_frequency_rad_s / (2.0 * std::numbers::pi),
                                             c.link_mode.mode.damping_ratio)}});
    if (c.drive_mode.available) {
      markers.push_back({{"x", c.drive_mode.mode.natural_frequency_rad_s / c.link_mode.mode.natural_frequency_rad_s},
                         {"label", fmt::format("drive model {:.3g} Hz, ζ {:.2g}",
                                               c.drive_mode.mode.natural_frequency_rad_s / (2.0 * std::numbers::pi),
                                               c.drive_mode.mode.damping_ratio)}});
    }
  }
  if (!curves.empty()) {
    std::vector<const std::vector<double>*> data{&ratio};
    for (const auto& v : curves) data.push_back(&v);
    write_data_csv(c, "sensitivity.csv", names, data);
    c.figures.push_back(
        {{"id", "shaper-sensitivity"},
         {"thesis_figure", nullptr},
         {"kind", "sensitivity"},
         {"title", on_link ? fmt::format("Shaper sensitivity on the link's residual mode (ζ = {:.2g}): residual "
                                         "vibration V (Eq. 2.19) vs ω/ω_link, every shaper as applied{}",
                                         c.link_mode.mode.damping_ratio,
                                         c.p.shaping.grid_hz > 0.0
                                             ? fmt::format(" on the {:g} Hz update grid", c.p.shaping.grid_hz)
                                             : std::string())
                           : std::string("Shaper sensitivity: residual vibration V vs frequency ratio ω/ωm (Eq. 2.19)")},
         {"file", c.data_file("sensitivity.csv")},
         {"x", {{"column", "frequency_ratio"}, {"label", on_link ? "ω / ω_link" : "ω / ωm"}}},
         {"y_label", "residual vibration V"},
         {"series", series},
         {"markers", markers},
         {"reference_mode", on_link ? "link-mode" : "own"}});
  }
  json designs = json::array();
  for (std::size_t j = 1; j < cols.size(); ++j) {
    json d = {{"key", cols[j].key}};
    if (cols[j].shaper) {
      json imps = json::array();
      for (const auto& i : cols[j].shaper->impulses()) imps.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
      d["impulses"] = imps;
      d["duration_s"] = cols[j].shaper->duration_s();
    } else {
      d["unavailable"] = cols[j].reason;
    }
    designs.push_back(d);
  }
  c.sections["shapers"] = designs;
}

}  // namespace clearshape::study::detail
