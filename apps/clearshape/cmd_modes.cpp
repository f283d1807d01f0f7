// clearshape modes: the dominant lightly damped modes of a record — a free decay of the link
// sensor after a move (ERA + damped-sinusoid least squares), or input/output data (subspace +
// output-error fit) — with frequency, damping ratio, amplitude and their 1σ, ready for shaper
// design (docs/design.md §2: the link's residual mode, not the drive's ζ ≈ 1 position model).
// The model order comes from a stabilisation diagram (ident/stabilisation.hpp; docs/cli.md).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/stabilisation.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "command.hpp"

namespace clearshape::cli {

namespace {

struct ModesState {
  std::string data;
  std::string input_column, output_column, time_column;
  double sample_time_s = 0.0;
  CLI::Option* sample_time_option = nullptr;
  std::size_t modes = 1;
  std::size_t order = 0;
  std::size_t from_sample = 0;
  std::size_t to_sample = 0;
  CLI::Option* from_s_option = nullptr;
  CLI::Option* to_s_option = nullptr;
  double from_s = 0.0, to_s = 0.0;
  double max_damping = 0.7;
  bool no_refine = false;
  bool no_offset = false;
  bool json = false;
  bool allow_unstable = false;  // --allow-unstable: report unstable or aliased poles with exit 0
  bool no_stabilisation = false;  // --no-stabilisation: order 2·modes(+2) as before the diagram
  ident::StabilisationOptions stabilisation;
  std::string diagram_csv;        // --diagram-csv: the stabilisation diagram for plotting
};

std::size_t column_index(const io::Table& t, const std::string& spec) {
  if (auto i = t.find(spec)) return *i;
  (void)t.column(spec);  // throws InputError listing the columns when neither a name nor an index
  return static_cast<std::size_t>(std::stoul(spec)) - 1;
}

std::optional<std::size_t> time_column(const io::Table& t) {
  if (const auto name = io::find_time_column(t)) return t.find(*name);
  return std::nullopt;
}

// The window in samples: --from-s/--to-s (seconds, need a sample time) or --from-sample/--to-sample.
std::pair<std::size_t, std::size_t> window(const ModesState& st, std::size_t size, double dt, bool per_sample) {
  const bool seconds = st.from_s_option->count() > 0 || st.to_s_option->count() > 0;
  std::size_t from = st.from_sample, end = st.to_sample > 0 ? st.to_sample : size;
  if (seconds) {
    if (st.from_sample > 0 || st.to_sample > 0) throw InvalidArgument("modes: give the window in seconds or in samples, not both");
    if (per_sample) throw InvalidArgument("modes: --from-s/--to-s need a time column or --sample-time");
    from = static_cast<std::size_t>(std::llround(std::max(0.0, st.from_s) / dt));
    end = st.to_s_option->count() > 0 ? static_cast<std::size_t>(std::llround(st.to_s / dt)) : size;
  }
  if (!(from < end && end <= size)) {
    throw InvalidArgument(fmt::format("modes: window [{}, {}) samples is out of range; the record has {} samples ({} s)", from, end,
                                      size, per_sample ? 0.0 : dt * static_cast<double>(size)));
  }
  return {from, end};
}

// A mode is stable when its pole decays (ζ > 0) and lies clearly below the Nyquist frequency: a
// discrete pole z = r·e^(iθ) with r ≥ 1 grows, and one at θ ≥ 0.9π (90 % of Nyquist) is an alias
// or an artefact of the sampling, not a mode the record resolves. Empty: stable.
constexpr double kNyquistFraction = 0.9;

std::string instability(const ident::ModeEstimate& m, double dt) {
  if (!(m.damping_ratio > 0.0)) {
    return fmt::format("damping ratio {:.4g} ≤ 0: a growing (unstable) pole, not a decaying mode", m.damping_ratio);
  }
  const double nyquist_fraction = m.damped_frequency_rad_s() * dt / kPi;  // θ / π
  if (nyquist_fraction >= kNyquistFraction) {
    return fmt::format("at {:.0f} % of the Nyquist frequency (limit {:.0f} %): aliased or an artefact of the sampling",
                       100.0 * nyquist_fraction, 100.0 * kNyquistFraction);
  }
  return {};
}

// The guard rails (docs/recordings.md): an unstable or aliased pole, a σ that is not finite, a
// damping ratio on the search's bound (0 or --max-damping), a poor fit, fewer modes than asked.
std::vector<std::string> modes_warnings(const ident::ModeIdentification& r, const ModesState& st, double dt) {
  std::vector<std::string> w;
  if (r.modes.size() < st.modes) {
    w.push_back(fmt::format("asked for {} modes, found {} with damping ratio below {}", st.modes, r.modes.size(), st.max_damping));
  }
  for (std::size_t i = 0; i < r.modes.size(); ++i) {
    const auto& m = r.modes[i];
    if (const std::string unstable = instability(m, dt); !unstable.empty()) {
      w.push_back(fmt::format("mode {}: not stable: {}", i + 1, unstable));
    }
    if (!std::isfinite(m.natural_frequency_std_rad_s) || !std::isfinite(m.damping_ratio_std)) {
      w.push_back(fmt::format("mode {}: its 1σ is not finite (the record does not determine it)", i + 1));
    }
    if ((m.damping_ratio >= 0.0 && m.damping_ratio <= 1e-6) || m.damping_ratio >= st.max_damping * (1.0 - 1e-6)) {
      w.push_back(fmt::format("mode {}: damping ratio {:.4g} sits at a bound (0 or --max-damping {})", i + 1, m.damping_ratio,
                              st.max_damping));
    }
  }
  if (!(r.fit_percent >= 80.0)) w.push_back(fmt::format("poor fit: {:.1f} % (below 80 %)", r.fit_percent));
  if (r.order_source == "modes" && !r.stabilisation.orders.empty()) {
    const bool damping = r.stabilisation.options.persistence_needs_damping.value_or(true);  // free response only
    w.push_back(fmt::format("no pole persists across the stabilisation diagram's orders {}–{} (|Δf| < {} %{}): the "
                            "model order {} follows --modes, and the frequencies may move with it",
                            r.stabilisation.orders.front().order, r.stabilisation.orders.back().order,
                            100.0 * st.stabilisation.frequency_tolerance,
                            damping ? fmt::format(", |Δζ| < {} %", 100.0 * st.stabilisation.damping_tolerance) : "",
                            r.order));
  }
  return w;
}

nlohmann::ordered_json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

// --- plan: the record's timing and window, the ident options ------------------------------------

// The record's sample time: a time column, --sample-time, or none (frequencies per sample).
struct Timing {
  double dt = 1.0;
  bool per_sample = false;
};

Timing timing(const ModesState& st, const io::Table& t) {
  const bool have_ts = st.sample_time_option != nullptr && st.sample_time_option->count() > 0;
  std::optional<std::size_t> tc;
  if (!st.time_column.empty()) {
    if (have_ts) throw InvalidArgument("modes: give either --time-column or --sample-time, not both");
    tc = column_index(t, st.time_column);
  } else if (!have_ts) {
    tc = time_column(t);
  }
  if (tc) return {io::uniform_sample_time(t, t.names[*tc]), false};
  if (have_ts) {
    require_positive("--sample-time", st.sample_time_s, "Give the sample time of the record in seconds.");
    return {st.sample_time_s, false};
  }
  return {1.0, true};  // frequencies in cycles/sample
}

struct ModesPlan {
  Timing timing;
  std::size_t from = 0, end = 0;  ///< the window, samples [from, end)
  std::vector<double> y;          ///< the output column in the window
  ident::ModeOptions options;
};

ModesPlan plan(const ModesState& st, const io::Table& t) {
  ModesPlan p;
  p.timing = timing(st, t);
  const std::vector<double>& y_all = t.columns[column_index(t, st.output_column)];
  std::tie(p.from, p.end) = window(st, y_all.size(), p.timing.dt, p.timing.per_sample);
  p.y.assign(y_all.begin() + static_cast<std::ptrdiff_t>(p.from), y_all.begin() + static_cast<std::ptrdiff_t>(p.end));
  p.options.modes = st.modes;
  p.options.order = st.order;
  p.options.refine = !st.no_refine;
  p.options.estimate_offset = !st.no_offset;
  p.options.max_damping_ratio = st.max_damping;
  p.options.use_stabilisation = !st.no_stabilisation;
  p.options.stabilisation = st.stabilisation;
  return p;
}

// --- run: free response or input/output ------------------------------------------------------------

struct ModesResult {
  ident::ModeIdentification identification;
  std::string kind;  ///< "free response" or "input-output"
};

ModesResult identify(const ModesState& st, const io::Table& t, const ModesPlan& p) {
  if (st.input_column.empty()) {
    return {ident::identify_free_response_modes(UniformSeries{0.0, p.timing.dt, p.y}, p.options), "free response"};
  }
  const std::vector<double>& u_all = t.columns[column_index(t, st.input_column)];
  const auto first = static_cast<std::ptrdiff_t>(p.from), last = static_cast<std::ptrdiff_t>(p.end);
  ident::Experiment e{st.data, p.timing.dt, std::vector<double>(u_all.begin() + first, u_all.begin() + last), p.y};
  return {ident::identify_modes(e, p.options), "input-output"};
}

// --- write: stdout ------------------------------------------------------------------------------------

// A ready `clearshape shape` command for the first one or two modes (needs Hz).
std::string shape_command(const ident::ModeIdentification& r, bool per_sample) {
  if (per_sample || r.modes.empty()) return {};
  std::string out = fmt::format("clearshape shape --method zvd --frequency-hz {:.6g} --zeta {:.6g}",
                                r.modes[0].natural_frequency_hz(), r.modes[0].damping_ratio);
  if (r.modes.size() > 1) {
    out += fmt::format(" --second-frequency-hz {:.6g} --second-zeta {:.6g}", r.modes[1].natural_frequency_hz(),
                       r.modes[1].damping_ratio);
  }
  return out;
}

nlohmann::ordered_json estimate_json(const ident::ModeEstimate& m, double dt, bool per_sample, bool input_output) {
  nlohmann::ordered_json j;
  const std::string unstable = instability(m, dt);
  j["stable"] = unstable.empty();
  j["stability_note"] = unstable.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(unstable);
  j[per_sample ? "frequency_cycles_per_sample" : "frequency_hz"] = m.natural_frequency_hz();
  j[per_sample ? "frequency_std_cycles_per_sample" : "frequency_std_hz"] = finite_or_null(m.natural_frequency_std_hz());
  j[per_sample ? "natural_frequency_rad_per_sample" : "natural_frequency_rad_s"] = m.natural_frequency_rad_s;
  j[per_sample ? "natural_frequency_std_rad_per_sample" : "natural_frequency_std_rad_s"] =
      finite_or_null(m.natural_frequency_std_rad_s);
  j[per_sample ? "damped_frequency_cycles_per_sample" : "damped_frequency_hz"] = m.damped_frequency_hz();
  j["damping_ratio"] = m.damping_ratio;
  j["damping_ratio_std"] = finite_or_null(m.damping_ratio_std);
  j["amplitude"] = m.amplitude;
  j["amplitude_std"] = finite_or_null(m.amplitude_std);
  j["amplitude_meaning"] = !input_output ? "initial amplitude of the damped sinusoid (output units)"
                                         : "peak gain of the mode's term (output per input unit)";
  j["rms_contribution"] = m.rms_contribution;
  return j;
}

// The stabilisation diagram: tolerances, every order's poles with their flags, the persistent modes
// and the chosen order (null when it was not computed: --order or --no-stabilisation).
nlohmann::ordered_json diagram_json(const ident::StabilisationDiagram& d, bool per_sample) {
  if (d.orders.empty()) return nullptr;
  const char* f_key = per_sample ? "frequency_cycles_per_sample" : "frequency_hz";
  nlohmann::ordered_json j;
  j["method"] = "stabilisation diagram (Peeters & De Roeck 2001)";
  j["tolerances"] = {{"frequency_relative", d.options.frequency_tolerance},
                     {"damping_relative", d.options.damping_tolerance},
                     {"amplitude_relative", d.options.amplitude_tolerance},
                     {"min_stable_orders", d.options.min_stable_orders},
                     {"min_stable_fraction", d.options.min_stable_fraction}};
  j["decimation"] = d.decimation;
  j["chosen_order"] = d.chosen_order;
  nlohmann::ordered_json modes = nlohmann::ordered_json::array();
  for (const auto& m : d.modes) {
    modes.push_back({{f_key, m.frequency_hz()}, {"damping_ratio", m.damping_ratio}, {"stable_orders", m.stable_orders}});
  }
  j["persistent_modes"] = modes;
  nlohmann::ordered_json orders = nlohmann::ordered_json::array();
  for (const auto& o : d.orders) {
    nlohmann::ordered_json poles = nlohmann::ordered_json::array();
    for (const auto& p : o.poles) {
      poles.push_back({{f_key, p.frequency_hz()}, {"damping_ratio", p.damping_ratio}, {"amplitude", p.amplitude},
                       {"stable_frequency", p.stable_frequency}, {"stable_damping", p.stable_damping},
                       {"stable", p.stable}});
    }
    orders.push_back({{"order", o.order}, {"poles", poles}});
  }
  j["orders"] = orders;
  return j;
}

// The diagram as a long CSV for plotting (one row per pole: order against frequency, marked by flags).
void write_diagram_csv(const std::string& path, const ident::StabilisationDiagram& d, bool per_sample) {
  if (d.orders.empty()) {
    throw InvalidArgument("modes: --diagram-csv needs the stabilisation diagram; drop --order / --no-stabilisation");
  }
  std::string out = fmt::format("order,{},damping_ratio,amplitude,stable_frequency,stable_damping,stable\n",
                                per_sample ? "frequency_cycles_per_sample" : "frequency_hz");
  for (const auto& o : d.orders) {
    for (const auto& p : o.poles) {
      out += fmt::format("{},{:.10g},{:.8g},{:.8g},{:d},{:d},{:d}\n", o.order, p.frequency_hz(), p.damping_ratio, p.amplitude,
                         p.stable_frequency, p.stable_damping, p.stable);
    }
  }
  io::write_text_atomic(path, out);
}

void print_modes_json(const ModesState& st, const ModesPlan& p, const ModesResult& res,
                      const std::vector<std::string>& warnings) {
  const ident::ModeIdentification& r = res.identification;
  const bool per_sample = p.timing.per_sample;
  auto doc = io::make_document();
  doc["command"] = "modes";
  doc["data"] = st.data;
  doc["kind"] = res.kind;
  doc["method"] = r.method;
  doc["samples"] = p.y.size();
  doc["window"] = {{"from_sample", p.from}, {"to_sample", p.end}};
  doc["sample_time_s"] = per_sample ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(p.timing.dt);
  doc["frequency_unit"] = per_sample ? "cycles/sample" : "Hz";
  if (per_sample) {
    doc["note"] = "no time column and no --sample-time: frequencies are per sample (cycles/sample); "
                  "give --sample-time or a time column for Hz";
  }
  doc["fit_percent"] = r.fit_percent;
  doc["rmse"] = r.rmse;
  doc["decimation"] = r.decimation;
  nlohmann::ordered_json modes = nlohmann::ordered_json::array();
  for (const auto& m : r.modes) modes.push_back(estimate_json(m, p.timing.dt, per_sample, !st.input_column.empty()));
  doc["modes"] = modes;
  doc["order"] = r.order;
  doc["order_source"] = r.order_source;
  doc["stabilisation"] = diagram_json(r.stabilisation, per_sample);
  const std::string shape = shape_command(r, per_sample);
  doc["shape_command"] = shape.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(shape);
  doc["trusted"] = warnings.empty();
  doc["warnings"] = warnings;
  print_json(doc);
}

void print_order_line(const ident::ModeIdentification& r) {
  const auto& d = r.stabilisation;
  if (r.order_source == "stabilisation") {
    fmt::print("model order {} from the stabilisation diagram (orders {}–{}, {} persistent mode{})\n", r.order,
               d.orders.front().order, d.orders.back().order, d.modes.size(), d.modes.size() == 1 ? "" : "s");
  } else {
    fmt::print("model order {} ({})\n", r.order, r.order_source == "option" ? "--order" : "from --modes");
  }
}

void print_modes_table(const ModesState& st, const ModesPlan& p, const ModesResult& res) {
  const ident::ModeIdentification& r = res.identification;
  const bool per_sample = p.timing.per_sample;
  fmt::print("{} modes of {} ({} samples, {}), fit {:.3f} %\n", res.kind, st.data, p.y.size(), r.method,
             r.fit_percent);
  if (per_sample) fmt::print("no sample time: frequencies are per sample (cycles/sample); give --sample-time for Hz\n");
  print_order_line(r);
  fmt::print("\n  #  {:>16} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
             std::string("frequency ") + (per_sample ? "cycles/sample" : "Hz"), "std", "zeta", "std", "amplitude",
             "std");
  std::size_t i = 0;
  for (const auto& m : r.modes) {
    const std::string unstable = instability(m, p.timing.dt);
    fmt::print("  {}  {:>16.7g} {:>12.3g} {:>12.6g} {:>12.3g} {:>12.5g} {:>12.3g}{}\n", ++i, m.natural_frequency_hz(),
               m.natural_frequency_std_hz(), m.damping_ratio, m.damping_ratio_std, m.amplitude, m.amplitude_std,
               unstable.empty() ? "" : "  NOT STABLE: " + unstable);
  }
  const std::string shape = shape_command(r, per_sample);
  if (!shape.empty()) fmt::print("\nshaper: {}\n", shape);
}

void run_modes(const ModesState& st) {
  const io::Table t = io::read_table(st.data);
  const ModesPlan p = plan(st, t);
  const ModesResult res = identify(st, t, p);
  if (!st.diagram_csv.empty()) write_diagram_csv(st.diagram_csv, res.identification.stabilisation, p.timing.per_sample);
  const auto warnings = modes_warnings(res.identification, st, p.timing.dt);
  for (const auto& w : warnings) fmt::print(stderr, "clearshape modes: warning: {}\n", w);
  if (!warnings.empty()) fmt::print(stderr, "clearshape modes: the result is NOT to be trusted (\"trusted\": false)\n");
  if (st.json) {
    print_modes_json(st, p, res, warnings);
  } else {
    print_modes_table(st, p, res);
  }
  // Unstable or aliased poles are no modes to shape: a run-time failure unless asked for.
  for (std::size_t i = 0; i < res.identification.modes.size(); ++i) {
    const std::string unstable = instability(res.identification.modes[i], p.timing.dt);
    if (!unstable.empty() && !st.allow_unstable) {
      throw RuntimeError(fmt::format("modes: {}: mode {} is not stable ({}); window the record on a free decay, lower --modes or "
                                     "--order, or give --allow-unstable to report it with exit 0",
                                     st.data, i + 1, unstable));
    }
  }
}

void setup_modes(CLI::App& sub) {
  auto st = std::make_shared<ModesState>();
  sub.add_option("--data", st->data, "Record (CSV or whitespace columns, header optional)")->required();
  sub.add_option("--output-column", st->output_column, "Measured column (e.g. the link gyro rate): name or 1-based index")
      ->required();
  sub.add_option("--input-column", st->input_column, "Input column for input/output identification (else: free response)");
  sub.add_option("--time-column", st->time_column, "Time column in s (default: time_s, time or t if present)");
  st->sample_time_option = sub.add_option("--sample-time", st->sample_time_s,
                                          "Sample time in s when there is no time column (else: cycles/sample)");
  sub.add_option("--modes", st->modes, "Number of dominant modes to report")->capture_default_str();
  sub.add_option("--order", st->order,
                 "Subspace model order (0: chosen by the stabilisation diagram; with --no-stabilisation 2·modes + 2 free "
                 "response, 2·modes input/output)")
      ->capture_default_str();
  sub.add_flag("--no-stabilisation", st->no_stabilisation, "Order 2·modes(+2) as before, without the stabilisation diagram");
  sub.add_option("--max-order", st->stabilisation.max_order, "Stabilisation diagram: highest model order")
      ->check(CLI::Range(3, 200))
      ->capture_default_str();
  sub.add_option("--frequency-tolerance", st->stabilisation.frequency_tolerance,
                 "Stabilisation diagram: a pole is stable when its frequency moves less than this (relative) from the "
                 "previous order")
      ->check(CLI::Range(1e-6, 0.5))
      ->capture_default_str();
  sub.add_option("--damping-tolerance", st->stabilisation.damping_tolerance,
                 "Stabilisation diagram: and its damping ratio less than this (relative)")
      ->check(CLI::Range(1e-6, 10.0))
      ->capture_default_str();
  sub.add_option("--diagram-csv", st->diagram_csv,
                 "Write the stabilisation diagram (order, frequency, ζ, amplitude, stable flags; one row per pole) to this CSV");
  sub.add_option("--from-sample", st->from_sample, "First sample of the window (0-based), e.g. the end of the move")
      ->capture_default_str();
  sub.add_option("--to-sample", st->to_sample, "End of the window (exclusive; 0 = end of the record)")->capture_default_str();
  st->from_s_option = sub.add_option("--from-s", st->from_s, "Start of the window, s (instead of --from-sample)");
  st->to_s_option = sub.add_option("--to-s", st->to_s, "End of the window, s (instead of --to-sample)");
  sub.add_option("--max-damping", st->max_damping, "Report only modes with damping ratio below this")->capture_default_str();
  sub.add_flag("--no-refine", st->no_refine, "Skip the least-squares refinement (subspace estimate only)");
  sub.add_flag("--no-offset", st->no_offset, "Free response: do not estimate a constant sensor offset");
  sub.add_flag("--json", st->json, "Print the result as JSON");
  sub.add_flag("--allow-unstable", st->allow_unstable,
               "Exit 0 even when a pole is unstable (ζ ≤ 0) or at ≥ 90 % of the Nyquist frequency (flagged \"stable\": false)");
  sub.callback([st] { run_modes(*st); });
}

const bool modes_registered = register_command(
    {"modes", "Identify the dominant lightly damped modes of a record (free decay or input/output) for shaper design", 31,
     setup_modes});

}  // namespace

}  // namespace clearshape::cli
