#pragma once
// Digital gyroscope on the link tip (thesis §3.2: InvenSense ITG-3205).
// Datasheet values: sensitivity 14.375 LSB per °/s; full-scale range ±2000 °/s; 16-bit
// two's-complement output; rate-noise density 0.03 °/s/√Hz; digital low-pass DLPF_CFG 0–6 with
// bandwidths 256, 188, 98, 42, 20, 10, 5 Hz.
// Model per sample, in this order: ω (°/s) + bias + white noise (σ = ρ·√(f_s/2), seeded
// std::mt19937_64) → optional first-order low-pass at the DLPF bandwidth (exact discretization
// at f_s; an approximation of the chip's filter) → saturation at ±full scale → quantization
// to round(·×sensitivity) clamped to int16 → latency of N samples → output raw/sensitivity.
// sample() is noexcept and allocation-free; the state (filter, delay line, RNG) lives inside.
#include <array>
#include <cstdint>
#include <random>

namespace clearshape::plant {

enum class GyroLowPass : std::uint8_t {
  off,      ///< no filtering (the raw 8 kHz path, ideal)
  hz256, hz188, hz98, hz42, hz20, hz10, hz5,
};
/// Bandwidth of a DLPF setting (0 for off).
double bandwidth_hz(GyroLowPass setting) noexcept;

inline constexpr int kMaxGyroLatencySamples = 64;

struct GyroscopeConfig {
  double sensitivity_lsb_per_dps = 14.375;
  double full_scale_dps = 2000.0;
  double noise_density_dps_per_rthz = 0.03;  ///< 0: no noise
  double bias_dps = 0.0;
  GyroLowPass low_pass = GyroLowPass::off;
  double sample_rate_hz = 1000.0;            ///< output data rate f_s (sample() call rate)
  int latency_samples = 0;                   ///< 0 … kMaxGyroLatencySamples
  std::uint64_t seed = 1;
  /// Throws InvalidArgument naming the field.
  void validate() const;
};

struct GyroSample {
  std::int16_t raw = 0;        ///< the chip's output word
  double rate_rad_s = 0.0;     ///< raw / sensitivity, in rad/s
  bool saturated = false;      ///< the (delayed) sample hit ±full scale or the int16 range
};

class Gyroscope {
 public:
  explicit Gyroscope(const GyroscopeConfig& config = {});
  /// One output sample for the true link rate at this instant.
  GyroSample sample(double true_rate_rad_s) noexcept;
  /// Clears the filter and delay line (to `rate_rad_s`) and reseeds the noise.
  void reset(double rate_rad_s = 0.0) noexcept;
  /// Quantization alone (no noise, filter or delay): the raw word of a rate.
  std::int16_t quantize(double rate_rad_s) const noexcept;
  double noise_std_dps() const noexcept { return noise_std_dps_; }
  const GyroscopeConfig& config() const noexcept { return config_; }

 private:
  GyroSample convert(double dps) const noexcept;  // saturation and quantization
  GyroscopeConfig config_;
  double noise_std_dps_ = 0.0;
  double filter_coefficient_ = 1.0;  // y += a (x − y)
  double filter_state_dps_ = 0.0;
  std::array<GyroSample, kMaxGyroLatencySamples + 1> delay_{};
  int head_ = 0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace clearshape::plant
