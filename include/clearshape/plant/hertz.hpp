#pragma once
// Hertz contact stiffness from materials and geometry (thesis Eq. 2.5–2.6;
// docs/design.md §5), and conversion of a linear contact law to the torsional
// play of a shaft (force at a radius r).
namespace clearshape::plant {

struct Material {
  double youngs_modulus_pa = 207e9;  ///< E
  double poisson_ratio = 0.3;        ///< ν
  /// Steel as in the clearance literature (E = 207 GPa, ν = 0.3).
  static Material steel() noexcept { return {}; }
};

/// R* = R₁R₂/(R₁+R₂): two convex bodies in external contact (thesis Eq. 2.6).
double effective_radius_external(double radius_1_m, double radius_2_m);
/// R* = R_J·R_B/(R_B − R_J): a journal inside a bearing (internal contact, concave bearing).
/// Not R_J·R_B/(R_J + R_B) — that common bug overestimates the curvature (clearance_sim §6.7).
/// Requires 0 < R_J < R_B.
double effective_radius_internal(double journal_radius_m, double bearing_radius_m);
/// E* from 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂.
double effective_modulus_pa(const Material& a, const Material& b);
/// h = (1−ν²)/(πE) (thesis Eq. 2.6).
double compliance_parameter(const Material& m);
/// K = (4/3) E* √R* in N/m^1.5 (Hertz point contact).
double hertz_stiffness(const Material& a, const Material& b, double effective_radius_m);
/// K = 4/(3π(h₁+h₂)) √R (thesis Eq. 2.5); equals hertz_stiffness() identically.
double hertz_stiffness_thesis(double h1, double h2, double effective_radius_m);

/// A law F = K_lin·δ_linⁿ acting at radius r gives the torque τ = r·F with δ_lin = r·δ_ang,
/// so K_ang = K_lin·r^(n+1) in N·m/rad^n (clearance_sim §3.1).
double torsional_stiffness(double linear_stiffness, double exponent, double radius_m);
/// A dashpot D_lin (N·s/m) at radius r: D_ang = D_lin·r² in N·m·s/rad.
double torsional_damping(double linear_damping, double radius_m);

}  // namespace clearshape::plant
