// A study protocol read from TOML: one parser per table, each key validated with its file, line and
// key path (protocol.hpp lists the tables); protocol_json.cpp writes it back as JSON.
#include "clearshape/study/protocol.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/parameters.hpp"
#include "toml_reader.hpp"

namespace clearshape::study {

using detail::TomlSection;
using json = nlohmann::ordered_json;

std::string_view to_string(MdSignal signal) noexcept {
  return signal == MdSignal::link_angle_deg ? "link_angle_deg" : "link_rate_deg_s";
}

std::string RigColumn::key() const {
  return shaper == "none" ? std::string("none") : fmt::format("{}@{}", shaper, mode_source);
}

const InputSpec& Protocol::input(std::string_view input_name) const {
  for (const auto& in : inputs) {
    if (in.name == input_name) return in;
  }
  throw InvalidArgument(fmt::format("protocol '{}' has no input '{}'", name, input_name));
}

const RigTable& Protocol::table(std::string_view id) const {
  for (const auto& t : rig_tests.tables) {
    if (t.id == id) return t;
  }
  throw InvalidArgument(fmt::format("protocol '{}' has no rig-test table '{}'", name, id));
}

std::string_view Protocol::command_unit() const noexcept {
  return mode == rig::CommandMode::position ? "deg" : "V";
}

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Protocol key → signal parameter name (units in the key; command unit u = deg | v).
std::optional<std::string> signal_key(std::string_view key, std::string_view u) {
  const std::string suffix = fmt::format("_{}", u);
  for (const char* base : {"amplitude", "second_amplitude", "offset", "limit", "levels"}) {
    if (key == std::string(base) + suffix) return std::string(base);
  }
  if (key == fmt::format("slope_{}_per_s", u)) return std::string("slope_per_s");
  if (key == fmt::format("acceleration_{}_per_s2", u)) return std::string("acceleration_per_s2");
  for (const char* plain : {"start_s", "rise_s", "hold_s", "fall_s", "dwell_s", "second_start_s",
                            "bit_period_s", "frequency_hz", "phase_rad", "order", "seed",
                            "rise_shape", "repeat"}) {
    if (key == plain) return std::string(plain);
  }
  return std::nullopt;
}

// The key a signal parameter takes in the protocol.
std::string protocol_key(std::string_view param, std::string_view u) {
  if (param == "slope_per_s") return fmt::format("slope_{}_per_s", u);
  if (param == "acceleration_per_s2") return fmt::format("acceleration_{}_per_s2", u);
  for (const char* base : {"amplitude", "second_amplitude", "offset", "limit", "levels"}) {
    if (param == base) return fmt::format("{}_{}", param, u);
  }
  return std::string(param);
}

// Start of the last change of a command signal (for the Eq. 5.1 search).
double last_move_start(const signal::Signal& s) {
  return std::visit(
      [](const auto& spec) -> double {
        using T = std::decay_t<decltype(spec)>;
        if constexpr (std::is_same_v<T, signal::DoubleStep>) {
          return spec.second_start_s;
        } else if constexpr (std::is_same_v<T, signal::StackedSteps>) {
          return spec.start_s + spec.dwell_s * static_cast<double>(spec.levels.size() - 1);
        } else if constexpr (std::is_same_v<T, signal::Trapezoid>) {
          return spec.start_s + spec.rise_s + spec.hold_s;
        } else {
          return spec.start_s;
        }
      },
      s.spec());
}

InputSpec parse_input(const TomlSection& t, rig::CommandMode mode) {
  const std::string u = mode == rig::CommandMode::position ? "deg" : "v";
  InputSpec in;
  in.name = t.text("name");
  if (in.name.empty()) t.fail("name", "must not be empty");
  in.label = t.text("label", in.name);
  const std::string type = t.text("type");
  std::span<const std::string_view> allowed_params;
  try {
    allowed_params = signal::parameter_names(type);
  } catch (const InvalidArgument& e) {
    t.fail("type", e.what());
  }
  std::vector<std::string> allowed_keys{"name", "label", "type"};
  for (const auto p : allowed_params) allowed_keys.push_back(protocol_key(p, u));
  signal::SignalParameters params;
  in.parameters["type"] = type;
  for (const auto& key : t.keys()) {
    if (key == "name" || key == "label" || key == "type") continue;
    const auto param = signal_key(key, u);
    const bool known = param && std::find(allowed_params.begin(), allowed_params.end(), *param) !=
                                    allowed_params.end();
    if (!known) {
      t.fail(key, fmt::format("unknown key for a {} input in {} mode; allowed: {}", type,
                              rig::to_string(mode), joined(allowed_keys)));
    }
    const toml::node& n = *t.node(key);
    if (n.is_boolean()) {
      params[*param] = *n.value<bool>();
      in.parameters[key] = *n.value<bool>();
    } else if (n.is_string()) {
      params[*param] = *n.value<std::string>();
      in.parameters[key] = *n.value<std::string>();
    } else if (n.is_array()) {
      const auto values = t.numbers(key);
      params[*param] = values;
      in.parameters[key] = values;
    } else if (n.is_integer() || n.is_floating_point()) {
      const double v = t.number(key);
      params[*param] = v;
      in.parameters[key] = v;
    } else {
      t.fail(key, "must be a number, a string, a boolean or an array of numbers");
    }
  }
  try {
    in.signal = signal::make_signal(type, params);
  } catch (const InvalidArgument& e) {
    throw InputError(t.file(), t.line(), t.key_path("type"), e.what());
  }
  in.last_move_start_s = last_move_start(in.signal);
  return in;
}

ThesisColumn parse_column(const TomlSection& t, std::string_view values_key, std::string_view mean_key,
                          std::string label) {
  ThesisColumn c;
  c.label = std::move(label);
  c.values = t.numbers(values_key);
  if (t.has(mean_key)) c.mean = t.number(mean_key);
  return c;
}

void check_input(const Protocol& p, const TomlSection& t, std::string_view key, const std::string& name) {
  for (const auto& in : p.inputs) {
    if (in.name == name) return;
  }
  std::vector<std::string> names;
  for (const auto& in : p.inputs) names.push_back(in.name);
  t.fail(key, fmt::format("refers to input '{}', which is not defined; defined: {}", name, joined(names)));
}

void check_shaper(const TomlSection& t, std::string_view key, const std::string& name, bool allow_none) {
  if (allow_none && name == "none") return;
  if (name == kClearanceAwareShaper) return;  // designed on the fitted model (clearance_aware.hpp)
  if (allow_none && name == kTakeUpShaper) return;  // rig tests only: per input (take_up.hpp)
  try {
    const auto method = shaping::method_from_string(name);
    if (method == shaping::Method::custom) {
      t.fail(key, fmt::format("shaper '{}' needs parameters a protocol cannot give; use zv, zvd, "
                              "zvdd, zvddd, mzv, ei, ei2, ei3, si, um-zv or clearance-aware", name));
    }
  } catch (const InvalidArgument& e) {
    t.fail(key, e.what());
  }
}

void check_mode_source(const TomlSection& t, std::string_view key, const std::string& s) {
  if (s != "drive-model" && s != "link-mode" && s != "clearance-model") {
    t.fail(key, fmt::format("'{}' is not a mode source; allowed: drive-model, link-mode, clearance-model", s));
  }
}

// clearance-aware is designed on the fitted clearance model, every other shaper on a mode.
void check_pairing(const TomlSection& t, std::string_view key, const std::string& shaper, const std::string& source) {
  if ((shaper == kClearanceAwareShaper || shaper == kTakeUpShaper) != (source == "clearance-model")) {
    t.fail(key, fmt::format("shaper '{}' with mode source '{}': clearance-aware and take-up go with clearance-model and "
                            "the linear shapers with drive-model or link-mode", shaper, source));
  }
}

// One function per protocol table: each reads its keys (defaults as documented in protocol.hpp),
// validates them against what the earlier tables defined, and rejects any other key with the
// file, line and key path (TomlSection::fail, finish).

void parse_study(const TomlSection& top, Protocol& p) {
  const auto study = top.table("study");
  if (!study) top.fail("", "missing table [study]");
  p.name = study->text("name");
  p.title = study->text("title", p.name);
  try {
    p.mode = rig::command_mode_from_string(study->text("mode"));
  } catch (const InvalidArgument& e) {
    study->fail("mode", e.what());
  }
  p.seed = static_cast<std::uint64_t>(study->integer("seed", 1, 0, INT64_MAX));
  p.sample_rate_hz = study->positive("sample_rate_hz", 1000.0);
  p.record_s = study->positive("record_s", 5.0);
  // The limits every run applies (rig::SimRigOptions, core's sampled-series cap), checked here so
  // that a study never creates its folder for a rate or a record length no run accepts.
  try {
    rig::SimRigOptions rate;
    rate.sample_rate_hz = p.sample_rate_hz;
    rate.validate();
  } catch (const InvalidArgument& e) {
    study->fail("sample_rate_hz", e.what());
  }
  if (p.record_s * p.sample_rate_hz > 1e9) {
    study->fail("record_s", fmt::format("{} s at {} Hz is {:.3g} samples per record; allowed: at most 1e9",
                                        p.record_s, p.sample_rate_hz, p.record_s * p.sample_rate_hz));
  }
  p.repetitions = static_cast<int>(study->integer("repetitions", 10, 2, 1000));
  p.rig = study->text("rig", "thesis");
  if (!rig::is_builtin_truth(p.rig)) {
    study->fail("rig", fmt::format("is '{}', not a built-in rig; allowed: {}", p.rig,
                                   fmt::join(rig::kBuiltinTruthNames, ", ")));
  }
  study->finish("name, title, mode, seed, sample_rate_hz, record_s, repetitions, rig");
}

void parse_measure(const TomlSection& top, Protocol& p) {
  const auto m = top.table("measure");
  if (!m) {
    p.measure.md_signal = p.mode == rig::CommandMode::position ? MdSignal::link_angle_deg
                                                               : MdSignal::link_rate_deg_s;
    return;
  }
  const std::string s = m->text("md_signal", p.mode == rig::CommandMode::position
                                                 ? "link_angle_deg" : "link_rate_deg_s");
  if (s == "link_angle_deg") {
    p.measure.md_signal = MdSignal::link_angle_deg;
  } else if (s == "link_rate_deg_s") {
    p.measure.md_signal = MdSignal::link_rate_deg_s;
  } else {
    m->fail("md_signal", fmt::format("'{}' is not a signal; allowed: link_angle_deg, link_rate_deg_s", s));
  }
  p.measure.bias_window_s = m->positive("bias_window_s", 0.4);
  p.measure.md_final_window_fraction = m->positive("md_final_window_fraction", 0.2);
  if (p.measure.md_final_window_fraction > 1.0) m->fail("md_final_window_fraction", "must be in (0, 1]");
  m->finish("md_signal, bias_window_s, md_final_window_fraction");
}

void parse_shaping(const TomlSection& top, Protocol& p) {
  const auto sh = top.table("shaping");
  if (!sh) return;
  p.shaping.grid_hz = sh->number("grid_hz", 0.0);
  if (p.shaping.grid_hz < 0.0) sh->fail("grid_hz", "must be >= 0 (0 = keep the designed impulse times)");
  p.shaping.clearance_aware_max_duration_s = sh->number("clearance_aware_max_duration_s", 0.0);
  const double bound = p.shaping.clearance_aware_max_duration_s;
  if (!(bound == 0.0 || (bound >= 1e-3 && bound <= 5.0))) {
    sh->fail("clearance_aware_max_duration_s", "must be 0 (ZVDD's duration for the link mode) or in [0.001, 5] s");
  }
  p.shaping.clearance_aware_max_evaluations = static_cast<int>(sh->number("clearance_aware_max_evaluations", 300.0));
  if (p.shaping.clearance_aware_max_evaluations < 10 || p.shaping.clearance_aware_max_evaluations > 100000) {
    sh->fail("clearance_aware_max_evaluations", "must be in [10, 100000]");
  }
  sh->finish("grid_hz, clearance_aware_max_duration_s, clearance_aware_max_evaluations");
}

void parse_inputs(const TomlSection& top, Protocol& p) {
  for (const auto& t : top.tables("input")) {
    InputSpec in = parse_input(t, p.mode);
    for (const auto& other : p.inputs) {
      if (other.name == in.name) t.fail("name", fmt::format("input '{}' is defined twice", in.name));
    }
    if (in.last_move_start_s < p.measure.bias_window_s) {
      t.fail("start_s", fmt::format("the move starts at {} s, before the end of the gyro-bias "
                                    "window ({} s); start it later", in.last_move_start_s,
                                    p.measure.bias_window_s));
    }
    p.inputs.push_back(std::move(in));
  }
  if (p.inputs.empty()) top.fail("", "no [[input]] defined");
}

void parse_consistency(const TomlSection& top, Protocol& p) {
  const auto c = top.table("consistency");
  if (!c) return;
  p.consistency.table = c->text("table", "4.1");
  p.consistency.inputs = c->texts("inputs");
  for (const auto& name : p.consistency.inputs) check_input(p, *c, "inputs", name);
  p.consistency.signal = c->text("signal", p.mode == rig::CommandMode::position ? "motor_angle_deg"
                                                                                : "motor_speed_deg_s");
  if (p.consistency.signal != "motor_angle_deg" && p.consistency.signal != "motor_speed_deg_s") {
    c->fail("signal", "allowed: motor_angle_deg, motor_speed_deg_s");
  }
  if (const auto th = c->table("thesis")) {
    for (const auto& key : th->keys()) {
      check_input(p, *th, key, key);
      const auto col = th->table(key);
      p.consistency.thesis[key] = parse_column(*col, "values", "mean", col->text("label", key));
      col->finish("label, values, mean");
    }
  }
  c->finish("table, inputs, signal, thesis");
}

void parse_identification(const TomlSection& top, Protocol& p) {
  const auto s = top.table("identification");
  if (!s) return;
  p.identification.structure = s->text("structure", "P3UZ");
  p.identification.inputs = s->texts("inputs");
  for (const auto& name : p.identification.inputs) check_input(p, *s, "inputs", name);
  p.identification.speed_chain = s->text("speed_chain", "causal");
  if (p.identification.speed_chain != "causal" && p.identification.speed_chain != "zero-phase") {
    s->fail("speed_chain", "allowed: causal, zero-phase");
  }
  if (const auto th = s->table("thesis")) {
    auto& m = p.identification.thesis;
    m.selected_input = th->text("selected_input", "");
    m.kp = th->number("kp");
    m.tz_s = th->number("tz_s");
    m.zeta = th->number("zeta");
    m.tw_s = th->number("tw_s");
    m.tp3_s = th->number("tp3_s");
    th->finish("selected_input, kp, tz_s, zeta, tw_s, tp3_s");
  }
  s->finish("structure, inputs, speed_chain, thesis");
}

void parse_link_mode(const TomlSection& top, Protocol& p) {
  const auto s = top.table("link_mode");
  if (!s) return;
  p.link_mode.input = s->text("input");
  check_input(p, *s, "input", p.link_mode.input);
  p.link_mode.start = s->text("start", "after-settling");
  if (p.link_mode.start != "after-settling" && p.link_mode.start != "after-command") {
    s->fail("start", "allowed: after-settling, after-command");
  }
  p.link_mode.settle_after_move_s = s->number("settle_after_move_s", 0.05);
  p.link_mode.window_s = s->positive("window_s", 1.5);
  p.link_mode.max_damping_ratio = s->positive("max_damping_ratio", 0.7);
  s->finish("input, start, settle_after_move_s, window_s, max_damping_ratio");
}

void parse_clearance(const TomlSection& top, Protocol& p) {
  const auto s = top.table("clearance");
  if (!s) return;
  auto& c = p.clearance;
  c.input = s->text("input");
  check_input(p, *s, "input", c.input);
  c.exponent = s->positive("exponent", 1.5);
  c.link_inertia_kg_m2 = s->positive("link_inertia_kg_m2", 5e-3);
  c.play_deg = s->positive("play_deg", 0.1);
  c.stiffness_n_m_per_rad_pow_n = s->positive("stiffness_n_m_per_rad_pow_n", 1e4);
  c.damping_n_m_s_per_rad = s->number("damping_n_m_s_per_rad", 300.0);
  if (c.damping_n_m_s_per_rad < 0.0) s->fail("damping_n_m_s_per_rad", "must be >= 0");
  c.contact_law = s->text("contact_law", "dashpot");
  if (c.contact_law != "dashpot" && c.contact_law != "flores") {
    s->fail("contact_law", fmt::format("'{}' is not a contact law; allowed: dashpot, flores", c.contact_law));
  }
  c.restitution = s->number("restitution", 0.6);
  if (!(c.restitution >= 0.05 && c.restitution <= 1.0)) s->fail("restitution", "must be in [0.05, 1]");
  const bool flores = c.contact_law == "flores";
  c.fit = s->texts("fit");
  for (auto& f : c.fit) {
    if (flores && f == "restitution") f = "damping";  // the Flores law's dissipation parameter is e
    if (f != "stiffness" && f != "damping" && f != "play" && f != "exponent") {
      s->fail("fit", fmt::format("'{}' cannot be fitted; allowed: stiffness, {}, play, exponent", f,
                                 flores ? "restitution (or damping)" : "damping"));
    }
  }
  c.filter_gyro = s->boolean("filter_gyro", false);
  c.window_s = s->positive("window_s", 2.0);
  c.max_evaluations = static_cast<int>(s->integer("max_evaluations", 150, 1, 100000));
  if (const auto th = s->table("thesis")) {
    if (th->has("stiffness")) c.thesis_stiffness = th->number("stiffness");
    if (th->has("damping")) c.thesis_damping = th->number("damping");
    if (th->has("agreement")) c.thesis_agreement = th->number("agreement");
    th->finish("stiffness, damping, agreement");
  }
  s->finish("input, exponent, link_inertia_kg_m2, play_deg, stiffness_n_m_per_rad_pow_n, "
            "damping_n_m_s_per_rad, contact_law, restitution, fit, filter_gyro, window_s, max_evaluations, thesis");
}

void parse_simulation(const TomlSection& top, Protocol& p) {
  const auto s = top.table("simulation");
  if (!s) return;
  auto& m = p.simulation;
  m.inputs = s->texts("inputs");
  for (const auto& name : m.inputs) check_input(p, *s, "inputs", name);
  m.shapers = s->texts("shapers");
  for (const auto& name : m.shapers) check_shaper(*s, "shapers", name, false);
  m.mode_sources = s->texts("mode_sources");
  for (const auto& src : m.mode_sources) check_mode_source(*s, "mode_sources", src);
  m.record_s = s->positive("record_s", p.record_s);
  s->finish("inputs, shapers, mode_sources, record_s");
}

// [[rig_tests.table.column]]: one column of a rig table, unique in `table`.
RigColumn parse_rig_column(const TomlSection& c, const RigTable& table) {
  RigColumn col;
  col.shaper = c.text("shaper", "none");
  check_shaper(c, "shaper", col.shaper, true);
  if (col.shaper != "none") {
    col.mode_source = c.text("mode_source");
    check_mode_source(c, "mode_source", col.mode_source);
    check_pairing(c, "mode_source", col.shaper, col.mode_source);
  }
  col.label = c.text("label", col.key());
  col.thesis = parse_column(c, "thesis", "thesis_mean", col.label);
  if (c.has("thesis_improvement")) col.thesis_improvement = c.number("thesis_improvement");
  for (const auto& other : table.columns) {
    if (other.key() == col.key()) c.fail("shaper", fmt::format("column '{}' appears twice", col.key()));
  }
  c.finish("shaper, mode_source, label, thesis, thesis_mean, thesis_improvement");
  return col;
}

// [[rig_tests.table]]: a rig table of `p` (the tables before it already in p.rig_tests).
RigTable parse_rig_table(const TomlSection& t, const Protocol& p) {
  RigTable table;
  table.id = t.text("id");
  table.title = t.text("title", table.id);
  table.input = t.text("input");
  check_input(p, t, "input", table.input);
  for (const auto& c : t.tables("column")) table.columns.push_back(parse_rig_column(c, table));
  if (table.columns.empty()) t.fail("column", "a table needs at least one [[rig_tests.table.column]]");
  for (const auto& other : p.rig_tests.tables) {
    if (other.id == table.id) t.fail("id", fmt::format("table '{}' is defined twice", table.id));
  }
  t.finish("id, title, input, column");
  return table;
}

// An improvement summary's tables need the unshaped column and the shaped one it names.
void check_improvement_columns(const TomlSection& t, const Protocol& p, const RigSummary& sum) {
  if (sum.column.empty()) t.fail("column", "an improvement summary names the shaped column");
  for (const auto& id : sum.tables) {
    const auto& table = p.table(id);
    const bool has = std::any_of(table.columns.begin(), table.columns.end(),
                                 [&](const RigColumn& c) { return c.key() == sum.column; });
    const bool has_none = std::any_of(table.columns.begin(), table.columns.end(),
                                      [&](const RigColumn& c) { return c.key() == "none"; });
    if (!has || !has_none) {
      t.fail("column", fmt::format("table '{}' needs columns 'none' and '{}'", id, sum.column));
    }
  }
}

// [[rig_tests.summary]]: a summary of rig tables already parsed.
RigSummary parse_rig_summary(const TomlSection& t, const Protocol& p) {
  RigSummary sum;
  sum.id = t.text("id");
  sum.title = t.text("title", sum.id);
  sum.kind = t.text("kind");
  if (sum.kind != "combine" && sum.kind != "improvement") t.fail("kind", "allowed: combine, improvement");
  sum.tables = t.texts("tables");
  for (const auto& id : sum.tables) {
    const bool found = std::any_of(p.rig_tests.tables.begin(), p.rig_tests.tables.end(),
                                   [&](const RigTable& x) { return x.id == id; });
    if (!found) t.fail("tables", fmt::format("refers to table '{}', which is not defined", id));
  }
  sum.column = t.text("column", "");
  if (sum.kind == "improvement") check_improvement_columns(t, p, sum);
  sum.thesis = t.numbers("thesis");
  if (!sum.thesis.empty() && sum.thesis.size() != sum.tables.size()) {
    t.fail("thesis", "needs one value per table");
  }
  t.finish("id, title, kind, tables, column, thesis");
  return sum;
}

void parse_rig_tests(const TomlSection& top, Protocol& p) {
  const auto s = top.table("rig_tests");
  if (!s) return;
  for (const auto& t : s->tables("table")) p.rig_tests.tables.push_back(parse_rig_table(t, p));
  for (const auto& t : s->tables("summary")) p.rig_tests.summaries.push_back(parse_rig_summary(t, p));
  // The floor is read in the tables' input windows: without a table it has none.
  p.rig_tests.floor_trials = static_cast<int>(s->integer("floor_trials", 0, 0, 1000));
  if (p.rig_tests.floor_trials > 0 && p.rig_tests.tables.empty()) {
    s->fail("floor_trials", "needs at least one [[rig_tests.table]] (the floor is read in its input's window)");
  }
  s->finish("table, summary, floor_trials");
}

void parse_quick(const TomlSection& top, Protocol& p) {
  const auto q = top.table("quick");
  if (!q) return;
  auto& r = p.quick_reduction;
  r.repetitions = static_cast<int>(q->integer("repetitions", 3, 2, 1000));
  r.record_s = q->positive("record_s", 3.0);
  r.simulation_inputs = q->texts("simulation_inputs");
  for (const auto& name : r.simulation_inputs) check_input(p, *q, "simulation_inputs", name);
  r.simulation_shapers = q->texts("simulation_shapers");
  for (const auto& name : r.simulation_shapers) check_shaper(*q, "simulation_shapers", name, false);
  r.clearance_max_evaluations = static_cast<int>(q->integer("clearance_max_evaluations", 40, 1, 100000));
  q->finish("repetitions, record_s, simulation_inputs, simulation_shapers, clearance_max_evaluations");
}

// Every input's last move must start inside the record (Eq. 5.1 needs its steady state there).
void check_moves_in_record(const Protocol& p, const std::string& file) {
  for (const auto& in : p.inputs) {
    if (in.last_move_start_s >= p.record_s) {
      throw InputError(file, 0, "input " + in.name,
                       fmt::format("the last move starts at {} s, after the record ends ({} s)",
                                   in.last_move_start_s, p.record_s));
    }
  }
}

}  // namespace

