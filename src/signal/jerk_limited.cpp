#include "clearshape/signal/jerk_limited.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::signal {

void AxisLimits::validate(std::string_view owner) const {
  const std::string o(owner);
  require_positive(o + ".velocity", velocity);
  require_positive(o + ".acceleration", acceleration);
  require_positive(o + ".jerk", jerk);
}

JerkLimitedProfile JerkLimitedProfile::minimum_time(double start, double end, const AxisLimits& limits) {
  limits.validate("limits");
  require_finite("start", start);
  require_finite("end", end);
  JerkLimitedProfile p;
  p.start_ = start;
  p.end_ = end;
  p.distance_ = std::abs(end - start);
  p.direction_ = end >= start ? 1.0 : -1.0;
  p.jerk_ = limits.jerk;
  if (p.distance_ == 0.0) return p;
  const double v = limits.velocity, a = limits.acceleration, j = limits.jerk, d = p.distance_;
  // Biagiotti & Melchiorri 2008, §3.4 (v0 = v1 = 0): is a_max reached on the way to v_max?
  double tj = v * j >= a * a ? a / j : std::sqrt(v / j);
  double ta = v * j >= a * a ? tj + v / a : 2.0 * tj;
  double tv = d / v - ta;  // cruise time: D = v·Ta + v·Tv
  if (tv <= 0.0) {         // v_max not reached: no cruise
    tv = 0.0;
    if (d >= 2.0 * a * a * a / (j * j)) {  // a_max reached: Ta² − Tj·Ta − D/a = 0
      tj = a / j;
      ta = 0.5 * tj + std::sqrt(0.25 * tj * tj + d / a);
    } else {  // neither: D = 2 j Tj³
      tj = std::cbrt(d / (2.0 * j));
      ta = 2.0 * tj;
    }
  }
  p.jerk_time_s_ = tj;
  p.acceleration_time_s_ = std::max(ta, 2.0 * tj);
  p.cruise_time_s_ = tv;
  p.duration_s_ = 2.0 * p.acceleration_time_s_ + tv;
  return p;
}

JerkLimitedProfile JerkLimitedProfile::time_scaled(double duration_s) const {
  require_finite("duration_s", duration_s);
  const double minimum_s = 2.0 * acceleration_time_s_ + cruise_time_s_;
  if (duration_s < minimum_s * (1.0 - 1e-12)) {
    throw_invalid("duration_s", duration_s, ">= the minimum time " + std::to_string(minimum_s) + " s",
                  "a jerk-limited move cannot be faster than its minimum time");
  }
  JerkLimitedProfile p = *this;
  p.duration_s_ = std::max(duration_s, minimum_s);
  p.time_scale_ = minimum_s > 0.0 ? minimum_s / p.duration_s_ : 1.0;
  return p;
}

double JerkLimitedProfile::peak_velocity() const noexcept {
  return time_scale_ * jerk_ * jerk_time_s_ * (acceleration_time_s_ - jerk_time_s_);
}

double JerkLimitedProfile::peak_acceleration() const noexcept {
  return distance_ > 0.0 ? time_scale_ * time_scale_ * jerk_ * jerk_time_s_ : 0.0;
}

// The unscaled profile on [0, Ta + Tv/2] (segments 1–3 and half the cruise), integrated exactly.
AxisState JerkLimitedProfile::nominal_first_half(double tau_s) const noexcept {
  const double j = jerk_, tj = jerk_time_s_, ta = acceleration_time_s_;
  const double ap = j * tj;  // peak acceleration
  if (tau_s <= tj) return {j * tau_s * tau_s * tau_s / 6.0, 0.5 * j * tau_s * tau_s, j * tau_s, j};
  const double v1 = 0.5 * j * tj * tj, p1 = j * tj * tj * tj / 6.0;
  const double t2 = ta - tj;  // end of the constant-acceleration segment
  if (tau_s <= t2) {
    const double dt = tau_s - tj;
    return {p1 + v1 * dt + 0.5 * ap * dt * dt, v1 + ap * dt, ap, 0.0};
  }
  const double d2 = t2 - tj;
  const double v2 = v1 + ap * d2, p2 = p1 + v1 * d2 + 0.5 * ap * d2 * d2;
  const double dt = std::min(tau_s, ta) - t2;
  const AxisState s3{p2 + v2 * dt + 0.5 * ap * dt * dt - j * dt * dt * dt / 6.0, v2 + ap * dt - 0.5 * j * dt * dt,
                     ap - j * dt, -j};
  if (tau_s <= ta) return s3;
  return {s3.position + s3.velocity * (tau_s - ta), s3.velocity, 0.0, 0.0};  // cruise
}

