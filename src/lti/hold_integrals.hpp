#pragma once
// Internal: exact integrals over one hold interval, shared by discretize.cpp and simulate.cpp.
#include <Eigen/Dense>

namespace clearshape::lti::detail {

/// For ẋ = A x + b u over [0, h] with u linear from ua to ub:
/// x(h) = Φ x(0) + (Γ − Λ) ua + Λ ub, where, from expm([A·h b·h 0; 0 0 1; 0 0 0]) (Van Loan 1978):
/// Φ = e^(Ah), Γ = ∫₀ʰ e^(A(h−σ)) b dσ, Λ = (1/h) ∫₀ʰ e^(A(h−σ)) b σ dσ. ZOH (ua = ub): Γ u.
struct HoldIntegrals {
  Eigen::MatrixXd phi;     ///< n×n
  Eigen::MatrixXd gamma;   ///< n×m
  Eigen::MatrixXd lambda;  ///< n×m
};
HoldIntegrals hold_integrals(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double h);

}  // namespace clearshape::lti::detail
