#pragma once
// Internal: drive + link whose bearing bore (radius R_B) sits on the motor shaft (journal,
// radius R_J) with radial clearance c (thesis Eq. 2.1, 2.9). Generalized coordinates of the
// link q = (p_x, p_y, θ): its pivot (bearing centre) relative to the fixed journal centre and
// its absolute angle. Mass matrix (centre of mass at p + r_c(cos θ, sin θ)):
//   M = [[m, 0, −m r_c sin θ], [0, m, m r_c cos θ], [−m r_c sin θ, m r_c cos θ, J]].
// State: [x (drive) | p_x, p_y, θ | ṗ_x, ṗ_y, ω | W_diss | W_drive].
#include <Eigen/Dense>

#include "joint_system.hpp"

namespace clearshape::plant::detail {

class PlanarSystem final : public JointSystem {
 public:
  PlanarSystem(const PlantModel& model, const SolverOptions& options);

  int rhs(double t, const double* y, double* ydot) noexcept override;
  int roots(double t, const double* y, double* g) noexcept override;
  void initial_state(const InitialState& init, double u0, double* y, EventLog& log) override;
  void tolerances(const SolverOptions& o, double* atol) const override;
  bool on_roots(double t, double* y, const int* found, EventLog& log) noexcept override;
  bool check_consistency(double t, double* y, EventLog& log) noexcept override;
  void sample(double t, const double* y, Sample& s) const noexcept override;
  std::string describe(double t, const double* y) const override;
  void reset_discrete() noexcept override;

 private:
  struct Terms {
    double u = 0.0, omega_m = 0.0;
    double delta = 0.0, delta_rate = 0.0;
    Eigen::Vector2d n = Eigen::Vector2d::UnitX(), t = Eigen::Vector2d::UnitY();
    ContactForce contact{};
    bool law_applied = false;
    double slip = 0.0, friction = 0.0;  // v_T and F_T (on the link, along t)
    Eigen::Matrix3d mass = Eigen::Matrix3d::Identity();
    Eigen::Vector3d force = Eigen::Vector3d::Zero();  // generalized force incl. velocity terms
  };
  Terms terms(double t, const double* y) const noexcept;
  Eigen::Matrix3d mass_matrix(double theta) const noexcept;
  bool onset(double t, double* y, EventLog& log) noexcept;

  DriveModel drive_;
  Link link_;
  PlanarClearance joint_;
  int nd_ = 0, ip_ = 0, iv_ = 0, idiss_ = 0, iwork_ = 0;
  double weight_ = 0.0;  // m g sin(tilt)
  double release_gap_ = 0.0;
  ContactMemory memory_{};
  ZenoGuard zeno_;
};

}  // namespace clearshape::plant::detail
