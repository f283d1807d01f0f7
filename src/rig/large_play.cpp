#include "clearshape/rig/large_play.hpp"

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::rig {

double PinInBore::radial_clearance_m() const noexcept {
  return 0.5 * deg_to_rad(play_deg) * lever_arm_m;  // arc = angle × radius, half the play each side
}

double PinInBore::linear_stiffness() const {
  const double r_star = plant::effective_radius_internal(pin_radius_m, bore_radius_m());  // Eq. 2.6, internal
  return plant::hertz_stiffness_thesis(plant::compliance_parameter(pin), plant::compliance_parameter(link),
                                       r_star);  // Eq. 2.5
}

double PinInBore::torsional_stiffness() const {
  return plant::torsional_stiffness(linear_stiffness(), 1.5, lever_arm_m);  // F at radius r: K r^(n+1)
}

void PinInBore::validate() const {
  require_in_closed("large-play.play_deg", play_deg, 0.5, 2.0, "The large-play rig is built for 0.5–2° of play");
  require_in_closed("large-play.pin_radius_m", pin_radius_m, 1e-3, 10e-3);
  require_in_closed("large-play.lever_arm_m", lever_arm_m, 5e-3, 0.1);
  require_in_closed("large-play.restitution", restitution, 0.4, 0.8, "Metal pairs at low speed: 0.4–0.8");
  require_non_negative("large-play.bearing_coulomb_n_m", bearing_coulomb_n_m);
  require_non_negative("large-play.bearing_viscous_n_m_s_per_rad", bearing_viscous_n_m_s_per_rad);
  if (!(lever_arm_m > bore_radius_m())) {
    throw_invalid("large-play.lever_arm_m", lever_arm_m, "> the bore radius", "The bore must not reach the shaft axis");
  }
}

RigTruth large_play_rig_truth(const PinInBore& joint) {
  joint.validate();
  RigTruth t = thesis_rig_truth();  // the thesis's drives, link, sensors, paths, solver, variation
  t.clearance_rad = deg_to_rad(joint.play_deg);
  ContactSpec contact;
  contact.model = ContactModel::flores;
  contact.stiffness = joint.torsional_stiffness();
  contact.exponent = 1.5;  // Hertz point contact (thesis Eq. 2.5)
  contact.damping = 0.0;
  contact.restitution = joint.restitution;
  t.position_contact = contact;
  t.speed_contact = contact;  // one joint
  t.joint_friction = plant::Friction{};
  t.joint_friction.coulomb = joint.bearing_coulomb_n_m;
  t.joint_friction.viscous = joint.bearing_viscous_n_m_s_per_rad;
  t.variation.flank_damping_rel_sigma = 0.0;  // the Flores law has no dashpot D to vary
  return t;
}

}  // namespace clearshape::rig
