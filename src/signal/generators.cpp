#include "clearshape/signal/generators.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "time_tolerance.hpp"

namespace clearshape::signal {

using detail::reached;

// ---- Step ----------------------------------------------------------------------------------

void Step::validate() const {
  require_finite("amplitude", amplitude);
  require_non_negative("start_s", start_s);
  require_non_negative("rise_s", rise_s, "Use 0 for an ideal step");
}

double Step::value_at(double t_s) const noexcept {
  return amplitude * transition(rise_shape, rise_s, start_s, t_s);
}

// ---- Ramp ----------------------------------------------------------------------------------

void Ramp::validate() const {
  require_finite("slope_per_s", slope_per_s);
  require_non_negative("start_s", start_s);
  if (limit) {
    require_finite("limit", *limit);
    if (!(*limit * slope_per_s > 0.0)) {
      throw_invalid("limit", *limit,
                    fmt::format("non-zero with the sign of slope_per_s = {}", slope_per_s),
                    "Drop the limit for an unbounded ramp");
    }
  }
}

double Ramp::value_at(double t_s) const noexcept {
  if (!reached(t_s, start_s)) return 0.0;
  const double v = slope_per_s * std::max(0.0, t_s - start_s);
  if (!limit) return v;
  return slope_per_s > 0.0 ? std::min(v, *limit) : std::max(v, *limit);
}

// ---- Sine ----------------------------------------------------------------------------------

void Sine::validate() const {
  require_finite("amplitude", amplitude);
  require_positive("frequency_hz", frequency_hz);
  require_finite("phase_rad", phase_rad);
  require_finite("offset", offset);
  require_non_negative("start_s", start_s);
}

double Sine::value_at(double t_s) const noexcept {
  if (!reached(t_s, start_s)) return offset;
  return offset + amplitude * std::sin(kTwoPi * frequency_hz * (t_s - start_s) + phase_rad);
}

// ---- DoubleStep ----------------------------------------------------------------------------

void DoubleStep::validate() const {
  require_finite("amplitude", amplitude);
  require_non_negative("start_s", start_s);
  require_finite("second_amplitude", second_amplitude);
  require_non_negative("rise_s", rise_s, "Use 0 for ideal steps");
  require_finite("second_start_s", second_start_s);
  if (second_start_s < start_s + rise_s) {
    throw_invalid("second_start_s", second_start_s,
                  fmt::format(">= start_s + rise_s = {}", start_s + rise_s),
                  "The second step starts after the first has risen; for overlapping moves use "
                  "stacked-steps or a shorter rise");
  }
}

double DoubleStep::value_at(double t_s) const noexcept {
  return amplitude * transition(rise_shape, rise_s, start_s, t_s) +
         second_amplitude * transition(rise_shape, rise_s, second_start_s, t_s);
}

// ---- StackedSteps --------------------------------------------------------------------------

void StackedSteps::validate() const {
  if (levels.empty() || levels.size() > 100000) {
    throw_invalid("levels (count)", static_cast<double>(levels.size()), "[1, 100000]",
                  "Give the staircase levels, e.g. 1,2,3");
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    require_finite(fmt::format("levels[{}]", i), levels[i]);
  }
  require_positive("dwell_s", dwell_s);
  require_non_negative("start_s", start_s);
  require_in_closed("rise_s", rise_s, 0.0, dwell_s, "The rise must fit in the dwell time");
}

double StackedSteps::value_at(double t_s) const noexcept {
  if (!reached(t_s, start_s)) return 0.0;
  const double k_real = std::max(0.0, detail::interval_index(t_s, start_s, dwell_s));
  const std::size_t m = levels.size();
  const auto level = [&](double k) {
    if (k < 0.0) return 0.0;
    if (repeat) return levels[static_cast<std::size_t>(std::fmod(k, static_cast<double>(m)))];
    return k >= static_cast<double>(m) ? levels.back() : levels[static_cast<std::size_t>(k)];
  };
  const double to = level(k_real);
  if (rise_s <= 0.0) return to;
  const double from = level(k_real - 1.0);
  const double elapsed_s = std::max(0.0, t_s - (start_s + k_real * dwell_s));
  return from + (to - from) * rise_fraction(rise_shape, elapsed_s / rise_s);
}

// ---- Parabolic -----------------------------------------------------------------------------

void Parabolic::validate() const {
  require_finite("acceleration_per_s2", acceleration_per_s2);
  require_non_negative("start_s", start_s);
}

double Parabolic::value_at(double t_s) const noexcept {
  if (!reached(t_s, start_s)) return 0.0;
  const double dt = std::max(0.0, t_s - start_s);
  return 0.5 * acceleration_per_s2 * dt * dt;  // constant acceleration (thesis §5.2.1)
}

// ---- Trapezoid -----------------------------------------------------------------------------

void Trapezoid::validate() const {
  require_finite("amplitude", amplitude);
  require_non_negative("start_s", start_s);
  require_non_negative("rise_s", rise_s, "Use 0 for a vertical edge");
  require_non_negative("hold_s", hold_s);
  require_non_negative("fall_s", fall_s, "Use 0 for a vertical edge");
}

double Trapezoid::value_at(double t_s) const noexcept {
  const double fall_start_s = start_s + rise_s + hold_s;
  return amplitude * (transition(rise_shape, rise_s, start_s, t_s) -
                      transition(rise_shape, fall_s, fall_start_s, t_s));
}

// ---- Chirp ---------------------------------------------------------------------------------

std::string_view to_string(ChirpSweep sweep) noexcept {
  return sweep == ChirpSweep::linear ? "linear" : "logarithmic";
}

ChirpSweep chirp_sweep_from_string(std::string_view name, std::string_view field) {
  if (name == "linear") return ChirpSweep::linear;
  if (name == "logarithmic") return ChirpSweep::logarithmic;
  throw InvalidArgument(fmt::format("{} = '{}' is not a sweep; allowed: linear, logarithmic", field, name));
}

void Chirp::validate() const {
  require_finite("amplitude", amplitude);
  require_positive("f0_hz", f0_hz);
  require_positive("f1_hz", f1_hz);
  require_positive("sweep_s", sweep_s);
  require_finite("phase_rad", phase_rad);
  require_finite("offset", offset);
  require_non_negative("start_s", start_s);
}

double Chirp::value_at(double t_s) const noexcept {
  if (!reached(t_s, start_s)) return offset;
  const double tau = t_s - start_s;
  if (tau > sweep_s) return offset;
  double theta = 0.0;
  if (sweep == ChirpSweep::linear || f0_hz == f1_hz) {
    theta = kTwoPi * (f0_hz * tau + 0.5 * (f1_hz - f0_hz) * tau * tau / sweep_s);  // scipy.signal.chirp, linear
  } else {
    const double log_ratio = std::log(f1_hz / f0_hz);  // scipy.signal.chirp, logarithmic
    theta = kTwoPi * f0_hz * sweep_s / log_ratio * std::expm1(log_ratio * tau / sweep_s);
  }
  return offset + amplitude * std::sin(theta + phase_rad);
}

}  // namespace clearshape::signal
