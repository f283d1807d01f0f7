#pragma once
// Continuous-time state-space model ẋ = A x + B u, y = C x + D u (single input, single output
// unless stated). The lti module builds these from transfer functions and process models.
#include <Eigen/Dense>

namespace clearshape::lti {

struct StateSpace {
  Eigen::MatrixXd a;  ///< n×n
  Eigen::MatrixXd b;  ///< n×m
  Eigen::MatrixXd c;  ///< p×n
  Eigen::MatrixXd d;  ///< p×m
  Eigen::Index order() const noexcept { return a.rows(); }
};

}  // namespace clearshape::lti
