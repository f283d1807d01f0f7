#pragma once
// Internal: parameter covariance (JᵀJ)⁻¹ from the Jacobian Ceres evaluates at the optimum.
// Columns are scaled to unit norm before the SVD (Ceres' own Covariance checks the condition of
// the unscaled JᵀJ, which parameters of very different magnitudes fail spuriously); a scaled
// reciprocal condition number below 1e-9 means a direction the data do not determine, and the
// covariance is then reported as NaN rather than as a pseudo-inverse that would understate it.
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>

namespace clearshape::ident::detail {

/// (JᵀJ)⁻¹ over the given parameter blocks (in that order), or a NaN matrix when rank deficient.
Eigen::MatrixXd inverse_gram(ceres::Problem& problem, const std::vector<double*>& blocks);

}  // namespace clearshape::ident::detail
