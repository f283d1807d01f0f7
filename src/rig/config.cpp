#include "clearshape/rig/config.hpp"

#include <cmath>
#include <functional>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "clearshape/io/atomic_file.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::rig {
namespace {

using Setter = std::function<void(const toml::node&, const std::string& key)>;
struct Key {
  std::string_view name;
  Setter set;
};
struct Section {
  std::string_view name;
  std::vector<Key> keys;
};

std::size_t line_of(const toml::node& node) {
  return static_cast<std::size_t>(node.source().begin.line);
}

double number(const toml::node& node, const std::string& key) {
  if (const auto v = node.value<double>(); v && (node.is_integer() || node.is_floating_point())) {
    return *v;
  }
  throw InvalidArgument(fmt::format("{} must be a number", key));
}
std::int64_t integer(const toml::node& node, const std::string& key) {
  if (const auto v = node.value<std::int64_t>(); v && node.is_integer()) return *v;
  throw InvalidArgument(fmt::format("{} must be an integer", key));
}
bool boolean(const toml::node& node, const std::string& key) {
  if (const auto v = node.value<bool>()) return *v;
  throw InvalidArgument(fmt::format("{} must be true or false", key));
}
std::string text(const toml::node& node, const std::string& key) {
  if (const auto v = node.value<std::string>()) return *v;
  throw InvalidArgument(fmt::format("{} must be a string", key));
}

plant::GyroLowPass low_pass_from_hz(double hz, const std::string& key) {
  for (const auto s : {plant::GyroLowPass::off, plant::GyroLowPass::hz256, plant::GyroLowPass::hz188,
                       plant::GyroLowPass::hz98, plant::GyroLowPass::hz42, plant::GyroLowPass::hz20,
                       plant::GyroLowPass::hz10, plant::GyroLowPass::hz5}) {
    if (plant::bandwidth_hz(s) == hz) return s;
  }
  throw_invalid(key, hz, "0 (off), 256, 188, 98, 42, 20, 10 or 5 (the ITG-3205 DLPF settings)");
}

struct DriveEdit {
  lti::ProcessParameters parameters;
  bool edited = false;
};

// Setters for the common kinds of key; the rest are written out where they are used.
Setter num(double& field) {
  return [&field](const toml::node& n, const std::string& k) { field = number(n, k); };
}
Setter ranged(double& field, double lo, double hi) {
  return [&field, lo, hi](const toml::node& n, const std::string& k) {
    const double v = number(n, k);
    require_in_closed(k, v, lo, hi);
    field = v;
  };
}
Setter int_in(int& field, std::int64_t lo, std::int64_t hi, std::string allowed) {
  return [&field, lo, hi, allowed = std::move(allowed)](const toml::node& n, const std::string& k) {
    const auto v = integer(n, k);
    if (v < lo || v > hi) throw_invalid(k, static_cast<double>(v), allowed);
    field = static_cast<int>(v);
  };
}
// A [contact] number: it overrides the law's default only when given.
Setter contact_override(double& field, bool& given) {
  return [&field, &given](const toml::node& n, const std::string& k) {
    field = number(n, k);
    given = true;
  };
}

// One table per section of the file (the schema in rig/config.hpp).
std::vector<Key> run_keys(RigConfig& c) {
  return {{"duration_s", num(c.run.duration_s)},
          {"output_rate_hz", num(c.run.output_rate_hz)},
          {"initial_play_fraction", num(c.run.initial_play_fraction)},
          {"seed",
           [&c](const toml::node& n, const std::string& k) {
             const auto v = integer(n, k);
             if (v < 0) throw_invalid(k, static_cast<double>(v), ">= 0");
             c.run.seed = static_cast<std::uint64_t>(v);
           }},
          {"sensor_noise", [&c](const toml::node& n, const std::string& k) { c.run.sensor_noise = boolean(n, k); }}};
}

std::vector<Key> joint_keys(RigTruth& t) {
  return {{"clearance_deg",
           [&t](const toml::node& n, const std::string& k) {
             const double v = number(n, k);
             require_non_negative(k, v, "0 means a rigid joint");
             t.clearance_rad = deg_to_rad(v);
           }},
          {"friction_viscous_n_m_s_per_rad", num(t.joint_friction.viscous)},
          {"friction_coulomb_n_m", num(t.joint_friction.coulomb)}};
}

std::vector<Key> contact_keys(RigConfig& c) {
  auto& o = c.contact_overrides;
  return {{"model",
           [&c](const toml::node& n, const std::string& k) {
             c.contact_model = contact_model_from_string(text(n, k));
           }},
          {"stiffness", contact_override(o.stiffness, c.has_stiffness)},
          {"exponent", contact_override(o.exponent, c.has_exponent)},
          {"damping", contact_override(o.damping, c.has_damping)},
          {"restitution", contact_override(o.restitution, c.has_restitution)},
          {"static_rate_rad_s", contact_override(o.static_rate_rad_s, c.has_static_rate)}};
}

std::vector<Key> link_keys(RigTruth& t) {
  return {{"inertia_kg_m2", num(t.link.inertia_kg_m2)},
          {"mass_kg", num(t.link.mass_kg)},
          {"com_distance_m", num(t.link.com_distance_m)},
          {"axis_tilt_deg",
           [&t](const toml::node& n, const std::string& k) { t.link.axis_tilt_rad = deg_to_rad(number(n, k)); }},
          {"ground_viscous_n_m_s_per_rad", num(t.link.ground_viscous_n_m_s_per_rad)}};
}

std::vector<Key> drive_keys(DriveEdit& d) {  // Eq. 4.2, P3UZ[D]
  auto p = [&d](double lti::ProcessParameters::*member) {
    return [&d, member](const toml::node& n, const std::string& k) {
      d.parameters.*member = number(n, k);
      d.edited = true;
    };
  };
  return {{"kp", p(&lti::ProcessParameters::kp)},   {"tz_s", p(&lti::ProcessParameters::tz)},
          {"zeta", p(&lti::ProcessParameters::zeta)}, {"tw_s", p(&lti::ProcessParameters::tw)},
          {"tp3_s", p(&lti::ProcessParameters::tp3)}, {"td_s", p(&lti::ProcessParameters::td)}};
}

std::vector<Key> encoder_keys(RigTruth& t) {
  return {{"lines_per_revolution", int_in(t.encoder.lines_per_revolution, 1, 100000000, "1 … 1e8")},
          {"decoding", [&t](const toml::node& n, const std::string& k) {
             const auto v = integer(n, k);
             if (v != 1 && v != 2 && v != 4) throw_invalid(k, static_cast<double>(v), "1, 2 or 4");
             t.encoder.decoding = static_cast<plant::Decoding>(v);
           }}};
}

std::vector<Key> gyroscope_keys(RigTruth& t) {
  return {{"sensitivity_lsb_per_dps", num(t.gyro.sensitivity_lsb_per_dps)},
          {"full_scale_dps", num(t.gyro.full_scale_dps)},
          {"noise_density_dps_per_rthz", num(t.gyro.noise_density_dps_per_rthz)},
          {"bias_dps", num(t.gyro.bias_dps)},
          {"low_pass_hz",
           [&t](const toml::node& n, const std::string& k) { t.gyro.low_pass = low_pass_from_hz(number(n, k), k); }},
          {"latency_samples", int_in(t.gyro.latency_samples, 0, plant::kMaxGyroLatencySamples,
                                     fmt::format("0 … {}", plant::kMaxGyroLatencySamples))}};
}

std::vector<Key> position_path_keys(RigTruth& t) {
  return {{"update_rate_hz", num(t.pulse_train.update_rate_hz)},
          {"counts_per_rev", num(t.pulse_train.counts_per_rev)},
          {"gear_ratio", num(t.pulse_train.gear_ratio)},
          {"max_pulse_frequency_hz", num(t.pulse_train.max_pulse_frequency_hz)}};
}

std::vector<Key> speed_path_keys(RigTruth& t) {
  return {{"volts_per_unit", num(t.analog_output.volts_per_unit)},
          {"resolution_bits", int_in(t.analog_output.resolution_bits, 1, 24, "1 … 24")},
          {"full_scale_v", num(t.analog_output.full_scale_v)}};
}

std::vector<Key> variation_keys(RigTruth& t) {  // run-to-run variation (rig/variation.hpp); SimRig only
  auto& v = t.variation;
  return {{"position_gain_rel_sigma", ranged(v.position_gain_rel_sigma, 0.0, 0.1)},
          {"speed_gain_rel_sigma", ranged(v.speed_gain_rel_sigma, 0.0, 0.1)},
          {"start_latency_max_s", ranged(v.start_latency_max_s, 0.0, 1e-3)},
          {"analog_noise_v", ranged(v.analog_noise_v, 0.0, 0.1)},
          {"analog_offset_sigma_v", ranged(v.analog_offset_sigma_v, 0.0, 0.1)},
          {"flank_damping_rel_sigma", ranged(v.flank_damping_rel_sigma, 0.0, 1.0)}};
}

std::vector<Key> solver_keys(RigTruth& t) {
  return {{"integrator",
           [&t](const toml::node& n, const std::string& k) {
             const std::string v = text(n, k);
             if (v == "bdf") {
               t.solver.integrator = plant::Integrator::bdf;
             } else if (v == "adams") {
               t.solver.integrator = plant::Integrator::adams;
             } else {
               throw InvalidArgument(fmt::format("{} = '{}' is not an integrator; allowed: bdf, adams", k, v));
             }
           }},
          {"relative_tolerance", num(t.solver.relative_tolerance)},
          {"angle_tolerance_rad", num(t.solver.angle_tolerance_rad)},
          {"rate_tolerance_rad_s", num(t.solver.rate_tolerance_rad_s)},
          {"max_step_s", num(t.solver.max_step_s)}};
}

std::vector<Section> schema(RigConfig& c, DriveEdit& position, DriveEdit& speed) {
  auto& t = c.truth;
  return {{"run", run_keys(c)},
          {"joint", joint_keys(t)},
          {"contact", contact_keys(c)},
          {"link", link_keys(t)},
          {"drive.position", drive_keys(position)},
          {"drive.speed", drive_keys(speed)},
          {"encoder", encoder_keys(t)},
          {"gyroscope", gyroscope_keys(t)},
          {"position_path", position_path_keys(t)},
          {"speed_path", speed_path_keys(t)},
          {"variation", variation_keys(t)},
          {"solver", solver_keys(t)}};
}

std::string key_list(const std::vector<Key>& keys) {
  std::string s;
  for (const auto& k : keys) s += (s.empty() ? "" : ", ") + std::string(k.name);
  return s;
}

void apply_table(const toml::table& table, const std::string& prefix, std::vector<Section>& sections,
                 const std::string& file) {
  for (const auto& [raw_key, node] : table) {
    const std::string key(raw_key.str());
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    Section* section = nullptr;
    for (auto& s : sections) {
      if (s.name == name) section = &s;
    }
    const bool is_prefix = [&] {
      for (const auto& s : sections) {
        if (s.name.starts_with(name + ".")) return true;
      }
      return false;
    }();
    if (node.is_table() && (section != nullptr || is_prefix)) {
      if (section == nullptr) {
        apply_table(*node.as_table(), name, sections, file);
        continue;
      }
      for (const auto& [item_key, item] : *node.as_table()) {
        const std::string item_name(item_key.str());
        const Key* match = nullptr;
        for (const auto& k : section->keys) {
          if (k.name == item_name) match = &k;
        }
        const std::string full = name + "." + item_name;
        if (match == nullptr) {
          throw InputError(file, line_of(item), full,
                           fmt::format("unknown key; [{}] takes: {}", name, key_list(section->keys)));
        }
        try {
          match->set(item, full);
        } catch (const InvalidArgument& e) {
          throw InputError(file, line_of(item), full, e.what());
        }
      }
      continue;
    }
    std::string tables;
    for (const auto& s : sections) tables += (tables.empty() ? "" : ", ") + std::string(s.name);
    throw InputError(file, line_of(node), name,
                     fmt::format("unknown {}; allowed tables: {}", node.is_table() ? "table" : "key",
                                 tables));
  }
}

}  // namespace

