// clearshape signal: generate a command signal (thesis §4.1, §5.2.1) and optionally pass it
// through a drive command path (position mode: 30 Hz held velocity and quadrature pulses;
// speed mode: 12-bit ±10 V D/A; thesis §3.2).
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "command.hpp"
#include "run_json.hpp"
#include "signal_options.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {

struct State {
  std::string type;
  cs::cli::SignalOptions signal_options;

  double rate_hz = 1000.0;
  double duration_s = 5.0;
  std::string output;
  bool json = false;
  std::string unit;
  std::string path = "none";

  double update_hz = 30.0;
  double counts_per_rev = 3000.0;
  double gear_ratio = 1.0;
  double max_pulse_hz = 500e3;
  std::string velocity_hold = "lookahead";
  std::vector<CLI::Option*> position_options;
  double daq_scale = 1.0;
  int daq_bits = 12;
  double daq_range_v = 10.0;
  std::vector<CLI::Option*> speed_options;
};

void require_path_options(const std::vector<CLI::Option*>& options, const std::string& path,
                          const std::string& needed) {
  for (const auto* o : options) {
    if (o->count() > 0 && path != needed) {
      throw cs::InvalidArgument(fmt::format("{} applies to --path {} only (given --path {})",
                                            o->get_name(), needed, path));
    }
  }
}

// Six significant digits for the human table (JSON keeps every digit).
std::string num(double v) { return fmt::format("{:.6g}", v); }

std::string column(std::string_view stem, const std::string& unit) {
  return unit == "1" ? std::string(stem) : fmt::format("{}_{}", stem, unit);
}

// --- plan: the checked options and the column unit ---------------------------------------------

// Checks --rate, --duration and the path options; returns the unit of the command column.
std::string checked_unit(const State& st) {
  if (!(st.rate_hz > 0.0 && st.rate_hz <= 1e6)) {
    cs::throw_invalid("--rate", st.rate_hz, "(0, 1e6] Hz", "Give the sample rate in Hz, e.g. 1000");
  }
  cs::require_non_negative("--duration", st.duration_s, "Give the duration in s, e.g. 5");
  if (st.rate_hz * st.duration_s > 1e7) {
    cs::throw_invalid("--rate x --duration", st.rate_hz * st.duration_s, "<= 1e7 samples",
                      "Lower the rate or shorten the duration");
  }
  std::string unit = st.unit.empty() ? (st.path == "position" ? "deg" : "1") : st.unit;
  if (st.path == "position" && unit != "deg") {
    throw cs::InvalidArgument(fmt::format(
        "--unit {} cannot drive --path position; allowed: deg (the trajectory is a motor angle)", unit));
  }
  require_path_options(st.position_options, st.path, "position");
  require_path_options(st.speed_options, st.path, "speed");
  return unit;
}

// A config's validate() names its field ("update_rate_hz = …"); the message names the option instead.
template <class Config>
void validate_naming_options(const Config& c, std::initializer_list<std::pair<const char*, const char*>> options) {
  try {
    c.validate();
  } catch (const cs::InvalidArgument& e) {
    std::string m = e.what();
    for (auto [key, option] : options) {
      if (m.rfind(std::string(key) + " = ", 0) == 0) m = option + m.substr(std::string(key).size());
    }
    throw cs::InvalidArgument(m);
  }
}

// --- run: the command through a drive's command path ----------------------------------------------

// The path's columns and its report (JSON and table rows); empty without a path.
struct PathOutput {
  std::vector<std::string> names;
  std::vector<double> commanded, second;
  nlohmann::ordered_json json;
  std::vector<std::pair<std::string, std::string>> rows;
};

sig::PulseTrainConfig pulse_train_config(const State& st) {
  sig::PulseTrainConfig c;
  c.update_rate_hz = st.update_hz;
  c.counts_per_rev = st.counts_per_rev;
  c.gear_ratio = st.gear_ratio;
  c.max_pulse_frequency_hz = st.max_pulse_hz;
  c.velocity_hold = st.velocity_hold == "sampled" ? sig::VelocityHold::sampled : sig::VelocityHold::lookahead;
  validate_naming_options(c, {{"update_rate_hz", "--update-hz"}, {"counts_per_rev", "--counts-per-rev"},
                              {"gear_ratio", "--gear-ratio"}, {"max_pulse_frequency_hz", "--max-pulse-hz"}});
  return c;
}

