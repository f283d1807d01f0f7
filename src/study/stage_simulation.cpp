// Stage 5: simulated tests (thesis §5.1.1, §5.2.1): every input on the study's calibrated model,
// unshaped and with each shaper designed from each mode source; Eq. 5.1, the delay each shaper
// adds (plan → run → tabulate, simulation.hpp); the shapers' sensitivity curves are drawn by
// simulation_sensitivity.cpp.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/residual.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/grid.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"
#include "simulation.hpp"

namespace clearshape::study::detail {

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

std::optional<shaping::Shaper> design_for(const Context& c, const std::string& method,
                                          const std::string& mode_source, std::string& reason) {
  auto off_grid = design_off_grid(c, method, mode_source, reason);
  if (!off_grid) return std::nullopt;
  try {
    const shaping::Shaper& designed = *off_grid;
    if (!(c.p.shaping.grid_hz > 0.0)) return designed;
    // The drive's update grid (§3.2): nearest update instant, coincident impulses merged.
    return shaping::on_update_grid(designed, 1.0 / c.p.shaping.grid_hz);
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

bool position_mode(const Context& c) { return c.p.mode == rig::CommandMode::position; }

std::vector<double> md_values(const Context& c, const ModelResponse& r) {
  return c.p.measure.md_signal == MdSignal::link_angle_deg ? r.link_angle_deg : r.link_rate_deg_s;
}

std::string md_name_of(const Context& c) {
  return c.p.measure.md_signal == MdSignal::link_angle_deg ? "link_angle_deg" : "link_rate_deg_s";
}

// The command unit in column names: deg (position) or v (speed).
std::string command_suffix(const Context& c) { return position_mode(c) ? "deg" : "v"; }

// The CSV of one input (data/simulation_<input>.csv): time, the unshaped command, then per
// column its shaped command (shaped columns only) and its Eq. 5.1 signal.
struct SimulatedInput {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
};

// Plan: unshaped, then every shaper designed from every mode source.
SimulationPlan plan_simulation(const Context& c) {
  const auto& sim = c.p.simulation;
  SimulationPlan plan;
  plan.columns.push_back({"none", "unshaped", std::nullopt, ""});
  for (const auto& src : sim.mode_sources) {
    for (const auto& method : sim.shapers) {
      SimulationColumn col;
      col.key = fmt::format("{}@{}", method, src);
      col.label = fmt::format("{} ({})", method, src);
      col.shaper = design_for(c, method, src, col.reason);
      plan.columns.push_back(std::move(col));
    }
  }
  return plan;
}

// Run: one input on the calibrated model in every column; Eq. 5.1 and the delay each shaper
// adds into `runs`, the input's CSV columns returned.
SimulatedInput simulate_input(const Context& c, const SimulationPlan& plan, const InputSpec& in, SimulationRuns& runs) {
  const double record_s = c.p.simulation.record_s;
  const std::string u = command_suffix(c);
  const UniformSeries command = c.command_of(in, record_s);
  SimulatedInput out{{"time_s", fmt::format("command_{}", u)}, {}};
  ModelResponse base;
  for (std::size_t j = 0; j < plan.columns.size(); ++j) {
    const SimulationColumn& col = plan.columns[j];
    if (j > 0 && !col.shaper) {
      runs.md[j].push_back(std::numeric_limits<double>::quiet_NaN());
      runs.delay[j].push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const UniformSeries shaped = j == 0 ? command : shaping::shape_offline(*col.shaper, command, false);
    const ModelResponse r = simulate_command(*c.model, shaped, record_s);
    UniformSeries s;
    s.sample_time_s = r.sample_time_s;
    s.values = md_values(c, r);
    runs.md[j].push_back(settles(in.signal) ? series_mean_deviation(s, c.p.measure, in.last_move_start_s).mean_deviation
                                            : std::numeric_limits<double>::quiet_NaN());
    if (j == 0) {
      base = r;
      runs.delay[j].push_back(0.0);
      out.columns.push_back(r.time_s);
      out.columns.push_back(command.values);
      out.columns.back().resize(r.time_s.size(), command.values.back());
      runs.unshaped_time = r.time_s;
      runs.unshaped_motor.push_back(position_mode(c) ? r.motor_angle_deg : r.motor_rate_deg_s);
      runs.unshaped_link.push_back(r.link_rate_deg_s);
    } else {
      UniformSeries a, b;
      a.sample_time_s = b.sample_time_s = r.sample_time_s;
      a.values = md_values(c, base);
      b.values = s.values;
      runs.delay[j].push_back(metrics::shaping_delay_s(a, b, 0.5, 0.0));
      std::vector<double> sc = shaped.values;
      sc.resize(r.time_s.size(), shaped.values.back());
      out.names.push_back(fmt::format("command_{}_{}", u, col.key));
      out.columns.push_back(std::move(sc));
    }
    out.names.push_back(fmt::format("{}_{}", md_name_of(c), col.key));
    out.columns.push_back(s.values);
  }
  return out;
}

// Tabulate: data/simulation_<input>.csv and the thesis's figure of the input: unshaped and the
// shapers it used (ZV/ZVD/ZVDD from the drive model in speed mode; ZVDD in position mode, here
// from the link mode).
void write_input_figure(Context& c, const SimulationPlan& plan, const InputSpec& in, const SimulatedInput& run) {
  const bool position = position_mode(c);
  const std::string md_name = md_name_of(c);
  std::vector<const std::vector<double>*> data;
  for (const auto& v : run.columns) data.push_back(&v);
  const std::string file = fmt::format("simulation_{}.csv", in.name);
  write_data_csv(c, file, run.names, data);
  json series = json::array();
  series.push_back({{"column", fmt::format("{}_none", md_name)}, {"label", "unshaped"}});
  for (std::size_t j = 1; j < plan.columns.size(); ++j) {
    const SimulationColumn& col = plan.columns[j];
    if (!col.shaper) continue;
    const bool thesis_like = position ? col.key == "zvdd@link-mode"
                                      : (col.key == "zv@drive-model" || col.key == "zvd@drive-model" ||
                                         col.key == "zvdd@drive-model");
    if (thesis_like) series.push_back({{"column", fmt::format("{}_{}", md_name, col.key)}, {"label", col.label}});
  }
  c.figures.push_back({{"id", fmt::format("simulation-{}", in.name)},
                       {"thesis_figure", figure_for(c, in)},
                       {"kind", "time-series"},
                       {"title", fmt::format("Simulation with clearance, {}: unshaped and shaped", in.label)},
                       {"file", c.data_file(file)},
                       {"x", {{"column", "time_s"}, {"label", "time (s)"}}},
                       {"y_label", position ? "link angle (deg)" : "link rate (deg/s)"},
                       {"series", series},
                       {"all_columns_prefix", md_name + "_"}});
}

// Figures 5.1/5.2 (speed) and 5.10/5.11 (position): every input unshaped, encoder and gyro
// (data/simulation_unshaped.csv).
void write_unshaped_figures(Context& c, SimulationRuns& runs) {
  const auto& inputs = c.p.simulation.inputs;
  const bool position = position_mode(c);
  std::vector<std::string> names{"time_s"};
  std::vector<const std::vector<double>*> data{&runs.unshaped_time};
  json motor_series = json::array(), link_series = json::array();
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    runs.unshaped_motor[i].resize(runs.unshaped_time.size());
    runs.unshaped_link[i].resize(runs.unshaped_time.size());
    names.push_back(fmt::format("motor_{}_{}", position ? "angle_deg" : "speed_deg_s", inputs[i]));
    data.push_back(&runs.unshaped_motor[i]);
    motor_series.push_back({{"column", names.back()}, {"label", c.p.input(inputs[i]).label}});
  }
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    names.push_back(fmt::format("link_rate_deg_s_{}", inputs[i]));
    data.push_back(&runs.unshaped_link[i]);
    link_series.push_back({{"column", names.back()}, {"label", c.p.input(inputs[i]).label}});
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

// The table's note: what the numbers are, and which inputs have no Eq. 5.1.
std::string simulation_note(const Context& c) {
  std::string unsettled;
  for (const auto& name : c.p.simulation.inputs) {
    if (!settles(c.p.input(name).signal)) unsettled += (unsettled.empty() ? "" : ", ") + c.p.input(name).label;
  }
  return fmt::format(
      "Model predictions on the study's calibrated model (no sensor noise). The thesis shows these tests as "
      "figures only (Fig. 5.4–5.7, 5.12–5.17). A shaper designed from a mode of this very model cancels it "
      "exactly here; the rig tests show what is left on the rig. The delay (delay_s in results.json) is the "
      "extra time to reach half of the unshaped response's final value.{}",
      unsettled.empty() ? std::string()
                        : fmt::format(" No steady state, so no Eq. 5.1 (—): {} — see their figures.", unsettled));
}

// Tabulate: the 5.1/5.2-simulation table, Eq. 5.1 per input (rows) and column.
void tabulate_simulation(Context& c, const SimulationPlan& plan, const SimulationRuns& runs) {
  const std::string md_unit = c.p.measure.md_signal == MdSignal::link_angle_deg ? "deg" : "deg/s";
  json table = make_table(position_mode(c) ? "5.2-simulation" : "5.1-simulation", "mean-deviation",
                          "Simulated tests on the calibrated model: Eq. 5.1 per input, unshaped and shaped", md_unit);
  json rows = json::array();
  for (const auto& name : c.p.simulation.inputs) rows.push_back(c.p.input(name).label);
  table["row_labels"] = rows;
  json tcols = json::array();
  for (std::size_t j = 0; j < plan.columns.size(); ++j) {
    const SimulationColumn& col = plan.columns[j];
    json tc = {{"key", col.key}, {"label", col.label}, {"ours", runs.md[j]}, {"delay_s", runs.delay[j]}};
    if (!col.shaper && j > 0) tc["note"] = col.reason;
    if (col.shaper) tc["shaper_duration_s"] = col.shaper->duration_s();
    tcols.push_back(tc);
  }
  table["columns"] = tcols;
  table["note"] = simulation_note(c);
  c.tables.push_back(table);
}

// results.json sections.shapers: every shaped column's impulses, or why it is unavailable.
void record_shaper_designs(Context& c, const SimulationPlan& plan) {
  json designs = json::array();
  for (std::size_t j = 1; j < plan.columns.size(); ++j) {
    const SimulationColumn& col = plan.columns[j];
    json d = {{"key", col.key}};
    if (col.shaper) {
      json imps = json::array();
      for (const auto& i : col.shaper->impulses()) imps.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
      d["impulses"] = imps;
      d["duration_s"] = col.shaper->duration_s();
    } else {
      d["unavailable"] = col.reason;
    }
    designs.push_back(d);
  }
  c.sections["shapers"] = designs;
}

}  // namespace

void stage_simulation(Context& c) {
  const auto& sim = c.p.simulation;
  if (sim.inputs.empty() || !c.model) {
    c.log("simulation: skipped (no inputs or no calibrated model)");
    return;
  }
  ensure_clearance_aware(c);
  const SimulationPlan plan = plan_simulation(c);
  SimulationRuns runs;
  runs.md.resize(plan.columns.size());
  runs.delay.resize(plan.columns.size());
  for (const auto& name : sim.inputs) {
    const InputSpec& in = c.p.input(name);
    const SimulatedInput run = simulate_input(c, plan, in, runs);
    write_input_figure(c, plan, in, run);
  }
  write_unshaped_figures(c, runs);
  tabulate_simulation(c, plan, runs);
  write_sensitivity_figure(c, plan);
  record_shaper_designs(c, plan);
}

}  // namespace clearshape::study::detail
