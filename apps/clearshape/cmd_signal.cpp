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
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "command.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {

// A signal parameter on the command line: its option, the library's parameter name and help.
struct ParameterOption {
  const char* names;  // CLI11 names, first long name is the canonical one
  const char* key;    // parameter name of clearshape/signal/parameters.hpp
  const char* help;
};

constexpr ParameterOption kNumberOptions[] = {
    {"--amplitude", "amplitude", "Step/sine/trapezoid amplitude; PRBS half swing (command units)"},
    {"--start-s", "start_s", "Start time (s)"},
    {"--rise-s", "rise_s", "Rise time of a step, double step, staircase or trapezoid (s); 0 = ideal"},
    {"--slope,--slope-per-s", "slope_per_s", "Ramp slope (command units per s)"},
    {"--limit", "limit", "Ramp saturation level (command units, same sign as the slope)"},
    {"--frequency-hz", "frequency_hz", "Sine frequency (Hz)"},
    {"--phase-deg", "phase_rad", "Sine phase (deg)"},
    {"--offset", "offset", "Sine or PRBS offset (command units)"},
    {"--order", "order", "PRBS register length n in [2, 31]; period 2^n - 1 bits"},
    {"--bit-period-s", "bit_period_s", "PRBS bit period (s)"},
    {"--seed", "seed", "PRBS initial register state in [1, 2^n - 1]"},
    {"--second-amplitude", "second_amplitude", "Double step: second step (command units, signed)"},
    {"--second-start-s", "second_start_s", "Double step: start of the second step (s)"},
    {"--dwell-s", "dwell_s", "Stacked steps: time on each level (s)"},
    {"--acceleration,--acceleration-per-s2", "acceleration_per_s2", "Parabolic: acceleration (command units per s^2)"},
    {"--hold-s", "hold_s", "Trapezoid: time at the amplitude (s)"},
    {"--fall-s", "fall_s", "Trapezoid: fall time (s); 0 = vertical edge"},
};

std::string canonical(const char* names) {
  const std::string_view all(names);
  return std::string(all.substr(0, all.find(',')));
}

std::string option_of_key(std::string_view key) {
  if (key == "rise_shape") return "--rise-shape";
  if (key == "levels") return "--levels";
  if (key == "repeat") return "--repeat";
  for (const auto& o : kNumberOptions) {
    if (key == o.key) return canonical(o.names);
  }
  return std::string(key);
}

struct State {
  std::string type;
  double numbers[std::size(kNumberOptions)] = {};
  CLI::Option* number_options[std::size(kNumberOptions)] = {};
  std::string rise_shape;
  CLI::Option* rise_shape_option = nullptr;
  std::string levels;
  CLI::Option* levels_option = nullptr;
  bool repeat = false;
  CLI::Option* repeat_option = nullptr;

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

std::vector<double> parse_levels(const std::string& text) {
  std::vector<double> levels;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    std::string item = text.substr(pos, comma - pos);
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (item.empty() || ec != std::errc() || end != item.data() + item.size()) {
      throw cs::InvalidArgument(fmt::format("--levels = '{}': item '{}' is not a number; allowed: "
                                            "a comma-separated list of numbers, e.g. 1,2,3",
                                            text, item));
    }
    levels.push_back(value);
    pos = comma + 1;
  }
  return levels;
}

// The signal from the options that were given; options the type does not take are errors.
sig::Signal build_signal(const State& st) {
  const auto names = sig::parameter_names(st.type);
  const auto takes = [&](std::string_view key) {
    return std::find(names.begin(), names.end(), key) != names.end();
  };
  const auto reject = [&](const std::string& option) {
    std::string allowed;
    for (const auto name : names) allowed += (allowed.empty() ? "" : ", ") + option_of_key(name);
    throw cs::InvalidArgument(
        fmt::format("{} does not apply to --type {}; it takes: {}", option, st.type, allowed));
  };
  sig::SignalParameters p;
  for (std::size_t i = 0; i < std::size(kNumberOptions); ++i) {
    if (st.number_options[i]->count() == 0) continue;
    const auto& o = kNumberOptions[i];
    if (!takes(o.key)) reject(canonical(o.names));
    const double v = std::string_view(o.key) == "phase_rad" ? cs::deg_to_rad(st.numbers[i]) : st.numbers[i];
    p[o.key] = v;
  }
  if (st.rise_shape_option->count() > 0) {
    if (!takes("rise_shape")) reject("--rise-shape");
    p["rise_shape"] = st.rise_shape;
  }
  if (st.levels_option->count() > 0) {
    if (!takes("levels")) reject("--levels");
    p["levels"] = parse_levels(st.levels);
  }
  if (st.repeat_option->count() > 0) {
    if (!takes("repeat")) reject("--repeat");
    p["repeat"] = st.repeat;
  }
  try {
    return sig::make_signal(st.type, p);
  } catch (const cs::InvalidArgument& e) {
    // Name the command-line option instead of the library parameter.
    std::string message = e.what();
    for (const auto name : names) {
      const std::string prefix = std::string(name) + " = ";
      if (message.rfind(prefix, 0) == 0 && name != "phase_rad") {
        message = option_of_key(name) + message.substr(name.size());
        break;
      }
    }
    throw cs::InvalidArgument(message);
  }
}

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

