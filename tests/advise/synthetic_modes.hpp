#pragma once
// Seeded synthetic records with known modes for the advise tests: the rate response of modes
// x'' + 2ζω x' + ω² x = u driven by one white input u (held over each sample), discretised
// exactly (zero-order hold, Van Loan's matrix exponential).
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/core/linalg.hpp"
#include "clearshape/core/series.hpp"
#include "clearshape/core/units.hpp"

namespace advise_test {

struct Line {
  double f_hz, zeta, gain;
};

/// y = Σ gain·ẋ of each line, all driven by one white input (seeded).
inline clearshape::UniformSeries rate_response(const std::vector<Line>& lines, double fs_hz, std::size_t n, std::uint64_t seed) {
  clearshape::UniformSeries y{0.0, 1.0 / fs_hz, std::vector<double>(n, 0.0)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> u(n);
  for (double& v : u) v = noise(rng);
  for (const Line& line : lines) {
    const double w = clearshape::kTwoPi * line.f_hz, dt = 1.0 / fs_hz, zeta = line.zeta;
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();  // [A B; 0 0] → exp gives [Ad Bd; 0 I] (Van Loan)
    m(0, 1) = 1.0;
    m(1, 0) = -w * w;
    m(1, 2) = 1.0;
    m(1, 1) = -2.0 * zeta * w;
    const Eigen::Matrix3d e = clearshape::linalg::expm(m * dt);  // MatrixFunctions, compiled once in core
    Eigen::Vector2d x = Eigen::Vector2d::Zero();
    for (std::size_t k = 0; k < n; ++k) {
      y.values[k] += line.gain * x(1);
      x = e.topLeftCorner<2, 2>() * x + e.topRightCorner<2, 1>() * u[k];
    }
  }
  return y;
}

/// Seeded white Gaussian noise of unit variance: a record without any resonance.
inline clearshape::UniformSeries white_noise(double fs_hz, std::size_t n, std::uint64_t seed) {
  clearshape::UniformSeries y{0.0, 1.0 / fs_hz, std::vector<double>(n, 0.0)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (double& v : y.values) v = noise(rng);
  return y;
}

}  // namespace advise_test
