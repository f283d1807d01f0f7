#pragma once
// The rig configuration file of `clearshape simulate --config` and `clearshape study --rig-config`
// (TOML, read with toml++; Python: clearshape.load_rig_config, rig_truth_from_toml). Every key is
// optional; what is absent keeps the built-in (calibrated) thesis rig (rig/truth.hpp). Unknown tables or
// keys, values of the wrong type and values out of range are InputErrors naming the file, the
// line and the key. Schema (units in the key names; see docs/cli.md "clearshape simulate"):
//   [run]            duration_s, output_rate_hz, initial_play_fraction, seed, sensor_noise
//   [joint]          clearance_deg, friction_viscous_n_m_s_per_rad, friction_coulomb_n_m
//   [contact]        model, stiffness, exponent, damping, restitution, static_rate_rad_s
//   [link]           inertia_kg_m2, mass_kg, com_distance_m, axis_tilt_deg,
//                    ground_viscous_n_m_s_per_rad
//   [drive.position] [drive.speed]   kp, tz_s, zeta, tw_s, tp3_s, td_s (Eq. 4.2, P3UZ[D])
//   [encoder]        lines_per_revolution, decoding (1, 2 or 4)
//   [gyroscope]      sensitivity_lsb_per_dps, full_scale_dps, noise_density_dps_per_rthz,
//                    bias_dps, low_pass_hz (0 = off, 256, 188, 98, 42, 20, 10, 5),
//                    latency_samples
//   [position_path]  update_rate_hz, counts_per_rev, gear_ratio, max_pulse_frequency_hz
//   [speed_path]     volts_per_unit, resolution_bits, full_scale_v
//   [variation]      position_gain_rel_sigma, speed_gain_rel_sigma, start_latency_max_s,
//                    analog_noise_v, analog_offset_sigma_v, flank_damping_rel_sigma
//                    (run-to-run variation, rig/variation.hpp; SimRig only)
//   [solver]         integrator ("bdf" | "adams"), relative_tolerance, angle_tolerance_rad,
//                    rate_tolerance_rad_s, max_step_s
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "clearshape/rig/contact.hpp"
#include "clearshape/rig/offline.hpp"
#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

/// What a config file sets, applied over the defaults in this order: file, then CLI flags.
struct RigConfig {
  RigTruth truth = thesis_rig_truth();
  RunOptions run{};
  std::optional<ContactModel> contact_model;  ///< [contact] model, if given
  ContactSpec contact_overrides{};            ///< [contact] numbers (see the flags below)
  bool has_stiffness = false, has_exponent = false, has_damping = false,
       has_restitution = false, has_static_rate = false;

  /// True when the file has a [contact] table with any key.
  [[nodiscard]] bool sets_contact() const {
    return contact_model || has_stiffness || has_exponent || has_damping || has_restitution || has_static_rate;
  }
};

/// Reads `path` over the defaults. Throws InputError (file, line, key).
RigConfig load_rig_config(const std::filesystem::path& path);
/// The same from text (`file` names it in messages); what load_rig_config parses.
RigConfig parse_rig_config(std::string_view text, const std::string& file);

/// The contact spec for `mode`: the truth's own contact if it uses `model` (the built-in rig:
/// the calibrated thesis law), else the model's defaults (ContactSpec::defaults); then the
/// config's numbers.
ContactSpec resolve_contact(const RigConfig& config, ContactModel model, CommandMode mode);

/// The truth the file describes, both modes' contact laws included: with a [contact] table, its
/// model (default thesis) resolved for position and speed (resolve_contact); validated. What
/// `clearshape study --rig-config` simulates.
RigTruth configured_truth(const RigConfig& config);

}  // namespace clearshape::rig
