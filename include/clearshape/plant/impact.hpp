#pragma once
// Discontinuous (impulse–momentum) impact with restitution (thesis Eq. 2.13–2.16;
// docs/design.md §5): at the contact instant the normal velocity w·u is reversed
// and scaled by e, with the impulse P_N = −(1+e)·wᵀu⁻/(wᵀM⁻¹w). Approaches slower than
// `static_rate` do not bounce but enter persistent contact (no Zeno chattering).
#include <Eigen/Dense>

namespace clearshape::plant {

struct ImpactLaw {
  double restitution = 0.5;   ///< e in [0, 1]
  double static_rate = 1e-3;  ///< v_static (rad/s or m/s): slower approaches stick
  void validate(const char* owner) const;
};

struct ImpulseResult {
  Eigen::VectorXd velocity_after;  ///< u⁺
  double impulse = 0.0;            ///< s_N = P_N (Eq. 2.14)
};

/// Eq. 2.15 solved by the Schur complement: u⁺ = u⁻ + M⁻¹w·P_N with P_N as above, so that
/// wᵀu⁺ = −e·wᵀu⁻ and M u⁺ − M u⁻ = w·P_N (Eq. 2.13). M symmetric positive definite.
ImpulseResult solve_impulse(const Eigen::MatrixXd& mass, const Eigen::VectorXd& normal,
                            const Eigen::VectorXd& velocity_before, double restitution);

/// Thesis Eq. 2.16: peak contact force of an undamped F = Kδⁿ impact that absorbs the impulse
/// s_N = m_e·v₀: F_max = ((n+1)/2 · K^(1/n)/m_e · s_N²)^(n/(n+1)).
double peak_contact_force(double stiffness, double exponent, double effective_mass,
                          double impulse);

}  // namespace clearshape::plant
