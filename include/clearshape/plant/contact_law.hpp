#pragma once
// Normal contact laws F(δ, δ̇) for a clearance joint (thesis §2.3.2.1, Eq. 2.2–2.7, Eq. 4.3;
// docs/design.md §5). A ContactLaw is an immutable, validated design (a value type);
// evaluate() is noexcept and allocation-free.
//
// Units. The law is unit-agnostic: δ is the penetration in the joint's coordinate and F the
// generalized force along it. For the torsional play (docs/design.md §2) δ is in rad and F is a
// torque in N·m, so K is in N·m/rad^n and D in N·m·s/rad; for the planar journal δ is in m,
// F in N, K in N/m^n and D in N·s/m.
//
// Conventions: δ > 0 means penetration; δ̇ > 0 means approach (compression). Outside contact
// (δ ≤ 0) every law gives F = 0. A positive F pushes the bodies apart.
#include <cstdint>
#include <string_view>

namespace clearshape::plant {

/// How a law whose damping does not vanish at δ = 0 is kept physical (docs/design.md §5).
enum class DampingPolicy : std::uint8_t {
  raw,      ///< F = F_spring + F_damper as written; may pull (F < 0) and jumps at onset
  clamped,  ///< F = max(F_spring + F_damper, 0): never pulls; still jumps at onset
  bounded,  ///< Modelica ElastoBacklash: |F_damper| ≤ F_spring, so 0 ≤ F ≤ 2 F_spring;
            ///< never pulls and is continuous at onset
};

/// Hysteresis-damping factor χ(e) of F = K δⁿ (1 + χ(e) δ̇/δ̇⁻) (docs/design.md §5).
enum class Hysteresis : std::uint8_t {
  hunt_crossley,        ///< 3(1−e)/2                     (Hunt & Crossley 1975)
  herbert_mcwhannell,   ///< 6(1−e)/((2e−1)²+3)           (Herbert & McWhannell 1977)
  lee_wang,             ///< 3(1−e)/4                     (Lee & Wang 1983)
  lankarani_nikravesh,  ///< 3(1−e²)/4  (thesis Eq. 2.7)  (Lankarani & Nikravesh 1990)
  gonthier,             ///< (1−e²)/e                     (Gonthier et al. 2004)
  zhiying_qishao,       ///< 3(1−e²)·exp(2(1−e))/4        (Zhiying & Qishao 2006)
  flores,               ///< 8(1−e)/(5e)                  (Flores et al. 2011)
  hu_guo,               ///< 3(1−e)/(2e)                  (Hu & Guo 2015)
};

/// χ(e) of a hysteresis law; e in (0, 1]. Throws InvalidArgument outside that range.
double hysteresis_factor(Hysteresis model, double restitution);
std::string_view to_string(Hysteresis model) noexcept;
std::string_view to_string(DampingPolicy policy) noexcept;

/// ζ(e) = −ln e / √(π² + ln² e): the damping ratio of a linear oscillator whose half cycle
/// returns velocity ratio e (exact for the raw Kelvin–Voigt law). e in (0, 1].
double kelvin_voigt_damping_ratio(double restitution);

/// z = D (m v₀²/K)^(2/5)/(m v₀): the single group that sets the restitution of the thesis law
/// F = K δ^1.5 + D δ̇ for a mass (inertia) m hitting at v₀ (docs/design.md §5; raw law
/// sticks for z ≳ 2). For exponent n the group is D (m v₀²/K)^(1/(n+1))/(m v₀).
double dashpot_group(double stiffness, double exponent, double damping, double mass,
                     double approach_rate);

/// Force and its partial derivatives (for the analytic Jacobian).
struct ContactForce {
  double force = 0.0;            ///< F (≥ 0 unless the policy is raw)
  double d_penetration = 0.0;    ///< ∂F/∂δ
  double d_rate = 0.0;           ///< ∂F/∂δ̇
  double elastic = 0.0;          ///< the conservative part F_el = dV/dδ (for energy balances)
  double elastic_d_penetration = 0.0;  ///< ∂F_el/∂δ
};

/// Discrete per-impact memory of a law, owned by the simulator.
struct ContactMemory {
  /// δ̇⁻: approach rate latched once at contact onset, floored (0 = not latched or persistent
  /// contact; hysteresis laws then have χ = 0).
  double approach_rate = 0.0;
  /// Thesis Kelvin–Voigt (Eq. 2.2–2.3): true once δ̇ has turned negative in this contact.
  bool unloading = false;
};

class ContactLaw {
 public:
  enum class Kind : std::uint8_t {
    hertz_dashpot,       ///< thesis Eq. 4.3 / 2.4: F = K δⁿ + D δ̇, with a DampingPolicy
    kelvin_voigt,        ///< F = k δ + c δ̇, with a DampingPolicy
    kelvin_voigt_thesis, ///< thesis Eq. 2.2–2.3: F = c δ while δ̇ > 0, F = e c δ after (rebound)
    hysteresis,          ///< F = max(K δⁿ (1 + χ(e) δ̇/δ̇⁻), 0), δ̇⁻ latched at onset
  };

