#include "clearshape/signal/position_path.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "time_tolerance.hpp"

namespace clearshape::signal {

namespace {

constexpr double kMaxCountMagnitude = 9.0e15;  // below 2^53: counts stay exact in a double

// Linear interpolation of a uniform series, held before the start and after the end.
double interpolate(const UniformSeries& s, double t_s) noexcept {
  const double x = (t_s - s.start_s) / s.sample_time_s;
  if (!(x > 0.0)) return s.values.front();
  const auto last = static_cast<double>(s.values.size() - 1);
  if (x >= last) return s.values.back();
  const double j = std::floor(x);
  const auto i = static_cast<std::size_t>(j);
  return s.values[i] + (x - j) * (s.values[i + 1] - s.values[i]);
}

}  // namespace

// ---- PulseTrainConfig ----------------------------------------------------------------------

void PulseTrainConfig::validate() const {
  if (!(update_rate_hz > 0.0 && update_rate_hz <= 10000.0)) {
    throw_invalid("update_rate_hz", update_rate_hz, "(0, 10000]",
                  "The thesis driver detects frequency changes at 30 Hz");
  }
  require_positive("counts_per_rev", counts_per_rev, "The thesis encoder has 3000 P/R");
  require_positive("gear_ratio", gear_ratio, "Use 1 for no electronic gear");
  if (!(max_pulse_frequency_hz > 0.0 && max_pulse_frequency_hz <= 1e9)) {
    throw_invalid("max_pulse_frequency_hz", max_pulse_frequency_hz, "(0, 1e9]",
                  "The thesis driver accepts pulses up to 500 kHz");
  }
  if (max_counts_per_update() < 1) {
    throw_invalid("max_pulse_frequency_hz", max_pulse_frequency_hz,
                  fmt::format(">= update_rate_hz = {} (one pulse per update)", update_rate_hz));
  }
}

double PulseTrainConfig::counts_per_rad() const noexcept {
  return counts_per_rev / (gear_ratio * kTwoPi);
}

std::int64_t PulseTrainConfig::max_counts_per_update() const noexcept {
  return static_cast<std::int64_t>(std::floor(max_pulse_frequency_hz / update_rate_hz + 1e-9));
}

// ---- PulseTrain ----------------------------------------------------------------------------

PulseTrain::PulseTrain(const PulseTrainConfig& config)
    : config_(config), counts_per_rad_(0.0), max_counts_(0) {
  config_.validate();
  counts_per_rad_ = config_.counts_per_rad();
  max_counts_ = config_.max_counts_per_update();
}

void PulseTrain::reset(double position_rad) noexcept {
  const double c = std::floor(position_rad * counts_per_rad_ + 0.5);
  count_ = std::isfinite(c) ? static_cast<std::int64_t>(std::clamp(c, -kMaxCountMagnitude, kMaxCountMagnitude)) : 0;
  pulses_ = 0;
}

Status PulseTrain::program(double target_rad) noexcept {
  count_ += pulses_;
  pulses_ = 0;
  if (!std::isfinite(target_rad)) return Status::not_finite;
  // Whole counts: the nearest count to the target (ties up).
  const double goal = std::clamp(std::floor(target_rad * counts_per_rad_ + 0.5), -kMaxCountMagnitude,
                                 kMaxCountMagnitude);
  const std::int64_t wanted = static_cast<std::int64_t>(goal) - count_;
  pulses_ = std::clamp(wanted, -max_counts_, max_counts_);
  return pulses_ == wanted ? Status::ok : Status::out_of_range;
}

std::int64_t PulseTrain::count_at(double elapsed_s) const noexcept {
  if (pulses_ == 0) return count_;
  const std::int64_t n = pulses_ < 0 ? -pulses_ : pulses_;
  const double fraction = std::clamp(elapsed_s * config_.update_rate_hz, 0.0, 1.0);
  // Pulses completed at constant frequency n/T; the 1e-9 absorbs rounding at a pulse's end.
  const auto done = std::min(n, static_cast<std::int64_t>(std::floor(static_cast<double>(n) * fraction + 1e-9)));
  return pulses_ < 0 ? count_ - done : count_ + done;
}

double PulseTrain::commanded_rad(double elapsed_s) const noexcept {
  return static_cast<double>(count_at(elapsed_s)) / counts_per_rad_;
}

double PulseTrain::pulse_frequency_hz() const noexcept {
  return static_cast<double>(pulses_) * config_.update_rate_hz;
}

// ---- apply_position_path -------------------------------------------------------------------

PositionPathResult apply_position_path(const UniformSeries& position_rad,
                                       const PulseTrainConfig& config,
                                       std::optional<double> initial_rad) {
  config.validate();
  if (position_rad.values.empty()) {
    throw InvalidArgument("apply_position_path: the position trajectory is empty");
  }
  require_positive("sample_time_s", position_rad.sample_time_s);
  for (std::size_t i = 0; i < position_rad.values.size(); ++i) {
    if (!std::isfinite(position_rad.values[i])) {
      throw_invalid(fmt::format("position sample {}", i), position_rad.values[i], "a finite number");
    }
  }

  const double period_s = config.update_period_s();
  const double start_s = position_rad.start_s;
  const double h_s = position_rad.sample_time_s;
  const auto updates = static_cast<std::size_t>(
      detail::interval_index(position_rad.end_s(), start_s, period_s)) + 1;
  const std::size_t n = position_rad.values.size();

  PositionPathResult r;
  r.counts_per_rad = config.counts_per_rad();
  r.commanded_rad = {start_s, h_s, std::vector<double>(n)};
  r.pulse_frequency_hz = {start_s, h_s, std::vector<double>(n)};
  r.held_velocity_rad_s = {start_s, period_s, std::vector<double>(updates)};
  r.pulses_per_update.resize(updates);

  const double initial = initial_rad.value_or(position_rad.values.front());
  require_finite("initial_rad", initial);
  PulseTrain train(config);
  train.reset(initial);
  r.initial_count = train.count();
  double aimed_rad = initial;  // where the pulses aim at the end of the period
  std::size_t i = 0;
  for (std::size_t k = 0; k < updates; ++k) {
    const double t_k = start_s + static_cast<double>(k) * period_s;
    double velocity_rad_s = 0.0;
    if (config.velocity_hold == VelocityHold::lookahead) {
      // §3.2/§4.1.2: hold the velocity that reaches the trajectory at the next update instant.
      const double next_rad = interpolate(position_rad, t_k + period_s);
      velocity_rad_s = (next_rad - aimed_rad) / period_s;
      aimed_rad = next_rad;
    } else {
      // §3.2: derivative of the trajectory (backward difference), sampled at the update.
      velocity_rad_s = (interpolate(position_rad, t_k) - interpolate(position_rad, t_k - h_s)) / h_s;
      aimed_rad += velocity_rad_s * period_s;
    }
    r.held_velocity_rad_s.values[k] = velocity_rad_s;
    if (train.program(aimed_rad) == Status::out_of_range) ++r.saturated_updates;
    r.pulses_per_update[k] = train.pulses();
    const double reached_rad = static_cast<double>(train.count() + train.pulses()) / r.counts_per_rad;
    r.max_lag_rad = std::max(r.max_lag_rad, std::abs(aimed_rad - reached_rad));

    for (; i < n; ++i) {
      const double t_i = position_rad.time_s(i);
      if (detail::interval_index(t_i, start_s, period_s) > static_cast<double>(k)) break;
      r.commanded_rad.values[i] = train.commanded_rad(std::max(0.0, t_i - t_k));
      r.pulse_frequency_hz.values[i] = train.pulse_frequency_hz();
    }
  }
  return r;
}

UniformSeries apply_realtime_position_path(const UniformSeries& position_rad, const PulseTrainConfig& config,
                                           double latency_s) {
  config.validate();
  if (position_rad.values.empty()) throw InvalidArgument("apply_realtime_position_path: the position trajectory is empty");
  require_positive("sample_time_s", position_rad.sample_time_s);
  const double ts = position_rad.sample_time_s, period_s = config.update_period_s();
  require_in_closed("latency_s", latency_s, 0.0, period_s);
  PulseTrain train(config);
  train.reset(0.0);
  UniformSeries drive{position_rad.start_s, ts, std::vector<double>(position_rad.values.size(), 0.0)};
  double update_start_s = latency_s, next_update_s = latency_s;
  for (std::size_t k = 0; k < drive.values.size(); ++k) {
    const double t = static_cast<double>(k) * ts;
    if (!std::isfinite(position_rad.values[k])) throw_invalid(fmt::format("position sample {}", k), position_rad.values[k], "a finite number");
    if (t >= next_update_s - 1e-9 * ts) {  // the loop's tick at or after the update instant
      update_start_s = next_update_s;
      while (next_update_s <= t + 1e-9 * ts) next_update_s += period_s;
      train.program(position_rad.values[k]);  // a capped move lags, as on the rig
    }
    drive.values[k] = train.commanded_rad(t - update_start_s);  // elapsed clamped to [0, T]: 0 before the first
  }
  return drive;
}

}  // namespace clearshape::signal
