#pragma once
// The shape of a finite rise (or fall) shared by the step-like command signals: a linear ramp,
// or a jerk-limited S-curve (thesis §5.2.1: "step input (with a finite jerk value)").
#include <string_view>

namespace clearshape::signal {

enum class RiseShape {
  linear,   ///< constant velocity over the rise time (infinite jerk at the corners)
  s_curve,  ///< piecewise-constant jerk ±32/T³: triangular acceleration up, down, up (finite jerk)
};

/// "linear" or "s-curve".
std::string_view to_string(RiseShape shape) noexcept;
/// Parses "linear" or "s-curve" (also "s_curve"). Throws InvalidArgument naming `parameter`.
RiseShape rise_shape_from_string(std::string_view text, std::string_view parameter = "rise_shape");

/// The normalised rise s(u) in [0, 1] for u = elapsed / rise time; s = 0 for u <= 0 and 1 for
/// u >= 1. Linear: s = u. S-curve: s = 16u³/3 on [0, 1/4], 1/12 + w + 4w² − 16w³/3 (w = u − 1/4)
/// on [1/4, 1/2], and s(u) = 1 − s(1 − u) on [1/2, 1] (constant jerk ±32 per unit³).
double rise_fraction(RiseShape shape, double u) noexcept;

/// Value of a transition from 0 to 1 that starts at `start_s` and lasts `rise_s` (0: ideal step,
/// right-continuous: 1 at t = start_s). Times within 1 ns of start_s count as start_s, so that
/// sample times i·dt hit the intended instant despite rounding.
double transition(RiseShape shape, double rise_s, double start_s, double t_s) noexcept;

}  // namespace clearshape::signal