  /// Thesis Eq. 4.3 (n = 1.5 in the thesis; calibrated K = 10000, D = 300 position mode,
  /// K = 5, D = 350 speed mode — units unstated there, N·m/rad^n and N·m·s/rad here).
  static ContactLaw hertz_dashpot(double stiffness, double exponent, double damping,
                                  DampingPolicy policy = DampingPolicy::clamped);
  /// Thesis §4.2 calibrations of Eq. 4.3 (n = 1.5), read in N·m/rad^1.5 and N·m·s/rad:
  /// position mode K = 10000, D = 300; speed mode K = 5, D = 350. The thesis's Eq. 2.4 applies
  /// the law as written whenever δ > 0 (raw); `clamped` or `bounded` remove its pulling.
  static ContactLaw thesis_position_mode(DampingPolicy policy = DampingPolicy::raw) {
    return hertz_dashpot(10000.0, 1.5, 300.0, policy);
  }
  static ContactLaw thesis_speed_mode(DampingPolicy policy = DampingPolicy::raw) {
    return hertz_dashpot(5.0, 1.5, 350.0, policy);
  }
  /// Linear Kelvin–Voigt with an explicit damping coefficient c.
  static ContactLaw kelvin_voigt(double stiffness, double damping,
                                 DampingPolicy policy = DampingPolicy::raw);
  /// Linear Kelvin–Voigt with c = 2 ζ(e) √(k m_eff): with the raw policy a single impact of
  /// the effective mass (inertia) m_eff returns exactly e (docs/design.md §5).
  static ContactLaw kelvin_voigt_restitution(double stiffness, double restitution,
                                             double effective_mass,
                                             DampingPolicy policy = DampingPolicy::raw);
  /// Thesis Eq. 2.2–2.3 (load with c, unload with e·c): the rebound returns velocity ratio √e.
  static ContactLaw kelvin_voigt_thesis(double stiffness, double restitution);
  /// Hysteresis-damping family, clamped at F ≥ 0. Approach rates below
  /// `minimum_approach_rate` latch as 0 (χ = 0: persistent contact, no division by ~0).
  static ContactLaw hysteresis(Hysteresis model, double stiffness, double exponent,
                               double restitution, double minimum_approach_rate = 1e-6);
  /// Thesis Eq. 2.7 (Lankarani–Nikravesh; the thesis's "D = H δ̇ⁿ" is read as H δⁿ).
  static ContactLaw lankarani_nikravesh(double stiffness, double exponent, double restitution,
                                        double minimum_approach_rate = 1e-6) {
    return hysteresis(Hysteresis::lankarani_nikravesh, stiffness, exponent, restitution,
                      minimum_approach_rate);
  }

  /// F(δ, δ̇) with derivatives; F = 0 for δ ≤ 0. noexcept, allocation-free.
  ContactForce evaluate(double penetration, double rate, const ContactMemory& memory) const noexcept;
  /// Continuation of a law that jumps at onset (raw/clamped dashpot) to δ ≤ 0, used only
  /// while the integrator steps across a separation it is about to locate: the spring is
  /// extended oddly (K·sign(δ)|δ|ⁿ), the dashpot and the policy are kept. Equals evaluate()
  /// for δ > 0.
  ContactForce evaluate_continued(double penetration, double rate) const noexcept;
  /// Elastic potential V(δ) = ∫₀^δ F_el (0 for δ ≤ 0), e.g. K δ^(n+1)/(n+1).
  double potential(double penetration) const noexcept;
  /// The value δ̇⁻ to latch at onset for an approach rate (floored; 0 means χ = 0).
  double latch_approach_rate(double rate) const noexcept;

  /// True if F ↛ 0 as δ → 0⁺ while δ̇ ≠ 0 (raw/clamped dashpot laws): the right-hand side
  /// jumps at onset and separation, so the integrator is restarted there.
  bool jumps_at_onset() const noexcept;
  /// The kinks of F(δ, δ̇) inside the contact: the damping policy's switches (clamped: the
  /// spring + dashpot sum crossing 0; bounded: |F_d| reaching F_el) and the hysteresis factor
  /// 1 + χ δ̇/δ̇⁻ crossing 0. Writes two smooth functions whose sign changes mark them (1 where
  /// the law has none), so that the integrator can stop there instead of stepping across a
  /// kink (a near-grazing unload otherwise separates late). δ ≤ 0 uses the continuation.
  void kink_functions(double penetration, double rate, const ContactMemory& memory,
                      double g[2]) const noexcept;
  /// True if the force depends on the latched δ̇⁻ (hysteresis laws).
  bool uses_approach_rate() const noexcept { return kind_ == Kind::hysteresis; }
  /// True if the law switches on the sign of δ̇ (kelvin_voigt_thesis): an event at δ̇ = 0.
  bool switches_on_rate() const noexcept { return kind_ == Kind::kelvin_voigt_thesis; }

  Kind kind() const noexcept { return kind_; }
  DampingPolicy policy() const noexcept { return policy_; }
  Hysteresis hysteresis_model() const noexcept { return hysteresis_; }
  double stiffness() const noexcept { return stiffness_; }          ///< K (or k, c of Eq. 2.2)
  double exponent() const noexcept { return exponent_; }            ///< n
  double damping() const noexcept { return damping_; }              ///< D (or c)
  double restitution() const noexcept { return restitution_; }      ///< e (0 if not used)
  double chi() const noexcept { return chi_; }                      ///< χ(e) (hysteresis)
  double minimum_approach_rate() const noexcept { return minimum_approach_rate_; }
  /// A one-line description with units, e.g. "hertz_dashpot K=10000 n=1.5 D=300 (clamped)".
  std::string_view kind_name() const noexcept;

 private:
  ContactLaw() = default;
  Kind kind_ = Kind::hertz_dashpot;
  DampingPolicy policy_ = DampingPolicy::clamped;
  Hysteresis hysteresis_ = Hysteresis::hunt_crossley;
  double stiffness_ = 0.0;
  double exponent_ = 1.0;
  double damping_ = 0.0;
  double restitution_ = 0.0;
  double chi_ = 0.0;
  double minimum_approach_rate_ = 0.0;
};

}  // namespace clearshape::plant
