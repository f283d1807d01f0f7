#pragma once
// The arm's rigid-body part (docs/arm.md): a serial chain of revolute joints read from URDF
// (urdfdom) whose joint-space dynamics come from Orocos KDL, not from hand-derived equations:
//   M(q) q̈ + C(q, q̇) q̇ + g(q) = τ
// M by KDL's composite-rigid-body solver, C q̇ + g by its recursive Newton–Euler solver with
// q̈ = 0 (Featherstone, Rigid Body Dynamics Algorithms, 2008, §5.3 and §6.2).
// A RigidChain is an immutable design: copies share the KDL chain; the solvers, their workspaces
// and a private copy of the KDL chain (KDL's joints cache their last pose) live in a
// ChainWorkspace (a state, one per simulation), so simulations may run on several threads.
#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

namespace clearshape::arm {

/// The URDF's revolute joints in chain order, with their limits (rad) if the URDF gives them.
struct ChainJoint {
  std::string name;
  std::string child_link;
  bool limited = false;  ///< revolute (true) or continuous (false)
  double lower_rad = 0.0;
  double upper_rad = 0.0;
};

class RigidChain {
 public:
  /// Reads a URDF document. `file` names it in errors (a path, or "<builtin scara-2>").
  /// Throws InputError naming the file, the element (joint/link) and the reason for malformed
  /// XML, a joint type other than revolute/continuous/fixed (prismatic, floating, planar), a
  /// link with two child joints (a branching tree; URDF cannot close a chain), a moving joint
  /// without a massive link after it, or a chain without any revolute joint.
  static RigidChain from_urdf(std::string_view urdf_xml, const std::string& file);
  /// Reads the URDF at `path` (InputError if it cannot be read).
  static RigidChain from_urdf_file(const std::string& path);

  int dof() const noexcept;
  const std::vector<ChainJoint>& joints() const noexcept;
  const std::string& robot_name() const noexcept;
  const std::string& tip_link() const noexcept;
  /// Gravity in the root link's frame (m/s²); URDF has none: (0, 0, −9.80665) by default.
  const Eigen::Vector3d& gravity_m_s2() const noexcept;
  /// A copy with another gravity vector (finite entries, else InvalidArgument).
  RigidChain with_gravity(const Eigen::Vector3d& gravity_m_s2) const;
  struct Data;  ///< opaque: the KDL chain and the joints (src/arm/chain_data.hpp)
  const Data& data() const noexcept;

 private:
  explicit RigidChain(std::shared_ptr<const Data> data) : data_(std::move(data)) {}
  std::shared_ptr<const Data> data_;
};

/// KDL's solvers for one chain with preallocated joint arrays (a state: not thread-safe).
class ChainWorkspace {
 public:
  explicit ChainWorkspace(const RigidChain& chain);
  ~ChainWorkspace();
  ChainWorkspace(const ChainWorkspace&) = delete;
  ChainWorkspace& operator=(const ChainWorkspace&) = delete;

  /// M(q), dof × dof, symmetric positive definite.
  void mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& m);
  /// C(q, q̇) q̇ + g(q): the torque that holds q̈ = 0 (RNE with zero acceleration).
  void bias_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& tau);
  /// g(q) alone (the torque that holds the arm still against gravity).
  void gravity_torque(const Eigen::VectorXd& q, Eigen::VectorXd& tau);
  /// The tip link's origin in the root frame (m), by KDL's forward kinematics.
  Eigen::Vector3d tip_position_m(const Eigen::VectorXd& q);
  /// The tip link's frame in the root frame (its rotation and origin), by KDL's forward kinematics.
  Eigen::Isometry3d tip_pose(const Eigen::VectorXd& q);
  /// One output sample of the chain, from a single outward pass of the recursive Newton–Euler
  /// algorithm over KDL's segments with the base accelerating at −g (Featherstone, Rigid Body
  /// Dynamics Algorithms, 2008, §5.3): each link's spatial velocity v_i and acceleration a_i in
  /// its own frame. The energies come from forward kinematics and the inertias, independently of
  /// KDL's dynamics solvers (energy checks).
  struct Sample {
    Eigen::Isometry3d tip_pose;   ///< the tip link's frame in the root frame (rotation, origin m)
    Eigen::Vector3d gyro_rad_s;   ///< the tip link's angular velocity, in its frame
    /// The specific force a − g at `mount_m` (in the tip link's frame), in that frame: what an
    /// accelerometer there reads (a point's classical acceleration is the spatial one + ω × v).
    Eigen::Vector3d accel_m_s2;
    double kinetic_j = 0.0;    ///< ½ Σ v_iᵀ I_i v_i (= ½ q̇ᵀ M(q) q̇)
    double potential_j = 0.0;  ///< −Σ m_i gᵀ c_i of every link's centre of mass c_i
  };
  Sample sample(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                const Eigen::Vector3d& mount_m);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clearshape::arm
