#pragma once
// Synthetic identification data for the ident tests: exact ZOH simulations of known models
// (lti::simulate) with seeded white noise.
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "clearshape/ident/experiment.hpp"
#include "clearshape/lti/simulate.hpp"

namespace clearshape::testing {

inline std::vector<double> step_input(std::size_t n, double amplitude = 1.0) { return std::vector<double>(n, amplitude); }

inline std::vector<double> ramp_input(std::size_t n, double dt, double slope) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = slope * static_cast<double>(k) * dt;
  return u;
}

inline std::vector<double> sine_input(std::size_t n, double dt, double amplitude, double frequency_hz) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = amplitude * std::sin(2.0 * 3.141592653589793 * frequency_hz * static_cast<double>(k) * dt);
  return u;
}

/// Random binary signal ±amplitude, switching with probability ½ every `hold` samples.
inline std::vector<double> prbs_input(std::size_t n, std::size_t hold, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> u(n);
  double level = amplitude;
  for (std::size_t k = 0; k < n; ++k) {
    if (k % hold == 0 && (rng() & 1U)) level = -level;
    u[k] = level;
  }
  return u;
}

inline double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

/// y += v with stationary AR(1) noise v[k+1] = ρ v[k] + w[k] (seeded) of RMS `noise` × RMS(y).
inline void add_ar1_noise(std::vector<double>& y, std::uint64_t seed, double rho, double noise) {
  const double sd = noise * rms(y);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  double v = sd * nd(rng);
  for (double& x : y) {
    x += v;
    v = rho * v + sd * std::sqrt(1.0 - rho * rho) * nd(rng);
  }
}

/// y = model(u) + noise·RMS(model(u))·N(0, 1) (seeded).
inline ident::Experiment make_data(const lti::ProcessModel& model, const std::vector<double>& u, double dt,
                                   double noise, std::uint64_t seed, std::string name = "data") {
  const auto y = lti::simulate(model, UniformSeries{0.0, dt, u});
  ident::Experiment e{std::move(name), dt, u, y.values};
  if (noise > 0.0) {
    const double s = noise * rms(y.values);
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    for (double& v : e.output) v += s * nd(rng);
  }
  return e;
}

}  // namespace clearshape::testing
