#include "clearshape/arm/modes.hpp"

#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::arm {

void JointModeOptions::validate() const { require_positive("flank_penetration_rad", flank_penetration_rad); }

shaping::Mode ArmModes::joint_mode(int joint) const {
  if (joint < 0 || joint >= static_cast<int>(dominant_mode.size())) {
    throw_invalid("joint", joint, "0 … " + std::to_string(dominant_mode.size()) + " − 1");
  }
  const int k = dominant_mode[static_cast<std::size_t>(joint)];
  return {natural_frequency_rad_s(k), damping_ratio(k)};
}

namespace {

// K_i and C_i: the law's tangent at the flank (persistent contact: no latched approach rate)
// plus the bearing's viscous friction.
void flank_linearisation(const ArmModel& arm, double penetration_rad, ArmModes& m) {
  const int n = arm.dof();
  m.stiffness_n_m_per_rad.resize(n);
  m.damping_n_m_s_per_rad.resize(n);
  for (int i = 0; i < n; ++i) {
    const ArmJoint& j = arm.joints[static_cast<std::size_t>(i)];
    const plant::ContactForce f = j.law.evaluate(penetration_rad, 0.0, plant::ContactMemory{});
    if (!(f.d_penetration > 0.0)) {
      throw InvalidArgument("joint[" + std::to_string(i) + "] '" + j.name + "': the contact law has no stiffness at " +
                            std::to_string(penetration_rad) + " rad; allowed: a law with ∂F/∂δ > 0 there");
    }
    m.stiffness_n_m_per_rad(i) = f.d_penetration;
    m.damping_n_m_s_per_rad(i) = f.d_rate + j.friction.viscous;
  }
}

}  // namespace

ArmModes joint_modes(const ArmModel& arm, const Eigen::VectorXd& pose_rad, const JointModeOptions& options) {
  options.validate();
  const int n = arm.dof();
  if (pose_rad.size() != n) {
    throw InvalidArgument("pose_rad has " + std::to_string(pose_rad.size()) + " angles; allowed: one per joint (" +
                          std::to_string(n) + ")");
  }
  for (int i = 0; i < n; ++i) require_finite("pose_rad[" + std::to_string(i) + "]", pose_rad(i));
  ArmModes m;
  m.pose_rad = pose_rad;
  flank_linearisation(arm, options.flank_penetration_rad, m);
  ChainWorkspace ws(arm.chain);
  Eigen::MatrixXd mass;
  ws.mass_matrix(pose_rad, mass);
  const Eigen::MatrixXd k = m.stiffness_n_m_per_rad.asDiagonal();
  // K φ = ω² M φ with φᵀ M φ = 1 (Eigen normalises the eigenvectors of the generalised problem so)
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, mass);
  if (eig.info() != Eigen::Success) throw RuntimeError("joint_modes: the eigenvalue problem K φ = ω² M φ failed");
  m.natural_frequency_rad_s = eig.eigenvalues().cwiseSqrt();
  m.shapes = eig.eigenvectors();
  m.damping_ratio.resize(n);
  m.share.resize(n, n);
  const Eigen::MatrixXd c = m.damping_n_m_s_per_rad.asDiagonal();
  for (int q = 0; q < n; ++q) {
    const double w = m.natural_frequency_rad_s(q);
    m.damping_ratio(q) = m.shapes.col(q).dot(c * m.shapes.col(q)) / (2.0 * w);  // ζ = φᵀCφ/(2ω)
    for (int i = 0; i < n; ++i) m.share(q, i) = m.shapes(i, q) * m.shapes(i, q) * m.stiffness_n_m_per_rad(i) / (w * w);
  }
  m.dominant_mode.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) m.share.col(i).maxCoeff(&m.dominant_mode[static_cast<std::size_t>(i)]);
  return m;
}

Eigen::VectorXd workspace_centre(const ArmModel& arm) {
  const auto& joints = arm.chain.joints();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints.size()));
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].limited) q(static_cast<Eigen::Index>(i)) = 0.5 * (joints[i].lower_rad + joints[i].upper_rad);
  }
  return q;
}

}  // namespace clearshape::arm
