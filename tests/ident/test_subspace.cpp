// Subspace identification on noise-free data from known discrete systems: N4SID/MOESP must return
// the exact poles and input/output behaviour, ERA the exact poles of a free response, and the
// continuous equivalent must invert lti::discretize. Tolerances 1e-8 (rounding in QR/SVD of
// Hankel matrices whose condition is ~1e3).
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/ident/subspace.hpp"
#include "clearshape/lti/discretize.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;

namespace {

lti::DiscreteStateSpace two_mode_system() {
  lti::DiscreteStateSpace m;
  const double r1 = 0.995, t1 = 0.37, r2 = 0.99, t2 = 0.8;
  m.a.resize(4, 4);
  m.a << r1 * std::cos(t1), -r1 * std::sin(t1), 0, 0, r1 * std::sin(t1), r1 * std::cos(t1), 0, 0, 0, 0,
      r2 * std::cos(t2), -r2 * std::sin(t2), 0, 0, r2 * std::sin(t2), r2 * std::cos(t2);
  m.b.resize(4, 1);
  m.b << 0, 1, 0, 1;
  m.c.resize(1, 4);
  m.c << 1, 0.5, -0.3, 0.8;
  m.d = Eigen::MatrixXd::Constant(1, 1, 0.2);
  m.sample_time_s = 0.01;
  return m;
}

std::vector<std::complex<double>> sorted_eigenvalues(const Eigen::MatrixXd& a) {
  const Eigen::VectorXcd eigenvalues = clearshape::linalg::eigen(a).values;  // Eigen's EigenSolver, compiled once
  std::vector<std::complex<double>> z;
  for (Eigen::Index k = 0; k < eigenvalues.size(); ++k) z.push_back(eigenvalues(k));
  std::sort(z.begin(), z.end(), [](auto p, auto q) { return p.real() != q.real() ? p.real() < q.real() : p.imag() < q.imag(); });
  return z;
}

}  // namespace

TEST(Subspace, ExactPolesAndResponseFromNoiseFreeData) {
  const auto truth = two_mode_system();
  std::mt19937_64 rng(1);
  std::normal_distribution<double> nd;
  std::vector<double> u(800);
  for (auto& v : u) v = nd(rng);
  // Start from a non-zero state: x0 must be estimated too.
  Eigen::VectorXd x0(4);
  x0 << 1.0, -0.5, 0.2, 0.3;
  const auto y = lti::simulate(truth, u, x0);
  const ident::Experiment e{"random", 0.01, u, y};
  for (const auto method : {ident::SubspaceMethod::moesp, ident::SubspaceMethod::n4sid}) {
    ident::SubspaceOptions o;
    o.method = method;
    const auto s = ident::n4sid(e, 4, o);
    const auto z = sorted_eigenvalues(s.model.a), zt = sorted_eigenvalues(truth.a);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_LT(std::abs(z[k] - zt[k]), 1e-8);
    const auto ys = lti::simulate(s.model, u, s.initial_state);
    for (std::size_t k = 0; k < y.size(); ++k) ASSERT_NEAR(ys[k], y[k], 1e-7 * (1.0 + std::abs(y[k])));
    EXPECT_NEAR(s.model.d(0, 0), 0.2, 1e-8);
    EXPECT_GT(s.singular_values[3], 1e6 * s.singular_values[4]) << "a clear gap after the true order";
  }
}

TEST(Subspace, EraRecoversTheModesOfAFreeResponse) {
  const auto truth = two_mode_system();
  Eigen::VectorXd x0(4);
  x0 << 1.0, 0.0, 0.5, -0.2;
  const auto y = lti::simulate(truth, std::vector<double>(400, 0.0), x0);
  const auto m = ident::era(y, 4);
  const auto z = sorted_eigenvalues(m.a), zt = sorted_eigenvalues(truth.a);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_LT(std::abs(z[k] - zt[k]), 1e-9);
  // The balanced realization reproduces the response: y[k] = C Aᵏ x0.
  Eigen::VectorXd x = m.x0;
  for (std::size_t k = 0; k < y.size(); ++k) {
    ASSERT_NEAR((m.c * x)(0), y[k], 1e-9);
    x = m.a * x;
  }
}

TEST(Subspace, RejectsTooShortRecords) {
  const ident::Experiment e{"short", 1.0, std::vector<double>(30, 1.0), std::vector<double>(30, 2.0)};
  EXPECT_THROW(ident::n4sid(e, 4), clearshape::InvalidArgument);
  EXPECT_THROW(ident::era(std::vector<double>(10, 1.0), 4), clearshape::InvalidArgument);
}
