#pragma once
// Building a Signal from a type name and named parameters (the CLI and the study's protocol
// files), and back. Parameter names are the field names of generators.hpp, with units:
//   step           amplitude, start_s, rise_s, rise_shape
//   ramp           slope_per_s, start_s, limit
//   sine           amplitude, frequency_hz, phase_rad, offset, start_s
//   prbs           order, bit_period_s, amplitude, offset, seed, start_s
//   double-step    amplitude, start_s, second_amplitude, second_start_s, rise_s, rise_shape
//   stacked-steps  levels, dwell_s, start_s, rise_s, rise_shape, repeat
//   parabolic      acceleration_per_s2, start_s
//   trapezoid      amplitude, start_s, rise_s, hold_s, fall_s, rise_shape
// Missing parameters take the defaults of generators.hpp.
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "clearshape/signal/signal.hpp"

namespace clearshape::signal {

/// A number, a flag (repeat), a name (rise_shape: "linear" | "s-curve") or a list (levels).
using ParameterValue = std::variant<double, bool, std::string, std::vector<double>>;
using SignalParameters = std::map<std::string, ParameterValue, std::less<>>;

/// The type names, in CLI order.
std::span<const std::string_view> signal_types();
/// The parameter names a type takes. Throws InvalidArgument for an unknown type.
std::span<const std::string_view> parameter_names(std::string_view type);

/// Builds and validates a signal. Throws InvalidArgument for an unknown type (listing the
/// known ones), a parameter the type does not take (listing those it takes), a value of the
/// wrong kind, a non-integer order/seed, or a value out of range.
Signal make_signal(std::string_view type, const SignalParameters& parameters);
/// Every parameter of `signal` (limit only when set): make_signal(s.type(), parameters_of(s))
/// rebuilds `s`.
SignalParameters parameters_of(const Signal& signal);

}  // namespace clearshape::signal
