#include "torsional_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Dense>

#include "clearshape/core/error.hpp"

namespace clearshape::plant::detail {

namespace {
constexpr double kIgnoredWeight = 1e30;  // absolute tolerance of the work integrals
}

TorsionalSystem::TorsionalSystem(const PlantModel& model, const SolverOptions& options)
    : drive_(model.drive), link_(model.link), joint_(std::get<TorsionalClearance>(model.joint)) {
  nd_ = drive_.order();
  iphi_ = nd_;
  iw_ = nd_ + 1;
  idiss_ = nd_ + 2;
  iwork_ = nd_ + 3;
  size = nd_ + 4;
  root_count = 5;  // two sides, the rate switch, two kinks of the law
  weight_rc_ = link_.in_plane_weight_n() * link_.com_distance_m;
  release_gap_ = options.release_gap_fraction * joint_.half_play_rad;
  zeno_.configure(options.zeno_events, options.zeno_window_s);
}

void TorsionalSystem::reset_discrete() noexcept {
  mode = ContactMode::free;
  side_ = 1;
  memory_ = {};
  zeno_.clear();
}

TorsionalSystem::Terms TorsionalSystem::terms(double t, const double* y) const noexcept {
  Terms r;
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  r.u = input.value(t);
  r.omega_m = drive_.rate_rad_s(x, r.u);
  const double phi = y[iphi_];
  const double w = y[iw_];
  r.phi_rate = w - r.omega_m;
  r.theta_l = drive_.angle_rad(x) + phi;
  if (weight_rc_ != 0.0) {  // τ_g = −m g sin(tilt) r_c cos θ
    r.tau_gravity = -weight_rc_ * std::cos(r.theta_l);
    r.d_tau_gravity = weight_rc_ * std::sin(r.theta_l);
  }
  r.tau_other = r.tau_gravity - link_.ground_viscous_n_m_s_per_rad * w + link_.external_torque_n_m;
  if (mode == ContactMode::locked) {
    r.s = side_;
    r.delta = side_ * phi - joint_.half_play_rad;
    return r;
  }
  r.joint = joint_.joint_friction.evaluate(r.phi_rate);
  r.s = mode == ContactMode::free ? (phi >= 0.0 ? 1 : -1) : side_;
  r.delta = r.s * phi - joint_.half_play_rad;  // δ = |φ| − β
  r.delta_rate = r.s * r.phi_rate;              // δ̇ = sign(φ) φ̇
  const ContactLaw& law = joint_.law;
  if (joint_.impact) {
    // impulse law: no continuous force in free flight
  } else if (mode == ContactMode::free) {
    if (r.delta > 0.0 && !law.jumps_at_onset()) {  // continuous extension until the onset event
      r.contact = law.evaluate(r.delta, r.delta_rate,
                               ContactMemory{law.latch_approach_rate(r.delta_rate), false});
      r.law_applied = true;
    }
  } else {
    r.contact = (mode == ContactMode::contact && r.delta <= 0.0)
                    ? law.evaluate_continued(r.delta, r.delta_rate)
                    : law.evaluate(r.delta, r.delta_rate, memory_);
    r.law_applied = true;
  }
  r.tau_contact = -r.s * r.contact.force;
  return r;
}

double TorsionalSystem::lock_force(double t, const double* y, int side) const noexcept {
  // J ω̇ = τ_c + τ_other with ω̇ = α_m ⇒ τ_c = J α_m − τ_other; F = −s τ_c ≥ 0 while locked
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double u = input.value(t);
  const double alpha = drive_.acceleration_rad_s2(x, u, input.rate(t));
  const double theta = drive_.angle_rad(x) + y[iphi_];
  const double tau_other = -weight_rc_ * std::cos(theta) -
                           link_.ground_viscous_n_m_s_per_rad * y[iw_] + link_.external_torque_n_m;
  return -side * (link_.inertia_kg_m2 * alpha - tau_other);
}

int TorsionalSystem::rhs(double t, const double* y, double* yd) noexcept {
  const auto& a = drive_.a();
  const auto& b = drive_.b();
  const Terms r = terms(t, y);
  for (int i = 0; i < nd_; ++i) {  // ẋ = A x + B u
    double v = b(i) * r.u;
    for (int j = 0; j < nd_; ++j) v += a(i, j) * y[j];
    yd[i] = v;
  }
  const double w = y[iw_];
  const double drag = link_.ground_viscous_n_m_s_per_rad * w * w;
  if (mode == ContactMode::locked) {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
    const double alpha = drive_.acceleration_rad_s2(x, r.u, input.rate(t));
    yd[iphi_] = 0.0;
    yd[iw_] = alpha;
    const double tau_c = link_.inertia_kg_m2 * alpha - r.tau_other;
    yd[idiss_] = drag;
    yd[iwork_] = tau_c * r.omega_m;
  } else {
    yd[iphi_] = r.phi_rate;
    yd[iw_] = (r.tau_contact + r.joint.force + r.tau_other) / link_.inertia_kg_m2;
    // dissipated power: (F − F_el) δ̇ − τ_jf φ̇ + b ω²; shaft power: (τ_c + τ_jf) ω_m
    yd[idiss_] = (r.contact.force - r.contact.elastic) * r.delta_rate - r.joint.force * r.phi_rate + drag;
    yd[iwork_] = (r.tau_contact + r.joint.force) * r.omega_m;
  }
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(yd[i])) return 1;  // recoverable: CVODE retries with a smaller step
  }
  return 0;
}

