#include "rig_config.hpp"

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

namespace clearshape::cli {
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

std::vector<Section> schema(RigConfig& c, DriveEdit& position, DriveEdit& speed) {
  auto& t = c.truth;
  auto num = [](double& field) {
    return [&field](const toml::node& n, const std::string& k) { field = number(n, k); };
  };
  auto ranged = [](double& field, double lo, double hi) {
    return [&field, lo, hi](const toml::node& n, const std::string& k) {
      const double v = number(n, k);
      require_in_closed(k, v, lo, hi);
      field = v;
    };
  };
  auto drive_keys = [&](DriveEdit& d) {
    auto p = [&d](double lti::ProcessParameters::*member) {
      return [&d, member](const toml::node& n, const std::string& k) {
        d.parameters.*member = number(n, k);
        d.edited = true;
      };
    };
    return std::vector<Key>{{"kp", p(&lti::ProcessParameters::kp)},
                            {"tz_s", p(&lti::ProcessParameters::tz)},
                            {"zeta", p(&lti::ProcessParameters::zeta)},
                            {"tw_s", p(&lti::ProcessParameters::tw)},
                            {"tp3_s", p(&lti::ProcessParameters::tp3)},
                            {"td_s", p(&lti::ProcessParameters::td)}};
  };
  return {
      {"run",
       {{"duration_s", num(c.run.duration_s)},
        {"output_rate_hz", num(c.run.output_rate_hz)},
        {"initial_play_fraction", num(c.run.initial_play_fraction)},
        {"seed",
         [&c](const toml::node& n, const std::string& k) {
           const auto v = integer(n, k);
           if (v < 0) throw_invalid(k, static_cast<double>(v), ">= 0");
           c.run.seed = static_cast<std::uint64_t>(v);
         }},
        {"sensor_noise", [&c](const toml::node& n, const std::string& k) { c.run.sensor_noise = boolean(n, k); }}}},
      {"joint",
       {{"clearance_deg",
         [&t](const toml::node& n, const std::string& k) {
           const double v = number(n, k);
           require_non_negative(k, v, "0 means a rigid joint");
           t.clearance_rad = deg_to_rad(v);
         }},
        {"friction_viscous_n_m_s_per_rad", num(t.joint_friction.viscous)},
        {"friction_coulomb_n_m", num(t.joint_friction.coulomb)}}},
      {"contact",
       {{"model",
         [&c](const toml::node& n, const std::string& k) {
           c.contact_model = rig::contact_model_from_string(text(n, k));
         }},
        {"stiffness", [&c](const toml::node& n, const std::string& k) { c.contact_overrides.stiffness = number(n, k); c.has_stiffness = true; }},
        {"exponent", [&c](const toml::node& n, const std::string& k) { c.contact_overrides.exponent = number(n, k); c.has_exponent = true; }},
        {"damping", [&c](const toml::node& n, const std::string& k) { c.contact_overrides.damping = number(n, k); c.has_damping = true; }},
        {"restitution", [&c](const toml::node& n, const std::string& k) { c.contact_overrides.restitution = number(n, k); c.has_restitution = true; }},
        {"static_rate_rad_s", [&c](const toml::node& n, const std::string& k) { c.contact_overrides.static_rate_rad_s = number(n, k); c.has_static_rate = true; }}}},
      {"link",
       {{"inertia_kg_m2", num(t.link.inertia_kg_m2)},
        {"mass_kg", num(t.link.mass_kg)},
        {"com_distance_m", num(t.link.com_distance_m)},
        {"axis_tilt_deg",
         [&t](const toml::node& n, const std::string& k) { t.link.axis_tilt_rad = deg_to_rad(number(n, k)); }},
        {"ground_viscous_n_m_s_per_rad", num(t.link.ground_viscous_n_m_s_per_rad)}}},
      {"drive.position", drive_keys(position)},
      {"drive.speed", drive_keys(speed)},
      {"encoder",
       {{"lines_per_revolution",
         [&t](const toml::node& n, const std::string& k) {
           const auto v = integer(n, k);
           if (v < 1 || v > 100000000) throw_invalid(k, static_cast<double>(v), "1 … 1e8");
           t.encoder.lines_per_revolution = static_cast<int>(v);
         }},
        {"decoding",
         [&t](const toml::node& n, const std::string& k) {
           const auto v = integer(n, k);
           if (v != 1 && v != 2 && v != 4) throw_invalid(k, static_cast<double>(v), "1, 2 or 4");
           t.encoder.decoding = static_cast<plant::Decoding>(v);
         }}}},
      {"gyroscope",
       {{"sensitivity_lsb_per_dps", num(t.gyro.sensitivity_lsb_per_dps)},
        {"full_scale_dps", num(t.gyro.full_scale_dps)},
        {"noise_density_dps_per_rthz", num(t.gyro.noise_density_dps_per_rthz)},
        {"bias_dps", num(t.gyro.bias_dps)},
        {"low_pass_hz",
         [&t](const toml::node& n, const std::string& k) { t.gyro.low_pass = low_pass_from_hz(number(n, k), k); }},
        {"latency_samples",
         [&t](const toml::node& n, const std::string& k) {
           const auto v = integer(n, k);
           if (v < 0 || v > plant::kMaxGyroLatencySamples) {
             throw_invalid(k, static_cast<double>(v), fmt::format("0 … {}", plant::kMaxGyroLatencySamples));
           }
           t.gyro.latency_samples = static_cast<int>(v);
         }}}},
      {"position_path",
       {{"update_rate_hz", num(t.pulse_train.update_rate_hz)},
        {"counts_per_rev", num(t.pulse_train.counts_per_rev)},
        {"gear_ratio", num(t.pulse_train.gear_ratio)},
        {"max_pulse_frequency_hz", num(t.pulse_train.max_pulse_frequency_hz)}}},
      {"speed_path",
       {{"volts_per_unit", num(t.analog_output.volts_per_unit)},
        {"resolution_bits",
         [&t](const toml::node& n, const std::string& k) {
           const auto v = integer(n, k);
           if (v < 1 || v > 24) throw_invalid(k, static_cast<double>(v), "1 … 24");
           t.analog_output.resolution_bits = static_cast<int>(v);
         }},
        {"full_scale_v", num(t.analog_output.full_scale_v)}}},
      {"variation",  // run-to-run variation (rig/variation.hpp); SimRig only
       {{"position_gain_rel_sigma", ranged(t.variation.position_gain_rel_sigma, 0.0, 0.1)},
        {"speed_gain_rel_sigma", ranged(t.variation.speed_gain_rel_sigma, 0.0, 0.1)},
        {"start_latency_max_s", ranged(t.variation.start_latency_max_s, 0.0, 1e-3)},
        {"analog_noise_v", ranged(t.variation.analog_noise_v, 0.0, 0.1)},
        {"analog_offset_sigma_v", ranged(t.variation.analog_offset_sigma_v, 0.0, 0.1)},
        {"flank_damping_rel_sigma", ranged(t.variation.flank_damping_rel_sigma, 0.0, 1.0)}}},
      {"solver",
       {{"integrator",
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
        {"max_step_s", num(t.solver.max_step_s)}}},
  };
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

rig::ContactSpec resolve_contact(const RigConfig& config, rig::ContactModel model,
                                 rig::CommandMode mode) {
  // The built-in (calibrated) truth's contact when the model is its own, else the model's defaults.
  const rig::ContactSpec& built_in = config.truth.contact(mode);
  rig::ContactSpec spec = built_in.model == model ? built_in : rig::ContactSpec::defaults(model, mode);
  const auto& o = config.contact_overrides;
  if (config.has_stiffness) spec.stiffness = o.stiffness;
  if (config.has_exponent) spec.exponent = o.exponent;
  if (config.has_damping) spec.damping = o.damping;
  if (config.has_restitution) spec.restitution = o.restitution;
  if (config.has_static_rate) spec.static_rate_rad_s = o.static_rate_rad_s;
  return spec;
}

}  // namespace clearshape::cli
