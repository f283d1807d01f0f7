// Clearance-joint dynamics oracles (docs/design.md §5) for the
// torsional play and the planar journal bearing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/plant/hertz.hpp"
#include "clearshape/plant/simulation.hpp"

namespace cp = clearshape::plant;

namespace {
// A motor that stays at rest (command 0): the stop is fixed.
cp::PlantModel fixed_stop(double inertia, double half_play, cp::ContactLaw law) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.01);
  m.link.inertia_kg_m2 = inertia;
  cp::TorsionalClearance j;
  j.half_play_rad = half_play;
  j.law = law;
  m.joint = j;
  return m;
}
cp::SimulationOptions tight(double duration, double rate_hz) {
  cp::SimulationOptions o;
  o.duration_s = duration;
  o.output_rate_hz = rate_hz;
  o.solver.relative_tolerance = 1e-11;
  o.solver.angle_tolerance_rad = 1e-13;
  o.solver.rate_tolerance_rad_s = 1e-12;
  return o;
}
long count(const cp::Simulation& r, cp::EventKind kind) {
  return std::count_if(r.events.begin(), r.events.end(),
                       [kind](const cp::ContactEvent& e) { return e.kind == kind; });
}
double energy_drift(const cp::Simulation& r) {
  double scale = 0.0;
  double drift = 0.0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    scale = std::max({scale, std::abs(r.kinetic_energy_j[k]), std::abs(r.drive_work_j[k]),
                      std::abs(r.dissipated_energy_j[k]), std::abs(r.potential_energy_j[k])});
    drift = std::max(drift, std::abs(r.energy_balance_j(k) - r.energy_balance_j(0)));
  }
  return drift / scale;
}
}  // namespace

// T5: inside the play the link flies ballistically: φ(t) = φ₀ + ω₀t + ½(τ/J)t², and the first
// contact happens at the analytic root.
TEST(Joint, FreeFlightIsBallisticAndOnsetIsExact) {
  auto m = fixed_stop(0.5, 0.05, cp::ContactLaw::hertz_dashpot(1e4, 1.5, 10.0));
  m.link.external_torque_n_m = 0.2;
  auto o = tight(0.19, 1000.0);
  o.initial.link_rate_rad_s = -0.3;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  for (std::size_t k = 0; k < r.size(); ++k) {
    const double t = r.time_s[k];
    ASSERT_NEAR(r.relative_angle_rad[k], -0.3 * t + 0.2 * t * t, 1e-12) << "t = " << t;
    ASSERT_NEAR(r.link_rate_rad_s[k], -0.3 + 0.4 * t, 1e-12);
  }
  auto o2 = tight(0.2, 1000.0);
  o2.initial = o.initial;
  const auto hit = cp::simulate(m, cp::Command::constant(0.0), o2);
  ASSERT_FALSE(hit.events.empty());
  const double t_contact = (0.3 - std::sqrt(0.09 - 0.04)) / 0.4;  // 0.2t² − 0.3t + 0.05 = 0
  EXPECT_EQ(hit.events.front().kind, cp::EventKind::onset);
  EXPECT_EQ(hit.events.front().side, -1);
  EXPECT_NEAR(hit.events.front().time_s, t_contact, 1e-12);
  EXPECT_NEAR(hit.events.front().rate, 0.3 - 0.4 * t_contact, 1e-11);  // approach rate
}

// T5 planar: the journal centred, gravity in the plane: p_y = −½ g t² until ‖p‖ = c at
// t = √(2c/g).
TEST(Joint, PlanarFreeFallIsBallistic) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.01);
  m.link.mass_kg = 1.0;
  m.link.inertia_kg_m2 = 1e-3;
  m.link.axis_tilt_rad = std::numbers::pi / 2;
  cp::PlanarClearance j;
  j.radial_clearance_m = 1e-4;
  j.law = cp::ContactLaw::hertz_dashpot(1e9, 1.5, 1e3);
  m.joint = j;
  cp::SimulationOptions o;
  o.duration_s = 0.005;
  o.output_rate_hz = 1e4;
  o.solver.relative_tolerance = 1e-11;
  o.solver.length_tolerance_m = 1e-16;
  o.solver.speed_tolerance_m_s = 1e-14;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  const double g = m.link.gravity_m_s2;
  const double t_contact = std::sqrt(2.0 * 1e-4 / g);
  for (std::size_t k = 0; k < r.size() && r.time_s[k] < t_contact; ++k) {
    const double t = r.time_s[k];
    ASSERT_NEAR(r.pivot_y_m[k], -0.5 * g * t * t, 1e-15) << "t = " << t;
    ASSERT_EQ(r.pivot_x_m[k], 0.0);
  }
  ASSERT_FALSE(r.events.empty());
  EXPECT_NEAR(r.events.front().time_s, t_contact, 1e-12);
  EXPECT_NEAR(r.events.front().rate, g * t_contact, 1e-9);
}

