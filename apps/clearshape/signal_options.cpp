#include "signal_options.hpp"

#include <algorithm>
#include <charconv>
#include <iterator>
#include <string_view>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/signal/parameters.hpp"

namespace clearshape::cli {

namespace {

// A signal parameter on the command line: its option, the library's parameter name and help.
struct ParameterOption {
  const char* names;  // CLI11 names, the first long name is the canonical one
  const char* key;    // parameter name of clearshape/signal/parameters.hpp
  const char* help;
};

// Command units: deg (position path), deg/s or V (speed), as the command says.
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
    {"--acceleration,--acceleration-per-s2", "acceleration_per_s2",
     "Parabolic: acceleration (command units per s^2)"},
    {"--hold-s", "hold_s", "Trapezoid: time at the amplitude (s)"},
    {"--fall-s", "fall_s", "Trapezoid: fall time (s); 0 = vertical edge"},
    {"--f0-hz", "f0_hz", "Chirp: start frequency (Hz)"},
    {"--f1-hz", "f1_hz", "Chirp: end frequency (Hz)"},
    {"--sweep-s", "sweep_s", "Chirp: duration of the sweep (s)"},
};

std::string canonical(const char* names) {
  const std::string_view all(names);
  return std::string(all.substr(0, all.find(',')));
}

std::string option_of_key(std::string_view key) {
  if (key == "rise_shape") return "--rise-shape";
  if (key == "levels") return "--levels";
  if (key == "repeat") return "--repeat";
  if (key == "sweep") return "--sweep";
  for (const auto& o : kNumberOptions) {
    if (key == o.key) return canonical(o.names);
  }
  return std::string(key);
}

}  // namespace

std::vector<double> parse_levels(const std::string& text, std::string_view option) {
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
      throw InvalidArgument(fmt::format("{} = '{}': item '{}' is not a number; allowed: "
                                        "a comma-separated list of numbers, e.g. 1,2,3",
                                        option, text, item));
    }
    levels.push_back(value);
    pos = comma + 1;
  }
  return levels;
}

std::string SignalOptions::type_list() {
  std::string types;
  for (const auto t : signal::signal_types()) types += (types.empty() ? "" : "|") + std::string(t);
  return types;
}

CLI::IsMember SignalOptions::type_check() {
  return CLI::IsMember(
      std::vector<std::string>(signal::signal_types().begin(), signal::signal_types().end()));
}

void SignalOptions::add_to(CLI::App& sub, std::string type_flag) {
  type_flag_ = std::move(type_flag);
  numbers_.assign(std::size(kNumberOptions), 0.0);  // sized once: CLI11 keeps the addresses
  number_options_.clear();
  for (std::size_t i = 0; i < std::size(kNumberOptions); ++i) {
    number_options_.push_back(sub.add_option(kNumberOptions[i].names, numbers_[i], kNumberOptions[i].help));
  }
  rise_shape_option_ =
      sub.add_option("--rise-shape", rise_shape_, "Rise/fall shape: linear (default) or s-curve (jerk-limited)")
          ->check(CLI::IsMember({"linear", "s-curve"}));
  levels_option_ = sub.add_option("--levels", levels_, "Stacked steps: comma-separated levels, e.g. 1,2,3 (command units)");
  repeat_option_ = sub.add_flag("--repeat", repeat_, "Stacked steps: start the sequence again after the last level");
  sweep_option_ = sub.add_option("--sweep", sweep_, "Chirp: linear (default) or logarithmic frequency sweep")
                      ->check(CLI::IsMember({"linear", "logarithmic"}));
}

signal::Signal SignalOptions::build(const std::string& type) const {
  const auto names = signal::parameter_names(type);
  const auto takes = [&](std::string_view key) {
    return std::find(names.begin(), names.end(), key) != names.end();
  };
  const auto reject = [&](const std::string& option) {
    std::string allowed;
    for (const auto name : names) allowed += (allowed.empty() ? "" : ", ") + option_of_key(name);
    throw InvalidArgument(fmt::format("{} does not apply to {} {}; it takes: {}", option,
                                      type_flag_, type, allowed));
  };
  signal::SignalParameters p;
  for (std::size_t i = 0; i < number_options_.size(); ++i) {
    if (number_options_[i]->count() == 0) continue;
    const auto& o = kNumberOptions[i];
    if (!takes(o.key)) reject(canonical(o.names));
    p[o.key] = std::string_view(o.key) == "phase_rad" ? deg_to_rad(numbers_[i]) : numbers_[i];
  }
  if (rise_shape_option_->count() > 0) {
    if (!takes("rise_shape")) reject("--rise-shape");
    p["rise_shape"] = rise_shape_;
  }
  if (levels_option_->count() > 0) {
    if (!takes("levels")) reject("--levels");
    p["levels"] = parse_levels(levels_);
  }
  if (repeat_option_->count() > 0) {
    if (!takes("repeat")) reject("--repeat");
    p["repeat"] = repeat_;
  }
  if (sweep_option_->count() > 0) {
    if (!takes("sweep")) reject("--sweep");
    p["sweep"] = sweep_;
  }
  try {
    return signal::make_signal(type, p);
  } catch (const InvalidArgument& e) {
    // Name the command-line option instead of the library parameter.
    std::string message = e.what();
    for (const auto name : names) {
      const std::string prefix = std::string(name) + " = ";
      if (message.rfind(prefix, 0) == 0 && name != "phase_rad") {
        message = option_of_key(name) + message.substr(name.size());
        break;
      }
    }
    throw InvalidArgument(message);
  }
}

}  // namespace clearshape::cli