PathOutput position_path(const State& st, const sig::Signal& signal, const cs::UniformSeries& command) {
  const sig::PulseTrainConfig c = pulse_train_config(st);
  cs::UniformSeries rad = command;
  for (double& v : rad.values) v = cs::deg_to_rad(v);
  // The driver starts where the signal is before it starts (0, or the offset).
  const sig::PositionPathResult r = sig::apply_position_path(rad, c, cs::deg_to_rad(signal.value_at(-1.0)));
  PathOutput out;
  out.commanded = r.commanded_rad.values;
  for (double& v : out.commanded) v = cs::rad_to_deg(v);
  out.second = r.pulse_frequency_hz.values;
  out.names = {"commanded_deg", "pulse_frequency_hz"};
  double max_f = 0.0;
  for (double f : out.second) max_f = std::max(max_f, std::abs(f));
  std::int64_t final_count = r.initial_count;
  for (auto n : r.pulses_per_update) final_count += n;
  const double final_deg = out.commanded.back();
  out.json = {{"mode", "position"},
              {"update_hz", c.update_rate_hz},
              {"counts_per_rev", c.counts_per_rev},
              {"gear_ratio", c.gear_ratio},
              {"max_pulse_frequency_hz", c.max_pulse_frequency_hz},
              {"velocity_hold", st.velocity_hold},
              {"updates", r.pulses_per_update.size()},
              {"saturated_updates", r.saturated_updates},
              {"max_lag_deg", cs::rad_to_deg(r.max_lag_rad)},
              {"peak_pulse_frequency_hz", max_f},
              {"final_count", final_count},
              {"final_commanded_deg", final_deg}};
  out.rows = {{"path", fmt::format("position: {} Hz updates, {} counts/rev, gear {}, {} velocity",
                                   num(c.update_rate_hz), num(c.counts_per_rev), num(c.gear_ratio), st.velocity_hold)},
              {"final commanded", fmt::format("{} deg ({} counts)", num(final_deg), final_count)},
              {"peak pulse frequency", fmt::format("{} Hz (cap {} Hz)", num(max_f), num(c.max_pulse_frequency_hz))},
              {"saturated updates", fmt::format("{} of {}", r.saturated_updates, r.pulses_per_update.size())},
              {"max lag", fmt::format("{} deg", num(cs::rad_to_deg(r.max_lag_rad)))}};
  if (r.saturated_updates > 0) {
    fmt::print(stderr, "clearshape signal: warning: {} update(s) hit the {} Hz pulse cap; the commanded "
                       "position lags the trajectory (max {} deg)\n",
               r.saturated_updates, c.max_pulse_frequency_hz, cs::rad_to_deg(r.max_lag_rad));
  }
  return out;
}

PathOutput speed_path(const State& st, const std::string& unit, const cs::UniformSeries& command) {
  sig::AnalogOutputConfig c;
  c.volts_per_unit = unit == "V" && st.speed_options[0]->count() == 0 ? 1.0 : st.daq_scale;
  c.resolution_bits = st.daq_bits;
  c.full_scale_v = st.daq_range_v;
  validate_naming_options(c, {{"volts_per_unit", "--daq-scale"}, {"resolution_bits", "--daq-bits"},
                              {"full_scale_v", "--daq-range-v"}});
  const sig::SpeedPathResult r = sig::apply_speed_path(command, c);
  PathOutput out;
  out.commanded = r.commanded.values;
  out.second = r.volts.values;
  out.names = {column("commanded", unit), "daq_v"};
  out.json = {{"mode", "speed"},
              {"volts_per_unit", c.volts_per_unit},
              {"resolution_bits", c.resolution_bits},
              {"full_scale_v", c.full_scale_v},
              {"lsb_v", c.lsb_v()},
              {"clipped_samples", r.clipped_samples},
              {"final_commanded", out.commanded.back()},
              {"final_v", out.second.back()}};
  out.rows = {{"path", fmt::format("speed: {}-bit D/A, +/-{} V, {} V per {}", c.resolution_bits,
                                   num(c.full_scale_v), num(c.volts_per_unit), unit)},
              {"final commanded", fmt::format("{} {} ({} V)", num(out.commanded.back()), unit, num(out.second.back()))},
              {"clipped samples", fmt::format("{} of {}", r.clipped_samples, command.size())}};
  if (r.clipped_samples > 0) {
    fmt::print(stderr, "clearshape signal: warning: {} sample(s) clipped at +/-{} V\n",
               r.clipped_samples, c.full_scale_v);
  }
  return out;
}

// --- write: the CSV and stdout ------------------------------------------------------------------

void print_json(const State& st, const sig::Signal& signal, const std::string& unit, const cs::UniformSeries& command,
                const std::vector<std::string>& names, const PathOutput& path) {
  const auto [lo, hi] = std::minmax_element(command.values.begin(), command.values.end());
  auto doc = cs::io::make_document();
  doc["command"] = "signal";
  doc["type"] = std::string(signal.type());
  doc["parameters"] = cs::cli::signal_parameters_json(signal);
  doc["unit"] = unit;
  doc["samples"] = command.size();
  doc["sample_time_s"] = command.sample_time_s;
  doc["duration_s"] = command.end_s();
  doc["min"] = *lo;
  doc["max"] = *hi;
  doc["final"] = command.values.back();
  doc["columns"] = names;
  doc["path"] = path.json.is_null() ? nlohmann::ordered_json("none") : path.json;
  doc["output"] = st.output.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(st.output);
  cs::cli::print_json(doc);
}