int TorsionalSystem::roots(double t, const double* y, double* g) noexcept {
  const double phi = y[iphi_];
  const double beta = joint_.half_play_rad;
  for (int k = 0; k < 2; ++k) {
    const int sigma = k == 0 ? 1 : -1;
    if (mode == ContactMode::persistent && side_ == sigma) {
      g[k] = sigma * phi - beta + release_gap_;
    } else if (mode == ContactMode::locked && side_ == sigma) {
      g[k] = lock_force(t, y, sigma);
    } else {
      g[k] = sigma * phi - beta;
    }
  }
  if (mode == ContactMode::contact && joint_.law.switches_on_rate() && !joint_.impact) {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
    g[2] = side_ * (y[iw_] - drive_.rate_rad_s(x, input.value(t)));
  } else {
    g[2] = 1.0;
  }
  g[3] = 1.0;
  g[4] = 1.0;
  if (mode == ContactMode::contact && !joint_.impact) {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
    const double delta = side_ * phi - beta;
    const double delta_rate = side_ * (y[iw_] - drive_.rate_rad_s(x, input.value(t)));
    joint_.law.kink_functions(delta, delta_rate, memory_, g + 3);
  }
  for (int k = 0; k < 5; ++k) {
    if (!std::isfinite(g[k])) return -1;
  }
  return 0;
}

int TorsionalSystem::jacobian(double t, const double* y, double* jac) noexcept {
  const int n = size;
  for (int i = 0; i < n * n; ++i) jac[i] = 0.0;
  auto at = [&](int row, int col) -> double& { return jac[row + n * col]; };
  const auto& a = drive_.a();
  const auto& c_rate = drive_.rate_output();
  const auto& c_angle = drive_.angle_output();
  for (int i = 0; i < nd_; ++i) {
    for (int j = 0; j < nd_; ++j) at(i, j) = a(i, j);
  }
  const double inv_j = 1.0 / link_.inertia_kg_m2;
  const double b = link_.ground_viscous_n_m_s_per_rad;
  const Terms r = terms(t, y);
  const double w = y[iw_];
  if (mode == ContactMode::locked) {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
    const double alpha = drive_.acceleration_rad_s2(x, r.u, input.rate(t));
    const double tau_c = link_.inertia_kg_m2 * alpha - r.tau_other;
    for (int j = 0; j < nd_; ++j) {  // ∂α_m/∂x = c_rateᵀ A
      double v = 0.0;
      for (int i = 0; i < nd_; ++i) v += c_rate(i) * a(i, j);
      at(iw_, j) = v;
      // shaft power (J α_m − τ_other) ω_m
      at(iwork_, j) = (link_.inertia_kg_m2 * v - r.d_tau_gravity * c_angle(j)) * r.omega_m +
                      tau_c * c_rate(j);
    }
    at(iwork_, iphi_) = -r.d_tau_gravity * r.omega_m;
    at(iwork_, iw_) = b * r.omega_m;
    at(idiss_, iw_) = 2.0 * b * w;
    return 0;
  }
  for (int j = 0; j < nd_; ++j) at(iphi_, j) = -c_rate(j);  // φ̇ = ω − c_rateᵀx − d u
  at(iphi_, iw_) = 1.0;
  const double d_rate = -r.contact.d_rate + r.joint.d_rate;  // ∂(τ_c + τ_jf)/∂φ̇
  for (int j = 0; j < nd_; ++j) {
    at(iw_, j) = (d_rate * (-c_rate(j)) + r.d_tau_gravity * c_angle(j)) * inv_j;
  }
  at(iw_, iphi_) = (-r.contact.d_penetration + r.d_tau_gravity) * inv_j;
  at(iw_, iw_) = (d_rate - b) * inv_j;
  // work integrals: P_diss = F_d δ̇ − τ_jf φ̇ + b ω², P_drive = (τ_c + τ_jf) ω_m, F_d = F − F_el
  const double s = r.s;
  const double f_d = r.contact.force - r.contact.elastic;
  const double dp_dphi = (r.contact.d_penetration - r.contact.elastic_d_penetration) * s * r.delta_rate;
  const double dp_dq = s * (r.contact.d_rate * r.delta_rate + f_d) -
                       (r.joint.d_rate * r.phi_rate + r.joint.force);
  at(idiss_, iphi_) = dp_dphi;
  at(idiss_, iw_) = dp_dq + 2.0 * b * w;
  const double dw_dq = (-r.contact.d_rate + r.joint.d_rate) * r.omega_m;
  const double torque = r.tau_contact + r.joint.force;
  at(iwork_, iphi_) = -r.contact.d_penetration * r.omega_m;
  at(iwork_, iw_) = dw_dq;
  for (int j = 0; j < nd_; ++j) {
    at(idiss_, j) = -dp_dq * c_rate(j);
    at(iwork_, j) = -dw_dq * c_rate(j) + torque * c_rate(j);
  }
  return 0;
}

