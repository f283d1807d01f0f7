#pragma once
// Internal: the arm's ODE with a discrete contact state per joint (docs/arm.md).
// State: [x_1 … x_n (drive blocks) | q (n) | q̇ (n)]; four roots per joint: the two flanks
// (φ − β, −φ − β) and the two kinks of the contact law (plant/contact_law.hpp). A joint without
// play has no events: its flanks meet at φ = 0 and the law acts on either side (a hysteresis
// law as its spring alone: there is no impact whose approach rate it could latch).
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/simulation.hpp"

namespace clearshape::arm::detail {

struct JointTerms {
  double u = 0.0, theta_out = 0.0, omega_out = 0.0, phi = 0.0, phi_rate = 0.0;
  double delta = 0.0, contact_torque = 0.0, contact_energy = 0.0;
  plant::ContactForce force{};  ///< F(δ, δ̇) and its derivatives as the right-hand side uses them
};

class ArmSystem {
 public:
  ArmSystem(const ArmModel& model, std::span<const plant::Command> commands);

  int size() const noexcept { return size_; }
  int root_count() const noexcept { return 4 * dof_; }
  int rhs(double t, const double* y, double* ydot) noexcept;
  void roots(double t, const double* y, double* g) noexcept;
  /// ∂f/∂y, dense column-major size × size: exact for the drives and the plays; the rigid
  /// part ∂(M q̈ + C q̇ + g)/∂(q, q̇) at fixed q̈ by forward differences of KDL's solvers.
  int jacobian(double t, const double* y, double* jac) noexcept;
  /// y(0) from the drives' rest states and the initial relative angles and rates.
  void initial_state(const ArmInitialState& init, double* y, std::vector<ArmEvent>& events);
  void tolerances(const ArmSolverOptions& o, double* atol) const;
  /// After a root return: updates the contact modes; true if the integrator must restart (a
  /// law that jumps at onset or separation, a kink of the law; plant/ does the same).
  bool on_roots(double t, const double* y, const int* found, std::vector<ArmEvent>& events) noexcept;
  /// At an output: an onset or separation the root finder could not see (a root function that
  /// was exactly 0 at a restart). True if a mode changed.
  bool check_consistency(double t, const double* y, std::vector<ArmEvent>& events) noexcept;
  /// Times (delay included) where a command jumps, sorted.
  std::vector<double> discontinuities_s() const;
  /// One output sample; `ydot` is ẏ(t) (q̈ for the accelerometer), or nullptr to evaluate f(t, y).
  void record(double t, const double* y, const double* ydot, ArmTrace& trace, Eigen::Index row);
  std::string describe(double t, const double* y) const;

 private:
  JointTerms terms(int i, double t, const double* y) const noexcept;
  void onset(int i, double t, int side, double rate, std::vector<ArmEvent>& events) noexcept;
  void separation(int i, double t, double rate, std::vector<ArmEvent>& events) noexcept;

  ArmModel model_;
  std::vector<plant::Command> commands_;
  ChainWorkspace workspace_;
  int dof_ = 0, size_ = 0, iq_ = 0, iv_ = 0;
  std::vector<int> offset_;                  // first drive state of joint i
  std::vector<int> side_;                    // 0 free, ±1 in contact on that flank
  std::vector<plant::ContactMemory> memory_;
  std::vector<plant::Encoder> encoders_;
  Eigen::VectorXd q_, v_, tau_, bias_, qdd_;
  Eigen::MatrixXd mass_, mass_step_, d_tau_, d_rigid_;
  Eigen::VectorXd q_step_, v_step_, bias_step_, d_tau_q_, d_tau_v_, d_tau_phi_rate_;
  std::vector<double> ydot_;  // record()'s right-hand side (q̈ for the accelerometer)
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace clearshape::arm::detail