// T6 / B3: bouncing penalty mass (EXUDYN postNewtonStepContactTest set-up) mapped to the play:
// J = 0.25, constant torque −J·g, linear penalty k = 2e4, no damping, gap 0.01, v₀ = −1.
// Exact: p(0.1) = 0.055827899, p(0.25) = −0.003956979, p(0.5) = 0.010939776; 6 switches.
TEST(Joint, BouncingPenaltyMassMatchesExactSolution) {
  auto m = fixed_stop(0.25, 0.1, cp::ContactLaw::kelvin_voigt(2e4, 0.0));
  m.link.external_torque_n_m = -0.25 * 9.81;
  auto o = tight(0.5, 200.0);
  o.initial.relative_angle_rad = -0.1 + 0.01;  // p = φ + β = 0.01
  o.initial.link_rate_rad_s = -1.0;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  auto p = [&](std::size_t k) { return r.relative_angle_rad[k] + 0.1; };
  EXPECT_NEAR(p(20), 0.055827899, 1e-8);
  EXPECT_NEAR(p(50), -0.003956979, 1e-8);
  EXPECT_NEAR(p(100), 0.010939776, 1e-8);  // reference tolerance 1e-6
  EXPECT_NEAR(r.link_rate_rad_s[100], 0.990737904, 1e-7);
  EXPECT_EQ(count(r, cp::EventKind::onset) + count(r, cp::EventKind::separation), 6);
  EXPECT_NEAR(r.events[0].rate, 1.093709285, 1e-8);                         // impact speed
  EXPECT_NEAR(r.events[1].time_s - r.events[0].time_s, 0.011331369, 1e-8);  // contact time
  EXPECT_NEAR(r.events[2].time_s - r.events[1].time_s, 0.222978447, 1e-8);  // flight time
  // the work integrals' truncation error grows ~1e-9 J per impact at rtol 1e-11 (scale 0.25 J)
  EXPECT_LT(energy_drift(r), 2e-8);
}

// T7 / B4: a steady torque presses the link on the stop: F_N → τ, δ = (τ/K)^(1/n), no
// chattering after settling.
TEST(Joint, StaticContactCarriesTheLoad) {
  const double k = 1e4, tau = 0.5;
  auto m = fixed_stop(1e-3, 0.01, cp::ContactLaw::hertz_dashpot(k, 1.5, 5.0));
  m.link.external_torque_n_m = tau;
  auto o = tight(0.5, 100.0);
  o.solver.angle_tolerance_rad = 1e-16;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  EXPECT_NEAR(r.normal_force.back() / tau, 1.0, 1e-9);
  EXPECT_NEAR(r.penetration.back() / std::pow(tau / k, 1.0 / 1.5), 1.0, 1e-9);
  EXPECT_NEAR(r.relative_angle_rad.back(), 0.01 + std::pow(tau / k, 1.0 / 1.5), 1e-12);
  EXPECT_LE(r.stats.events, 2);
}