void TorsionalSystem::initial_state(const InitialState& init, double u0, double* y, EventLog& log) {
  reset_discrete();
  const DriveModel::Vector x = initial_drive_state(drive_, init, u0);
  require_finite("initial.relative_angle_rad", init.relative_angle_rad);
  require_finite("initial.link_rate_rad_s", init.link_rate_rad_s);
  for (int i = 0; i < nd_; ++i) y[i] = x(i);
  y[iphi_] = init.relative_angle_rad;
  y[iw_] = init.link_rate_rad_s;
  y[idiss_] = 0.0;
  y[iwork_] = 0.0;
  const double beta = joint_.half_play_rad;
  const double phi = init.relative_angle_rad;
  const int sigma = phi >= 0.0 ? 1 : -1;
  const double delta = sigma * phi - beta;
  const double rate = sigma * (y[iw_] - drive_.rate_rad_s(x, input.value(0.0)));
  if (joint_.impact && delta > 0.0) {
    throw_invalid("initial.relative_angle_rad", phi, "|phi| <= half_play_rad for an impulse law",
                  "a rigid impact law admits no penetration; start inside the play");
  }
  if (delta > 0.0 || (delta == 0.0 && rate > 0.0)) {
    onset(0.0, y, sigma, log);
    return;
  }
  // On the boundary at rest (e.g. zero play): contact if the link accelerates into a stop.
  for (int s : {1, -1}) {
    if (s * phi - beta != 0.0) continue;
    const double rel_rate = s * (y[iw_] - drive_.rate_rad_s(x, input.value(0.0)));
    if (rel_rate == 0.0 && free_approach_acceleration(0.0, y, s) > 0.0) {
      if (joint_.impact) {
        plastic_lock(0.0, y, s, 0.0, log);
      } else {
        onset(0.0, y, s, log);
      }
      return;
    }
  }
}

double TorsionalSystem::free_approach_acceleration(double t, const double* y, int sigma) const noexcept {
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double u = input.value(t);
  const double w = y[iw_];
  const double phi_rate = w - drive_.rate_rad_s(x, u);
  const double theta = drive_.angle_rad(x) + y[iphi_];
  const double tau = -weight_rc_ * std::cos(theta) - link_.ground_viscous_n_m_s_per_rad * w +
                     link_.external_torque_n_m + joint_.joint_friction.evaluate(phi_rate).force;
  return sigma * (tau / link_.inertia_kg_m2 - drive_.acceleration_rad_s2(x, u, input.rate(t)));
}

