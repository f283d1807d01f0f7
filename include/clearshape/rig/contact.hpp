#pragma once
// The contact-law choices of the simulated rig's torsional play (docs/design.md §2; thesis Eq. 4.3;
// docs/design.md §5). Units: δ in rad, torque in N·m, so a Hertz-type stiffness K
// is in N·m/rad^n, a linear one in N·m/rad, and a dashpot D in N·m·s/rad.
#include <cstdint>
#include <optional>
#include <string_view>

#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/impact.hpp"
#include "clearshape/rig/types.hpp"

namespace clearshape::rig {

enum class ContactModel : std::uint8_t {
  thesis,               ///< F = K δⁿ + D δ̇ (Eq. 4.3), F clamped at >= 0
  kelvin_voigt,         ///< F = k δ + c δ̇, c from the restitution for the link inertia
  hunt_crossley,        ///< F = K δⁿ (1 + 3(1−e)/2 · δ̇/δ̇⁻)
  lankarani_nikravesh,  ///< F = K δⁿ (1 + 3(1−e²)/4 · δ̇/δ̇⁻) (Eq. 2.7)
  flores,               ///< F = K δⁿ (1 + 8(1−e)/(5e) · δ̇/δ̇⁻)
  impulse,              ///< rigid impacts with restitution e (Eq. 2.13–2.15)
};
std::string_view to_string(ContactModel model) noexcept;
/// Parses the CLI names: thesis, kelvin-voigt, hunt-crossley, lankarani-nikravesh, flores,
/// impulse. Throws InvalidArgument listing them.
ContactModel contact_model_from_string(std::string_view name);

struct ContactSpec {
  ContactModel model = ContactModel::thesis;
  double stiffness = 1e4;    ///< K (N·m/rad^n) or, for kelvin_voigt, k (N·m/rad)
  double exponent = 1.5;     ///< n (Hertz-type laws; 1 for kelvin_voigt)
  double damping = 300.0;    ///< D (N·m·s/rad), thesis law only
  double restitution = 0.5;  ///< e, restitution-based laws and impulse
  double static_rate_rad_s = 1e-3;  ///< impulse: slower approaches lock to the shaft

  /// Thesis §4.2 calibration: position mode K = 10000, D = 300; speed mode K = 5, D = 350
  /// (n = 1.5; the thesis gives no units — here N·m/rad^1.5 and N·m·s/rad).
  static ContactSpec thesis_for(CommandMode mode) noexcept;
  /// The default of each model for a mode: thesis → thesis_for(mode); kelvin_voigt →
  /// k = 1e4 N·m/rad, e = 0.5; Hertz-type hysteresis laws → K = 1e4 N·m/rad^1.5, n = 1.5,
  /// e = 0.5; impulse → e = 0.5.
  static ContactSpec defaults(ContactModel model, CommandMode mode) noexcept;
  /// Throws InvalidArgument naming the field.
  void validate() const;
};

/// The plant's contact law for a spec (`link_inertia_kg_m2` sets the Kelvin–Voigt damping).
plant::ContactLaw make_contact_law(const ContactSpec& spec, double link_inertia_kg_m2);
/// The impulse law, for ContactModel::impulse only.
std::optional<plant::ImpactLaw> make_impact_law(const ContactSpec& spec);

}  // namespace clearshape::rig
