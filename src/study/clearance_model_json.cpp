#include "clearshape/study/clearance_model_json.hpp"

#include <limits>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/rig/types.hpp"

namespace clearshape::study {
namespace {

using json = nlohmann::json;

const json& at(const json& j, const std::string& key, const std::string& file, const std::string& path) {
  if (!j.is_object() || !j.contains(key)) throw InputError(file, 0, path + key, "missing");
  return j.at(key);
}

double number(const json& j, const std::string& key, const std::string& file, const std::string& path) {
  const json& v = at(j, key, file, path);
  if (!v.is_number()) throw InputError(file, 0, path + key, "is not a number");
  return v.get<double>();
}

// An optional number (a file written before the key existed): `fallback` when absent.
double optional_number(const json& j, const std::string& key, double fallback, const std::string& file,
                       const std::string& path) {
  return j.is_object() && j.contains(key) ? number(j, key, file, path) : fallback;
}

// The joint's friction (absent in files written before it was fitted: none).
void friction_of(const json& coulomb, const json& viscous, const json& regularization, ClearanceModel& m,
                 const std::string& file, const std::string& path) {
  m.coulomb_n_m = coulomb.is_null() ? 0.0 : number(coulomb, "value", file, path + "coulomb.");
  m.viscous_n_m_s_per_rad = viscous.is_null() ? 0.0 : number(viscous, "value", file, path + "viscous.");
  if (!regularization.is_null()) m.friction_regularization_rad_s = regularization.get<double>();
  if (!(m.coulomb_n_m >= 0.0)) throw InputError(file, 0, path + "coulomb.value", "must be >= 0 N·m");
  if (!(m.viscous_n_m_s_per_rad >= 0.0)) throw InputError(file, 0, path + "viscous.value", "must be >= 0 N·m·s/rad");
  if (!(m.friction_regularization_rad_s > 0.0)) {
    throw InputError(file, 0, "friction_regularization_rad_s", "must be > 0 rad/s");
  }
}

// The contact law (absent in files written before it was a choice, or for the default: dashpot)
// and the Flores law's restitution e ∈ (0, 1] at `key` of `e_holder`.
void contact_law_of(const json& doc, const json& e_holder, const std::string& e_key, const std::string& e_path,
                    ClearanceModel& m, const std::string& file, const std::string& path) {
  if (!doc.contains("contact_law")) return;
  const json& law = doc.at("contact_law");
  if (!law.is_string() || (law != "dashpot" && law != "flores")) {
    throw InputError(file, 0, path + "contact_law", "must be \"dashpot\" or \"flores\"");
  }
  m.contact_law = contact_law_from_string(law.get<std::string>());
  if (m.contact_law != ContactLawChoice::flores) return;
  m.restitution = number(e_holder, e_key, file, e_path);
  if (!(m.restitution > 0.0 && m.restitution <= 1.0)) throw InputError(file, 0, e_path + e_key, "must be in (0, 1]");
}

lti::ProcessModel drive_of(const json& d, const std::string& file, const std::string& path) {
  lti::ProcessParameters p;
  for (const auto& [name, v] : at(d, "parameters", file, path).items()) {
    p.set(name, v.is_object() ? number(v, "value", file, path + "parameters." + name + ".") : v.get<double>());
  }
  const json& code = d.contains("model") ? d.at("model") : at(d, "structure", file, path);
  return lti::ProcessModel(code.get<std::string>(), p);
}

// model_sigma (a study's sections.clearance, or fit-clearance --per-run): each σ a number ≥ 0, or
// null (not known: read as NaN).
ClearanceModelSigma sigma_of(const json& j, const std::string& file, const std::string& path) {
  const auto read = [&](const char* key, double absent) {
    if (!j.contains(key)) return absent;
    if (j.at(key).is_null()) return std::numeric_limits<double>::quiet_NaN();
    const double v = number(j, key, file, path);
    if (!(v >= 0.0)) throw InputError(file, 0, path + key, "must be >= 0 or null");
    return v;
  };
  ClearanceModelSigma s;
  s.play_rel_sigma = read("play_rel_sigma", 0.0);
  s.stiffness_rel_sigma = read("stiffness_rel_sigma", 0.0);
  s.coulomb_rel_sigma = read("coulomb_rel_sigma", 0.0);
  s.damping_spread = read("damping_spread", 0.0);
  return s;
}

// `clearshape fit-clearance --json`: parameters with their uncertainty, the drive, the inertia.
IdentifiedClearanceModel from_fit_clearance(const json& doc, const std::string& file) {
  IdentifiedClearanceModel out;
  ClearanceModel& m = out.model;
  const json& p = at(doc, "parameters", file, "");
  m.stiffness = number(at(p, "stiffness", file, "parameters."), "value", file, "parameters.stiffness.");
  contact_law_of(doc, p.contains("restitution") ? p.at("restitution") : json(), "value", "parameters.restitution.", m, file, "");
  if (m.contact_law == ContactLawChoice::dashpot) {
    m.damping = number(at(p, "damping", file, "parameters."), "value", file, "parameters.damping.");
  }
  m.exponent = number(at(p, "exponent", file, "parameters."), "value", file, "parameters.exponent.");
  m.play_rad = deg_to_rad(number(at(p, "play", file, "parameters."), "value", file, "parameters.play."));
  const json none;
  const json& reg = doc.contains("friction_regularization_rad_s") ? doc.at("friction_regularization_rad_s") : none;
  if (!reg.is_null() && !reg.is_number()) throw InputError(file, 0, "friction_regularization_rad_s", "is not a number");
  friction_of(p.contains("coulomb") ? p.at("coulomb") : none, p.contains("viscous") ? p.at("viscous") : none, reg, m, file,
              "parameters.");
  m.link_inertia_kg_m2 = number(doc, "link_inertia_kg_m2", file, "");
  m.mode = rig::command_mode_from_string(at(doc, "mode", file, "").get<std::string>());
  m.drive = drive_of(at(doc, "drive", file, ""), file, "drive.");
  if (doc.contains("model_sigma") && doc.at("model_sigma").is_object()) out.sigma = sigma_of(doc.at("model_sigma"), file, "model_sigma.");
  return out;
}

// A study's results.json: sections.clearance, the selected drive model, the link mode.
IdentifiedClearanceModel from_study(const json& doc, const std::string& file) {
  IdentifiedClearanceModel out;
  ClearanceModel& m = out.model;
  const json& s = doc.at("sections");
  const json& c = s.at("clearance");
  const std::string cp = "sections.clearance.";
  m.stiffness = number(c, "stiffness_n_m_per_rad_pow_n", file, cp);
  m.damping = number(c, "damping_n_m_s_per_rad", file, cp);
  contact_law_of(c, c, "restitution", cp, m, file, cp);
  m.exponent = number(c, "exponent", file, cp);
  m.play_rad = deg_to_rad(number(c, "play_deg", file, cp));
  m.coulomb_n_m = optional_number(c, "coulomb_n_m", 0.0, file, cp);
  m.viscous_n_m_s_per_rad = optional_number(c, "viscous_n_m_s_per_rad", 0.0, file, cp);
  m.friction_regularization_rad_s =
      optional_number(c, "friction_regularization_rad_s", m.friction_regularization_rad_s, file, cp);
  if (!(m.coulomb_n_m >= 0.0)) throw InputError(file, 0, cp + "coulomb_n_m", "must be >= 0 N·m");
  if (!(m.viscous_n_m_s_per_rad >= 0.0)) throw InputError(file, 0, cp + "viscous_n_m_s_per_rad", "must be >= 0 N·m·s/rad");
  if (!(m.friction_regularization_rad_s > 0.0)) {
    throw InputError(file, 0, cp + "friction_regularization_rad_s", "must be > 0 rad/s");
  }
  m.link_inertia_kg_m2 = number(c, "link_inertia_kg_m2", file, cp);
  m.mode = rig::command_mode_from_string(at(at(doc, "protocol", file, ""), "mode", file, "protocol.").get<std::string>());
  const json& ident = at(s, "identification", file, "sections.");
  const std::string selected = at(ident, "selected_input", file, "sections.identification.").get<std::string>();
  bool found = false;
  for (const auto& model : at(ident, "models", file, "sections.identification.")) {
    if (model.is_object() && model.contains("input") && model.at("input") == selected) {
      m.drive = drive_of(model, file, "sections.identification.models[" + selected + "].");
      found = true;
    }
  }
  if (!found) throw InputError(file, 0, "sections.identification.models", "has no model for the selected input " + selected);
  if (s.contains("link_mode") && s.at("link_mode").value("available", false)) {
    out.link_frequency_hz = number(s.at("link_mode"), "natural_frequency_hz", file, "sections.link_mode.");
    out.link_damping_ratio = number(s.at("link_mode"), "damping_ratio", file, "sections.link_mode.");
  }
  if (c.contains("model_sigma") && c.at("model_sigma").is_object()) out.sigma = sigma_of(c.at("model_sigma"), file, "sections.clearance.model_sigma.");
  return out;
}

// A document with no clearance model: say why (a study whose clearance stage was skipped) or
// what was expected.
[[noreturn]] void throw_no_model(const json& doc, const std::string& file) {
  if (doc.contains("skipped_stages") && doc.at("skipped_stages").is_array()) {
    for (const auto& s : doc.at("skipped_stages")) {
      if (s.value("stage", "") != "clearance") continue;
      std::string missing;
      if (s.contains("missing_runs") && s.at("missing_runs").is_array()) {
        for (const auto& id : s.at("missing_runs")) missing += (missing.empty() ? "" : ", ") + id.get<std::string>();
      }
      throw InputError(file, 0, "sections.clearance",
                       fmt::format("this study has no clearance model: its clearance stage was skipped ({}{}); record those runs and "
                                   "run the study again",
                                   s.value("reason", "no reason given"), missing.empty() ? "" : ": " + missing));
    }
  }
  throw InputError(file, 0, "command",
                   "expected the JSON of `clearshape fit-clearance --json` or a study's results.json (sections.clearance)");
}

}  // namespace

IdentifiedClearanceModel read_clearance_model_json(const std::filesystem::path& path) {
  const std::string file = path.string();
  json doc;
  try {
    doc = json::parse(io::read_text_file(path));
  } catch (const json::parse_error& e) {
    throw InputError(file, 0, "", fmt::format("not JSON: {}", e.what()));
  }
  if (doc.value("command", "") == "fit-clearance") return from_fit_clearance(doc, file);
  if (doc.contains("sections") && doc.at("sections").contains("clearance")) return from_study(doc, file);
  throw_no_model(doc, file);
}

}  // namespace clearshape::study
