#pragma once
// A command signal of any kind as one value type, and its sampling on a uniform grid.
//
//   signal::Signal s = signal::Step{.amplitude = 10.0, .start_s = 0.5, .rise_s = 0.2};
//   UniformSeries command = signal::sample(s, 1000.0, 5.0);   // 1 kHz, 0 … 5 s inclusive
#include <concepts>
#include <string_view>
#include <utility>
#include <variant>

#include "clearshape/core/series.hpp"
#include "clearshape/signal/generators.hpp"

namespace clearshape::signal {

using SignalSpec =
    std::variant<Step, Ramp, Sine, Prbs, DoubleStep, StackedSteps, Parabolic, Trapezoid, Chirp>;

/// A validated command signal (value semantics: copy freely).
class Signal {
 public:
  /// Validates the parameters; throws InvalidArgument naming the field.
  Signal(SignalSpec spec);  // NOLINT(google-explicit-constructor): Signal s = Step{...};
  template <class T>
    requires std::constructible_from<SignalSpec, T>
  Signal(T spec) : Signal(SignalSpec(std::move(spec))) {}  // NOLINT(google-explicit-constructor)

  /// The type name used by the CLI and the study: "step", "ramp", "sine", "prbs",
  /// "double-step", "stacked-steps", "parabolic", "trapezoid" or "chirp".
  std::string_view type() const noexcept;
  const SignalSpec& spec() const noexcept { return spec_; }
  template <class T>
  const T* get_if() const noexcept { return std::get_if<T>(&spec_); }

  double value_at(double t_s) const noexcept;

 private:
  SignalSpec spec_;
};

/// Samples `signal` at t = i / sample_rate_hz for i = 0 … floor(duration·rate) (both ends
/// included, as sample_count()). Throws InvalidArgument for a non-positive rate or a negative
/// duration. PRBS is generated bit by bit (O(samples)), every other signal by value_at().
UniformSeries sample(const Signal& signal, double sample_rate_hz, double duration_s);

}  // namespace clearshape::signal