// T7 planar: steel journal on the bearing under W = 100 N: F_N = W, δ = (W/K)^(2/3) = 1.318e-6 m,
// friction → 0.
TEST(Joint, PlanarStaticContactCarriesTheWeight) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.01);
  m.link.mass_kg = 100.0 / 9.80665;
  m.link.inertia_kg_m2 = 1e-2;
  m.link.axis_tilt_rad = std::numbers::pi / 2;
  cp::PlanarClearance j;
  j.radial_clearance_m = 5e-4;
  j.journal_radius_m = 9.5e-3;
  const double k = cp::hertz_stiffness(cp::Material::steel(), cp::Material::steel(),
                                       cp::effective_radius_internal(9.5e-3, 10e-3));
  j.law = cp::ContactLaw::hertz_dashpot(k, 1.5, 5e4);
  j.friction.coefficient = 0.1;
  m.joint = j;
  cp::SimulationOptions o;
  o.duration_s = 0.1;
  o.output_rate_hz = 100.0;
  o.initial.pivot_y_m = -5e-4;  // resting on the bearing, no penetration yet
  o.solver.relative_tolerance = 1e-10;
  o.solver.length_tolerance_m = 1e-17;
  o.solver.speed_tolerance_m_s = 1e-15;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  EXPECT_NEAR(r.normal_force.back() / 100.0, 1.0, 1e-9);
  EXPECT_NEAR(r.penetration.back(), 1.318e-6, 0.001e-6);
  EXPECT_NEAR(r.penetration.back() / std::pow(100.0 / k, 1.0 / 1.5), 1.0, 1e-9);
  EXPECT_NEAR(r.friction_force_n.back(), 0.0, 1e-9);
  EXPECT_LE(r.stats.events, 2);
}

// T8: the energy balance E_kin + E_pot + V − W_drive + W_diss closes (drive step, gravity,
// joint friction, drag, several impacts, clamped thesis law).
TEST(Joint, EnergyBalanceCloses) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::thesis_position_mode();
  m.link.inertia_kg_m2 = 2e-3;
  m.link.mass_kg = 0.2;
  m.link.com_distance_m = 0.05;
  m.link.axis_tilt_rad = 0.3;
  m.link.ground_viscous_n_m_s_per_rad = 1e-4;
  cp::TorsionalClearance j;
  j.half_play_rad = clearshape::deg_to_rad(0.5);
  j.law = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 2.0, cp::DampingPolicy::clamped);
  j.joint_friction.coulomb = 2e-3;
  j.joint_friction.viscous = 1e-4;
  j.joint_friction.regularization_rate = 1e-2;
  m.joint = j;
  auto o = tight(0.6, 1000.0);
  const auto r = cp::simulate(m, cp::Command::step(0.05, 10.0), o);
  EXPECT_GE(count(r, cp::EventKind::onset), 2);
  EXPECT_GT(r.dissipated_energy_j.back(), 0.0);
  EXPECT_LT(energy_drift(r), 1e-6);
}

// T8 planar: journal bearing with friction, gravity and a turning shaft.
TEST(Joint, PlanarEnergyBalanceCloses) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.02);
  m.link.mass_kg = 0.2;
  m.link.inertia_kg_m2 = 1e-3;
  m.link.com_distance_m = 0.03;
  m.link.axis_tilt_rad = std::numbers::pi / 2;
  cp::PlanarClearance j;
  j.radial_clearance_m = 1e-4;
  j.journal_radius_m = 5e-3;
  j.law = cp::ContactLaw::hysteresis(cp::Hysteresis::flores, 1e9, 1.5, 0.7);
  j.friction.coefficient = 0.2;
  j.friction.regularization_rate = 1e-3;
  m.joint = j;
  cp::SimulationOptions o;
  o.duration_s = 0.1;
  o.output_rate_hz = 2000.0;
  o.solver.relative_tolerance = 1e-10;
  o.solver.length_tolerance_m = 1e-15;
  o.solver.speed_tolerance_m_s = 1e-12;
  o.solver.angle_tolerance_rad = 1e-13;
  o.solver.rate_tolerance_rad_s = 1e-11;
  const auto r = cp::simulate(m, cp::Command::step(0.01, 30.0), o);
  EXPECT_GE(count(r, cp::EventKind::onset), 2);
  EXPECT_GT(r.drive_work_j.back(), 0.0);  // the shaft drives the link through friction
  EXPECT_LT(energy_drift(r), 1e-6);
}

