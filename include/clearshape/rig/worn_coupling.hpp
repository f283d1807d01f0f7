#pragma once
// The third built-in truth, "worn-coupling": the calibrated thesis rig (truth.hpp) whose coupling
// has worn to a play that dominates the residual vibration (docs/worn-coupling.md, issue 19).
//
//   play        total 2β = 1° (a worn keyed/set-screw coupling; allowed 0.5–2°)
//   flank       the calibrated soft linear flank of the thesis rig: thesis Eq. 4.3 with n = 1,
//               K = 45.16 N·m/rad, D = 0.1236 N·m·s/rad (link mode √(K/J)/2π = 15.1 Hz)
//   friction    the link's bearing on the shaft: Coulomb 0.01 N·m (tanh-regularized at
//               1e-3 rad/s, plant/friction.hpp) plus the thesis rig's viscous 1e-3 N·m·s/rad on
//               the relative rate — without the Coulomb torque a link that leaves its flank
//               rattles across the play for J/b ≈ 5 s
//   start       SimRig draws the link's place in the play uniformly in [−β, β] per run
//   the rest    the thesis rig's drives, link (J = 5e-3 kg·m²), encoder, gyroscope, command
//               paths, solver and run-to-run variation
#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

struct WornCoupling {
  double play_deg = 1.0;                   ///< total angular play 2β, [0.5, 2] deg
  double coulomb_n_m = 0.01;               ///< bearing Coulomb torque, [0, 0.1] N·m
  double viscous_n_m_s_per_rad = 1e-3;     ///< bearing viscous torque, [0, 0.1] N·m·s/rad
  /// Throws InvalidArgument naming the field and its range.
  void validate() const;
};

/// The worn-coupling truth (values in the header comment).
RigTruth worn_coupling_rig_truth(const WornCoupling& joint = {});

}  // namespace clearshape::rig
