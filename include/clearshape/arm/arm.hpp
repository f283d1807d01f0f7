#pragma once
// The arm as a plant (docs/arm.md): a serial chain of thesis joints. Each joint i is the single
// joint of docs/design.md §1 with a gearbox: a drive (Eq. 4.2, position or speed mode) imposes
// the motor angle θ_m,i (one-way coupling); the gearbox output turns by θ_m,i / N_i; the link
// sits in a play of total width 2β_i around it and feels the contact torque of a contact law
// (plant/contact_law.hpp) when the play closes, plus bearing friction on its joint rate. The
// links obey the rigid-body dynamics of the chain (arm/chain.hpp):
//   M(q) q̈ + C(q, q̇) q̇ + g(q) = τ_contact(q, θ_m/N, q̇, ω_m/N) + τ_friction(q̇).
// An ArmModel is an immutable design read from a URDF (the chain) and a TOML (drives, gears,
// play, contact, friction and encoders per joint).
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/chain.hpp"
#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/friction.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/speed_path.hpp"

namespace clearshape::arm {

/// What carries a joint's command to its drive (docs/arm.md §1), as for the single joint
/// (rig::simulate_run): `ideal` passes the command unchanged; `pulse_train` is the position-mode
/// path of thesis §3.2, §4.1.2 (signal::apply_position_path: a velocity held per update period,
/// whole counts, a capped pulse frequency), the command read as motor degrees; `analog` the
/// speed-mode D/A of thesis §3.2, Table 3.2 (signal::apply_speed_path, each sample held).
enum class CommandPathKind { ideal, pulse_train, analog };

struct ArmCommandPath {
  CommandPathKind kind = CommandPathKind::ideal;
  signal::PulseTrainConfig pulse_train{};  ///< used by kind pulse_train
  signal::AnalogOutputConfig analog{};     ///< used by kind analog
  /// Throws InvalidArgument naming "<field>.kind" when the path does not suit `mode` (a pulse
  /// train needs a position drive, the D/A a speed drive) or the config's field otherwise.
  void validate(plant::DriveMode mode, const std::string& field) const;
};

struct ArmJoint {
  std::string name;  ///< the URDF joint's name
  plant::DriveModel drive = plant::DriveModel::first_order_position(0.01);
  double gear_ratio = 1.0;     ///< N > 0: the gearbox output turns θ_m / N
  double half_play_rad = 0.0;  ///< β ≥ 0 at the link: it turns freely for |q − θ_m/N| ≤ β
  plant::ContactLaw law = plant::ContactLaw::kelvin_voigt(1e4, 0.0);  ///< torque on the link
  plant::Friction friction{};      ///< bearing friction on the joint rate q̇ (N·m, rad/s)
  plant::EncoderConfig encoder{};  ///< on the motor shaft
  ArmCommandPath path{};           ///< between the joint's command and its drive
};

/// The 3-axis gyroscope and accelerometer on the last link (the URDF's tip link), read in that
/// link's frame: gyro = the link's angular velocity, accelerometer = the specific force a − g at
/// the mount point (what an IMU measures). Per sample: truth + white noise N(0, σ²) (seeded
/// std::mt19937_64) → clipped at ±range per axis.
struct ArmImu {
  Eigen::Vector3d mount_m = Eigen::Vector3d::Zero();  ///< in the tip link's frame; 0: the tool point
  double gyro_noise_rad_s = 0.0;   ///< σ per axis and sample, >= 0
  double accel_noise_m_s2 = 0.0;   ///< σ per axis and sample, >= 0
  double gyro_range_rad_s = std::numeric_limits<double>::infinity();  ///< full scale ±, > 0
  double accel_range_m_s2 = std::numeric_limits<double>::infinity();  ///< full scale ±, > 0
  std::uint64_t seed = 1;
  /// Throws InvalidArgument naming "imu.field" and the allowed range.
  void validate() const;
};

struct ArmModel {
  std::string name;
  RigidChain chain;
  std::vector<ArmJoint> joints;  ///< one per revolute joint of the chain, in chain order
  ArmImu imu{};                  ///< on the last link
  /// Throws InvalidArgument naming "joint[i].field" and the allowed range.
  void validate() const;
  int dof() const noexcept { return chain.dof(); }
};

/// The arm of a URDF and its TOML (docs/arm.md, "Bring your own arm"). Every revolute joint of
/// the URDF needs one [[joint]] table with its name; errors name the file, line and key.
ArmModel load_arm(const std::string& urdf_path, const std::string& toml_path);
/// The same from texts; `urdf_file` and `toml_file` name them in errors.
ArmModel arm_from_text(std::string_view urdf, const std::string& urdf_file, std::string_view toml,
                       const std::string& toml_file);

/// The arms shipped with clearshape: "scara-2", "vertical-2" (docs/arm.md).
std::vector<std::string> builtin_arm_names();
struct ArmText {
  std::string urdf;
  std::string toml;
};
/// The URDF and TOML texts of a built-in arm (InvalidArgument listing the names otherwise).
ArmText builtin_arm_text(std::string_view name);
ArmModel builtin_arm(std::string_view name);

}  // namespace clearshape::arm
