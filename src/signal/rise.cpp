#include "clearshape/signal/rise.hpp"

#include <algorithm>
#include <string>

#include "clearshape/core/error.hpp"
#include "time_tolerance.hpp"

namespace clearshape::signal {

std::string_view to_string(RiseShape shape) noexcept {
  switch (shape) {
    case RiseShape::linear: return "linear";
    case RiseShape::s_curve: return "s-curve";
  }
  return "linear";
}

RiseShape rise_shape_from_string(std::string_view text, std::string_view parameter) {
  if (text == "linear") return RiseShape::linear;
  if (text == "s-curve" || text == "s_curve") return RiseShape::s_curve;
  throw InvalidArgument(std::string(parameter) + " = '" + std::string(text) +
                        "' is not a rise shape; allowed: linear, s-curve");
}

double rise_fraction(RiseShape shape, double u) noexcept {
  if (!(u > 0.0)) return 0.0;
  if (u >= 1.0) return 1.0;
  if (shape == RiseShape::linear) return u;
  // Jerk-limited S-curve: jerk +32, −32, −32, +32 (per unit time³) on the four quarters, so the
  // acceleration is a triangle up then down and position, velocity, acceleration are continuous
  // (double-S profile without constant phases; Biagiotti & Melchiorri 2008, §3.4).
  const auto first_half = [](double v) {
    if (v <= 0.25) return 16.0 / 3.0 * v * v * v;
    const double w = v - 0.25;
    return 1.0 / 12.0 + w + 4.0 * w * w - 16.0 / 3.0 * w * w * w;
  };
  return u <= 0.5 ? first_half(u) : 1.0 - first_half(1.0 - u);
}

double transition(RiseShape shape, double rise_s, double start_s, double t_s) noexcept {
  if (!detail::reached(t_s, start_s)) return 0.0;
  if (rise_s <= 0.0) return 1.0;
  return rise_fraction(shape, std::max(0.0, t_s - start_s) / rise_s);
}

}  // namespace clearshape::signal
