#pragma once
// The command that drives the plant, as a function of time built from samples
// (e.g. the signal module's output, or a drive command path's 30 Hz staircase).
//   zero_order_hold: u(t) = u[k] for t_k ≤ t < t_{k+1} (the DAQ/driver holds each sample);
//                    each change of value is a discontinuity where the integrator stops and
//                    restarts exactly at t_k.
//   linear:          piecewise-linear between samples (no stops; the kinks are mild).
// Before the first sample the first value holds; after the last, the last value holds.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "clearshape/core/series.hpp"

namespace clearshape::plant {

enum class Interpolation : std::uint8_t { zero_order_hold, linear };

class Command {
 public:
  /// Throws InvalidArgument on an empty series, a non-positive sample time or non-finite
  /// values (naming the sample index).
  Command(UniformSeries samples, Interpolation interpolation = Interpolation::zero_order_hold);
  /// A constant command.
  static Command constant(double value);
  /// A step from `before` to `after` at `time_s` (zero-order hold, one discontinuity).
  static Command step(double time_s, double after, double before = 0.0);

  double value(double t_s) const noexcept;
  /// du/dt (0 for zero-order hold; the segment slope for linear).
  double rate(double t_s) const noexcept;
  /// First discontinuity strictly after t_s (+infinity if none).
  double next_discontinuity_s(double t_s) const noexcept;
  const std::vector<double>& discontinuities_s() const noexcept { return jumps_s_; }

  const UniformSeries& samples() const noexcept { return samples_; }
  Interpolation interpolation() const noexcept { return interpolation_; }

 private:
  std::size_t segment(double t_s) const noexcept;
  UniformSeries samples_;
  Interpolation interpolation_;
  std::vector<double> jumps_s_;
};

}  // namespace clearshape::plant
