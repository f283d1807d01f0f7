#pragma once
// Command signals of the thesis (§4.1.1: step, ramp, sine, PRBS in speed mode; §4.1.2 and
// §5.2.1: step and double step with finite jerk, two steps on top of each other, parabolic and
// trapezoid/pulse in position mode). Each is a small value type: public fields with units,
// validate() throws InvalidArgument naming the field, value and allowed range, and value_at()
// evaluates the signal at any time. Values are in "command units" (deg, deg/s, V, … as chosen
// by the caller); times are in seconds. Before its start every signal is 0 (sine and PRBS: offset).
#include <cstdint>
#include <optional>
#include <vector>

#include "clearshape/signal/rise.hpp"

namespace clearshape::signal {

/// A step of `amplitude` at `start_s`, ideal (rise_s = 0) or with a finite rise.
struct Step {
  double amplitude = 1.0;
  double start_s = 0.0;
  double rise_s = 0.0;  ///< duration of the rise; 0 = ideal step
  RiseShape rise_shape = RiseShape::linear;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// slope·(t − start) from `start_s`, optionally held once it reaches `limit`.
struct Ramp {
  double slope_per_s = 1.0;    ///< command units per second
  double start_s = 0.0;
  std::optional<double> limit{};  ///< saturation level (same sign as the slope); none = unbounded

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// offset + amplitude·sin(2π·f·(t − start) + phase) from `start_s`.
struct Sine {
  double amplitude = 1.0;
  double frequency_hz = 1.0;
  double phase_rad = 0.0;
  double offset = 0.0;
  double start_s = 0.0;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// Pseudo-random binary signal from a maximal-length LFSR (see prbs.hpp): bit k of the sequence
/// is held for bit_period_s from start_s + k·bit_period_s; a 1 gives offset + amplitude and a 0
/// gives offset − amplitude. The sequence repeats every 2^order − 1 bits.
struct Prbs {
  int order = 7;               ///< register length n in [2, 31]
  double bit_period_s = 0.01;
  double amplitude = 1.0;      ///< half the peak-to-peak swing
  double offset = 0.0;
  std::uint32_t seed = 1;      ///< initial register state in [1, 2^n − 1]; bit j = output bit j
  double start_s = 0.0;

  void validate() const;
  /// Evaluates bit floor((t − start)/bit_period) by an O(n² log k) jump of the register.
  double value_at(double t_s) const noexcept;
  /// The value for a bit (true = 1).
  double level(bool bit) const noexcept { return bit ? offset + amplitude : offset - amplitude; }
};

/// Two steps one after the other (thesis Fig. 4.6, 5.15): `amplitude` at start_s, then
/// `second_amplitude` (signed, relative to the first) at second_start_s; both rise alike.
struct DoubleStep {
  double amplitude = 1.0;
  double start_s = 0.0;
  double second_amplitude = 1.0;
  double second_start_s = 1.0;  ///< >= start_s + rise_s: the second step starts after the first ends
  double rise_s = 0.0;
  RiseShape rise_shape = RiseShape::linear;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// A staircase of levels (steps on top of each other, thesis Fig. 5.14 "repeating sequence"):
/// from start_s + k·dwell_s the signal moves from the previous level (0 before the first) to
/// levels[k] over rise_s. After the last level it holds it, or with `repeat` starts again.
struct StackedSteps {
  std::vector<double> levels{1.0, 2.0};
  double dwell_s = 1.0;
  double start_s = 0.0;
  double rise_s = 0.0;  ///< <= dwell_s
  RiseShape rise_shape = RiseShape::linear;
  bool repeat = false;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// ½·a·(t − start)² from start_s: constant acceleration (thesis Fig. 5.16).
struct Parabolic {
  double acceleration_per_s2 = 1.0;  ///< command units per s²
  double start_s = 0.0;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// A trapezoid / pulse (thesis Fig. 5.17): rises to `amplitude` over rise_s from start_s, holds
/// for hold_s, falls back to 0 over fall_s (rise_s = fall_s = 0: a rectangular pulse).
struct Trapezoid {
  double amplitude = 1.0;
  double start_s = 0.0;
  double rise_s = 0.1;
  double hold_s = 1.0;
  double fall_s = 0.1;
  RiseShape rise_shape = RiseShape::linear;  ///< shape of both the rise and the fall

  void validate() const;
  double value_at(double t_s) const noexcept;
};

/// How a chirp's frequency moves from f0 to f1 (scipy.signal.chirp's `method`).
enum class ChirpSweep { linear, logarithmic };
std::string_view to_string(ChirpSweep sweep) noexcept;
/// "linear" | "logarithmic"; throws InvalidArgument naming `field` otherwise.
ChirpSweep chirp_sweep_from_string(std::string_view name, std::string_view field = "sweep");

/// A swept sine for resonance tests: offset + amplitude·sin(θ(τ) + phase), τ = t − start, for
/// 0 ≤ τ ≤ sweep_s, with the instantaneous frequency θ'/2π going from f0_hz to f1_hz —
/// linear: θ = 2π(f0 τ + (f1 − f0) τ²/(2T)); logarithmic: θ = 2π f0 T (r^(τ/T) − 1)/ln r,
/// r = f1/f0 (scipy.signal.chirp with phi = phase − 90°). The offset before and after.
struct Chirp {
  double amplitude = 1.0;
  double f0_hz = 0.5;
  double f1_hz = 10.0;
  double sweep_s = 10.0;
  ChirpSweep sweep = ChirpSweep::linear;
  double phase_rad = 0.0;
  double offset = 0.0;
  double start_s = 0.0;

  void validate() const;
  double value_at(double t_s) const noexcept;
};

}  // namespace clearshape::signal