nlohmann::ordered_json to_json(const sig::ParameterValue& v) {
  return std::visit([](const auto& x) { return nlohmann::ordered_json(x); }, v);
}

void run(const State& st) {
  const sig::Signal signal = build_signal(st);
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

  const cs::UniformSeries command = sig::sample(signal, st.rate_hz, st.duration_s);
  const auto [lo, hi] = std::minmax_element(command.values.begin(), command.values.end());
  const std::vector<double> time = command.times_s();

  std::vector<std::string> names = {"time_s", column("command", unit)};
  std::vector<const std::vector<double>*> columns = {&time, &command.values};
  nlohmann::ordered_json path_json;
  std::vector<std::pair<std::string, std::string>> path_rows;
  std::vector<double> commanded;
  std::vector<double> second;

  if (st.path == "position") {
    sig::PulseTrainConfig c;
    c.update_rate_hz = st.update_hz;
    c.counts_per_rev = st.counts_per_rev;
    c.gear_ratio = st.gear_ratio;
    c.max_pulse_frequency_hz = st.max_pulse_hz;
    c.velocity_hold = st.velocity_hold == "sampled" ? sig::VelocityHold::sampled : sig::VelocityHold::lookahead;
    try {
      c.validate();
    } catch (const cs::InvalidArgument& e) {  // name the options
      std::string m = e.what();
      for (auto [key, option] : {std::pair{"update_rate_hz", "--update-hz"}, {"counts_per_rev", "--counts-per-rev"},
                                 {"gear_ratio", "--gear-ratio"}, {"max_pulse_frequency_hz", "--max-pulse-hz"}}) {
        if (m.rfind(std::string(key) + " = ", 0) == 0) m = option + m.substr(std::string(key).size());
      }
      throw cs::InvalidArgument(m);
    }
    cs::UniformSeries rad = command;
    for (double& v : rad.values) v = cs::deg_to_rad(v);
    // The driver starts where the signal is before it starts (0, or the offset).
    const sig::PositionPathResult r = sig::apply_position_path(rad, c, cs::deg_to_rad(signal.value_at(-1.0)));
    commanded = r.commanded_rad.values;
    for (double& v : commanded) v = cs::rad_to_deg(v);
    second = r.pulse_frequency_hz.values;
    names.push_back("commanded_deg");
    names.push_back("pulse_frequency_hz");
    columns.push_back(&commanded);
    columns.push_back(&second);
    double max_f = 0.0;
    for (double f : second) max_f = std::max(max_f, std::abs(f));
    std::int64_t final_count = r.initial_count;
    for (auto n : r.pulses_per_update) final_count += n;
    path_json = {{"mode", "position"},
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
                 {"final_commanded_deg", commanded.back()}};
    path_rows = {{"path", fmt::format("position: {} Hz updates, {} counts/rev, gear {}, {} velocity",
                                      num(c.update_rate_hz), num(c.counts_per_rev), num(c.gear_ratio), st.velocity_hold)},
                 {"final commanded", fmt::format("{} deg ({} counts)", num(commanded.back()), final_count)},
                 {"peak pulse frequency", fmt::format("{} Hz (cap {} Hz)", num(max_f), num(c.max_pulse_frequency_hz))},
                 {"saturated updates", fmt::format("{} of {}", r.saturated_updates, r.pulses_per_update.size())},
                 {"max lag", fmt::format("{} deg", num(cs::rad_to_deg(r.max_lag_rad)))}};
    if (r.saturated_updates > 0) {
      fmt::print(stderr, "clearshape signal: warning: {} update(s) hit the {} Hz pulse cap; the commanded "
                         "position lags the trajectory (max {} deg)\n",
                 r.saturated_updates, c.max_pulse_frequency_hz, cs::rad_to_deg(r.max_lag_rad));
    }
  } else if (st.path == "speed") {
    sig::AnalogOutputConfig c;
    c.volts_per_unit = unit == "V" && st.speed_options[0]->count() == 0 ? 1.0 : st.daq_scale;
    c.resolution_bits = st.daq_bits;
    c.full_scale_v = st.daq_range_v;
    try {
      c.validate();
    } catch (const cs::InvalidArgument& e) {
      std::string m = e.what();
      for (auto [key, option] : {std::pair{"volts_per_unit", "--daq-scale"}, {"resolution_bits", "--daq-bits"},
                                 {"full_scale_v", "--daq-range-v"}}) {
        if (m.rfind(std::string(key) + " = ", 0) == 0) m = option + m.substr(std::string(key).size());
      }
      throw cs::InvalidArgument(m);
    }
    const sig::SpeedPathResult r = sig::apply_speed_path(command, c);
    commanded = r.commanded.values;
    second = r.volts.values;
    names.push_back(column("commanded", unit));
    names.push_back("daq_v");
    columns.push_back(&commanded);
    columns.push_back(&second);
    path_json = {{"mode", "speed"},
                 {"volts_per_unit", c.volts_per_unit},
                 {"resolution_bits", c.resolution_bits},
                 {"full_scale_v", c.full_scale_v},
                 {"lsb_v", c.lsb_v()},
                 {"clipped_samples", r.clipped_samples},
                 {"final_commanded", commanded.back()},
                 {"final_v", second.back()}};
    path_rows = {{"path", fmt::format("speed: {}-bit D/A, +/-{} V, {} V per {}", c.resolution_bits,
                                      num(c.full_scale_v), num(c.volts_per_unit), unit)},
                 {"final commanded", fmt::format("{} {} ({} V)", num(commanded.back()), unit, num(second.back()))},
                 {"clipped samples", fmt::format("{} of {}", r.clipped_samples, command.size())}};
    if (r.clipped_samples > 0) {
      fmt::print(stderr, "clearshape signal: warning: {} sample(s) clipped at +/-{} V\n",
                 r.clipped_samples, c.full_scale_v);
    }
  }

  if (!st.output.empty()) {
    cs::io::write_csv(st.output, names, columns);
    fmt::print(stderr, "clearshape signal: wrote {} ({} rows)\n", st.output, command.size());
  }

  if (st.json) {
    auto doc = cs::io::make_document();
    doc["command"] = "signal";
    doc["type"] = std::string(signal.type());
    nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
    for (const auto& [key, value] : sig::parameters_of(signal)) parameters[key] = to_json(value);
    doc["parameters"] = parameters;
    doc["unit"] = unit;
    doc["samples"] = command.size();
    doc["sample_time_s"] = command.sample_time_s;
    doc["duration_s"] = command.end_s();
    doc["min"] = *lo;
    doc["max"] = *hi;
    doc["final"] = command.values.back();
    doc["columns"] = names;
    doc["path"] = path_json.is_null() ? nlohmann::ordered_json("none") : path_json;
    doc["output"] = st.output.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(st.output);
    cs::cli::print_json(doc);
    return;
  }
  const std::string u = unit == "1" ? "" : " " + unit;
  std::vector<std::pair<std::string, std::string>> rows = {
      {"signal", std::string(signal.type())},
      {"samples", fmt::format("{} ({} Hz, 0 ... {} s)", command.size(), num(st.rate_hz), num(command.end_s()))},
      {"min", num(*lo) + u},
      {"max", num(*hi) + u},
      {"final", num(command.values.back()) + u}};
  rows.insert(rows.end(), path_rows.begin(), path_rows.end());
  if (!st.output.empty()) rows.emplace_back("output", st.output);
  for (const auto& [k, v] : rows) fmt::print("{:<22}{}\n", k, v);
}

void setup(CLI::App& sub) {
  auto st = std::make_shared<State>();
  std::string types;
  for (const auto t : sig::signal_types()) types += (types.empty() ? "" : "|") + std::string(t);
  sub.add_option("--type", st->type, "Signal type: " + types)
      ->required()
      ->check(CLI::IsMember(std::vector<std::string>(sig::signal_types().begin(), sig::signal_types().end())));
  for (std::size_t i = 0; i < std::size(kNumberOptions); ++i) {
    st->number_options[i] = sub.add_option(kNumberOptions[i].names, st->numbers[i], kNumberOptions[i].help);
  }
  st->rise_shape_option = sub.add_option("--rise-shape", st->rise_shape, "Rise/fall shape: linear (default) or s-curve (jerk-limited)")
                              ->check(CLI::IsMember({"linear", "s-curve"}));
  st->levels_option = sub.add_option("--levels", st->levels, "Stacked steps: comma-separated levels, e.g. 1,2,3 (command units)");
  st->repeat_option = sub.add_flag("--repeat", st->repeat, "Stacked steps: start the sequence again after the last level");

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

const bool registered = cs::cli::register_command(
    {"signal", "Generate a command signal, optionally through the drive's command path", 10, setup});

}  // namespace
