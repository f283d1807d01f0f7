#include "clearshape/plant/contact_law.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

double hysteresis_factor(Hysteresis model, double e) {
  require_in_closed("restitution", e, 0.0, 1.0,
                    "use a coefficient of restitution e with 0 < e <= 1");
  if (!(e > 0.0)) {
    throw_invalid("restitution", e, "(0, 1]",
                  "e = 0 (perfectly plastic) makes chi infinite; use an impulse law (ImpactLaw "
                  "with restitution 0) or a small e such as 0.01");
  }
  switch (model) {
    case Hysteresis::hunt_crossley: return 1.5 * (1.0 - e);                     // Hunt & Crossley 1975
    case Hysteresis::herbert_mcwhannell:                                         // Herbert & McWhannell 1977
      return 6.0 * (1.0 - e) / ((2.0 * e - 1.0) * (2.0 * e - 1.0) + 3.0);
    case Hysteresis::lee_wang: return 0.75 * (1.0 - e);                          // Lee & Wang 1983
    case Hysteresis::lankarani_nikravesh: return 0.75 * (1.0 - e * e);           // thesis Eq. 2.7
    case Hysteresis::gonthier: return (1.0 - e * e) / e;                         // Gonthier et al. 2004
    case Hysteresis::zhiying_qishao:                                             // Zhiying & Qishao 2006
      return 0.75 * (1.0 - e * e) * std::exp(2.0 * (1.0 - e));
    case Hysteresis::flores: return 8.0 * (1.0 - e) / (5.0 * e);                 // Flores et al. 2011
    case Hysteresis::hu_guo: return 1.5 * (1.0 - e) / e;                         // Hu & Guo 2015
  }
  return 0.0;
}

std::string_view to_string(Hysteresis model) noexcept {
  switch (model) {
    case Hysteresis::hunt_crossley: return "hunt_crossley";
    case Hysteresis::herbert_mcwhannell: return "herbert_mcwhannell";
    case Hysteresis::lee_wang: return "lee_wang";
    case Hysteresis::lankarani_nikravesh: return "lankarani_nikravesh";
    case Hysteresis::gonthier: return "gonthier";
    case Hysteresis::zhiying_qishao: return "zhiying_qishao";
    case Hysteresis::flores: return "flores";
    case Hysteresis::hu_guo: return "hu_guo";
  }
  return "unknown";
}

std::string_view to_string(DampingPolicy policy) noexcept {
  switch (policy) {
    case DampingPolicy::raw: return "raw";
    case DampingPolicy::clamped: return "clamped";
    case DampingPolicy::bounded: return "bounded";
  }
  return "unknown";
}

double kelvin_voigt_damping_ratio(double e) {
  require_in_closed("restitution", e, 0.0, 1.0, "use 0 < e <= 1");
  if (!(e > 0.0)) throw_invalid("restitution", e, "(0, 1]", "e = 0 needs infinite damping");
  const double l = std::log(e);
  return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);  // linear oscillator, half cycle
}

double dashpot_group(double stiffness, double exponent, double damping, double mass,
                     double approach_rate) {
  require_positive("stiffness", stiffness);
  require_in_closed("exponent", exponent, 1.0, 10.0);
  require_non_negative("damping", damping);
  require_positive("mass", mass);
  require_positive("approach_rate", approach_rate);
  // length scale (m v₀²/K)^(1/(n+1)), force scale m v₀/(that time scale) (clearance_sim §3.4)
  const double length = std::pow(mass * approach_rate * approach_rate / stiffness, 1.0 / (exponent + 1.0));
  return damping * length / (mass * approach_rate);
}

namespace {
void check_stiffness(double k) {
  require_positive("stiffness", k, "the contact stiffness K must be > 0");
}
void check_exponent(double n) {
  require_in_closed("exponent", n, 1.0, 10.0,
                    "use n = 1.5 (Hertz point contact, thesis Eq. 4.3) or n = 1 (linear)");
}
}  // namespace

ContactLaw ContactLaw::hertz_dashpot(double stiffness, double exponent, double damping,
                                     DampingPolicy policy) {
  check_stiffness(stiffness);
  check_exponent(exponent);
  require_non_negative("damping", damping, "the dashpot D must be >= 0");
  ContactLaw law;
  law.kind_ = Kind::hertz_dashpot;
  law.policy_ = policy;
  law.stiffness_ = stiffness;
  law.exponent_ = exponent;
  law.damping_ = damping;
  return law;
}

