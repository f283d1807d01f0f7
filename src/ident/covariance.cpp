#include "covariance.hpp"

#include <limits>

namespace clearshape::ident::detail {

Eigen::MatrixXd inverse_gram(ceres::Problem& problem, const std::vector<double*>& blocks) {
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  eo.num_threads = 1;
  ceres::CRSMatrix crs;
  double cost = 0.0;
  int cols = 0;
  for (double* b : blocks) cols += problem.ParameterBlockSize(b);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Constant(cols, cols, std::numeric_limits<double>::quiet_NaN());
  if (!problem.Evaluate(eo, &cost, nullptr, nullptr, &crs)) return nan;
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[static_cast<std::size_t>(r)]; k < crs.rows[static_cast<std::size_t>(r) + 1]; ++k)
      j(r, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
  Eigen::VectorXd scale = j.colwise().norm().transpose();
  for (Eigen::Index i = 0; i < scale.size(); ++i) {
    if (!(scale(i) > 0.0)) return nan;  // a parameter the residuals do not depend on
    scale(i) = 1.0 / scale(i);
  }
  const Eigen::MatrixXd js = j * scale.asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(js, Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  if (s.size() == 0 || !(s(s.size() - 1) > 1e-9 * s(0))) return nan;
  const Eigen::MatrixXd v = svd.matrixV();
  const Eigen::MatrixXd inv = v * s.cwiseAbs2().cwiseInverse().asDiagonal() * v.transpose();
  return scale.asDiagonal() * inv * scale.asDiagonal();
}

}  // namespace clearshape::ident::detail
