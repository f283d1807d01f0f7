#include "clearshape/shaping/shaper.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::shaping {

Mode Mode::from_hz(double natural_frequency_hz, double damping_ratio) {
  return Mode{hz_to_rad_s(natural_frequency_hz), damping_ratio};
}

double Mode::natural_frequency_hz() const noexcept { return rad_s_to_hz(natural_frequency_rad_s); }

double Mode::damped_frequency_rad_s() const noexcept {
  if (damping_ratio >= 1.0) return 0.0;
  return natural_frequency_rad_s * std::sqrt(1.0 - damping_ratio * damping_ratio);  // Eq. 2.24
}

Shaper::Shaper(std::string method, std::vector<Impulse> impulses, Normalize normalize)
    : method_(std::move(method)), impulses_(std::move(impulses)) {
  if (impulses_.empty()) throw InvalidArgument(fmt::format("shaper '{}': needs at least one impulse", method_));
  double sum = 0.0;
  for (std::size_t i = 0; i < impulses_.size(); ++i) {
    const Impulse& p = impulses_[i];
    if (!std::isfinite(p.time_s) || !std::isfinite(p.amplitude)) {
      throw InvalidArgument(fmt::format("shaper '{}': impulse {} (t = {} s, A = {}) is not finite",
                                        method_, i + 1, p.time_s, p.amplitude));
    }
    if (p.time_s < 0.0) {
      throw InvalidArgument(fmt::format("shaper '{}': impulse {} time t = {} s is out of range; "
                                        "allowed: t >= 0", method_, i + 1, p.time_s));
    }
    if (i > 0 && !(p.time_s > impulses_[i - 1].time_s)) {
      throw InvalidArgument(fmt::format("shaper '{}': impulse times must increase strictly; impulse {} "
                                        "at t = {} s follows t = {} s", method_, i + 1, p.time_s,
                                        impulses_[i - 1].time_s));
    }
    sum += p.amplitude;
  }
  if (!(std::abs(sum) > 1e-12)) {
    throw InvalidArgument(fmt::format("shaper '{}': the amplitudes sum to {}; a shaper must pass the "
                                      "command's final value (ΣA ≠ 0, Eq. 2.21)", method_, sum));
  }
  if (normalize == Normalize::yes) {
    for (Impulse& p : impulses_) p.amplitude /= sum;
  }
}

double Shaper::amplitude_sum() const noexcept {
  double sum = 0.0;
  for (const Impulse& p : impulses_) sum += p.amplitude;
  return sum;
}

bool Shaper::is_positive() const noexcept {
  for (const Impulse& p : impulses_) {
    if (p.amplitude < 0.0) return false;
  }
  return true;
}

Shaper positive_shaper_on_slots(std::string method, std::span<const double> slot_times_s,
                                std::span<const double> weights) {
  if (weights.size() != slot_times_s.size() || slot_times_s.empty()) {
    throw_invalid("weights size", static_cast<double>(weights.size()),
                  fmt::format("{} (one per slot, at least one)", slot_times_s.size()));
  }
  double sum = 0.0;
  for (const double x : weights) sum += std::max(0.0, x);
  std::vector<Impulse> impulses;
  for (std::size_t k = 0; k < slot_times_s.size(); ++k) {
    const double a = sum > 0.0 ? std::max(0.0, weights[k]) / sum : (k == 0 ? 1.0 : 0.0);
    if (a > 0.0) impulses.push_back({slot_times_s[k], a});
  }
  return Shaper(std::move(method), std::move(impulses));
}

}  // namespace clearshape::shaping
