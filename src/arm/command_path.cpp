// The joints' command paths (docs/arm.md §1): what each drive receives, through the single
// joint's own path functions (signal/position_path.hpp, signal/speed_path.hpp).
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "clearshape/arm/simulation.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::arm {

namespace {

constexpr double kHoldSampleTime_s = 1e-3;  // a held command is sampled at the rig's 1 kHz loop

// The command as samples the path can read, running at least `hold_s` past its last sample (held
// there): linear commands keep their samples; a held one is sampled at 1 kHz.
UniformSeries path_input(const plant::Command& command, double hold_s) {
  const UniformSeries& s = command.samples();
  const double last_s = s.start_s + static_cast<double>(s.size() - 1) * s.sample_time_s;
  if (command.interpolation() == plant::Interpolation::linear) {
    UniformSeries out = s;
    out.values.resize(s.size() + static_cast<std::size_t>(std::ceil(hold_s / s.sample_time_s)) + 1, s.values.back());
    return out;
  }
  const auto n = static_cast<std::size_t>(std::ceil((last_s + hold_s - s.start_s) / kHoldSampleTime_s)) + 1;
  UniformSeries out{s.start_s, kHoldSampleTime_s, std::vector<double>(n)};
  for (std::size_t k = 0; k < n; ++k) out.values[k] = command.value(s.start_s + static_cast<double>(k) * kHoldSampleTime_s);
  return out;
}

// Time for the pulses to reach the command's end (held there): one update period, plus as many
// as the capped pulses need to make up the largest possible lag, the command's whole travel.
double pulse_hold_s(const plant::Command& command, const signal::PulseTrainConfig& config) {
  config.validate();
  const std::vector<double>& v = command.samples().values;
  double travel_deg = 0.0;
  for (std::size_t k = 1; k < v.size(); ++k) travel_deg += std::abs(v[k] - v[k - 1]);
  const double counts = deg_to_rad(travel_deg) * config.counts_per_rad();
  return config.update_period_s() * (2.0 + std::ceil(counts / static_cast<double>(config.max_counts_per_update())));
}

// Position mode (thesis §3.2, §4.1.2): the command read as motor degrees becomes pulses.
plant::Command through_pulse_train(const plant::Command& command, const signal::PulseTrainConfig& config) {
  UniformSeries motor_rad = path_input(command, pulse_hold_s(command, config));
  for (double& v : motor_rad.values) v = deg_to_rad(v);
  UniformSeries received = signal::apply_position_path(motor_rad, config).commanded_rad;
  for (double& v : received.values) v = rad_to_deg(v);
  return plant::Command(std::move(received), plant::Interpolation::linear);
}

// Speed mode (thesis §3.2, Table 3.2): each sample through the D/A, held.
plant::Command through_analog(const plant::Command& command, const signal::AnalogOutputConfig& config) {
  return plant::Command(signal::apply_speed_path(command.samples(), config).commanded, plant::Interpolation::zero_order_hold);
}

}  // namespace

std::vector<plant::Command> received_commands(const ArmModel& model, std::span<const plant::Command> commands) {
  if (commands.size() != model.joints.size()) {
    throw InvalidArgument(fmt::format("arm '{}' has {} joints but {} commands were given; allowed: one per joint",
                                      model.name, model.joints.size(), commands.size()));
  }
  std::vector<plant::Command> out;
  out.reserve(commands.size());
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const ArmCommandPath& path = model.joints[i].path;
    switch (path.kind) {
      case CommandPathKind::ideal: out.push_back(commands[i]); break;
      case CommandPathKind::pulse_train: out.push_back(through_pulse_train(commands[i], path.pulse_train)); break;
      case CommandPathKind::analog: out.push_back(through_analog(commands[i], path.analog)); break;
    }
  }
  return out;
}

}  // namespace clearshape::arm