// T9: impulse law — δ̇⁺ = −e δ̇⁻ exactly; the rigid impacts dissipate ½J(1−e²)δ̇⁻² each.
TEST(Joint, ImpulseLawReversesTheApproachRate) {
  auto m = fixed_stop(0.2, 0.05, cp::ContactLaw::kelvin_voigt(1.0, 0.0));
  std::get<cp::TorsionalClearance>(m.joint).impact = cp::ImpactLaw{0.6, 1e-3};
  auto o = tight(0.3, 1000.0);
  o.initial.link_rate_rad_s = 1.0;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  ASSERT_GE(count(r, cp::EventKind::impact), 2);
  double v = 1.0;
  int side = 1;
  double t = 0.0;
  double expected_t = 0.05;  // first impact at φ = β
  for (const auto& e : r.events) {
    ASSERT_EQ(e.kind, cp::EventKind::impact);
    EXPECT_EQ(e.side, side);
    EXPECT_NEAR(e.time_s, expected_t, 1e-12);
    EXPECT_NEAR(e.rate, v, 1e-12);
    EXPECT_DOUBLE_EQ(e.rate_after, -0.6 * e.rate);
    t = e.time_s;
    v *= 0.6;
    side = -side;
    expected_t = t + 0.1 / v;  // crosses the play 2β at the new rate
  }
  const double ke0 = 0.5 * 0.2 * 1.0;
  EXPECT_NEAR(r.kinetic_energy_j.back() + r.dissipated_energy_j.back(), ke0, 1e-12);
}

// T9: a slow approach locks the link to the shaft; the lock holds while the constraint torque
// pushes and releases when it would pull (here: when the shaft starts to decelerate, α_m = 0
// at t = τ for a critically damped drive θ = θ_f(1 − (1 + t/τ)e^(−t/τ))).
TEST(Joint, SlowApproachLocksUntilTheConstraintWouldPull) {
  const double tau = 0.1;
  clearshape::lti::StateSpace ss;  // 1/(τ s + 1)²
  ss.a = Eigen::MatrixXd(2, 2);
  ss.a << -1.0 / tau, 0.0, 1.0 / tau, -1.0 / tau;
  ss.b = Eigen::MatrixXd(2, 1);
  ss.b << 1.0 / tau, 0.0;
  ss.c = Eigen::MatrixXd(1, 2);
  ss.c << 0.0, 1.0;
  ss.d = Eigen::MatrixXd::Zero(1, 1);
  cp::PlantModel m;
  m.drive = cp::DriveModel::position_mode(ss, 1.0);  // command in rad
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 0.02;
  j.impact = cp::ImpactLaw{0.5, 1e-3};
  m.joint = j;
  auto o = tight(0.2, 1000.0);
  o.initial.relative_angle_rad = -0.02 + 1e-9;  // touching the trailing stop
  o.initial.drive_state = Eigen::VectorXd::Zero(2);  // the command steps at t = 0
  const auto r = cp::simulate(m, cp::Command::constant(1.0), o);
  ASSERT_GE(r.events.size(), 2u);
  EXPECT_EQ(r.events[0].kind, cp::EventKind::lock);
  EXPECT_EQ(r.events[0].side, -1);
  EXPECT_LT(r.events[0].rate, 1e-3);
  EXPECT_EQ(r.events[1].kind, cp::EventKind::release);
  EXPECT_NEAR(r.events[1].time_s, tau, 1e-9);
  for (std::size_t k = 1; k < 100; ++k) {  // locked: link = motor − β, contact torque = J α_m
    const double t = r.time_s[k];
    ASSERT_NEAR(r.link_angle_rad[k], r.motor_angle_rad[k] - 0.02, 1e-8);
    const double alpha = std::exp(-t / tau) * (1.0 - t / tau) / (tau * tau);
    ASSERT_NEAR(r.contact_torque_n_m[k], 1e-3 * alpha, 1e-9) << "t = " << t;
  }
}

// T11: zero clearance with a stiff, damped joint follows the rigid drive.
TEST(Joint, ZeroClearanceFollowsTheRigidDrive) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::thesis_position_mode();
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 0.0;
  const double k = 1e5;  // N·m/rad: ω_n = 1e4 rad/s against the drive's ~100 rad/s
  j.law = cp::ContactLaw::kelvin_voigt_restitution(k, 0.3, 1e-3);
  m.joint = j;
  cp::SimulationOptions o;
  o.duration_s = 0.3;
  o.output_rate_hz = 1000.0;
  o.initial.drive_state = Eigen::VectorXd::Zero(m.drive.order());
  const auto r = cp::simulate(m, cp::Command::constant(20.0), o);
  double worst = 0.0;
  double worst_quasi_static = 0.0;
  for (std::size_t k2 = 1; k2 < r.size(); ++k2) {
    worst = std::max(worst, std::abs(r.link_angle_rad[k2] - r.motor_angle_rad[k2]));
    const double alpha = (r.motor_rate_rad_s[k2] - r.motor_rate_rad_s[k2 - 1]) * 1000.0;
    worst_quasi_static = std::max(worst_quasi_static, std::abs(1e-3 * alpha / k));
  }
  EXPECT_LT(worst, 1e-4 * clearshape::deg_to_rad(20.0));  // within 1e-4 of the motion
  EXPECT_LT(worst, 2.0 * worst_quasi_static + 1e-9);      // ≈ J α_m / k
  EXPECT_NEAR(r.link_angle_rad.back(), clearshape::deg_to_rad(20.0 * 0.9959), 1e-9);
}

