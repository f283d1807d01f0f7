#pragma once
// Exact discretization of a continuous state-space model (matrix exponential of an augmented
// matrix, Van Loan 1978, via core/linalg.hpp: Eigen unsupported MatrixFunctions), with SciPy's cont2discrete
// conventions.
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/lti/state_space.hpp"

namespace clearshape::lti {

/// How the input is reconstructed between samples.
enum class Hold {
  zoh,  ///< zero-order hold: piecewise constant
  foh,  ///< first-order (triangle) hold: piecewise linear between samples, non-causal by one sample
};

/// x[k+1] = a x[k] + b u[k], y[k] = c x[k] + d u[k].
struct DiscreteStateSpace {
  Eigen::MatrixXd a;
  Eigen::MatrixXd b;
  Eigen::MatrixXd c;
  Eigen::MatrixXd d;
  double sample_time_s = 0.0;
  Hold hold = Hold::zoh;
  Eigen::Index order() const noexcept { return a.rows(); }
};

/// ZOH: expm([A B; 0 0]·T) = [Φ Γ; 0 I] → a = Φ, b = Γ, c = C, d = D.
/// FOH (scipy.signal.cont2discrete 'foh'): M = expm([A·T B·T 0; 0 0 I; 0 0 0]);
/// a = M11, b = M12 − M13 + M11 M13, c = C, d = D + C M13. The FOH state is
/// ξ[k] = x(kT) − M13 u[k]. Throws InvalidArgument on a bad model or sample time.
DiscreteStateSpace discretize(const StateSpace& model, double sample_time_s, Hold hold = Hold::zoh);

/// The continuous model whose ZOH discretization is `model` (the inverse of discretize, as
/// MATLAB d2c 'zoh'): [A_c B_c; 0 0]·T = log [Φ Γ; 0 I] (principal matrix logarithm).
/// Throws RuntimeError when the logarithm is not real (a pole on the non-positive real axis).
StateSpace continuous_equivalent(const DiscreteStateSpace& model);

/// Runs a SISO discrete model (as scipy.signal.dlsim); `x0` empty means zero.
std::vector<double> simulate(const DiscreteStateSpace& model, std::span<const double> input,
                             const Eigen::VectorXd& x0 = {});

}  // namespace clearshape::lti
