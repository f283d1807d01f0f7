// core/linalg.hpp against closed forms: e^(θJ) of the rotation generator is the rotation by θ,
// log undoes exp, the companion matrix of (s+1)(s+2)(s²+2s+5) has roots −1, −2, −1 ± 2i, and a
// symmetric matrix's eigenpairs satisfy A·v = λ·v with orthonormal vectors, and a matrix built as
// Q₁ diag(σ) Q₂ᵀ from Householder reflections has exactly the singular values σ.
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

// I − 2vvᵀ/(vᵀv): orthogonal and symmetric by construction (Golub & Van Loan §5.1.2).
Eigen::MatrixXd householder(Eigen::Index n, double phase) {
  Eigen::VectorXd v(n);
  for (Eigen::Index k = 0; k < n; ++k) v(k) = std::sin(phase * static_cast<double>(k + 1)) + 0.1;
  return Eigen::MatrixXd::Identity(n, n) - 2.0 * v * v.transpose() / v.squaredNorm();
}

TEST(Linalg, SingularValuesOfAnOrthogonallyBuiltMatrixAreTheOnesItWasBuiltWith) {
  // 40 × 30 (BDCSVD divides and conquers above 16 columns), rank 3: σ = 5, 2, 0.5, then zeros.
  const Eigen::Index m = 40, n = 30;
  Eigen::MatrixXd sigma = Eigen::MatrixXd::Zero(m, n);
  sigma(0, 0) = 5.0, sigma(1, 1) = 2.0, sigma(2, 2) = 0.5;
  const Eigen::MatrixXd a = householder(m, 0.7) * sigma * householder(n, 1.3).transpose();
  for (const SvdMethod method : {SvdMethod::jacobi, SvdMethod::divide_and_conquer}) {
    const SingularValueDecomposition d = svd(a, method, true, true);
    ASSERT_EQ(d.values.size(), n);
    EXPECT_NEAR(d.values(0), 5.0, 1e-13);
    EXPECT_NEAR(d.values(1), 2.0, 1e-13);
    EXPECT_NEAR(d.values(2), 0.5, 1e-13);
    EXPECT_LT(d.values.tail(n - 3).maxCoeff(), 1e-13);
    ASSERT_EQ(d.u.rows(), m);
    ASSERT_EQ(d.u.cols(), n);
    ASSERT_EQ(d.v.rows(), n);
    EXPECT_LT((d.u * d.values.asDiagonal() * d.v.transpose() - a).norm(), 1e-13);
    EXPECT_LT((d.v.transpose() * d.v - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-13);
    const SingularValueDecomposition values_only = svd(a, method, false, false);
    EXPECT_EQ(values_only.u.size(), 0);
    EXPECT_EQ(values_only.v.size(), 0);
    EXPECT_EQ(values_only.values, d.values);  // the factors do not change the values
  }
}

}  // namespace
}  // namespace clearshape::linalg
