#pragma once
// Sensor configuration shared by SimRig and simulate_run (internal header).
#include <cstdint>

#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/rig/truth.hpp"

namespace clearshape::rig::detail {

/// SplitMix64 (Steele, Lea & Flood 2014): derives independent seeds from one user seed.
constexpr std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t stream) noexcept {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

inline plant::GyroscopeConfig gyro_config(const RigTruth& truth, double sample_rate_hz,
                                          std::uint64_t seed, bool noise) {
  plant::GyroscopeConfig config = truth.gyro;
  config.sample_rate_hz = sample_rate_hz;
  config.seed = mix_seed(seed, 0);
  if (!noise) config.noise_density_dps_per_rthz = 0.0;
  return config;
}

}  // namespace clearshape::rig::detail