// T12: the gyroscope sampled on the simulated link rate (dense output) equals ω_l at the
// sample instants: free flight under a constant torque, ω = ω₀ + (τ/J) t.
TEST(Joint, GyroscopeSamplesTheLinkRate) {
  auto m = fixed_stop(0.5, 1.0, cp::ContactLaw::hertz_dashpot(1e4, 1.5, 10.0));
  m.link.external_torque_n_m = 0.1;
  auto o = tight(0.5, 1000.0);
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  cp::GyroscopeConfig cfg;
  cfg.noise_density_dps_per_rthz = 0.0;
  cp::Gyroscope g(cfg);
  for (std::size_t k = 0; k < r.size(); ++k) {
    const double exact = 0.2 * r.time_s[k];
    ASSERT_EQ(g.sample(r.link_rate_rad_s[k]).raw, g.quantize(exact)) << "t = " << r.time_s[k];
  }
}

// Zeno guard: a rigid bounce under a steady torque with e = 0.8 and no static threshold would
// accumulate infinitely many impacts; the guard locks it.
TEST(Joint, ZenoGuardLocksAnAccumulatingBounce) {
  auto m = fixed_stop(0.1, 0.05, cp::ContactLaw::kelvin_voigt(1.0, 0.0));
  std::get<cp::TorsionalClearance>(m.joint).impact = cp::ImpactLaw{0.8, 0.0};
  m.link.external_torque_n_m = 1.0;
  cp::SimulationOptions o;
  o.duration_s = 1.0;
  o.solver.zeno_events = 20;
  o.solver.zeno_window_s = 0.05;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  EXPECT_EQ(count(r, cp::EventKind::zeno), 1);
  EXPECT_EQ(r.mode.back(), static_cast<std::uint8_t>(cp::ContactMode::locked));
  EXPECT_NEAR(r.normal_force.back(), 1.0, 1e-9);
  EXPECT_NEAR(r.relative_angle_rad.back(), 0.05, 1e-12);
}

// The streaming Simulator (rig) reproduces the offline run tick by tick.
TEST(Joint, StreamingSimulatorMatchesOffline) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::thesis_position_mode();
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = clearshape::deg_to_rad(0.5);
  j.law = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 300.0, cp::DampingPolicy::clamped);
  m.joint = j;
  cp::SimulationOptions o;
  o.duration_s = 0.3;
  const auto offline = cp::simulate(m, cp::Command::step(0.05, 10.0), o);
  cp::Simulator sim(m, o.solver);
  for (std::size_t k = 1; k < offline.size(); ++k) {
    const double t = offline.time_s[k];
    const double command = t > 0.05 + 1e-9 ? 10.0 : 0.0;  // held over (t_{k−1}, t_k]
    ASSERT_EQ(sim.advance(t, offline.time_s[k - 1] >= 0.05 - 1e-12 ? 10.0 : command), clearshape::Status::ok)
        << sim.error_message();
    ASSERT_NEAR(sim.state().link_angle_rad, offline.link_angle_rad[k], 1e-6) << "t = " << t;
  }
  EXPECT_EQ(sim.advance(0.1, 0.0), clearshape::Status::out_of_range);
  EXPECT_EQ(sim.advance(1.0, std::nan("")), clearshape::Status::not_finite);
}