RigConfig load_rig_config(const std::filesystem::path& path) {
  return parse_rig_config(io::read_text_file(path), path.string());
}

RigConfig parse_rig_config(std::string_view text, const std::string& file) {
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(file, static_cast<std::size_t>(e.source().begin.line), "",
                     std::string(e.description()));
  }
  RigConfig config;
  DriveEdit position{lti::thesis_position_mode_model().parameters(), false};
  DriveEdit speed{lti::thesis_speed_mode_model().parameters(), false};
  auto sections = schema(config, position, speed);
  apply_table(root, "", sections, file);
  const auto rebuild = [&](DriveEdit& d, plant::DriveMode mode, const char* table) {
    if (!d.edited) return;
    try {
      const lti::ProcessModel model(d.parameters.td > 0.0 ? "P3UZD" : "P3UZ", d.parameters);
      (mode == plant::DriveMode::position ? config.truth.position_drive : config.truth.speed_drive) =
          plant::DriveModel::from_process_model(mode, model);
    } catch (const InvalidArgument& e) {
      throw InputError(file, 0, table, e.what());
    }
  };
  rebuild(position, plant::DriveMode::position, "drive.position");
  rebuild(speed, plant::DriveMode::speed, "drive.speed");
  try {
    config.truth.validate();
    config.run.validate();
  } catch (const InvalidArgument& e) {
    throw InputError(file, 0, "", e.what());
  }
  return config;
}

ContactSpec resolve_contact(const RigConfig& config, ContactModel model,
                                 CommandMode mode) {
  // The built-in (calibrated) truth's contact when the model is its own, else the model's defaults.
  const ContactSpec& built_in = config.truth.contact(mode);
  ContactSpec spec = built_in.model == model ? built_in : ContactSpec::defaults(model, mode);
  const auto& o = config.contact_overrides;
  if (config.has_stiffness) spec.stiffness = o.stiffness;
  if (config.has_exponent) spec.exponent = o.exponent;
  if (config.has_damping) spec.damping = o.damping;
  if (config.has_restitution) spec.restitution = o.restitution;
  if (config.has_static_rate) spec.static_rate_rad_s = o.static_rate_rad_s;
  return spec;
}

RigTruth configured_truth(const RigConfig& config) {
  RigTruth truth = config.truth;
  if (config.sets_contact()) {
    const ContactModel model = config.contact_model.value_or(ContactModel::thesis);
    truth.position_contact = resolve_contact(config, model, CommandMode::position);
    truth.speed_contact = resolve_contact(config, model, CommandMode::speed);
  }
  truth.validate();
  return truth;
}

}  // namespace clearshape::rig
