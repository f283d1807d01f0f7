#include "planar_system.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "clearshape/core/error.hpp"

namespace clearshape::plant::detail {

namespace {
constexpr double kIgnoredWeight = 1e30;
}

PlanarSystem::PlanarSystem(const PlantModel& model, const SolverOptions& options)
    : drive_(model.drive), link_(model.link), joint_(std::get<PlanarClearance>(model.joint)) {
  nd_ = drive_.order();
  ip_ = nd_;
  iv_ = nd_ + 3;
  idiss_ = nd_ + 6;
  iwork_ = nd_ + 7;
  size = nd_ + 8;
  root_count = 2;
  weight_ = link_.in_plane_weight_n();
  release_gap_ = options.release_gap_fraction * joint_.radial_clearance_m;
  zeno_.configure(options.zeno_events, options.zeno_window_s);
}

void PlanarSystem::reset_discrete() noexcept {
  mode = ContactMode::free;
  memory_ = {};
  zeno_.clear();
}

Eigen::Matrix3d PlanarSystem::mass_matrix(double theta) const noexcept {
  const double m = link_.mass_kg;
  const double mr = m * link_.com_distance_m;
  const double s = std::sin(theta);
  const double c = std::cos(theta);
  Eigen::Matrix3d mm;
  mm << m, 0.0, -mr * s, 0.0, m, mr * c, -mr * s, mr * c, link_.inertia_kg_m2;
  return mm;
}

PlanarSystem::Terms PlanarSystem::terms(double t, const double* y) const noexcept {
  Terms r;
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  r.u = input.value(t);
  r.omega_m = drive_.rate_rad_s(x, r.u);
  const Eigen::Vector2d p(y[ip_], y[ip_ + 1]);
  const Eigen::Vector2d v(y[iv_], y[iv_ + 1]);
  const double theta = y[ip_ + 2];
  const double w = y[iv_ + 2];
  const double dist = std::hypot(p.x(), p.y());
  r.delta = dist - joint_.radial_clearance_m;  // Eq. 2.1: δ = −g_n = ‖p‖ − c
  if (dist > 0.0) {
    r.n = -p / dist;                 // from the bearing centre towards the journal
    r.delta_rate = p.dot(v) / dist;  // δ̇ = −n·ṗ
  }
  r.t = Eigen::Vector2d(-r.n.y(), r.n.x());  // t = k × n
  const ContactLaw& law = joint_.law;
  if (mode == ContactMode::free) {
    if (!joint_.impact && r.delta > 0.0 && !law.jumps_at_onset()) {
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
  const double fn = r.contact.force;
  const double rj = joint_.journal_radius_m;
  const double rb = joint_.bearing_radius_m();
  // slip of the journal surface relative to the bearing surface along t
  r.slip = r.omega_m * rj - v.dot(r.t) - w * rb;
  if (fn != 0.0) r.friction = joint_.friction.factor(r.slip).force * fn;  // Eq. 2.9 (regularized)
  const double m = link_.mass_kg;
  const double rc = link_.com_distance_m;
  const Eigen::Vector2d f = fn * r.n + r.friction * r.t + Eigen::Vector2d(0.0, -weight_);
  const double tau_g = -weight_ * rc * std::cos(theta);
  r.force << f.x() + m * rc * w * w * std::cos(theta), f.y() + m * rc * w * w * std::sin(theta),
      rb * r.friction + tau_g - link_.ground_viscous_n_m_s_per_rad * w + link_.external_torque_n_m;
  r.mass = mass_matrix(theta);
  return r;
}

int PlanarSystem::rhs(double t, const double* y, double* yd) noexcept {
  const auto& a = drive_.a();
  const auto& b = drive_.b();
  const Terms r = terms(t, y);
  for (int i = 0; i < nd_; ++i) {
    double v = b(i) * r.u;
    for (int j = 0; j < nd_; ++j) v += a(i, j) * y[j];
    yd[i] = v;
  }
  for (int k = 0; k < 3; ++k) yd[ip_ + k] = y[iv_ + k];
  const Eigen::Vector3d acc = r.mass.inverse() * r.force;  // M q̈ = Q + h
  for (int k = 0; k < 3; ++k) yd[iv_ + k] = acc(k);
  const double w = y[iv_ + 2];
  yd[idiss_] = (r.contact.force - r.contact.elastic) * r.delta_rate + r.friction * r.slip +
               link_.ground_viscous_n_m_s_per_rad * w * w;
  yd[iwork_] = r.friction * joint_.journal_radius_m * r.omega_m;
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(yd[i])) return 1;
  }
  return 0;
}

int PlanarSystem::roots(double, const double* y, double* g) noexcept {
  const double dist = std::hypot(y[ip_], y[ip_ + 1]);
  const double delta = dist - joint_.radial_clearance_m;
  g[0] = mode == ContactMode::persistent ? delta + release_gap_ : delta;
  if (mode == ContactMode::contact && joint_.law.switches_on_rate() && dist > 0.0) {
    g[1] = (y[ip_] * y[iv_] + y[ip_ + 1] * y[iv_ + 1]) / dist;
  } else {
    g[1] = 1.0;
  }
  return std::isfinite(g[0]) && std::isfinite(g[1]) ? 0 : -1;
}

void PlanarSystem::initial_state(const InitialState& init, double u0, double* y, EventLog& log) {
  reset_discrete();
  const DriveModel::Vector x = initial_drive_state(drive_, init, u0);
  require_finite("initial.pivot_x_m", init.pivot_x_m);
  require_finite("initial.pivot_y_m", init.pivot_y_m);
  require_finite("initial.pivot_vx_m_s", init.pivot_vx_m_s);
  require_finite("initial.pivot_vy_m_s", init.pivot_vy_m_s);
  require_finite("initial.relative_angle_rad", init.relative_angle_rad);
  require_finite("initial.link_rate_rad_s", init.link_rate_rad_s);
  for (int i = 0; i < nd_; ++i) y[i] = x(i);
  y[ip_] = init.pivot_x_m;
  y[ip_ + 1] = init.pivot_y_m;
  y[ip_ + 2] = drive_.angle_rad(x) + init.relative_angle_rad;
  y[iv_] = init.pivot_vx_m_s;
  y[iv_ + 1] = init.pivot_vy_m_s;
  y[iv_ + 2] = init.link_rate_rad_s;
  y[idiss_] = 0.0;
  y[iwork_] = 0.0;
  const double dist = std::hypot(y[ip_], y[ip_ + 1]);
  const double delta = dist - joint_.radial_clearance_m;
  const double rate = dist > 0.0 ? (y[ip_] * y[iv_] + y[ip_ + 1] * y[iv_ + 1]) / dist : 0.0;
  if (joint_.impact && delta > 0.0) {
    throw_invalid("initial.pivot", dist, "<= radial_clearance_m for an impulse law",
                  "a rigid impact law admits no penetration; start inside the clearance");
  }
  if (delta > 0.0 || (delta == 0.0 && rate > 0.0)) {
    onset(0.0, y, log);
    return;
  }
  if (delta == 0.0 && rate == 0.0 && dist > 0.0) {
    // on the boundary at rest: contact if the pivot accelerates outwards (δ̈ = p·a/‖p‖ > 0)
    std::vector<double> yd(static_cast<std::size_t>(size));
    rhs(0.0, y, yd.data());
    const double acc = (y[ip_] * yd[static_cast<std::size_t>(iv_)] +
                        y[ip_ + 1] * yd[static_cast<std::size_t>(iv_ + 1)]) / dist;
    if (acc > 0.0) onset(0.0, y, log);
  }
}

bool PlanarSystem::check_consistency(double t, double* y, EventLog& log) noexcept {
  const double dist = std::hypot(y[ip_], y[ip_ + 1]);
  const double delta = dist - joint_.radial_clearance_m;
  if (mode == ContactMode::free && delta > 0.0) return onset(t, y, log) || true;
  if (mode == ContactMode::contact && delta < 0.0) {
    const double rate = dist > 0.0 ? (y[ip_] * y[iv_] + y[ip_ + 1] * y[iv_ + 1]) / dist : 0.0;
    log.push({t, EventKind::separation, 0, rate, 0.0});
    mode = ContactMode::free;
    memory_ = {};
    return true;
  }
  return false;
}

void PlanarSystem::tolerances(const SolverOptions& o, double* atol) const {
  const double angle_scale = drive_.angle_output().cwiseAbs().maxCoeff();
  const double rate_scale = drive_.rate_output().cwiseAbs().maxCoeff();
  for (int i = 0; i < nd_; ++i) {
    double tol = o.angle_tolerance_rad;
    if (drive_.mode() == DriveMode::position) {
      if (angle_scale > 0.0) tol /= angle_scale;
    } else if (drive_.angle_output()(i) == 0.0 && rate_scale > 0.0) {
      tol = o.rate_tolerance_rad_s / rate_scale;
    }
    atol[i] = tol;
  }
  atol[ip_] = atol[ip_ + 1] = o.length_tolerance_m;
  atol[ip_ + 2] = o.angle_tolerance_rad;
  atol[iv_] = atol[iv_ + 1] = o.speed_tolerance_m_s;
  atol[iv_ + 2] = o.rate_tolerance_rad_s;
  // energy integrals: J·(rate tolerance)·(1 rad/s), or out of the error test
  const double energy_tol = o.control_energy_error ? link_.inertia_kg_m2 * o.rate_tolerance_rad_s : kIgnoredWeight;
  atol[idiss_] = energy_tol;
  atol[iwork_] = energy_tol;
}

bool PlanarSystem::onset(double t, double* y, EventLog& log) noexcept {
  const double px = y[ip_];
  const double py = y[ip_ + 1];
  const double dist = std::hypot(px, py);
  const double rate = dist > 0.0 ? (px * y[iv_] + py * y[iv_ + 1]) / dist : 0.0;
  const bool zeno = zeno_.onset(t);
  if (zeno) log.push({t, EventKind::zeno, 0, rate, 0.0});
  if (joint_.impact && !zeno && dist > 0.0) {
    const ImpactLaw& im = *joint_.impact;
    if (rate >= im.static_rate && im.restitution * rate >= im.static_rate) {
      // Eq. 2.13–2.15: frictionless impulse along w = (p/‖p‖, 0), δ̇ = wᵀu
      const Eigen::Matrix3d m = mass_matrix(y[ip_ + 2]);
      const Eigen::Vector3d w(px / dist, py / dist, 0.0);
      Eigen::Vector3d u(y[iv_], y[iv_ + 1], y[iv_ + 2]);
      const double ke_before = 0.5 * u.dot(m * u);
      const Eigen::Vector3d minv_w = m.inverse() * w;
      const double impulse = -(1.0 + im.restitution) * w.dot(u) / w.dot(minv_w);
      u += minv_w * impulse;
      const double ke_after = 0.5 * u.dot(m * u);
      y[idiss_] += ke_before - ke_after;  // the journal centre is fixed: no work
      for (int k = 0; k < 3; ++k) y[iv_ + k] = u(k);
      const double scale = joint_.radial_clearance_m / dist;  // back onto the boundary
      y[ip_] = px * scale;
      y[ip_ + 1] = py * scale;
      log.push({t, EventKind::impact, 0, rate, w.dot(u)});
      return true;
    }
  }
  const ContactLaw& law = joint_.law;
  mode = zeno ? ContactMode::persistent : ContactMode::contact;
  memory_ = ContactMemory{zeno ? 0.0 : law.latch_approach_rate(rate), false};
  log.push({t, EventKind::onset, 0, rate, 0.0});
  return zeno || law.jumps_at_onset() || joint_.impact.has_value();
}

bool PlanarSystem::on_roots(double t, double* y, const int* found, EventLog& log) noexcept {
  const double dist = std::hypot(y[ip_], y[ip_ + 1]);
  const double rate = dist > 0.0 ? (y[ip_] * y[iv_] + y[ip_ + 1] * y[iv_ + 1]) / dist : 0.0;
  switch (mode) {
    case ContactMode::free:
      if (found[0] > 0) return onset(t, y, log);
      return false;
    case ContactMode::contact:
      if (found[0] < 0) {
        log.push({t, EventKind::separation, 0, rate, 0.0});
        mode = ContactMode::free;
        memory_ = {};
        return joint_.law.jumps_at_onset() || joint_.impact.has_value();
      }
      if (found[1] != 0) {
        memory_.unloading = found[1] < 0;
        log.push({t, EventKind::rate_switch, 0, rate, 0.0});
        return true;
      }
      return false;
    case ContactMode::persistent:
    case ContactMode::locked:
      if (found[0] < 0) {
        log.push({t, EventKind::release, 0, rate, 0.0});
        mode = ContactMode::free;
        memory_ = {};
        return true;
      }
      return false;
  }
  return false;
}

void PlanarSystem::sample(double t, const double* y, Sample& s) const noexcept {
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  const Terms r = terms(t, y);
  s.motor_angle = drive_.angle_rad(x);
  s.motor_rate = r.omega_m;
  s.link_angle = y[ip_ + 2];
  s.link_rate = y[iv_ + 2];
  s.relative_angle = s.link_angle - s.motor_angle;
  s.contact_torque = joint_.bearing_radius_m() * r.friction;
  s.penetration = r.delta;
  s.normal_force = r.contact.force;
  s.pivot_x = y[ip_];
  s.pivot_y = y[ip_ + 1];
  s.friction_force = r.friction;
  s.mode = mode;
  const Eigen::Vector3d u(y[iv_], y[iv_ + 1], y[iv_ + 2]);
  s.kinetic = 0.5 * u.dot(r.mass * u);
  s.potential = weight_ * (y[ip_ + 1] + link_.com_distance_m * std::sin(y[ip_ + 2])) -
                link_.external_torque_n_m * y[ip_ + 2];
  s.contact_energy = r.law_applied ? joint_.law.potential(r.delta) : 0.0;
  s.dissipated = y[idiss_];
  s.drive_work = y[iwork_];
}

std::string PlanarSystem::describe(double t, const double* y) const {
  std::ostringstream o;
  o.precision(9);
  const Eigen::Map<const Eigen::VectorXd> x(y, nd_);
  o << "t = " << t << " s, mode " << to_string(mode) << ", pivot p = (" << y[ip_] << ", "
    << y[ip_ + 1] << ") m (clearance " << joint_.radial_clearance_m << " m), pivot velocity = ("
    << y[iv_] << ", " << y[iv_ + 1] << ") m/s, link angle = " << y[ip_ + 2]
    << " rad, link rate = " << y[iv_ + 2] << " rad/s, motor angle = " << drive_.angle_rad(x)
    << " rad";
  return o.str();
}

}  // namespace clearshape::plant::detail
