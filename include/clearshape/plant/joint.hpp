#pragma once
// The plant: a drive (imposed motor motion) and a link joined to the motor shaft through a
// joint with clearance (docs/design.md §2, thesis §2.3). Two joint models behind one interface:
//   TorsionalClearance: 1-D angular play ±β between shaft and link (the primary model).
//     φ = θ_link − θ_motor, penetration δ = |φ| − β when |φ| > β, δ̇ = sign(φ)·φ̇;
//     the contact torque −sign(φ)·F(δ, δ̇) acts on the link (its reaction on the motor is
//     absorbed by the servo loop: one-way coupling).
//   PlanarClearance: journal (the motor shaft, centre fixed, radius R_J) in the link's bearing
//     bore (radius R_B = R_J + c). The link's pivot (bearing centre) translates by p = (x, y)
//     (thesis Eq. 2.1: g_n = c − ‖p‖, 2 extra DOF); normal law along n = −p/‖p‖ plus Coulomb
//     friction (Eq. 2.9) on the slip v_T = ω_m R_J − ṗ·t − ω_l R_B, t = k × n. Without a key the
//     shaft turns the link only through friction.
#include <optional>
#include <variant>

#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/friction.hpp"
#include "clearshape/plant/impact.hpp"

namespace clearshape::plant {

inline constexpr double kStandardGravity_m_s2 = 9.80665;

/// The link (rigid body turning about the joint axis).
struct Link {
  double inertia_kg_m2 = 1e-3;      ///< J about the joint axis (bearing centre)
  double mass_kg = 0.0;             ///< m (gravity; planar translation). 0: no gravity
  double com_distance_m = 0.0;      ///< r_c, centre of mass from the joint axis
  /// Angle between the rotation axis and the vertical: 0 = vertical axis (link turns in a
  /// horizontal plane, no gravity torque), π/2 = horizontal axis. θ_link = 0 is the link
  /// horizontal in the plane of rotation; gravity torque τ_g = −m g sin(tilt) r_c cos θ_link.
  double axis_tilt_rad = 0.0;
  double gravity_m_s2 = kStandardGravity_m_s2;
  /// Viscous drag relative to the ground (N·m·s/rad), e.g. air and sensor cable.
  double ground_viscous_n_m_s_per_rad = 0.0;
  /// External constant torque on the link (N·m), e.g. a static load for tests.
  double external_torque_n_m = 0.0;

  /// m·g·sin(tilt): the in-plane gravity force (N).
  double in_plane_weight_n() const noexcept;
  void validate() const;
};

struct TorsionalClearance {
  double half_play_rad = 1e-3;     ///< β: the link turns freely for |φ| ≤ β
  ContactLaw law = ContactLaw::hertz_dashpot(1e4, 1.5, 300.0, DampingPolicy::clamped);
  /// Friction in the joint on the relative rate φ̇ (N·m, N·m·s/rad, rad/s).
  Friction joint_friction{};
  /// If set, impacts are impulses (Eq. 2.13–2.15) and approaches slower than static_rate lock
  /// the link to the shaft at the stop until the constraint torque would pull; `law` is unused.
  std::optional<ImpactLaw> impact{};
  void validate() const;
};

struct PlanarClearance {
  double radial_clearance_m = 1e-4;  ///< c = R_B − R_J
  double journal_radius_m = 5e-3;    ///< R_J (motor shaft)
  ContactLaw law = ContactLaw::hysteresis(Hysteresis::flores, 1e10, 1.5, 0.8);
  CoulombContactFriction friction{};  ///< Eq. 2.9 at the contact point
  /// If set, impacts faster than static_rate are frictionless impulses (Eq. 2.13–2.15);
  /// slower contacts use `law` (persistent contact).
  std::optional<ImpactLaw> impact{};
  double bearing_radius_m() const noexcept { return journal_radius_m + radial_clearance_m; }
  void validate() const;
};

using ClearanceJoint = std::variant<TorsionalClearance, PlanarClearance>;

struct PlantModel {
  DriveModel drive = DriveModel::first_order_position(0.01);
  Link link{};
  ClearanceJoint joint = TorsionalClearance{};
  /// Throws InvalidArgument naming the offending field (e.g. "link.mass_kg").
  void validate() const;
};

/// Initial state of the link relative to the shaft; the drive starts at rest for the command
/// value at t = 0 (DriveModel::rest_state) unless `drive_state` is given.
struct InitialState {
  double relative_angle_rad = 0.0;   ///< φ(0) = θ_link − θ_motor
  double link_rate_rad_s = 0.0;      ///< ω_link(0)
  double pivot_x_m = 0.0;            ///< planar: p(0)
  double pivot_y_m = 0.0;
  double pivot_vx_m_s = 0.0;         ///< planar: ṗ(0)
  double pivot_vy_m_s = 0.0;
  double motor_angle_offset_rad = 0.0;  ///< speed mode: initial motor angle
  std::optional<Eigen::VectorXd> drive_state{};
};

}  // namespace clearshape::plant
