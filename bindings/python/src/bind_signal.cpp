// Python: command signals (signal/parameters.hpp) and the drive's command paths (§3.2:
// position_path.hpp, speed_path.hpp).
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/signal/speed_path.hpp"

namespace clearshape::python {
namespace {

namespace sig = clearshape::signal;

// A Python value as a signal parameter: bool, number, name or list of numbers.
sig::ParameterValue parameter_value(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  try {
    return value.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw InvalidArgument("signal parameter " + name +
                          ": expected a number, a bool, a name or a list of numbers");
  }
}

py::tuple sample_signal(const std::string& type, double rate_hz, double duration_s, const py::kwargs& kwargs) {
  sig::SignalParameters parameters;
  for (const auto& [key, value] : kwargs) {
    const auto name = key.cast<std::string>();
    parameters[name] = parameter_value(name, value);
  }
  const sig::Signal s = sig::make_signal(type, parameters);
  const UniformSeries series = sig::sample(s, rate_hz, duration_s);
  return py::make_tuple(to_array(series.times_s()), to_array(series.values));
}

py::dict position_path(const DoubleArray& position_rad, double sample_time_s, double update_rate_hz,
                       double counts_per_rev, double gear_ratio, double max_pulse_frequency_hz,
                       const std::string& velocity_hold, std::optional<double> initial_rad) {
  sig::PulseTrainConfig config;
  config.update_rate_hz = update_rate_hz;
  config.counts_per_rev = counts_per_rev;
  config.gear_ratio = gear_ratio;
  config.max_pulse_frequency_hz = max_pulse_frequency_hz;
  if (velocity_hold == "lookahead") {
    config.velocity_hold = sig::VelocityHold::lookahead;
  } else if (velocity_hold == "sampled") {
    config.velocity_hold = sig::VelocityHold::sampled;
  } else {
    throw InvalidArgument("velocity_hold = " + velocity_hold + " is not known; allowed: lookahead, sampled");
  }
  if (initial_rad) require_finite("initial_rad", *initial_rad);
  const auto r =
      sig::apply_position_path(to_series(position_rad, sample_time_s, 0.0, "position_rad"), config, initial_rad);
  py::dict d;
  d["commanded_rad"] = to_array(r.commanded_rad.values);
  d["pulse_frequency_hz"] = to_array(r.pulse_frequency_hz.values);
  d["pulses_per_update"] = to_array(r.pulses_per_update);
  d["saturated_updates"] = r.saturated_updates;
  d["max_lag_rad"] = r.max_lag_rad;
  d["counts_per_rad"] = r.counts_per_rad;
  return d;
}

py::dict speed_path(const DoubleArray& command, double sample_time_s, double volts_per_unit,
                    int resolution_bits, double full_scale_v) {
  sig::AnalogOutputConfig config;
  config.volts_per_unit = volts_per_unit;
  config.resolution_bits = resolution_bits;
  config.full_scale_v = full_scale_v;
  const auto r = sig::apply_speed_path(to_series(command, sample_time_s, 0.0, "command"), config);
  py::dict d;
  d["volts"] = to_array(r.volts.values);
  d["commanded"] = to_array(r.commanded.values);
  d["clipped_samples"] = r.clipped_samples;
  return d;
}

}  // namespace

void bind_signal(py::module_& m) {
  m.def("signal_types", [] {
    std::vector<std::string> names;
    for (auto n : sig::signal_types()) names.emplace_back(n);
    return names;
  }, "The signal type names: step, ramp, sine, prbs, double-step, stacked-steps, parabolic, trapezoid, chirp.");
  m.def("signal_parameters", [](const std::string& type) {
    std::vector<std::string> names;
    for (auto n : sig::parameter_names(type)) names.emplace_back(n);
    return names;
  }, py::arg("type"), "The parameter names a signal type takes (units in the name: start_s, frequency_hz, …).");
  m.def("signal", &sample_signal, py::arg("type"), py::arg("rate_hz") = 1000.0, py::arg("duration_s") = 5.0,
        R"doc(Samples a command signal at t = i / rate_hz, i = 0 … floor(duration_s · rate_hz).

type: a name from signal_types(); keyword arguments are the type's parameters (see
signal_parameters(type)), e.g. signal("step", amplitude=20, start_s=0.5, rise_s=0.1).
Amplitudes are in command units (deg in position mode, V in speed mode), times in s.
Returns (time_s, values), two float64 arrays. Raises ValueError naming a bad parameter.)doc");
  m.def("position_path", &position_path, py::arg("position_rad"), py::arg("sample_time_s"),
        py::arg("update_rate_hz") = 30.0, py::arg("counts_per_rev") = 3000.0, py::arg("gear_ratio") = 1.0,
        py::arg("max_pulse_frequency_hz") = 500e3, py::arg("velocity_hold") = "lookahead",
        py::arg("initial_rad") = py::none(),
        R"doc(The position-mode command path (thesis §3.2): a velocity held per update period
(update_rate_hz, 30 Hz), whole command pulses (counts_per_rev per motor revolution), the
driver's pulse-rate cap (max_pulse_frequency_hz); the driver starts at initial_rad (default:
the first sample; a step at t = 0 then needs initial_rad=0). position_rad: the target position (rad) at
sample_time_s (s). Returns a dict: commanded_rad (what the driver receives, rad),
pulse_frequency_hz, pulses_per_update, saturated_updates, max_lag_rad, counts_per_rad.)doc");
  m.def("speed_path", &speed_path, py::arg("command"), py::arg("sample_time_s"), py::arg("volts_per_unit") = 1.0,
        py::arg("resolution_bits") = 12, py::arg("full_scale_v") = 10.0,
        R"doc(The speed-mode command path (thesis §3.2): the D/A converter (resolution_bits,
±full_scale_v V, volts_per_unit V per command unit). Returns a dict: volts (D/A output, V),
commanded (back in command units), clipped_samples.)doc");
}

}  // namespace clearshape::python
