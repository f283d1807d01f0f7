#pragma once
// Internal: switching instants compare with a 1 ns tolerance, so that a sample time computed as
// i·dt lands on the instant it was meant to hit despite rounding (tests/golden/gen_signal.py
// uses the same rule).
#include <cmath>

namespace clearshape::signal::detail {

inline constexpr double kTimeTolerance_s = 1e-9;

/// True when t_s is at or after instant_s.
inline bool reached(double t_s, double instant_s) noexcept {
  return t_s >= instant_s - kTimeTolerance_s;
}

/// The index k of the interval [origin + k·period, origin + (k+1)·period) holding t_s (t >= origin).
inline double interval_index(double t_s, double origin_s, double period_s) noexcept {
  return std::floor((t_s - origin_s + kTimeTolerance_s) / period_s);
}

}  // namespace clearshape::signal::detail
