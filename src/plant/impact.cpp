#include "clearshape/plant/impact.hpp"

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

void ImpactLaw::validate(const char* owner) const {
  const std::string p = std::string(owner) + ".impact.";
  require_in_closed(p + "restitution", restitution, 0.0, 1.0);
  require_non_negative(p + "static_rate", static_rate,
                       "approaches slower than this lock the contact; e.g. 1e-3");
}

ImpulseResult solve_impulse(const Eigen::MatrixXd& mass, const Eigen::VectorXd& normal,
                            const Eigen::VectorXd& velocity_before, double restitution) {
  const auto n = mass.rows();
  if (mass.cols() != n || normal.size() != n || velocity_before.size() != n || n == 0) {
    throw InvalidArgument("solve_impulse: mass must be n×n and normal, velocity_before of size n");
  }
  require_in_closed("restitution", restitution, 0.0, 1.0);
  const Eigen::LLT<Eigen::MatrixXd> llt(mass);
  if (llt.info() != Eigen::Success) {
    throw InvalidArgument("solve_impulse: the mass matrix is not symmetric positive definite");
  }
  const Eigen::VectorXd minv_w = llt.solve(normal);
  const double w_minv_w = normal.dot(minv_w);
  if (!(w_minv_w > 0.0)) throw InvalidArgument("solve_impulse: the normal vector is zero");
  ImpulseResult out;
  // Eq. 2.15 by the Schur complement: P_N = −(1+e) wᵀu⁻ / (wᵀM⁻¹w); u⁺ = u⁻ + M⁻¹w P_N
  out.impulse = -(1.0 + restitution) * normal.dot(velocity_before) / w_minv_w;
  out.velocity_after = velocity_before + minv_w * out.impulse;
  return out;
}

double peak_contact_force(double stiffness, double exponent, double effective_mass,
                          double impulse) {
  require_positive("stiffness", stiffness);
  require_in_closed("exponent", exponent, 1.0, 10.0);
  require_positive("effective_mass", effective_mass);
  require_finite("impulse", impulse);
  // thesis Eq. 2.16
  return std::pow((exponent + 1.0) / 2.0 * std::pow(stiffness, 1.0 / exponent) / effective_mass *
                      impulse * impulse,
                  exponent / (exponent + 1.0));
}

}  // namespace clearshape::plant