void print_table(const State& st, const sig::Signal& signal, const std::string& unit, const cs::UniformSeries& command,
                 const PathOutput& path) {
  const auto [lo, hi] = std::minmax_element(command.values.begin(), command.values.end());
  const std::string u = unit == "1" ? "" : " " + unit;
  std::vector<std::pair<std::string, std::string>> rows = {
      {"signal", std::string(signal.type())},
      {"samples", fmt::format("{} ({} Hz, 0 ... {} s)", command.size(), num(st.rate_hz), num(command.end_s()))},
      {"min", num(*lo) + u},
      {"max", num(*hi) + u},
      {"final", num(command.values.back()) + u}};
  rows.insert(rows.end(), path.rows.begin(), path.rows.end());
  if (!st.output.empty()) rows.emplace_back("output", st.output);
  for (const auto& [k, v] : rows) fmt::print("{:<22}{}\n", k, v);
}

void run(const State& st) {
  const sig::Signal signal = st.signal_options.build(st.type);
  const std::string unit = checked_unit(st);
  const cs::UniformSeries command = sig::sample(signal, st.rate_hz, st.duration_s);
  PathOutput path;
  if (st.path == "position") path = position_path(st, signal, command);
  if (st.path == "speed") path = speed_path(st, unit, command);

  const std::vector<double> time = command.times_s();
  std::vector<std::string> names = {"time_s", column("command", unit)};
  std::vector<const std::vector<double>*> columns = {&time, &command.values};
  if (!path.names.empty()) {
    names.insert(names.end(), path.names.begin(), path.names.end());
    columns.insert(columns.end(), {&path.commanded, &path.second});
  }
  if (!st.output.empty()) {
    cs::io::write_csv(st.output, names, columns);
    fmt::print(stderr, "clearshape signal: wrote {} ({} rows)\n", st.output, command.size());
  }
  if (st.json) {
    print_json(st, signal, unit, command, names, path);
  } else {
    print_table(st, signal, unit, command, path);
  }
}

void setup_signal(CLI::App& sub) {
  auto st = std::make_shared<State>();
  sub.add_option("--type", st->type, "Signal type: " + cs::cli::SignalOptions::type_list())
      ->required()
      ->check(cs::cli::SignalOptions::type_check());
  st->signal_options.add_to(sub, "--type");

  sub.add_option("--rate", st->rate_hz, "Sample rate (Hz)")->capture_default_str();
  sub.add_option("--duration", st->duration_s, "Duration (s); samples at 0 ... duration inclusive")->capture_default_str();
  sub.add_option("--output,-o", st->output, "Write the samples to this CSV file (atomically)");
  sub.add_flag("--json", st->json, "Print a JSON summary on stdout instead of the table");
  sub.add_option("--unit", st->unit, "Command unit for the column suffix: deg|deg_s|V|1 (default deg for --path position, else 1)")
      ->check(CLI::IsMember({"deg", "deg_s", "V", "1"}));
  sub.add_option("--path", st->path, "Drive command path: none|position|speed")
      ->check(CLI::IsMember({"none", "position", "speed"}))
      ->capture_default_str();

  st->position_options = {
      sub.add_option("--update-hz", st->update_hz, "Position path: velocity update rate (Hz)")->capture_default_str(),
      sub.add_option("--counts-per-rev", st->counts_per_rev, "Position path: command pulses per motor revolution")->capture_default_str(),
      sub.add_option("--gear-ratio", st->gear_ratio, "Position path: electronic gear (motor counts per command pulse)")->capture_default_str(),
      sub.add_option("--max-pulse-hz", st->max_pulse_hz, "Position path: pulse frequency limit of the driver (Hz)")->capture_default_str(),
      sub.add_option("--velocity-hold", st->velocity_hold, "Position path: lookahead (reach the trajectory at each update) or sampled (dp/dt at each update)")
          ->check(CLI::IsMember({"lookahead", "sampled"}))
          ->capture_default_str()};
  st->speed_options = {
      sub.add_option("--daq-scale", st->daq_scale, "Speed path: volts per command unit (default 1)"),
      sub.add_option("--daq-bits", st->daq_bits, "Speed path: D/A resolution (bits)")->capture_default_str(),
      sub.add_option("--daq-range-v", st->daq_range_v, "Speed path: D/A range +/- (V)")->capture_default_str()};

  sub.footer(
      "Examples:\n"
      "  clearshape signal --type step --amplitude 10 --start-s 0.5 --rise-s 0.2 --rise-shape s-curve\n"
      "  clearshape signal --type prbs --order 7 --bit-period-s 0.02 --amplitude 50 --unit deg_s -o prbs.csv\n"
      "  clearshape signal --type step --amplitude 20 --path position --duration 2 -o step.csv --json");
  sub.callback([st] { run(*st); });
}

const bool signal_registered = cs::cli::register_command(
    {"signal", "Generate a command signal, optionally through the drive's command path", 10, setup_signal});

}  // namespace
