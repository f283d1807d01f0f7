#include "clearshape/core/linalg.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
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

namespace {

template <typename Decomposition>
SingularValueDecomposition factors(const Eigen::MatrixXd& a, bool with_u, bool with_v) {
  const unsigned int options = (with_u ? static_cast<unsigned int>(Eigen::ComputeThinU) : 0u) |
                               (with_v ? static_cast<unsigned int>(Eigen::ComputeThinV) : 0u);
  const Decomposition d(a, options);
  SingularValueDecomposition out;
  out.values = d.singularValues();
  if (with_u) out.u = d.matrixU();
  if (with_v) out.v = d.matrixV();
  return out;
}

}  // namespace

SingularValueDecomposition svd(const Eigen::MatrixXd& a, SvdMethod method, bool with_u, bool with_v) {
  return method == SvdMethod::jacobi ? factors<Eigen::JacobiSVD<Eigen::MatrixXd>>(a, with_u, with_v)
                                     : factors<Eigen::BDCSVD<Eigen::MatrixXd>>(a, with_u, with_v);
}

Eigen::MatrixXd expm(const Eigen::MatrixXd& a) { return a.exp(); }

Eigen::MatrixXd logm(const Eigen::MatrixXd& a) { return a.log(); }

}  // namespace clearshape::linalg