TEST(Joint, FailuresNameTimeStateAndRemedy) {
  auto m = fixed_stop(1e-3, 0.01, cp::ContactLaw::hertz_dashpot(1e4, 1.5, 300.0));
  cp::SimulationOptions o;
  o.duration_s = 1.0;
  o.initial.link_rate_rad_s = 2.0;
  o.solver.max_steps_per_output = 3;
  try {
    (void)cp::simulate(m, cp::Command::constant(0.0), o);
    FAIL() << "expected RuntimeError";
  } catch (const clearshape::RuntimeError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("t = "), std::string::npos) << what;
    EXPECT_NE(what.find("relative angle"), std::string::npos) << what;
    EXPECT_NE(what.find("max_steps_per_output"), std::string::npos) << what;
  }
  cp::SimulationOptions bad;
  bad.solver.relative_tolerance = -1.0;
  EXPECT_THROW((void)cp::simulate(m, cp::Command::constant(0.0), bad), clearshape::InvalidArgument);
  m.link.inertia_kg_m2 = 0.0;
  EXPECT_THROW((void)cp::simulate(m, cp::Command::constant(0.0), {}), clearshape::InvalidArgument);
}

// T14 / B8: Modelica Rotational.Examples.Backlash parameters (J = 5 kg·m², c = 2e4 N·m/rad,
// d = 50 N·m·s/rad, b = 45°, φ(0) = 90°): the ElastoBacklash (bounded damper) torque never
// pulls and is continuous at onset; the ElastoBacklash2 (clamped) torque jumps by d·δ̇⁻.
TEST(Joint, ModelicaBacklashVariants) {
  const double beta = clearshape::deg_to_rad(22.5);
  for (auto policy : {cp::DampingPolicy::bounded, cp::DampingPolicy::clamped}) {
    auto m = fixed_stop(5.0, beta, cp::ContactLaw::kelvin_voigt(2e4, 50.0, policy));
    cp::SimulationOptions o;
    o.duration_s = 1.0;
    o.output_rate_hz = 1e4;
    o.initial.relative_angle_rad = clearshape::deg_to_rad(90.0);
    const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
    EXPECT_GE(*std::min_element(r.normal_force.begin(), r.normal_force.end()), 0.0);
    const auto onset = std::find_if(r.events.begin(), r.events.end(), [](const cp::ContactEvent& e) {
      return e.kind == cp::EventKind::onset && e.time_s > 0.0;
    });
    ASSERT_NE(onset, r.events.end()) << cp::to_string(policy);
    const auto k = static_cast<std::size_t>(std::ceil(onset->time_s * 1e4 + 1e-9));
    const double jump = 50.0 * onset->rate;
    if (policy == cp::DampingPolicy::bounded) {
      EXPECT_LE(r.normal_force[k], 2.0 * 2e4 * r.penetration[k] * (1 + 1e-9));
      EXPECT_LT(r.normal_force[k], 0.2 * jump);
    } else {
      EXPECT_GT(r.normal_force[k], 0.8 * jump);
    }
  }
}

// T9 planar: frictionless impulses of the pivot against the bearing (M with the link's
// rotation coupled through r_c): δ̇⁺ = −e δ̇⁻ along the normal, kinetic energy lost only to the
// impacts, and the pivot stays inside the clearance.
TEST(Joint, PlanarImpulsesReverseTheNormalRate) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.01);
  m.link.mass_kg = 0.3;
  m.link.inertia_kg_m2 = 2e-3;
  m.link.com_distance_m = 0.04;
  cp::PlanarClearance j;
  j.radial_clearance_m = 1e-3;
  j.law = cp::ContactLaw::hertz_dashpot(1e8, 1.5, 0.0);
  j.impact = cp::ImpactLaw{0.7, 1e-4};
  m.joint = j;
  auto o = tight(0.05, 1e4);
  o.solver.length_tolerance_m = 1e-15;
  o.solver.speed_tolerance_m_s = 1e-13;
  o.initial.pivot_vx_m_s = 0.2;
  o.initial.pivot_vy_m_s = 0.05;
  o.initial.link_rate_rad_s = 3.0;
  const auto r = cp::simulate(m, cp::Command::constant(0.0), o);
  ASSERT_GE(count(r, cp::EventKind::impact), 3);
  for (const auto& e : r.events) {
    if (e.kind != cp::EventKind::impact) continue;
    EXPECT_NEAR(e.rate_after, -0.7 * e.rate, 1e-12 * std::abs(e.rate));
  }
  for (std::size_t k = 0; k < r.size(); ++k) {
    ASSERT_LE(std::hypot(r.pivot_x_m[k], r.pivot_y_m[k]), 1e-3 * (1 + 1e-9));
  }
  EXPECT_LT(energy_drift(r), 1e-8);
  EXPECT_GT(r.dissipated_energy_j.back(), 0.0);
}