ContactLaw ContactLaw::kelvin_voigt(double stiffness, double damping, DampingPolicy policy) {
  check_stiffness(stiffness);
  require_non_negative("damping", damping, "the dashpot c must be >= 0");
  ContactLaw law;
  law.kind_ = Kind::kelvin_voigt;
  law.policy_ = policy;
  law.stiffness_ = stiffness;
  law.exponent_ = 1.0;
  law.damping_ = damping;
  return law;
}

ContactLaw ContactLaw::kelvin_voigt_restitution(double stiffness, double restitution,
                                                double effective_mass, DampingPolicy policy) {
  check_stiffness(stiffness);
  require_positive("effective_mass", effective_mass,
                   "give the mass (or inertia) that hits the stop");
  const double zeta = kelvin_voigt_damping_ratio(restitution);
  // c = 2 ζ √(k m) (docs/design.md §5, Chrono "Hooke" mapping)
  ContactLaw law = kelvin_voigt(stiffness, 2.0 * zeta * std::sqrt(stiffness * effective_mass),
                                policy);
  law.restitution_ = restitution;
  return law;
}

ContactLaw ContactLaw::kelvin_voigt_thesis(double stiffness, double restitution) {
  check_stiffness(stiffness);
  require_in_closed("restitution", restitution, 0.0, 1.0, "use 0 <= e <= 1");
  ContactLaw law;
  law.kind_ = Kind::kelvin_voigt_thesis;
  law.policy_ = DampingPolicy::clamped;
  law.stiffness_ = stiffness;
  law.exponent_ = 1.0;
  law.restitution_ = restitution;
  return law;
}

ContactLaw ContactLaw::hysteresis(Hysteresis model, double stiffness, double exponent,
                                  double restitution, double minimum_approach_rate) {
  check_stiffness(stiffness);
  check_exponent(exponent);
  ContactLaw law;
  law.kind_ = Kind::hysteresis;
  law.policy_ = DampingPolicy::clamped;
  law.hysteresis_ = model;
  law.stiffness_ = stiffness;
  law.exponent_ = exponent;
  law.restitution_ = restitution;
  law.chi_ = hysteresis_factor(model, restitution);
  require_positive("minimum_approach_rate", minimum_approach_rate,
                   "a small floor such as 1e-6 (MBDyn EpsPrimeTol) avoids dividing by ~0");
  law.minimum_approach_rate_ = minimum_approach_rate;
  return law;
}

namespace {
// F = F_el + F_d with the policy (docs/design.md §5; MSL ElastoBacklash for `bounded`).
ContactForce combine(double fe, double dfe, double fd, double dfd_rate, DampingPolicy policy) noexcept {
  ContactForce out;
  out.elastic = fe;
  out.elastic_d_penetration = dfe;
  switch (policy) {
    case DampingPolicy::raw:
      out.force = fe + fd;
      out.d_penetration = dfe;
      out.d_rate = dfd_rate;
      break;
    case DampingPolicy::clamped:
      if (fe + fd > 0.0) {
        out.force = fe + fd;
        out.d_penetration = dfe;
        out.d_rate = dfd_rate;
      }
      break;
    case DampingPolicy::bounded:
      if (fd >= fe) {          // damper limited to +F_el
        out.force = 2.0 * fe;
        out.d_penetration = 2.0 * dfe;
      } else if (fd <= -fe) {  // damper limited to −F_el: no pulling
        out.force = 0.0;
      } else {
        out.force = fe + fd;
        out.d_penetration = dfe;
        out.d_rate = dfd_rate;
      }
      break;
  }
  return out;
}
}  // namespace