Protocol parse_protocol(std::string_view text, const std::filesystem::path& source) {
  const std::string file = source.string();
  const toml::table root = detail::parse_toml(text, file);
  const TomlSection top(root, "", file);
  Protocol p;
  p.source = source;
  const std::string format = top.text("format");
  if (format != kProtocolFormat) {
    top.fail("format", fmt::format("is '{}'; this clearshape reads '{}'", format, kProtocolFormat));
  }
  // In this order: a table may refer to what an earlier one defined (inputs, rig tables).
  parse_study(top, p);
  parse_measure(top, p);
  parse_shaping(top, p);
  parse_inputs(top, p);
  parse_consistency(top, p);
  parse_identification(top, p);
  parse_link_mode(top, p);
  parse_clearance(top, p);
  parse_simulation(top, p);
  parse_rig_tests(top, p);
  parse_quick(top, p);
  check_moves_in_record(p, file);
  top.finish("format, study, measure, shaping, input, consistency, identification, link_mode, clearance, "
             "simulation, rig_tests, quick");
  return p;
}

Protocol load_protocol(const std::filesystem::path& path) {
  return parse_protocol(io::read_text_file(path), path);
}

Protocol quick_variant(const Protocol& protocol) {
  Protocol p = protocol;
  if (p.quick) return p;
  const auto& r = p.quick_reduction;
  p.quick = true;
  p.repetitions = std::min(p.repetitions, r.repetitions);
  p.rig_tests.floor_trials = std::min(p.rig_tests.floor_trials, r.repetitions);
  p.record_s = std::min(p.record_s, r.record_s);
  p.simulation.record_s = std::min(p.simulation.record_s, r.record_s);
  if (!r.simulation_inputs.empty()) p.simulation.inputs = r.simulation_inputs;
  if (!r.simulation_shapers.empty()) p.simulation.shapers = r.simulation_shapers;
  p.clearance.max_evaluations = std::min(p.clearance.max_evaluations, r.clearance_max_evaluations);
  p.clearance.window_s = std::min(p.clearance.window_s, p.record_s);
  return p;
}

}  // namespace clearshape::study
