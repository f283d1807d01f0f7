#pragma once
// What the study's clearance-model tests share: the thesis's position drive under a ClearanceModel,
// and a rig truth's joint (Flores law) as a ClearanceModel.
#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::testing {

/// A position-mode ClearanceModel on the thesis's drive (Eq. 4.2, §4.2: P3UZ, Kp 0.9959,
/// Tz 0.0042, ζ 0.9968, Tw 0.0102, Tp3 0.0034) with a 5e-3 kg·m² link; the contact, the play
/// and the friction are the caller's to set.
inline study::ClearanceModel thesis_position_clearance_model() {
  study::ClearanceModel m;
  m.mode = rig::CommandMode::position;
  m.drive = lti::thesis_position_mode_model();
  m.link_inertia_kg_m2 = 5e-3;
  return m;
}

/// A rig truth's joint as a ClearanceModel (Flores law, the truth's restitution and bearing
/// friction), drive = the thesis's Eq. 4.2.
inline study::ClearanceModel flores_model_of_truth(const rig::RigTruth& t) {
  study::ClearanceModel m;
  m.mode = rig::CommandMode::position;
  m.drive = lti::thesis_position_mode_model();
  m.link_inertia_kg_m2 = t.link.inertia_kg_m2;
  m.play_rad = t.clearance_rad;
  m.stiffness = t.position_contact.stiffness;
  m.exponent = t.position_contact.exponent;
  m.contact_law = study::ContactLawChoice::flores;
  m.restitution = t.position_contact.restitution;
  m.coulomb_n_m = t.joint_friction.coulomb;
  m.viscous_n_m_s_per_rad = t.joint_friction.viscous;
  m.friction_regularization_rad_s = t.joint_friction.regularization_rate;
  return m;
}

}  // namespace clearshape::testing