bool TorsionalSystem::check_consistency(double t, double* y, EventLog& log) noexcept {
  const double phi = y[iphi_];
  const double beta = joint_.half_play_rad;
  if (mode == ContactMode::free) {
    for (int s : {1, -1}) {
      if (s * phi - beta > 0.0) return onset(t, y, s, log) || true;
    }
  } else if (mode == ContactMode::contact && side_ * phi - beta < 0.0) {
    const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
    log.push({t, EventKind::separation, side_,
              side_ * (y[iw_] - drive_.rate_rad_s(x, input.value(t))), 0.0});
    mode = ContactMode::free;
    memory_ = {};
    if (-side_ * phi - beta > 0.0) onset(t, y, -side_, log);
    return true;
  }
  return false;
}

void TorsionalSystem::tolerances(const SolverOptions& o, double* atol) const {
  const auto& ca = drive_.angle_output();
  const auto& cr = drive_.rate_output();
  const double angle_scale = ca.cwiseAbs().maxCoeff();
  for (int i = 0; i < nd_; ++i) {
    double tol = o.angle_tolerance_rad;
    if (drive_.mode() == DriveMode::position) {
      if (angle_scale > 0.0) tol = o.angle_tolerance_rad / angle_scale;
    } else if (ca(i) == 0.0) {  // speed subsystem: scaled by the speed output
      const double rate_scale = cr.cwiseAbs().maxCoeff();
      if (rate_scale > 0.0) tol = o.rate_tolerance_rad_s / rate_scale;
    }
    atol[i] = tol;
  }
  atol[iphi_] = o.angle_tolerance_rad;
  atol[iw_] = o.rate_tolerance_rad_s;
  // energy integrals: J·(rate tolerance)·(1 rad/s), or out of the error test
  const double energy_tol = o.control_energy_error ? link_.inertia_kg_m2 * o.rate_tolerance_rad_s : kIgnoredWeight;
  atol[idiss_] = energy_tol;
  atol[iwork_] = energy_tol;
}

void TorsionalSystem::plastic_lock(double t, double* y, int side, double rate, EventLog& log) noexcept {
  // perfectly plastic impulse: the link takes the shaft's rate (Eq. 2.14 with e = 0)
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double omega_m = drive_.rate_rad_s(x, input.value(t));
  const double j = link_.inertia_kg_m2;
  const double dphi = y[iw_] - omega_m;
  y[idiss_] += 0.5 * j * dphi * dphi;
  y[iwork_] += j * (omega_m - y[iw_]) * omega_m;
  y[iw_] = omega_m;
  y[iphi_] = side * joint_.half_play_rad;
  const bool holds = lock_force(t, y, side) >= 0.0;
  if (holds) {
    mode = ContactMode::locked;
    side_ = side;
  } else {
    mode = ContactMode::free;
  }
  log.push({t, holds ? EventKind::lock : EventKind::impact, side, rate, 0.0});
}

bool TorsionalSystem::onset(double t, double* y, int sigma, EventLog& log) noexcept {
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double omega_m = drive_.rate_rad_s(x, input.value(t));
  const double rate = sigma * (y[iw_] - omega_m);
  const bool zeno = zeno_.onset(t);
  if (zeno) log.push({t, EventKind::zeno, sigma, rate, 0.0});
  if (joint_.impact) {
    const ImpactLaw& im = *joint_.impact;
    if (!zeno && rate >= im.static_rate && im.restitution * rate >= im.static_rate) {
      // Eq. 2.13–2.15 with the shaft imposed (infinite inertia): φ̇⁺ = −e φ̇⁻
      const double j = link_.inertia_kg_m2;
      const double e = im.restitution;
      const double w_before = y[iw_];
      const double w_after = omega_m - e * (w_before - omega_m);
      y[idiss_] += 0.5 * j * (1.0 - e * e) * rate * rate;
      y[iwork_] += j * (w_after - w_before) * omega_m;
      y[iw_] = w_after;
      y[iphi_] = sigma * joint_.half_play_rad;
      log.push({t, EventKind::impact, sigma, rate, -e * rate});
    } else {
      plastic_lock(t, y, sigma, rate, log);
    }
    return true;
  }
  const ContactLaw& law = joint_.law;
  mode = ContactMode::contact;
  side_ = sigma;
  memory_ = ContactMemory{law.latch_approach_rate(rate), false};
  log.push({t, EventKind::onset, sigma, rate, 0.0});
  if (zeno) {
    mode = ContactMode::persistent;
    memory_.approach_rate = 0.0;
    return true;
  }
  return law.jumps_at_onset();
}

