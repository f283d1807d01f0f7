#pragma once
// The arm's linearised modes at a pose (issue 24; docs/arm.md §7). With every play closed on a
// flank the links see the gearbox outputs through the flank stiffness K_i and damping C_i (the
// contact law's tangent at a small penetration, plus the bearing's viscous friction); the drives
// impose the outputs (one-way coupling, docs/design.md §1), so they do not enter the links' modes:
//   M(q) δq̈ + C δq̇ + K δq = K δθ_out,  K = diag(K_i), C = diag(C_i).
// The undamped natural frequencies are ω_k² = eig(M(q)⁻¹ K) (generalised symmetric problem
// K φ = ω² M φ, φᵀ M φ = 1); the damping ratios are the modal ones, ζ_k = φ_kᵀ C φ_k / (2 ω_k)
// (exact for classically damped systems; Inman, Engineering Vibration, ch. 4, modal damping).
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/arm.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::arm {

struct JointModeOptions {
  /// Penetration at which a non-linear contact law's tangent stiffness ∂F/∂δ is taken (rad; a
  /// linear law, n = 1, does not depend on it). > 0.
  double flank_penetration_rad = 1e-4;
  void validate() const;
};

struct ArmModes {
  Eigen::VectorXd pose_rad;                ///< q at which the arm was linearised
  Eigen::VectorXd stiffness_n_m_per_rad;   ///< K_i
  Eigen::VectorXd damping_n_m_s_per_rad;   ///< C_i
  Eigen::VectorXd natural_frequency_rad_s; ///< ω_k, ascending
  Eigen::VectorXd damping_ratio;           ///< ζ_k
  Eigen::MatrixXd shapes;                  ///< column k: φ_k, mass-normalised (φᵀMφ = 1)
  /// (k, i): the share of mode k in joint i's static response to its own gearbox output,
  /// φ_k,i² K_i / ω_k² (modal superposition; each column sums to 1).
  Eigen::MatrixXd share;
  std::vector<int> dominant_mode;          ///< per joint: the mode with the largest share
  /// The dominant mode of joint i as a shaping::Mode.
  shaping::Mode joint_mode(int joint) const;
};

/// The modes of `arm` linearised at `pose_rad` (one angle per joint). Throws InvalidArgument for
/// a wrong size, a non-finite angle, or a joint whose flank has no stiffness at the penetration.
ArmModes joint_modes(const ArmModel& arm, const Eigen::VectorXd& pose_rad, const JointModeOptions& options = {});

/// The centre of the joint ranges of the URDF (0 for a continuous joint): the pose where a
/// fixed shaper is designed.
Eigen::VectorXd workspace_centre(const ArmModel& arm);

}  // namespace clearshape::arm
