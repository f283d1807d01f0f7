#include "arm_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::arm::detail {

ArmSystem::ArmSystem(const ArmModel& model, std::span<const plant::Command> commands)
    : model_(model), commands_(commands.begin(), commands.end()), workspace_(model.chain) {
  model_.validate();
  dof_ = model_.dof();
  if (static_cast<int>(commands_.size()) != dof_) {
    throw InvalidArgument(fmt::format("arm '{}' has {} joints but {} commands were given; allowed: one per joint",
                                      model_.name, dof_, commands_.size()));
  }
  int n = 0;
  for (const ArmJoint& j : model_.joints) {
    offset_.push_back(n);
    n += j.drive.order();
    encoders_.emplace_back(j.encoder);
  }
  iq_ = n;
  iv_ = n + dof_;
  size_ = n + 2 * dof_;
  side_.assign(static_cast<std::size_t>(dof_), 0);
  memory_.assign(static_cast<std::size_t>(dof_), plant::ContactMemory{});
  q_.setZero(dof_);
  v_.setZero(dof_);
  tau_.setZero(dof_);
  bias_.setZero(dof_);
  qdd_.setZero(dof_);
  mass_.setZero(dof_, dof_);
  mass_step_.setZero(dof_, dof_);
  d_tau_.setZero(dof_, dof_);
  d_rigid_.setZero(dof_, dof_);
  q_step_.setZero(dof_);
  v_step_.setZero(dof_);
  bias_step_.setZero(dof_);
  d_tau_q_.setZero(dof_);
  d_tau_v_.setZero(dof_);
  d_tau_phi_rate_.setZero(dof_);
  llt_ = Eigen::LLT<Eigen::MatrixXd>(dof_);
  ydot_.assign(static_cast<std::size_t>(size_), 0.0);
}

JointTerms ArmSystem::terms(int i, double t, const double* y) const noexcept {
  const auto k = static_cast<std::size_t>(i);
  const ArmJoint& j = model_.joints[k];
  const Eigen::Map<const Eigen::VectorXd> x(y + offset_[k], j.drive.order());
  JointTerms r;
  r.u = commands_[k].value(t - j.drive.delay_s());
  r.theta_out = j.drive.angle_rad(x) / j.gear_ratio;  // the gearbox output θ_m / N
  r.omega_out = j.drive.rate_rad_s(x, r.u) / j.gear_ratio;
  r.phi = y[iq_ + i] - r.theta_out;
  r.phi_rate = y[iv_ + i] - r.omega_out;
  const int s = side_[k] != 0 ? side_[k] : (r.phi >= 0.0 ? 1 : -1);
  r.delta = s * r.phi - j.half_play_rad;  // δ = |φ| − β (thesis §2.3, docs/design.md §1)
  const double delta_rate = s * r.phi_rate;
  plant::ContactForce f{};
  if (side_[k] == 0) {  // free: a continuous law acts already until the onset event is located;
    // without play the flanks meet at φ = 0 and the law acts on either side with no events
    if (r.delta > 0.0 && (!j.law.jumps_at_onset() || j.half_play_rad == 0.0)) {
      // zero play: no impact to latch (χ = 0, a hysteresis law is its spring; else its force
      // would jump with the sign of δ̇ on every tiny oscillation about φ = 0)
      const double latched = j.half_play_rad == 0.0 ? 0.0 : j.law.latch_approach_rate(delta_rate);
      f = j.law.evaluate(r.delta, delta_rate, plant::ContactMemory{latched, false});
      if (j.law.uses_approach_rate()) f.d_rate = 0.0;  // δ̇/δ̇⁻ is 1 (or χ is 0) while δ̇⁻ follows δ̇
    }
  } else {
    f = r.delta <= 0.0 ? j.law.evaluate_continued(r.delta, delta_rate) : j.law.evaluate(r.delta, delta_rate, memory_[k]);
  }
  r.force = f;
  r.contact_torque = -s * f.force;
  r.contact_energy = r.delta > 0.0 ? j.law.potential(r.delta) : 0.0;
  return r;
}

