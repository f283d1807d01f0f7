#pragma once
// Simulating the arm (docs/arm.md): SUNDIALS CVODE (BDF, dense linear solver) on the state
//   y = [x_1 … x_n (drives) | q (links) | q̇ (links)],
// with root finding on the onset and separation of contact in every joint, a restart after
// every event and every command discontinuity (as plant/simulation.hpp does for one joint).
// Each drive turns by its own command (one-way coupling, docs/design.md §1).
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/arm.hpp"
#include "clearshape/plant/command.hpp"

namespace clearshape::arm {

/// The defaults keep the link angles of bench_arm's 10 s run within 0.023° of a run at
/// rtol 1e-11 (docs/arm.md, "Accuracy and speed").
struct ArmSolverOptions {
  double relative_tolerance = 1e-7;
  double angle_tolerance_rad = 1e-8;   ///< absolute tolerance of q and the drive states' angles
  double rate_tolerance_rad_s = 1e-6;  ///< absolute tolerance of q̇
  double max_step_s = 0.0;             ///< 0: unlimited
  long max_steps_per_output = 500000;
  /// ArmSystem's Jacobian (exact for drives and plays, differences of KDL for the rigid part);
  /// false: CVODE's difference quotients of the whole right-hand side.
  bool analytic_jacobian = true;
  void validate() const;
};

/// The links relative to their gearbox outputs at t = 0; the drives start at rest for the
/// command's first value. Empty vectors mean zeros.
struct ArmInitialState {
  Eigen::VectorXd relative_angle_rad;  ///< φ_i(0) = q_i − θ_m,i/N_i
  Eigen::VectorXd link_rate_rad_s;     ///< q̇_i(0)
};

struct ArmSimulationOptions {
  double duration_s = 1.0;
  double output_rate_hz = 1000.0;  ///< samples at k/output_rate_hz, t ≤ duration
  ArmSolverOptions solver{};
  ArmInitialState initial{};
  void validate(int dof) const;
};

struct ArmEvent {
  double time_s = 0.0;
  int joint = 0;
  int side = 0;        ///< +1: the link ahead of the gearbox output, −1: behind
  bool onset = true;   ///< onset (true) or separation (false)
  double rate_rad_s = 0.0;  ///< approach (onset) or separation rate of the play
};

/// Samples × joints matrices (rows: time), tool position samples × 3.
struct ArmTrace {
  std::vector<double> time_s;
  Eigen::MatrixXd motor_angle_rad;     ///< θ_m (true)
  Eigen::MatrixXd encoder_angle_rad;   ///< θ_m through each joint's encoder (quantised)
  Eigen::MatrixXd output_angle_rad;    ///< θ_m / N: the gearbox output
  Eigen::MatrixXd link_angle_rad;      ///< q
  Eigen::MatrixXd link_rate_rad_s;     ///< q̇
  Eigen::MatrixXd contact_torque_n_m;  ///< torque of the play on each link
  Eigen::MatrixXd tool_position_m;     ///< the URDF's tip link origin in the root frame
  /// The last link's IMU (ArmModel::imu), samples × 3 in the tip link's frame, noise and range
  /// applied: its angular velocity, and the specific force a − g at the mount point.
  Eigen::MatrixXd gyro_rad_s;
  Eigen::MatrixXd accel_m_s2;
  std::vector<double> kinetic_j;       ///< ½ Σ vᵀ I v over the links (= ½ q̇ᵀ M q̇)
  std::vector<double> potential_j;     ///< −Σ m gᵀ c (from forward kinematics)
  std::vector<double> contact_energy_j;  ///< Σ elastic energy stored in the plays
  std::vector<ArmEvent> events;
  long steps = 0;
  long rhs_evaluations = 0;
};

/// What each drive receives: each joint's command through its command path (ArmJoint::path;
/// docs/arm.md §1), as rig::simulate_run does for the single joint. ideal: the command itself.
/// pulse_train: the command's samples (a zero-order-hold command sampled at 1 kHz first), held
/// for one update period after the last, read as motor degrees, through
/// signal::apply_position_path from rest at the first sample; the commanded position in degrees,
/// linear between samples (the pulses arrive at a constant rate within an update period).
/// analog: the samples through signal::apply_speed_path, each held (the D/A's zero-order hold).
/// Throws InvalidArgument for a wrong number of commands.
std::vector<plant::Command> received_commands(const ArmModel& model, std::span<const plant::Command> commands);

/// Simulates `model` under one command per joint (the drive's command units: motor degrees
/// for a Kp = 1 position drive), each through its joint's command path (received_commands).
/// Throws InvalidArgument for a wrong number of commands or bad options, RuntimeError if CVODE
/// fails (naming the time and the joints' state).
ArmTrace simulate_arm(const ArmModel& model, std::span<const plant::Command> commands,
                      const ArmSimulationOptions& options);

}  // namespace clearshape::arm