AxisState JerkLimitedProfile::at(double t_s) const noexcept {
  if (distance_ == 0.0 || !(t_s > 0.0)) return {start_, 0.0, 0.0, 0.0};
  if (t_s >= duration_s_) return {end(), 0.0, 0.0, 0.0};
  const double s = time_scale_, total_s = 2.0 * acceleration_time_s_ + cruise_time_s_;
  const double tau = s * t_s;
  AxisState n;
  if (tau <= 0.5 * total_s) {
    n = nominal_first_half(tau);
  } else {  // the rest-to-rest profile is odd about its midpoint: p(τ) = D − p(T − τ)
    const AxisState m = nominal_first_half(total_s - tau);
    n = {distance_ - m.position, m.velocity, -m.acceleration, m.jerk};
  }
  const double d = direction_;
  return {start_ + d * n.position, d * s * n.velocity, d * s * s * n.acceleration, d * s * s * s * n.jerk};
}

SynchronizedMove synchronized_move(std::span<const double> start, std::span<const double> end,
                                   std::span<const AxisLimits> limits) {
  if (start.empty() || start.size() != end.size() || start.size() != limits.size()) {
    throw InvalidArgument("synchronized_move: start, end and limits need one entry per axis (got " +
                          std::to_string(start.size()) + ", " + std::to_string(end.size()) + ", " +
                          std::to_string(limits.size()) + "; at least one axis)");
  }
  SynchronizedMove move;
  for (std::size_t i = 0; i < start.size(); ++i) {
    const std::string axis = "axis[" + std::to_string(i) + "]";
    limits[i].validate(axis + ".limits");
    require_finite(axis + ".start", start[i]);
    require_finite(axis + ".end", end[i]);
    move.axes.push_back(JerkLimitedProfile::minimum_time(start[i], end[i], limits[i]));
    if (move.axes.back().duration_s() > move.duration_s) {
      move.duration_s = move.axes.back().duration_s();
      move.limiting_axis = i;
    }
  }
  for (JerkLimitedProfile& axis : move.axes) axis = axis.time_scaled(move.duration_s);
  return move;
}

std::vector<SampledAxis> sample_move(const SynchronizedMove& move, double sample_time_s) {
  require_positive("sample_time_s", sample_time_s);
  const double steps = std::ceil(move.duration_s / sample_time_s - 1e-9);
  if (!(steps < 1e7)) throw_invalid("sample_time_s", sample_time_s, "at most 1e7 samples per move");
  const std::size_t n = static_cast<std::size_t>(std::max(steps, 1.0)) + 1;  // a still move: 2 samples at rest
  std::vector<SampledAxis> out(move.axes.size());
  for (std::size_t i = 0; i < move.axes.size(); ++i) {
    SampledAxis& s = out[i];
    for (UniformSeries* u : {&s.position, &s.velocity, &s.acceleration}) {
      u->sample_time_s = sample_time_s;
      u->values.resize(n);
    }
    for (std::size_t k = 0; k < n; ++k) {
      const AxisState st = move.axes[i].at(static_cast<double>(k) * sample_time_s);
      s.position.values[k] = st.position;
      s.velocity.values[k] = st.velocity;
      s.acceleration.values[k] = st.acceleration;
    }
  }
  return out;
}

}  // namespace clearshape::signal
