#pragma once
// Friction torque (or force) as a smooth function of the sliding rate v: viscous + regularized
// Coulomb with an optional Stribeck peak (docs/design.md §5):
//   τ(v) = −b·v − [F_c + (F_s − F_c)·exp(−(v/v_S)²)]·tanh(v/v_t)
// v_t is the regularization scale: |v| ≫ v_t slides at the full Coulomb level; the tanh adds
// a stiffness of order F_c/v_t to the ODE (choose v_t ≈ 1e-4…1e-3 of the typical rate).
// Units follow the joint: torsional N·m and rad/s; planar N and m/s.
namespace clearshape::plant {

struct FrictionValue {
  double force = 0.0;   ///< τ(v), opposes v
  double d_rate = 0.0;  ///< ∂τ/∂v
};

struct Friction {
  double viscous = 0.0;                ///< b   (N·m·s/rad or N·s/m)
  double coulomb = 0.0;                ///< F_c (N·m or N)
  double static_level = 0.0;           ///< F_s ≥ F_c enables the Stribeck peak; ≤ F_c: none
  double stribeck_rate = 1e-2;         ///< v_S (rad/s or m/s)
  double regularization_rate = 1e-3;   ///< v_t (rad/s or m/s)

  /// Throws InvalidArgument naming the field on negative coefficients or non-positive rates.
  void validate(const char* owner) const;
  bool active() const noexcept { return viscous > 0.0 || coulomb > 0.0 || static_level > 0.0; }
  FrictionValue evaluate(double rate) const noexcept;
};

/// Coulomb friction of the contact (thesis Eq. 2.9: F_T = −μ F_N v_T/|v_T|), regularized by
/// tanh(v_T/v_t) so it is smooth through v_T = 0.
struct CoulombContactFriction {
  double coefficient = 0.0;            ///< μ
  double regularization_rate = 1e-3;   ///< v_t in m/s
  void validate(const char* owner) const;
  /// Magnitude factor μ·tanh(v/v_t) and its derivative in v; F_T = −factor·F_N.
  FrictionValue factor(double slip_rate) const noexcept;
};

}  // namespace clearshape::plant
