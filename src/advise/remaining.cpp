#include "clearshape/advise/remaining.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::advise {

namespace {

// V(ω, ζ) of Eq. 2.19 (Magee & Book 1992), each term decayed to the last impulse, over ΣA.
double residual(std::span<const shaping::Impulse> impulses, double omega_rad_s, double zeta, double amplitude_sum) noexcept {
  const double t_last = impulses.back().time_s;
  const double sigma = zeta * omega_rad_s;
  const double omega_d = omega_rad_s * std::sqrt(1.0 - zeta * zeta);
  double re = 0.0, im = 0.0;
  for (const auto& i : impulses) {
    const double w = i.amplitude * std::exp(-sigma * (t_last - i.time_s));
    re += w * std::cos(omega_d * i.time_s);
    im += w * std::sin(omega_d * i.time_s);
  }
  return std::hypot(re, im) / amplitude_sum;
}

// Σ max(V(s·f_k, ζ_k)·P_k − P_thr, 0) / Σ max(P_k − P_thr, 0), ζ_k = zeta_of(k).
template <typename ZetaOf>
double remaining_of(const shaping::Shaper& shaper, const WeightedBins& bins, ZetaOf zeta_of, double frequency_scale) {
  const double sum = shaper.amplitude_sum();
  double remaining = 0.0;
  for (std::size_t k = 0; k < bins.power.size(); ++k) {
    const double v = residual(shaper.impulses(), kTwoPi * frequency_scale * bins.frequency_hz[k], zeta_of(k), sum);
    remaining += std::max(v * bins.power[k] - bins.threshold, 0.0);
  }
  return bins.total > 0.0 ? remaining / bins.total : 0.0;
}

}  // namespace

WeightedBins weighted_bins(const MeasuredSpectrum& spectrum, double threshold_fraction, double min_frequency_hz) {
  require_in_open("threshold_fraction", threshold_fraction, 0.0, 1.0);
  WeightedBins b;
  double peak = 0.0;
  for (std::size_t k = 0; k < spectrum.power.size(); ++k) {
    if (spectrum.frequency_hz[k] >= min_frequency_hz) peak = std::max(peak, spectrum.power[k]);
  }
  if (!(peak > 0.0)) throw InvalidArgument(fmt::format("{}: the spectrum has no positive power above {} Hz", spectrum.source, min_frequency_hz));
  b.threshold = threshold_fraction * peak;
  for (std::size_t k = 0; k < spectrum.power.size(); ++k) {
    if (spectrum.frequency_hz[k] < min_frequency_hz || spectrum.power[k] <= b.threshold) continue;
    // Bins at or below the threshold never count: V ≤ 1 for a positive shaper (and the
    // remaining part of a bin is max(V·P − P_thr, 0)). Negative shapers are not candidates.
    b.frequency_hz.push_back(spectrum.frequency_hz[k]);
    b.power.push_back(spectrum.power[k]);
    b.total += spectrum.power[k] - b.threshold;
  }
  return b;
}

std::vector<double> klipper_normalized_power(const std::vector<double>& frequency_hz, const std::vector<double>& power) {
  if (power.size() != frequency_hz.size()) {
    throw InvalidArgument(fmt::format("klipper_normalized_power: {} powers for {} frequencies", power.size(), frequency_hz.size()));
  }
  constexpr double kLowHz = 2.0 * 5.0;  // 2 × Klipper's MIN_FREQ (shaper_calibrate.py)
  std::vector<double> out(power.size());
  for (std::size_t k = 0; k < power.size(); ++k) {
    const double f = frequency_hz[k] + 0.1;  // "avoid division by zero" (shaper_calibrate.py)
    out[k] = power[k] / f;
    if (frequency_hz[k] < kLowHz) out[k] *= std::exp(1.0 - (kLowHz / f) * (kLowHz / f));  // low-frequency noise removed
  }
  return out;
}

MeasuredSpectrum scored_spectrum(const MeasuredSpectrum& spectrum) {
  if (!spectrum.klipper_normalizes) return spectrum;
  MeasuredSpectrum out = spectrum;
  out.power = klipper_normalized_power(spectrum.frequency_hz, spectrum.power);
  out.klipper_normalizes = false;
  return out;
}

double remaining_vibration(const shaping::Shaper& shaper, const WeightedBins& bins, double damping_ratio, double frequency_scale) {
  return remaining_of(shaper, bins, [damping_ratio](std::size_t) { return damping_ratio; }, frequency_scale);
}

double remaining_vibration(const shaping::Shaper& shaper, const WeightedBins& bins, std::span<const double> damping_ratio_per_bin,
                           double frequency_scale) {
  if (damping_ratio_per_bin.size() != bins.power.size()) {
    throw InvalidArgument(fmt::format("remaining_vibration: {} damping ratios for {} bins", damping_ratio_per_bin.size(), bins.power.size()));
  }
  return remaining_of(shaper, bins, [damping_ratio_per_bin](std::size_t k) { return damping_ratio_per_bin[k]; }, frequency_scale);
}

double worst_remaining_vibration(const shaping::Shaper& shaper, const std::vector<WeightedBins>& spectra,
                                 const std::vector<double>& damping_ratios, const std::vector<double>& frequency_scales) {
  double worst = 0.0;
  for (const auto& bins : spectra) {
    for (const double zeta : damping_ratios) {
      for (const double scale : frequency_scales) worst = std::max(worst, remaining_vibration(shaper, bins, zeta, scale));
    }
  }
  return worst;
}

std::vector<double> worst_response(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                   const std::vector<double>& damping_ratios, const std::vector<double>& frequency_scales) {
  std::vector<double> out(frequency_hz.size(), 0.0);
  const double sum = shaper.amplitude_sum();
  for (std::size_t k = 0; k < frequency_hz.size(); ++k) {
    for (const double zeta : damping_ratios) {
      for (const double scale : frequency_scales) {
        out[k] = std::max(out[k], residual(shaper.impulses(), kTwoPi * scale * frequency_hz[k], zeta, sum));
      }
    }
  }
  return out;
}

std::vector<double> power_after_shaper(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                       const std::vector<double>& power, const std::vector<double>& damping_ratios,
                                       const std::vector<double>& frequency_scales) {
  if (power.size() != frequency_hz.size()) {
    throw InvalidArgument(fmt::format("power_after_shaper: {} powers for {} frequencies", power.size(), frequency_hz.size()));
  }
  std::vector<double> out = worst_response(shaper, frequency_hz, damping_ratios, frequency_scales);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = power[k] * out[k] * out[k];  // |residual/unshaped|² of power
  return out;
}

}  // namespace clearshape::advise
