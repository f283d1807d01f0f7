#include "clearshape/plant/joint.hpp"

#include <cmath>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

double Link::in_plane_weight_n() const noexcept {
  return mass_kg * gravity_m_s2 * std::sin(axis_tilt_rad);
}

void Link::validate() const {
  require_positive("link.inertia_kg_m2", inertia_kg_m2,
                   "give the link's moment of inertia about the joint axis");
  require_non_negative("link.mass_kg", mass_kg);
  require_non_negative("link.com_distance_m", com_distance_m);
  require_in_closed("link.axis_tilt_rad", axis_tilt_rad, -3.2, 3.2,
                    "0 = vertical axis (no gravity torque), pi/2 = horizontal axis");
  require_non_negative("link.gravity_m_s2", gravity_m_s2);
  require_non_negative("link.ground_viscous_n_m_s_per_rad", ground_viscous_n_m_s_per_rad);
  require_finite("link.external_torque_n_m", external_torque_n_m);
  if (mass_kg * com_distance_m * com_distance_m > inertia_kg_m2 * (1.0 + 1e-12)) {
    throw_invalid("link.inertia_kg_m2", inertia_kg_m2,
                  ">= mass_kg * com_distance_m^2 (parallel-axis theorem)",
                  "the inertia about the joint axis includes m·r_c²; increase it or reduce r_c");
  }
}

void TorsionalClearance::validate() const {
  require_non_negative("joint.half_play_rad", half_play_rad,
                       "the play is ±beta; 0 gives a joint without clearance");
  joint_friction.validate("joint.joint_friction");
  if (impact) impact->validate("joint");
}

void PlanarClearance::validate() const {
  require_positive("joint.radial_clearance_m", radial_clearance_m,
                   "c = R_B − R_J must be > 0 (e.g. 1e-4 m)");
  require_positive("joint.journal_radius_m", journal_radius_m);
  friction.validate("joint.friction");
  if (impact) impact->validate("joint");
}

void PlantModel::validate() const {
  link.validate();
  std::visit([](const auto& j) { j.validate(); }, joint);
  if (std::holds_alternative<PlanarClearance>(joint) && !(link.mass_kg > 0.0)) {
    throw_invalid("link.mass_kg", link.mass_kg, "> 0 for the planar clearance joint",
                  "the journal-in-bearing model translates the link: give its mass");
  }
}

}  // namespace clearshape::plant
