#include "clearshape/rig/worn_coupling.hpp"

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::rig {

void WornCoupling::validate() const {
  require_in_closed("worn-coupling.play_deg", play_deg, 0.5, 2.0, "The worn-coupling rig is built for 0.5–2° of play");
  require_in_closed("worn-coupling.coulomb_n_m", coulomb_n_m, 0.0, 0.1);
  require_in_closed("worn-coupling.viscous_n_m_s_per_rad", viscous_n_m_s_per_rad, 0.0, 0.1);
}

RigTruth worn_coupling_rig_truth(const WornCoupling& joint) {
  joint.validate();
  RigTruth t = thesis_rig_truth();  // calibrated drives, soft linear flank, link, sensors, variation
  t.clearance_rad = deg_to_rad(joint.play_deg);
  t.joint_friction.coulomb = joint.coulomb_n_m;
  t.joint_friction.viscous = joint.viscous_n_m_s_per_rad;
  t.random_initial_play = true;
  return t;
}

}  // namespace clearshape::rig
