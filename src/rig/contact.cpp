#include "clearshape/rig/contact.hpp"

#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::rig {

std::string_view to_string(ContactModel model) noexcept {
  switch (model) {
    case ContactModel::thesis: return "thesis";
    case ContactModel::kelvin_voigt: return "kelvin-voigt";
    case ContactModel::hunt_crossley: return "hunt-crossley";
    case ContactModel::lankarani_nikravesh: return "lankarani-nikravesh";
    case ContactModel::flores: return "flores";
    case ContactModel::impulse: return "impulse";
  }
  return "unknown";
}

ContactModel contact_model_from_string(std::string_view name) {
  for (const auto model : {ContactModel::thesis, ContactModel::kelvin_voigt,
                           ContactModel::hunt_crossley, ContactModel::lankarani_nikravesh,
                           ContactModel::flores, ContactModel::impulse}) {
    if (name == to_string(model)) return model;
  }
  throw InvalidArgument("contact = '" + std::string(name) +
                        "' is not a contact law; allowed: thesis, kelvin-voigt, hunt-crossley, "
                        "lankarani-nikravesh, flores, impulse");
}

ContactSpec ContactSpec::thesis_for(CommandMode mode) noexcept {
  ContactSpec spec;
  spec.model = ContactModel::thesis;
  spec.exponent = 1.5;  // thesis §4.2: n = 1.5
  if (mode == CommandMode::position) {
    spec.stiffness = 10000.0;  // thesis §4.2, position mode
    spec.damping = 300.0;
  } else {
    spec.stiffness = 5.0;  // thesis §4.2, speed mode
    spec.damping = 350.0;
  }
  return spec;
}

ContactSpec ContactSpec::defaults(ContactModel model, CommandMode mode) noexcept {
  if (model == ContactModel::thesis) return thesis_for(mode);
  ContactSpec spec;
  spec.model = model;
  spec.stiffness = 1e4;
  spec.exponent = model == ContactModel::kelvin_voigt ? 1.0 : 1.5;
  spec.damping = 0.0;
  spec.restitution = 0.5;
  return spec;
}

void ContactSpec::validate() const {
  require_positive("contact.stiffness", stiffness);
  require_in_closed("contact.exponent", exponent, 1.0, 3.0, "Hertz contact uses n = 1.5");
  require_non_negative("contact.damping", damping);
  if (model == ContactModel::impulse) {
    require_in_closed("contact.restitution", restitution, 0.0, 1.0);
  } else if (model != ContactModel::thesis) {
    require_in_closed("contact.restitution", restitution, 1e-3, 1.0,
                      "Continuous laws need e > 0; use --contact impulse for e = 0");
  }
  require_positive("contact.static_rate_rad_s", static_rate_rad_s);
}

plant::ContactLaw make_contact_law(const ContactSpec& spec, double link_inertia_kg_m2) {
  spec.validate();
  switch (spec.model) {
    case ContactModel::thesis:  // Eq. 4.3: F = K δⁿ + D δ̇, never pulling
      return plant::ContactLaw::hertz_dashpot(spec.stiffness, spec.exponent, spec.damping,
                                              plant::DampingPolicy::clamped);
    case ContactModel::kelvin_voigt:
      return plant::ContactLaw::kelvin_voigt_restitution(spec.stiffness, spec.restitution,
                                                         link_inertia_kg_m2);
    case ContactModel::hunt_crossley:
      return plant::ContactLaw::hysteresis(plant::Hysteresis::hunt_crossley, spec.stiffness,
                                           spec.exponent, spec.restitution);
    case ContactModel::lankarani_nikravesh:
      return plant::ContactLaw::lankarani_nikravesh(spec.stiffness, spec.exponent,
                                                    spec.restitution);
    case ContactModel::flores:
      return plant::ContactLaw::hysteresis(plant::Hysteresis::flores, spec.stiffness,
                                           spec.exponent, spec.restitution);
    case ContactModel::impulse:  // the law is unused; the impact law decides
      return plant::ContactLaw::hertz_dashpot(spec.stiffness, spec.exponent, 0.0);
  }
  return plant::ContactLaw::hertz_dashpot(spec.stiffness, spec.exponent, spec.damping);
}

std::optional<plant::ImpactLaw> make_impact_law(const ContactSpec& spec) {
  if (spec.model != ContactModel::impulse) return std::nullopt;
  return plant::ImpactLaw{spec.restitution, spec.static_rate_rad_s};
}

}  // namespace clearshape::rig