ContactForce ContactLaw::evaluate(double delta, double rate,
                                  const ContactMemory& memory) const noexcept {
  if (!(delta > 0.0)) return {};
  switch (kind_) {
    case Kind::hertz_dashpot: {  // thesis Eq. 4.3: F = K δⁿ + D δ̇
      const double pow_nm1 = std::pow(delta, exponent_ - 1.0);
      const double fe = stiffness_ * pow_nm1 * delta;
      return combine(fe, exponent_ * stiffness_ * pow_nm1, damping_ * rate, damping_, policy_);
    }
    case Kind::kelvin_voigt:  // F = k δ + c δ̇
      return combine(stiffness_ * delta, stiffness_, damping_ * rate, damping_, policy_);
    case Kind::kelvin_voigt_thesis: {  // thesis Eq. 2.2 (loading) / Eq. 2.3 (unloading)
      ContactForce out;
      const double k = memory.unloading ? restitution_ * stiffness_ : stiffness_;
      out.force = k * delta;
      out.d_penetration = k;
      out.elastic = stiffness_ * delta;
      out.elastic_d_penetration = stiffness_;
      return out;
    }
    case Kind::hysteresis: {  // F = K δⁿ (1 + χ δ̇/δ̇⁻), clamped (docs/design.md §5)
      const double pow_nm1 = std::pow(delta, exponent_ - 1.0);
      const double fe = stiffness_ * pow_nm1 * delta;
      ContactForce out;
      out.elastic = fe;
      out.elastic_d_penetration = exponent_ * stiffness_ * pow_nm1;
      const double g = memory.approach_rate > 0.0 ? chi_ / memory.approach_rate : 0.0;
      const double factor = 1.0 + g * rate;
      if (factor > 0.0) {
        out.force = fe * factor;
        out.d_penetration = exponent_ * stiffness_ * pow_nm1 * factor;
        out.d_rate = fe * g;
      }
      return out;
    }
  }
  return {};
}

ContactForce ContactLaw::evaluate_continued(double delta, double rate) const noexcept {
  if (delta > 0.0 || !jumps_at_onset()) return evaluate(delta, rate, ContactMemory{});
  const double mag = -delta;
  const double pow_nm1 = std::pow(mag, exponent_ - 1.0);
  return combine(-stiffness_ * pow_nm1 * mag, exponent_ * stiffness_ * pow_nm1, damping_ * rate,
                 damping_, policy_);
}

double ContactLaw::potential(double delta) const noexcept {
  if (!(delta > 0.0)) return 0.0;
  return stiffness_ * std::pow(delta, exponent_ + 1.0) / (exponent_ + 1.0);
}

double ContactLaw::latch_approach_rate(double rate) const noexcept {
  if (kind_ != Kind::hysteresis) return rate > 0.0 ? rate : 0.0;
  return rate >= minimum_approach_rate_ ? rate : 0.0;
}

void ContactLaw::kink_functions(double delta, double rate, const ContactMemory& memory,
                                double g[2]) const noexcept {
  g[0] = 1.0;
  g[1] = 1.0;
  if (kind_ == Kind::hertz_dashpot || kind_ == Kind::kelvin_voigt) {
    if (policy_ == DampingPolicy::raw || damping_ == 0.0) return;
    const double n = kind_ == Kind::kelvin_voigt ? 1.0 : exponent_;
    const double fe = stiffness_ * std::copysign(std::pow(std::abs(delta), n), delta);
    const double fd = damping_ * rate;
    g[0] = fe + fd;                                      // clamp / no-pull switch
    if (policy_ == DampingPolicy::bounded) g[1] = fe - fd;  // damper limited to +F_el
  } else if (kind_ == Kind::hysteresis && memory.approach_rate > 0.0) {
    g[0] = 1.0 + chi_ / memory.approach_rate * rate;  // factor of Eq. 2.4–2.7 family
  }
}

bool ContactLaw::jumps_at_onset() const noexcept {
  if (kind_ == Kind::hertz_dashpot || kind_ == Kind::kelvin_voigt) {
    return damping_ > 0.0 && policy_ != DampingPolicy::bounded;
  }
  return false;
}

std::string_view ContactLaw::kind_name() const noexcept {
  switch (kind_) {
    case Kind::hertz_dashpot: return "hertz_dashpot";
    case Kind::kelvin_voigt: return "kelvin_voigt";
    case Kind::kelvin_voigt_thesis: return "kelvin_voigt_thesis";
    case Kind::hysteresis: return to_string(hysteresis_);
  }
  return "unknown";
}

}  // namespace clearshape::plant
