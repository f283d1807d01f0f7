#pragma once
// The second built-in truth, "large-play": the thesis's drive, command paths and sensors with a
// joint whose clearance is large enough to dominate the residual vibration (docs/large-play.md).
//
// The joint: a steel driver pin, fixed in a hub on the motor shaft at lever arm r from the
// axis, sits in a bore of the (aluminium) link. The link's hub turns on the shaft in a ball
// bearing; the pin is its only drive. A total angular play 2β needs a radial clearance
// c = β·r between pin (radius R_J) and bore (R_B = R_J + c).
//   stiffness   Hertz point contact, n = 1.5 (thesis Eq. 2.5–2.6): K = 4/(3π(h₁+h₂))·√R*,
//               h = (1−ν²)/(πE), R* = R_J·R_B/(R_B − R_J) (internal contact); at the pin's
//               radius r the torsional law is K_ang = K·r^(n+1) in N·m/rad^1.5 (hertz.hpp)
//   dissipation Flores et al. (2011) hysteresis law F = K δⁿ (1 + 8(1−e)/(5e)·δ̇/δ̇⁻),
//               restitution e (default 0.6; metal pairs at a few cm/s: 0.4–0.8)
//   friction    the link's bearing on the shaft: Coulomb 2e-3 N·m, viscous 1e-4 N·m·s/rad on
//               the relative rate (a small deep-groove ball bearing, light load)
//   the rest    the calibrated thesis rig's drives, link inertia, encoder, gyroscope, command
//               paths, solver and run-to-run variation (truth.hpp), except the flank-damping
//               σ (the Flores law has no D to vary)
#include "clearshape/plant/hertz.hpp"
#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

/// The aluminium alloy 6061-T6 of the link: E = 68.9 GPa, ν = 0.33 (ASM Aerospace Specification
/// Metals data sheet for 6061-T6).
inline plant::Material aluminium_6061() noexcept { return {68.9e9, 0.33}; }

struct PinInBore {
  double play_deg = 1.0;           ///< total angular play 2β, [0.5, 2] deg
  double pin_radius_m = 3e-3;      ///< R_J: a 6 mm steel dowel pin, [1e-3, 10e-3] m
  double lever_arm_m = 0.02;       ///< r: pin axis to shaft axis, [5e-3, 0.1] m
  plant::Material pin = plant::Material::steel();
  plant::Material link = aluminium_6061();
  double restitution = 0.6;        ///< e, [0.4, 0.8]
  double bearing_coulomb_n_m = 2e-3;
  double bearing_viscous_n_m_s_per_rad = 1e-4;

  /// c = β·r (m): the pin's free travel to either side, radially in the bore.
  double radial_clearance_m() const noexcept;
  double bore_radius_m() const noexcept { return pin_radius_m + radial_clearance_m(); }
  /// K of the pin–bore contact, N/m^1.5 (thesis Eq. 2.5 with Eq. 2.6 and the internal R*).
  double linear_stiffness() const;
  /// K_ang = K·r^2.5, N·m/rad^1.5: the law of the torsional play.
  double torsional_stiffness() const;
  /// Throws InvalidArgument naming the field and its range.
  void validate() const;
};

/// The large-play truth for a pin joint (values in the header comment and docs/large-play.md).
RigTruth large_play_rig_truth(const PinInBore& joint = {});

}  // namespace clearshape::rig
