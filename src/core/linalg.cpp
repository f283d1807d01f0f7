#include "clearshape/core/linalg.hpp"

#include <Eigen/Eigenvalues>
// Eigen's MatrixFunction (behind log()) trips GCC 12's -Wnull-dereference inside Eigen itself.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <unsupported/Eigen/MatrixFunctions>
#pragma GCC diagnostic pop

namespace clearshape::linalg {

EigenDecomposition eigen(const Eigen::MatrixXd& a, bool with_vectors) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(a, with_vectors);
  EigenDecomposition out;
  out.converged = es.info() == Eigen::Success;
  out.values = es.eigenvalues();
  if (with_vectors) out.vectors = es.eigenvectors();
  return out;
}

SymmetricEigenDecomposition symmetric_eigen(const Eigen::MatrixXd& a) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(a);
  return {es.eigenvalues(), es.eigenvectors(), es.info() == Eigen::Success};
}

Eigen::MatrixXd expm(const Eigen::MatrixXd& a) { return a.exp(); }

Eigen::MatrixXd logm(const Eigen::MatrixXd& a) { return a.log(); }

}  // namespace clearshape::linalg
