#pragma once
// Internal: drive + link with 1-D torsional play (the primary joint model, docs/design.md §2).
// State: [x (drive) | φ = θ_link − θ_motor | ω_link | W_diss | W_drive].
#include "joint_system.hpp"

namespace clearshape::plant::detail {

class TorsionalSystem final : public JointSystem {
 public:
  TorsionalSystem(const PlantModel& model, const SolverOptions& options);

  int rhs(double t, const double* y, double* ydot) noexcept override;
  int roots(double t, const double* y, double* g) noexcept override;
  bool has_jacobian() const noexcept override { return true; }
  int jacobian(double t, const double* y, double* jac) noexcept override;
  void initial_state(const InitialState& init, double u0, double* y, EventLog& log) override;
  void tolerances(const SolverOptions& o, double* atol) const override;
  bool on_roots(double t, double* y, const int* found, EventLog& log) noexcept override;
  void on_input_jump(double t, double* y) noexcept override;
  bool check_consistency(double t, double* y, EventLog& log) noexcept override;
  void sample(double t, const double* y, Sample& s) const noexcept override;
  std::string describe(double t, const double* y) const override;
  void reset_discrete() noexcept override;

 private:
  struct Terms {
    double u = 0.0, omega_m = 0.0, phi_rate = 0.0, theta_l = 0.0;
    int s = 1;
    double delta = 0.0, delta_rate = 0.0;
    ContactForce contact{};
    bool law_applied = false;
    double tau_contact = 0.0;
    FrictionValue joint{};
    double tau_gravity = 0.0, d_tau_gravity = 0.0;
    double tau_other = 0.0;  // gravity + ground drag + external (locked mode)
  };
  Terms terms(double t, const double* y) const noexcept;
  double lock_force(double t, const double* y, int side) const noexcept;
  /// σ·φ̈ without contact force: > 0 means the link accelerates into the stop on side σ.
  double free_approach_acceleration(double t, const double* y, int sigma) const noexcept;
  bool onset(double t, double* y, int side, EventLog& log) noexcept;
  void plastic_lock(double t, double* y, int side, double rate, EventLog& log) noexcept;

  DriveModel drive_;
  Link link_;
  TorsionalClearance joint_;
  int nd_ = 0, iphi_ = 0, iw_ = 0, idiss_ = 0, iwork_ = 0;
  double weight_rc_ = 0.0;  // m g sin(tilt) r_c
  double release_gap_ = 0.0;
  int side_ = 1;
  ContactMemory memory_{};
  ZenoGuard zeno_;
};

}  // namespace clearshape::plant::detail
