// The arm's TOML: drives, gears, play, contact, friction and encoders per joint (docs/arm.md).
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "clearshape/arm/arm.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/toml_section.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::arm {

namespace {

using io::TomlSection;
constexpr double kDeg = std::numbers::pi / 180.0;

double non_negative(const TomlSection& t, std::string_view key, double fallback) {
  const double v = t.number(key, fallback);
  if (v < 0.0) t.fail(key, fmt::format("= {} is out of range; allowed: >= 0", v));
  return v;
}

// [joint.drive]: a process model of thesis §4.2 (MATLAB procest codes), the thesis's Eq. 4.2,
// or a first-order lag; outputs in degrees (deg/s in speed mode) of the motor per command unit.
plant::DriveModel read_drive(const TomlSection& t) {
  const std::string model = t.text("model");
  const std::string mode = t.text("mode", "position");
  if (mode != "position" && mode != "speed") t.fail("mode", fmt::format("'{}' is not a drive mode; allowed: position, speed", mode));
  const auto drive_mode = mode == "position" ? plant::DriveMode::position : plant::DriveMode::speed;
  if (model == "thesis") {
    t.finish("model, mode, path");
    return drive_mode == plant::DriveMode::position ? plant::DriveModel::thesis_position_mode()
                                                   : plant::DriveModel::thesis_speed_mode();
  }
  if (model == "first-order") {
    if (drive_mode != plant::DriveMode::position) t.fail("mode", "a first-order drive is a position-mode drive; allowed: position");
    const double tau = t.positive("time_constant_s", 0.01);
    t.finish("model, mode, time_constant_s, path");
    return plant::DriveModel::first_order_position(tau);
  }
  lti::ProcessStructure structure;
  try {
    structure = lti::ProcessStructure::parse(model);
  } catch (const InvalidArgument& e) {
    t.fail("model", fmt::format("'{}': {}; allowed also: thesis, first-order", model, e.what()));
  }
  lti::ProcessParameters p;
  std::string allowed = "model, mode, path";
  for (std::string_view name : structure.parameter_names()) {
    std::string key(name);
    for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    p.set(name, t.number(key));
    allowed += ", " + key;
  }
  t.finish(allowed);
  try {
    return plant::DriveModel::from_process_model(drive_mode, lti::ProcessModel(structure, p));
  } catch (const InvalidArgument& e) {
    t.fail("", e.what());
  }
}

double in_range(const TomlSection& t, std::string_view key, double fallback, double hi, const char* allowed) {
  const double v = t.number(key, fallback);
  if (!(v > 0.0 && v <= hi)) t.fail(key, fmt::format("= {} is out of range; allowed: {}", v, allowed));
  return v;
}

// [joint.drive.path] kind = "pulse-train": signal::PulseTrainConfig (thesis §3.2, §4.1.2).
signal::PulseTrainConfig read_pulse_train(const TomlSection& t) {
  signal::PulseTrainConfig c;
  c.update_rate_hz = in_range(t, "update_rate_hz", c.update_rate_hz, 1e4, "(0, 10000] (the thesis driver: 30 Hz)");
  c.counts_per_rev = t.positive("counts_per_rev", c.counts_per_rev);
  c.gear_ratio = t.positive("gear_ratio", c.gear_ratio);
  c.max_pulse_frequency_hz = in_range(t, "max_pulse_frequency_hz", c.max_pulse_frequency_hz, 1e9, "(0, 1e9] (the thesis driver: 500 kHz)");
  if (c.max_counts_per_update() < 1) {
    t.fail("max_pulse_frequency_hz", fmt::format("= {} is out of range; allowed: >= update_rate_hz = {} (one pulse per update)",
                                                 c.max_pulse_frequency_hz, c.update_rate_hz));
  }
  const std::string hold = t.text("velocity_hold", "lookahead");
  if (hold != "lookahead" && hold != "sampled") t.fail("velocity_hold", fmt::format("'{}' is not a velocity hold; allowed: lookahead, sampled", hold));
  c.velocity_hold = hold == "lookahead" ? signal::VelocityHold::lookahead : signal::VelocityHold::sampled;
  t.finish("kind, update_rate_hz, counts_per_rev, gear_ratio, max_pulse_frequency_hz, velocity_hold");
  return c;
}

// [joint.drive.path] kind = "analog": signal::AnalogOutputConfig (thesis §3.2, Table 3.2).
signal::AnalogOutputConfig read_analog(const TomlSection& t) {
  signal::AnalogOutputConfig c;
  c.volts_per_unit = t.number("volts_per_unit", c.volts_per_unit);
  if (c.volts_per_unit == 0.0) t.fail("volts_per_unit", "= 0 is out of range; allowed: finite and non-zero (volts per command unit)");
  c.resolution_bits = static_cast<int>(t.integer("resolution_bits", c.resolution_bits, 1, 24));
  c.full_scale_v = t.positive("full_scale_v", c.full_scale_v);
  t.finish("kind, volts_per_unit, resolution_bits, full_scale_v");
  return c;
}

// [joint.drive.path]: what carries the command to a drive of `mode` (ArmCommandPath).
ArmCommandPath read_path(const TomlSection& t, plant::DriveMode mode) {
  ArmCommandPath p;
  const std::string kind = t.text("kind", "ideal");
  const bool position = mode == plant::DriveMode::position;
  if (kind == "ideal") {
    t.finish("kind");
  } else if (kind == "pulse-train") {
    if (!position) t.fail("kind", "'pulse-train' carries positions (thesis §3.2) but the drive's mode is speed; allowed: ideal, analog");
    p.kind = CommandPathKind::pulse_train;
    p.pulse_train = read_pulse_train(t);
  } else if (kind == "analog") {
    if (position) t.fail("kind", "'analog' carries a speed command (thesis §3.2) but the drive's mode is position; allowed: ideal, pulse-train");
    p.kind = CommandPathKind::analog;
    p.analog = read_analog(t);
  } else {
    t.fail("kind", fmt::format("'{}' is not a command path; allowed: ideal, pulse-train, analog", kind));
  }
  return p;
}

plant::DampingPolicy read_policy(const TomlSection& t) {
  const std::string p = t.text("policy", "clamped");
  if (p == "raw") return plant::DampingPolicy::raw;
  if (p == "clamped") return plant::DampingPolicy::clamped;
  if (p == "bounded") return plant::DampingPolicy::bounded;
  t.fail("policy", fmt::format("'{}' is not a damping policy; allowed: raw, clamped, bounded", p));
}

// [joint.contact]: one of plant/contact_law.hpp's laws; δ in rad at the link, torque in N·m.
plant::ContactLaw read_contact(const TomlSection& t) {
  const std::string law = t.text("law");
  const double k = t.positive("stiffness", 1.0);
  try {
    if (law == "kelvin-voigt" || law == "hertz-dashpot") {
      const double n = law == "kelvin-voigt" ? 1.0 : t.positive("exponent", 1.5);
      const double d = non_negative(t, "damping", 0.0);
      const plant::DampingPolicy policy = read_policy(t);
      t.finish(law == "kelvin-voigt" ? "law, stiffness, damping, policy" : "law, stiffness, exponent, damping, policy");
      return law == "kelvin-voigt" ? plant::ContactLaw::kelvin_voigt(k, d, policy)
                                   : plant::ContactLaw::hertz_dashpot(k, n, d, policy);
    }
    const plant::Hysteresis h = law == "hunt-crossley"         ? plant::Hysteresis::hunt_crossley
                                : law == "lankarani-nikravesh" ? plant::Hysteresis::lankarani_nikravesh
                                : law == "flores"              ? plant::Hysteresis::flores
                                                               : (t.fail("law", fmt::format(
                                                                      "'{}' is not a contact law; allowed: kelvin-voigt, "
                                                                      "hertz-dashpot, hunt-crossley, lankarani-nikravesh, flores",
                                                                      law)),
                                                                  plant::Hysteresis::flores);
    const double n = t.positive("exponent", 1.5);
    const double e = t.number("restitution");
    if (!(e > 0.0 && e <= 1.0)) t.fail("restitution", fmt::format("= {} is out of range; allowed: (0, 1]", e));
    t.finish("law, stiffness, exponent, restitution");
    return plant::ContactLaw::hysteresis(h, k, n, e);
  } catch (const InvalidArgument& e) {
    t.fail("", e.what());
  }
}

plant::Friction read_friction(const TomlSection& t) {
  plant::Friction f;
  f.viscous = non_negative(t, "viscous_n_m_s_per_rad", 0.0);
  f.coulomb = non_negative(t, "coulomb_n_m", 0.0);
  f.regularization_rate = t.positive("regularization_rate_rad_s", f.regularization_rate);
  t.finish("viscous_n_m_s_per_rad, coulomb_n_m, regularization_rate_rad_s");
  return f;
}

plant::EncoderConfig read_encoder(const TomlSection& t) {
  plant::EncoderConfig e;
  e.lines_per_revolution = static_cast<int>(t.integer("lines_per_revolution", 3000, 1, 1 << 24));
  const auto decoding = t.integer("decoding", 4, 1, 4);
  if (decoding == 3) t.fail("decoding", "= 3 is not a decoding; allowed: 1, 2, 4");
  e.decoding = static_cast<plant::Decoding>(decoding);
  t.finish("lines_per_revolution, decoding");
  return e;
}

// [imu]: the last link's gyroscope and accelerometer (ArmImu); absent ranges are unlimited.
ArmImu read_imu(const TomlSection& t) {
  ArmImu imu;
  if (t.has("mount_m")) {
    const std::vector<double> m = t.numbers("mount_m");
    if (m.size() != 3) t.fail("mount_m", fmt::format("has {} numbers; allowed: 3 (x, y, z in the tip link's frame, m)", m.size()));
    imu.mount_m = Eigen::Vector3d(m[0], m[1], m[2]);
  }
  imu.gyro_noise_rad_s = non_negative(t, "gyro_noise_rad_s", 0.0);
  imu.accel_noise_m_s2 = non_negative(t, "accel_noise_m_s2", 0.0);
  if (t.has("gyro_range_rad_s")) imu.gyro_range_rad_s = t.positive("gyro_range_rad_s", 1.0);
  if (t.has("accel_range_m_s2")) imu.accel_range_m_s2 = t.positive("accel_range_m_s2", 1.0);
  imu.seed = static_cast<std::uint64_t>(t.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  t.finish("mount_m, gyro_noise_rad_s, accel_noise_m_s2, gyro_range_rad_s, accel_range_m_s2, seed");
  return imu;
}

ArmJoint read_joint(const TomlSection& t) {
  ArmJoint j;
  j.name = t.text("name");
  j.gear_ratio = t.positive("gear_ratio", 1.0);
  j.half_play_rad = 0.5 * non_negative(t, "play_deg", 0.0) * kDeg;  // play = total width 2β
  const auto drive = t.table("drive");
  if (!drive) t.fail("drive", "missing table [joint.drive]");
  const auto path = drive->table("path");  // read before read_drive finishes [joint.drive]
  j.drive = read_drive(*drive);
  if (path) j.path = read_path(*path, j.drive.mode());
  const auto contact = t.table("contact");
  if (!contact) t.fail("contact", "missing table [joint.contact]");
  j.law = read_contact(*contact);
  if (const auto f = t.table("friction")) j.friction = read_friction(*f);
  if (const auto e = t.table("encoder")) j.encoder = read_encoder(*e);
  t.finish("name, gear_ratio, play_deg, drive, contact, friction, encoder");
  return j;
}

// Orders the [[joint]] tables as the chain's joints; every chain joint exactly once.
std::vector<ArmJoint> match_joints(const TomlSection& root, const RigidChain& chain) {
  const std::vector<TomlSection> tables = root.tables("joint");
  std::string names;
  for (const ChainJoint& c : chain.joints()) names += (names.empty() ? "" : ", ") + c.name;
  std::vector<ArmJoint> read;
  for (const TomlSection& t : tables) read.push_back(read_joint(t));
  std::vector<ArmJoint> ordered;
  for (const ChainJoint& c : chain.joints()) {
    int found = -1;
    for (std::size_t i = 0; i < read.size(); ++i) {
      if (read[i].name != c.name) continue;
      if (found >= 0) tables[i].fail("name", fmt::format("joint '{}' is given twice", c.name));
      found = static_cast<int>(i);
    }
    if (found < 0) root.fail("joint", fmt::format("no [[joint]] for the URDF's joint '{}'; the URDF's joints: {}", c.name, names));
    ordered.push_back(read[static_cast<std::size_t>(found)]);
  }
  for (std::size_t i = 0; i < read.size(); ++i) {
    bool known = false;
    for (const ChainJoint& c : chain.joints()) known = known || c.name == read[i].name;
    if (!known) tables[i].fail("name", fmt::format("'{}' is not a revolute joint of the URDF; allowed: {}", read[i].name, names));
  }
  return ordered;
}

std::string read_text(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", fmt::format("cannot open the {} file", what));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

void ArmImu::validate() const {
  if (!mount_m.allFinite()) throw InvalidArgument("imu.mount_m must hold 3 finite values (m, in the tip link's frame)");
  require_non_negative("imu.gyro_noise_rad_s", gyro_noise_rad_s);
  require_non_negative("imu.accel_noise_m_s2", accel_noise_m_s2);
  for (const auto& [field, range] : {std::pair{"imu.gyro_range_rad_s", gyro_range_rad_s},
                                     std::pair{"imu.accel_range_m_s2", accel_range_m_s2}}) {
    if (!(range > 0.0)) throw_invalid(field, range, "> 0 (infinity: unlimited)");
  }
}

void ArmCommandPath::validate(plant::DriveMode mode, const std::string& field) const {
  const bool position = mode == plant::DriveMode::position;
  if (kind == CommandPathKind::pulse_train && !position) {
    throw InvalidArgument(field + ".kind = pulse-train needs a position-mode drive; allowed: ideal, analog");
  }
  if (kind == CommandPathKind::analog && position) {
    throw InvalidArgument(field + ".kind = analog needs a speed-mode drive; allowed: ideal, pulse-train");
  }
  try {
    if (kind == CommandPathKind::pulse_train) pulse_train.validate();
    if (kind == CommandPathKind::analog) analog.validate();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(fmt::format("{}: {}", field, e.what()));
  }
}

void ArmModel::validate() const {
  if (static_cast<int>(joints.size()) != chain.dof()) {
    throw InvalidArgument(fmt::format("arm '{}' has {} joint configurations for {} chain joints; allowed: one per joint",
                                      name, joints.size(), chain.dof()));
  }
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const ArmJoint& j = joints[i];
    const std::string field = fmt::format("joint[{}]", i);
    if (j.name != chain.joints()[i].name) {
      throw InvalidArgument(fmt::format("{}.name = '{}' but the chain's joint {} is '{}'", field, j.name, i, chain.joints()[i].name));
    }
    require_positive(field + ".gear_ratio", j.gear_ratio);
    require_non_negative(field + ".half_play_rad", j.half_play_rad);
    j.friction.validate(field.c_str());
    j.path.validate(j.drive.mode(), field + ".path");
  }
  imu.validate();
}

ArmModel arm_from_text(std::string_view urdf, const std::string& urdf_file, std::string_view toml,
                       const std::string& toml_file) {
  RigidChain chain = RigidChain::from_urdf(urdf, urdf_file);
  const toml::table doc = io::parse_toml(toml, toml_file);
  const TomlSection root(doc, "", toml_file);
  std::string name = chain.robot_name();
  if (const auto arm = root.table("arm")) {
    name = arm->text("name", name);
    const std::vector<double> g = arm->numbers("gravity_m_s2");
    if (arm->has("gravity_m_s2")) {
      if (g.size() != 3) arm->fail("gravity_m_s2", "must hold 3 numbers (x, y, z in the URDF's root frame, m/s²)");
      chain = chain.with_gravity(Eigen::Vector3d(g[0], g[1], g[2]));
    }
    arm->finish("name, gravity_m_s2");
  }
  ArmModel model{name, chain, match_joints(root, chain), {}};
  if (const auto imu = root.table("imu")) model.imu = read_imu(*imu);
  root.finish("arm, joint, imu");
  model.validate();
  return model;
}

ArmModel load_arm(const std::string& urdf_path, const std::string& toml_path) {
  return arm_from_text(read_text(urdf_path, "URDF"), urdf_path, read_text(toml_path, "TOML"), toml_path);
}

}  // namespace clearshape::arm
