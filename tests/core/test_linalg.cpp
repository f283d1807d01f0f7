// core/linalg.hpp against closed forms: e^(θJ) of the rotation generator is the rotation by θ,
// log undoes exp, the companion matrix of (s+1)(s+2)(s²+2s+5) has roots −1, −2, −1 ± 2i, and a
// symmetric matrix's eigenpairs satisfy A·v = λ·v with orthonormal vectors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <utility>
#include <vector>

#include "clearshape/core/linalg.hpp"

namespace clearshape::linalg {
namespace {

TEST(Linalg, ExpOfTheRotationGeneratorIsTheRotation) {
  const double theta = 0.7;
  Eigen::MatrixXd j(2, 2);
  j << 0.0, -theta, theta, 0.0;
  const Eigen::MatrixXd r = expm(j);
  EXPECT_NEAR(r(0, 0), std::cos(theta), 1e-15);
  EXPECT_NEAR(r(0, 1), -std::sin(theta), 1e-15);
  EXPECT_NEAR(r(1, 0), std::sin(theta), 1e-15);
  EXPECT_NEAR(r(1, 1), std::cos(theta), 1e-15);
  EXPECT_LT((logm(r) - j).norm(), 1e-14);
}

TEST(Linalg, EigenvaluesOfACompanionMatrixAreThePolynomialsRoots) {
  // (s+1)(s+2)(s²+2s+5) = s⁴ + 5s³ + 13s² + 19s + 10
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(4, 4);
  c.row(0) << -5.0, -13.0, -19.0, -10.0;
  c(1, 0) = c(2, 1) = c(3, 2) = 1.0;
  const EigenDecomposition e = eigen(c, true);
  ASSERT_TRUE(e.converged);
  std::vector<std::complex<double>> roots(e.values.data(), e.values.data() + 4);
  const auto key = [](std::complex<double> z) { return std::make_pair(std::round(z.real() * 1e6), z.imag()); };
  std::sort(roots.begin(), roots.end(), [&](auto a, auto b) { return key(a) < key(b); });
  const std::vector<std::complex<double>> want{{-2.0, 0.0}, {-1.0, -2.0}, {-1.0, 0.0}, {-1.0, 2.0}};
  for (std::size_t k = 0; k < 4; ++k) EXPECT_LT(std::abs(roots[k] - want[k]), 1e-12) << k;
  for (Eigen::Index k = 0; k < 4; ++k) {  // C·v = λ·v
    EXPECT_LT((c.cast<std::complex<double>>() * e.vectors.col(k) - e.values(k) * e.vectors.col(k)).norm(), 1e-12);
  }
  EXPECT_EQ(eigen(c).vectors.size(), 0);
}

TEST(Linalg, SymmetricEigenpairsAreOrthonormalAndAscending) {
  Eigen::MatrixXd a(3, 3);
  a << 4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 1.0;
  const SymmetricEigenDecomposition e = symmetric_eigen(a);
  ASSERT_TRUE(e.converged);
  EXPECT_LT(e.values(0), e.values(1));
  EXPECT_LT(e.values(1), e.values(2));
  EXPECT_NEAR(e.values.sum(), a.trace(), 1e-13);
  EXPECT_LT((a * e.vectors - e.vectors * e.values.asDiagonal()).norm(), 1e-13);
  EXPECT_LT((e.vectors.transpose() * e.vectors - Eigen::MatrixXd::Identity(3, 3)).norm(), 1e-14);
}

}  // namespace
}  // namespace clearshape::linalg
