#pragma once
// Records of known modes for the ident tests: seeded free decays (a gyro rate after a move),
// y(t) = Σ A e^(−ζωn t) cos(ωd t + φ) + drift e^(−t/τ) + offset + noise.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/simulate.hpp"

namespace clearshape::testing {

struct TrueMode {
  double fn_hz, zeta, amplitude, phase;
};

// y(t) = Σ A e^(−ζωn t) cos(ωd t + φ) + drift e^(−t/τ) + offset + noise (gyro rate after a move).
inline UniformSeries free_decay(const std::vector<TrueMode>& modes, double dt, std::size_t n, double noise,
                         std::uint64_t seed, double offset = 0.3, double drift = 0.5, double tau = 0.4) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  UniformSeries y{0.0, dt, std::vector<double>(n)};
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    double v = offset + drift * std::exp(-t / tau);
    for (const auto& m : modes) {
      const double wn = 2 * std::numbers::pi * m.fn_hz, wd = wn * std::sqrt(1 - m.zeta * m.zeta);
      v += m.amplitude * std::exp(-m.zeta * wn * t) * std::cos(wd * t + m.phase);
    }
    y.values[k] = v + noise * nd(rng);
  }
  return y;
}

/// Two resonances ωn²/(s² + 2ζωn s + ωn²)-like in parallel, outputs weighted 100 and 300, ZOH at dt.
inline lti::DiscreteStateSpace two_resonances(double w1, double z1, double w2, double z2, double dt) {
  lti::StateSpace c;
  c.a = Eigen::MatrixXd::Zero(4, 4);
  c.a(0, 1) = 1;
  c.a(1, 0) = -w1 * w1;
  c.a(1, 1) = -2 * z1 * w1;
  c.a(2, 3) = 1;
  c.a(3, 2) = -w2 * w2;
  c.a(3, 3) = -2 * z2 * w2;
  c.b = Eigen::MatrixXd::Zero(4, 1);
  c.b(1, 0) = 1;
  c.b(3, 0) = 1;
  c.c = Eigen::MatrixXd::Zero(1, 4);
  c.c(0, 0) = 100;
  c.c(0, 2) = 300;
  c.d = Eigen::MatrixXd::Zero(1, 1);
  return lti::discretize(c, dt);
}

/// A seeded white input (2000 samples at 200 Hz) through two resonances (4 Hz ζ 0.02, 11 Hz
/// ζ 0.05; two_resonances) with white output noise of `noise` × the output's RMS.
inline ident::Experiment two_resonance_record(std::uint64_t seed, double noise) {
  const double two_pi = 2.0 * std::numbers::pi;
  const auto d = two_resonances(two_pi * 4.0, 0.02, two_pi * 11.0, 0.05, 0.005);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  std::vector<double> u(2000);
  for (auto& v : u) v = nd(rng);
  auto y = lti::simulate(d, u);
  double rms = 0.0;
  for (double v : y) rms += v * v;
  rms = std::sqrt(rms / static_cast<double>(y.size()));
  for (double& v : y) v += noise * rms * nd(rng);
  return {"io", 0.005, u, y};
}

}  // namespace clearshape::testing