int ArmSystem::rhs(double t, const double* y, double* yd) noexcept {
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const plant::DriveModel& d = model_.joints[k].drive;
    const int o = offset_[k];
    const double u = commands_[k].value(t - d.delay_s());
    for (int r = 0; r < d.order(); ++r) {  // ẋ = A x + B u (thesis Eq. 4.2 realised)
      double acc = d.b()(r) * u;
      for (int c = 0; c < d.order(); ++c) acc += d.a()(r, c) * y[o + c];
      yd[o + r] = acc;
    }
    const JointTerms jt = terms(i, t, y);
    q_(i) = y[iq_ + i];
    v_(i) = y[iv_ + i];
    tau_(i) = jt.contact_torque + model_.joints[k].friction.evaluate(v_(i)).force;
  }
  workspace_.mass_matrix(q_, mass_);
  workspace_.bias_torque(q_, v_, bias_);
  llt_.compute(mass_);
  if (llt_.info() != Eigen::Success) return -1;
  qdd_ = llt_.solve(tau_ - bias_);  // M q̈ = τ − (C q̇ + g)
  for (int i = 0; i < dof_; ++i) {
    yd[iq_ + i] = v_(i);
    yd[iv_ + i] = qdd_(i);
  }
  for (int i = 0; i < size_; ++i) {
    if (!std::isfinite(yd[i])) return 1;  // recoverable: CVODE retries with a smaller step
  }
  return 0;
}

int ArmSystem::jacobian(double t, const double* y, double* jac) noexcept {
  const int n = size_;
  std::fill(jac, jac + static_cast<std::ptrdiff_t>(n) * n, 0.0);
  auto at = [&](int row, int col) -> double& { return jac[row + n * col]; };
  if (rhs(t, y, jac) != 0) return 1;  // q̈, M, τ and the bias at y (jac's first column as scratch)
  std::fill(jac, jac + n, 0.0);
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ArmJoint& j = model_.joints[k];
    const plant::DriveModel& d = j.drive;
    const int o = offset_[k];
    for (int r = 0; r < d.order(); ++r) {
      for (int c = 0; c < d.order(); ++c) at(o + r, o + c) = d.a()(r, c);
    }
    at(iq_ + i, iv_ + i) = 1.0;
    // τ_i = −s F(δ, δ̇) + τ_f(q̇): ∂τ/∂φ = −F_δ, ∂τ/∂φ̇ = −F_δ̇ (s² = 1)
    const plant::ContactForce f = terms(i, t, y).force;
    d_tau_q_(i) = -f.d_penetration;
    d_tau_phi_rate_(i) = -f.d_rate;
    d_tau_v_(i) = -f.d_rate + j.friction.evaluate(v_(i)).d_rate;
  }
  llt_.compute(mass_);
  // rigid part: ∂(M(q) q̈ + b(q, q̇))/∂q_j and ∂b/∂q̇_j by forward differences
  for (int c = 0; c < dof_; ++c) {
    const double hq = 1e-7 * (1.0 + std::abs(q_(c)));
    q_step_ = q_;
    q_step_(c) += hq;
    workspace_.mass_matrix(q_step_, mass_step_);
    workspace_.bias_torque(q_step_, v_, bias_step_);
    d_rigid_.col(c) = (mass_step_ * qdd_ + bias_step_ - mass_ * qdd_ - bias_) / hq;
    d_rigid_(c, c) -= d_tau_q_(c);
    d_tau_.col(c) = -llt_.solve(d_rigid_.col(c));  // ∂q̈/∂q_c
    for (int r = 0; r < dof_; ++r) at(iv_ + r, iq_ + c) = d_tau_(r, c);
    const double hv = 1e-7 * (1.0 + std::abs(v_(c)));
    v_step_ = v_;
    v_step_(c) += hv;
    workspace_.bias_torque(q_, v_step_, bias_step_);
    d_rigid_.col(c) = (bias_step_ - bias_) / hv;
    d_rigid_(c, c) -= d_tau_v_(c);
    d_tau_.col(c) = -llt_.solve(d_rigid_.col(c));  // ∂q̈/∂q̇_c
    for (int r = 0; r < dof_; ++r) at(iv_ + r, iv_ + c) = d_tau_(r, c);
  }
  // drives: τ_c depends on x_c through φ = q − c_angleᵀx/N and φ̇ = q̇ − (c_rateᵀx + d u)/N
  for (int c = 0; c < dof_; ++c) {
    const auto k = static_cast<std::size_t>(c);
    const ArmJoint& j = model_.joints[k];
    const plant::DriveModel& d = j.drive;
    for (int r = 0; r < d.order(); ++r) {
      const double dtau = -(d_tau_q_(c) * d.angle_output()(r) + d_tau_phi_rate_(c) * d.rate_output()(r)) / j.gear_ratio;
      const Eigen::VectorXd col = llt_.solve(Eigen::VectorXd::Unit(dof_, c)) * dtau;
      for (int row = 0; row < dof_; ++row) at(iv_ + row, offset_[k] + r) = col(row);
    }
  }
  return 0;
}