bool TorsionalSystem::on_roots(double t, double* y, const int* found, EventLog& log) noexcept {
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double omega_m = drive_.rate_rad_s(x, input.value(t));
  auto idx = [](int sigma) { return sigma > 0 ? 0 : 1; };
  bool restart = false;
  switch (mode) {
    case ContactMode::free:
      for (int sigma : {1, -1}) {
        if (found[idx(sigma)] > 0) {
          restart = onset(t, y, sigma, log) || restart;
          break;
        }
      }
      break;
    case ContactMode::contact: {
      const int s = side_;
      if (found[idx(s)] < 0) {
        log.push({t, EventKind::separation, s, s * (y[iw_] - omega_m), 0.0});
        mode = ContactMode::free;
        memory_ = {};
        restart = joint_.law.jumps_at_onset();
        if (found[idx(-s)] > 0) restart = onset(t, y, -s, log) || restart;  // β = 0: other side
      } else if (found[2] != 0) {
        memory_.unloading = found[2] < 0;  // Eq. 2.3 from δ̇ < 0 on
        log.push({t, EventKind::rate_switch, s, s * (y[iw_] - omega_m), 0.0});
        restart = true;
      } else if (found[3] != 0 || found[4] != 0) {
        restart = true;  // a kink of the law (clamp/bound): restart the multistep history
      }
      break;
    }
    case ContactMode::persistent:
    case ContactMode::locked: {
      const int s = side_;
      if (found[idx(s)] < 0) {
        log.push({t, EventKind::release, s, s * (y[iw_] - omega_m), 0.0});
        if (mode == ContactMode::locked) y[iphi_] = s * joint_.half_play_rad;
        mode = ContactMode::free;
        memory_ = {};
        restart = true;
      } else if (found[idx(-s)] > 0) {
        mode = ContactMode::free;
        restart = onset(t, y, -s, log) || true;
      }
      break;
    }
  }
  return restart;
}

void TorsionalSystem::on_input_jump(double t, double* y) noexcept {
  if (mode != ContactMode::locked) return;
  // the shaft's rate may jump with the command (d_rate ≠ 0): the locked link follows rigidly
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const double w_new = drive_.rate_rad_s(x, input.value(t));
  y[iwork_] += 0.5 * link_.inertia_kg_m2 * (w_new * w_new - y[iw_] * y[iw_]);
  y[iw_] = w_new;
}

void TorsionalSystem::sample(double t, const double* y, Sample& s) const noexcept {
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const Terms r = terms(t, y);
  s.motor_angle = drive_.angle_rad(x);
  s.motor_rate = r.omega_m;
  s.link_angle = r.theta_l;
  s.link_rate = y[iw_];
  s.relative_angle = y[iphi_];
  s.mode = mode;
  if (mode == ContactMode::locked) {
    const double f = lock_force(t, y, side_);
    s.normal_force = f;
    s.contact_torque = -side_ * f;
    s.penetration = side_ * y[iphi_] - joint_.half_play_rad;
    s.contact_energy = 0.0;
  } else {
    s.normal_force = r.contact.force;
    s.contact_torque = r.tau_contact;
    s.penetration = r.delta;
    s.contact_energy = r.law_applied ? joint_.law.potential(r.delta) : 0.0;
  }
  const double w = y[iw_];
  s.kinetic = 0.5 * link_.inertia_kg_m2 * w * w;
  s.potential = weight_rc_ * std::sin(r.theta_l) - link_.external_torque_n_m * r.theta_l;
  s.dissipated = y[idiss_];
  s.drive_work = y[iwork_];
}

std::string TorsionalSystem::describe(double t, const double* y) const {
  std::ostringstream o;
  o.precision(9);
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  o << "t = " << t << " s, mode " << to_string(mode);
  if (mode != ContactMode::free) o << (side_ > 0 ? "(+)" : "(-)");
  o << ", relative angle phi = " << y[iphi_] << " rad (half play " << joint_.half_play_rad
    << " rad), link rate = " << y[iw_] << " rad/s, motor angle = " << drive_.angle_rad(x)
    << " rad, motor rate = " << drive_.rate_rad_s(x, input.value(t)) << " rad/s, command = "
    << input.value(t);
  return o.str();
}

}  // namespace clearshape::plant::detail
