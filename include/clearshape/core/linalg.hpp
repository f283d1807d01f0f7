#pragma once
// Dense decompositions compiled once (src/core/linalg.cpp) for every module that needs them.
// Eigen's EigenSolver and MatrixFunctions are heavy templates: each file that instantiated them
// spent 6–11 s compiling them again (docs/design.md, "Build time"). These are thin wrappers around
// the same Eigen algorithms, so results are bit-for-bit those of calling Eigen directly.
//
//   const linalg::EigenDecomposition eig = linalg::eigen(a);   // values only
//   const Eigen::MatrixXd phi = linalg::expm(a * h);      // e^(Ah)
//   const linalg::SingularValueDecomposition d = linalg::svd(h, linalg::SvdMethod::divide_and_conquer, true, true);
#include <Eigen/Core>

namespace clearshape::linalg {

/// Eigenvalues (and, when asked, eigenvectors, columns in the values' order) of a real square
/// matrix: Eigen::EigenSolver — Hessenberg reduction and the Francis double-shift QR to the real
/// Schur form (Golub & Van Loan, Matrix Computations, 4th ed., §7.5).
struct EigenDecomposition {
  Eigen::VectorXcd values;
  Eigen::MatrixXcd vectors;  ///< empty unless asked for
  bool converged = false;    ///< Eigen::Success
};
EigenDecomposition eigen(const Eigen::MatrixXd& a, bool with_vectors = false);

/// Eigenvalues (ascending) and orthonormal eigenvectors of a symmetric matrix (only its lower
/// triangle is read): Eigen::SelfAdjointEigenSolver — tridiagonalisation and the implicit
/// symmetric QR step (Golub & Van Loan §8.3).
struct SymmetricEigenDecomposition {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  bool converged = false;  ///< Eigen::Success
};
SymmetricEigenDecomposition symmetric_eigen(const Eigen::MatrixXd& a);

/// The thin singular value decomposition a = U diag(σ) Vᵀ, σ descending; U and V only when asked.
/// `jacobi`: two-sided Jacobi rotations after a column-pivoting QR (Eigen::JacobiSVD; Demmel &
/// Veselić 1992), accurate to the small singular values; `divide_and_conquer`: bidiagonalisation
/// and Gu & Eisenstat's divide and conquer (Eigen::BDCSVD; Gu & Eisenstat 1995), for large matrices.
enum class SvdMethod { jacobi, divide_and_conquer };
struct SingularValueDecomposition {
  Eigen::VectorXd values;
  Eigen::MatrixXd u;  ///< m × min(m, n); empty unless asked for
  Eigen::MatrixXd v;  ///< n × min(m, n); empty unless asked for
};
SingularValueDecomposition svd(const Eigen::MatrixXd& a, SvdMethod method, bool with_u, bool with_v);

/// e^A by Padé approximation with scaling and squaring (Higham 2005), Eigen's MatrixFunctions.
Eigen::MatrixXd expm(const Eigen::MatrixXd& a);

/// The principal logarithm log(A) by inverse scaling and squaring (Higham & Al-Mohy 2012),
/// Eigen's MatrixFunctions. A must have no eigenvalue on the closed negative real axis.
Eigen::MatrixXd logm(const Eigen::MatrixXd& a);

}  // namespace clearshape::linalg