void ArmSystem::roots(double t, const double* y, double* g) noexcept {
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ArmJoint& j = model_.joints[k];
    const JointTerms jt = terms(i, t, y);
    double* gi = g + 4 * i;
    const bool play = j.half_play_rad > 0.0;  // zero play: no flank to cross, no events
    gi[0] = play ? jt.phi - j.half_play_rad : 1.0;   // the + flank
    gi[1] = play ? -jt.phi - j.half_play_rad : 1.0;  // the − flank
    gi[2] = 1.0;
    gi[3] = 1.0;
    if (side_[k] != 0) j.law.kink_functions(jt.delta, side_[k] * jt.phi_rate, memory_[k], gi + 2);
  }
}

void ArmSystem::onset(int i, double t, int side, double rate, std::vector<ArmEvent>& events) noexcept {
  const auto k = static_cast<std::size_t>(i);
  side_[k] = side;
  memory_[k] = plant::ContactMemory{model_.joints[k].law.latch_approach_rate(rate), false};
  events.push_back({t, i, side, true, rate});
}

void ArmSystem::separation(int i, double t, double rate, std::vector<ArmEvent>& events) noexcept {
  const auto k = static_cast<std::size_t>(i);
  events.push_back({t, i, side_[k], false, rate});
  side_[k] = 0;
  memory_[k] = {};
}

bool ArmSystem::on_roots(double t, const double* y, const int* found, std::vector<ArmEvent>& events) noexcept {
  bool restart = false;  // a law that jumps at onset, or a kink of the law: new multistep history
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int* fi = found + 4 * i;
    const JointTerms jt = terms(i, t, y);
    const bool jumps = model_.joints[k].law.jumps_at_onset();
    if (side_[k] == 0) {
      for (int sigma : {1, -1}) {
        if (fi[sigma > 0 ? 0 : 1] > 0) {
          onset(i, t, sigma, sigma * jt.phi_rate, events);
          restart = restart || jumps;
          break;
        }
      }
      continue;
    }
    const int s = side_[k];
    if (fi[s > 0 ? 0 : 1] < 0) {
      separation(i, t, s * jt.phi_rate, events);
      if (fi[s > 0 ? 1 : 0] > 0) onset(i, t, -s, -s * jt.phi_rate, events);  // β = 0: the other flank
      restart = restart || jumps;
    } else if (fi[2] != 0 || fi[3] != 0) {
      restart = true;
    }
  }
  return restart;
}

bool ArmSystem::check_consistency(double t, const double* y, std::vector<ArmEvent>& events) noexcept {
  bool changed = false;
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const JointTerms jt = terms(i, t, y);
    const double beta = model_.joints[k].half_play_rad;
    if (beta == 0.0) continue;  // zero play: the law acts on either side without events
    if (side_[k] == 0) {
      const int s = jt.phi >= 0.0 ? 1 : -1;
      if (s * jt.phi - beta > 0.0) {
        onset(i, t, s, s * jt.phi_rate, events);
        changed = true;
      }
    } else if (side_[k] * jt.phi - beta < 0.0) {
      const int s = side_[k];
      separation(i, t, s * jt.phi_rate, events);
      if (-s * jt.phi - beta > 0.0) onset(i, t, -s, -s * jt.phi_rate, events);
      changed = true;
    }
  }
  return changed;
}

