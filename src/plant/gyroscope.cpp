#include "clearshape/plant/gyroscope.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::plant {

double bandwidth_hz(GyroLowPass setting) noexcept {
  switch (setting) {  // ITG-3205 datasheet, DLPF_CFG 0…6
    case GyroLowPass::off: return 0.0;
    case GyroLowPass::hz256: return 256.0;
    case GyroLowPass::hz188: return 188.0;
    case GyroLowPass::hz98: return 98.0;
    case GyroLowPass::hz42: return 42.0;
    case GyroLowPass::hz20: return 20.0;
    case GyroLowPass::hz10: return 10.0;
    case GyroLowPass::hz5: return 5.0;
  }
  return 0.0;
}

void GyroscopeConfig::validate() const {
  require_positive("gyroscope.sensitivity_lsb_per_dps", sensitivity_lsb_per_dps,
                   "the ITG-3205 has 14.375 LSB per deg/s");
  require_positive("gyroscope.full_scale_dps", full_scale_dps, "the ITG-3205 has ±2000 deg/s");
  require_non_negative("gyroscope.noise_density_dps_per_rthz", noise_density_dps_per_rthz);
  require_finite("gyroscope.bias_dps", bias_dps);
  require_positive("gyroscope.sample_rate_hz", sample_rate_hz);
  require_in_closed("gyroscope.latency_samples", latency_samples, 0.0, kMaxGyroLatencySamples);
}

Gyroscope::Gyroscope(const GyroscopeConfig& config) : config_(config), rng_(config.seed) {
  config_.validate();
  // white noise of one-sided density ρ sampled at f_s: σ = ρ·√(f_s/2)
  noise_std_dps_ = config_.noise_density_dps_per_rthz * std::sqrt(0.5 * config_.sample_rate_hz);
  const double fc = bandwidth_hz(config_.low_pass);
  // exact ZOH discretization of 1/(τ s + 1), τ = 1/(2π f_c): y ← y + (1 − e^(−T/τ))(x − y)
  filter_coefficient_ = fc > 0.0 ? 1.0 - std::exp(-kTwoPi * fc / config_.sample_rate_hz) : 1.0;
  reset(0.0);
}

void Gyroscope::reset(double rate_rad_s) noexcept {
  rng_.seed(config_.seed);
  normal_.reset();
  const double dps = rad_to_deg(rate_rad_s) + config_.bias_dps;
  filter_state_dps_ = dps;
  delay_.fill(convert(dps));  // as if the sensor had rested at this rate
  head_ = 0;
}

GyroSample Gyroscope::convert(double dps) const noexcept {
  GyroSample out;
  double clipped = std::isnan(dps) ? 0.0 : dps;
  out.saturated = !(std::abs(clipped) < config_.full_scale_dps);
  clipped = std::clamp(clipped, -config_.full_scale_dps, config_.full_scale_dps);
  const double lsb = std::nearbyint(clipped * config_.sensitivity_lsb_per_dps);
  if (lsb > 32767.0 || lsb < -32768.0) out.saturated = true;
  out.raw = static_cast<std::int16_t>(std::clamp(lsb, -32768.0, 32767.0));
  out.rate_rad_s = deg_to_rad(static_cast<double>(out.raw) / config_.sensitivity_lsb_per_dps);
  return out;
}

std::int16_t Gyroscope::quantize(double rate_rad_s) const noexcept {
  double dps = rad_to_deg(rate_rad_s);
  if (std::isnan(dps)) dps = 0.0;
  dps = std::clamp(dps, -config_.full_scale_dps, config_.full_scale_dps);
  const double lsb = std::nearbyint(dps * config_.sensitivity_lsb_per_dps);
  return static_cast<std::int16_t>(std::clamp(lsb, -32768.0, 32767.0));
}

GyroSample Gyroscope::sample(double true_rate_rad_s) noexcept {
  double dps = rad_to_deg(true_rate_rad_s) + config_.bias_dps;
  if (noise_std_dps_ > 0.0) dps += noise_std_dps_ * normal_(rng_);
  if (filter_coefficient_ < 1.0) {
    filter_state_dps_ += filter_coefficient_ * (dps - filter_state_dps_);
    dps = filter_state_dps_;
  }
  const GyroSample now = convert(dps);
  if (config_.latency_samples == 0) return now;
  // delay line of latency_samples + 1 slots: write the newest, read the oldest
  const int size = config_.latency_samples + 1;
  delay_[static_cast<std::size_t>(head_)] = now;
  head_ = (head_ + 1) % size;
  return delay_[static_cast<std::size_t>(head_)];
}

}  // namespace clearshape::plant
