#include "clearshape/plant/command.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

namespace {
// A time within this fraction of a sample below a knot counts as the knot (right-continuous
// hold robust to rounding of k·T).
constexpr double kKnotTolerance = 1e-9;
}  // namespace

Command::Command(UniformSeries samples, Interpolation interpolation)
    : samples_(std::move(samples)), interpolation_(interpolation) {
  if (samples_.values.empty()) {
    throw InvalidArgument("command: the sample series is empty; give at least one sample");
  }
  require_finite("command.start_s", samples_.start_s);
  require_positive("command.sample_time_s", samples_.sample_time_s);
  for (std::size_t i = 0; i < samples_.values.size(); ++i) {
    if (!std::isfinite(samples_.values[i])) {
      throw_invalid("command.values[" + std::to_string(i) + "]", samples_.values[i],
                    "finite numbers", "remove NaN/Inf samples from the command");
    }
  }
  if (interpolation_ == Interpolation::zero_order_hold) {
    for (std::size_t i = 1; i < samples_.values.size(); ++i) {
      if (samples_.values[i] != samples_.values[i - 1]) jumps_s_.push_back(samples_.time_s(i));
    }
  }
}

Command Command::constant(double value) {
  UniformSeries s;
  s.start_s = 0.0;
  s.sample_time_s = 1.0;
  s.values = {value};
  return Command(std::move(s));
}

Command Command::step(double time_s, double after, double before) {
  require_finite("step.time_s", time_s);
  if (time_s <= 0.0) return constant(after);
  UniformSeries s;
  s.start_s = 0.0;
  s.sample_time_s = time_s;
  s.values = {before, after};
  return Command(std::move(s));
}

std::size_t Command::segment(double t) const noexcept {
  const double r = (t - samples_.start_s) / samples_.sample_time_s;
  if (!(r > 0.0)) return 0;  // also NaN
  const double k = std::floor(r + kKnotTolerance * std::max(1.0, r));
  const double last = static_cast<double>(samples_.values.size() - 1);
  return static_cast<std::size_t>(std::min(k, last));
}

double Command::value(double t) const noexcept {
  const std::size_t k = segment(t);
  if (interpolation_ == Interpolation::zero_order_hold || k + 1 >= samples_.values.size()) {
    return samples_.values[k];
  }
  const double frac = std::clamp((t - samples_.time_s(k)) / samples_.sample_time_s, 0.0, 1.0);
  return samples_.values[k] + frac * (samples_.values[k + 1] - samples_.values[k]);
}

double Command::rate(double t) const noexcept {
  if (interpolation_ == Interpolation::zero_order_hold) return 0.0;
  if (t < samples_.start_s) return 0.0;
  const std::size_t k = segment(t);
  if (k + 1 >= samples_.values.size()) return 0.0;
  return (samples_.values[k + 1] - samples_.values[k]) / samples_.sample_time_s;
}

double Command::next_discontinuity_s(double t) const noexcept {
  const double tol = kKnotTolerance * samples_.sample_time_s * std::max(1.0, std::abs(t));
  const auto it = std::upper_bound(jumps_s_.begin(), jumps_s_.end(), t + tol);
  return it == jumps_s_.end() ? std::numeric_limits<double>::infinity() : *it;
}

}  // namespace clearshape::plant