void ArmSystem::initial_state(const ArmInitialState& init, double* y, std::vector<ArmEvent>& events) {
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ArmJoint& j = model_.joints[k];
    const plant::DriveModel::Vector x = j.drive.rest_state(commands_[k].value(-j.drive.delay_s()));
    for (int r = 0; r < j.drive.order(); ++r) y[offset_[k] + r] = x(r);
    const double phi = init.relative_angle_rad.size() > 0 ? init.relative_angle_rad(i) : 0.0;
    const double rate = init.link_rate_rad_s.size() > 0 ? init.link_rate_rad_s(i) : 0.0;
    y[iq_ + i] = j.drive.angle_rad(x) / j.gear_ratio + phi;
    y[iv_ + i] = rate;
    side_[k] = 0;
    memory_[k] = {};
    const int s = phi >= 0.0 ? 1 : -1;
    const double delta = s * phi - j.half_play_rad;
    if (delta > 0.0 && j.half_play_rad > 0.0) onset(i, 0.0, s, s * terms(i, 0.0, y).phi_rate, events);
  }
}

void ArmSystem::tolerances(const ArmSolverOptions& o, double* atol) const {
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const plant::DriveModel& d = model_.joints[k].drive;
    const double scale = d.angle_output().cwiseAbs().maxCoeff();
    // drive states are scaled so that the motor angle's error is the link's times N
    const double tol = o.angle_tolerance_rad * model_.joints[k].gear_ratio / (scale > 0.0 ? scale : 1.0);
    for (int r = 0; r < d.order(); ++r) atol[offset_[k] + r] = tol;
    atol[iq_ + i] = o.angle_tolerance_rad;
    atol[iv_ + i] = o.rate_tolerance_rad_s;
  }
}

std::vector<double> ArmSystem::discontinuities_s() const {
  std::vector<double> out;
  for (std::size_t k = 0; k < commands_.size(); ++k) {
    for (double t : commands_[k].discontinuities_s()) out.push_back(t + model_.joints[k].drive.delay_s());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void ArmSystem::record(double t, const double* y, const double* ydot, ArmTrace& tr, Eigen::Index row) {
  // q̈ at the sample: the derivative of the integrator's interpolating polynomial if it has one
  // (no extra KDL solves), else f(t, y) (docs/arm.md §1, "Sensors", for its accuracy)
  if (ydot == nullptr) {
    ydot = ydot_.data();
    if (rhs(t, y, ydot_.data()) != 0) std::fill(ydot_.begin(), ydot_.end(), std::numeric_limits<double>::quiet_NaN());
  }
  double contact = 0.0;
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ArmJoint& j = model_.joints[k];
    const JointTerms jt = terms(i, t, y);
    const double theta_m = jt.theta_out * j.gear_ratio;
    tr.motor_angle_rad(row, i) = theta_m;
    tr.encoder_angle_rad(row, i) = encoders_[k].measure(theta_m);
    tr.output_angle_rad(row, i) = jt.theta_out;
    tr.link_angle_rad(row, i) = y[iq_ + i];
    tr.link_rate_rad_s(row, i) = y[iv_ + i];
    tr.contact_torque_n_m(row, i) = jt.contact_torque;
    q_(i) = y[iq_ + i];
    v_(i) = y[iv_ + i];
    qdd_(i) = ydot[iv_ + i];
    contact += jt.contact_energy;
  }
  tr.time_s.push_back(t);
  const ChainWorkspace::Sample chain = workspace_.sample(q_, v_, qdd_, model_.imu.mount_m);
  tr.tool_position_m.row(row) = chain.tip_pose.translation().transpose();
  tr.gyro_rad_s.row(row) = chain.gyro_rad_s.transpose();
  tr.accel_m_s2.row(row) = chain.accel_m_s2.transpose();
  tr.kinetic_j.push_back(chain.kinetic_j);
  tr.potential_j.push_back(chain.potential_j);
  tr.contact_energy_j.push_back(contact);
}

std::string ArmSystem::describe(double t, const double* y) const {
  std::ostringstream o;
  o.precision(9);
  o << "t = " << t << " s";
  for (int i = 0; i < dof_; ++i) {
    const JointTerms jt = terms(i, t, y);
    o << "; joint '" << model_.joints[static_cast<std::size_t>(i)].name << "': q = " << y[iq_ + i]
      << " rad, q_rate = " << y[iv_ + i] << " rad/s, phi = " << jt.phi << " rad, contact side "
      << side_[static_cast<std::size_t>(i)];
  }
  return o.str();
}

}  // namespace clearshape::arm::detail
