// Take-up design (study/take_up.hpp) against the physics it is derived from: the drive's rate
// response against the first-order law in closed form, the design against its pure-delay closed
// form on a drive that barely lags, the take-up in a noise-free simulation of the nonlinear model
// (the link gains exactly the play on the motor in the dip and then rides the braking flank to
// rest), and the flank-keeping bound α = c/J reproduced by simulation on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/study/take_up.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;

namespace {

constexpr double kT = 1.0 / 30.0;

cs::lti::ProcessModel thesis_position_drive() {
  cs::lti::ProcessParameters p;  // thesis Eq. 4.2, position mode
  p.kp = 0.9959;
  p.tz = 0.0042;
  p.zeta = 0.9968;
  p.tw = 0.0102;
  p.tp3 = 0.0034;
  return cs::lti::ProcessModel("P3UZ", p);
}

// The large-play rig's joint as the thesis law can state it: 1° of play, a stiff n = 1.5 flank,
// the bearing's Coulomb friction 2e-3 N·m on J = 5e-3 kg·m² (α = 0.4 rad/s²).
st::ClearanceModel large_play_model() {
  st::ClearanceModel m;
  m.mode = cs::rig::CommandMode::position;
  m.drive = thesis_position_drive();
  m.link_inertia_kg_m2 = 5e-3;
  m.play_rad = cs::deg_to_rad(1.0);
  m.stiffness = 1e6;
  m.exponent = 1.5;
  m.damping = 2.0;
  m.coulomb_n_m = 2e-3;
  return m;
}

// What the pulse generator delivers for a shaped step (signal/position_path.hpp): the position
// ramps at v_k = a_k·θ/T through slot k, from `start_s`; sampled at T/32 so the slots align.
constexpr double kTs = kT / 32.0;

st::ModelResponse respond(const st::ClearanceModel& m, double move, const cs::shaping::Shaper& shaper, double start_s,
                          double duration_s, double initial_play_fraction) {
  const auto n = static_cast<std::size_t>(duration_s / kTs) + 1;
  cs::UniformSeries drive{0.0, kTs, std::vector<double>(n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * kTs - start_s;
    for (const auto& i : shaper.impulses()) drive.values[k] += move * i.amplitude * std::clamp((t - i.time_s) / kT, 0.0, 1.0);
  }
  return st::simulate_drive_command(m, drive, duration_s, initial_play_fraction);
}

double at(const std::vector<double>& v, double t_s) { return v[static_cast<std::size_t>(std::lround(t_s / kTs))]; }

}  // namespace

TEST(TakeUp, DriveRateResponseIsTheFirstOrderLawInClosedForm) {
  const double tau = 0.01;
  cs::lti::ProcessParameters p;
  p.tp1 = tau;
  const cs::lti::ProcessModel drive("P1", p);
  const double dt = kT / 100.0;
  const auto w = st::drive_rate_response(drive, {90.0}, kT, dt, 3.0 * kT);
  ASSERT_EQ(w.size(), 301u);
  for (std::size_t i = 0; i < w.size(); i += 7) {
    const double t = static_cast<double>(i) * dt;
    // ω = v(1 − e^(−t/τ)) while the slot lasts, then the free decay from ω(T).
    const double expected = t <= kT ? 90.0 * (1.0 - std::exp(-t / tau))
                                    : 90.0 * (1.0 - std::exp(-kT / tau)) * std::exp(-(t - kT) / tau);
    EXPECT_NEAR(w[i], expected, 1e-9 * 90.0) << "t = " << t;
  }
}

TEST(TakeUp, OnADriveThatBarelyLagsTheDesignIsThePureDelayClosedForm) {
  st::TakeUpRequest r;
  r.model = large_play_model();
  cs::lti::ProcessParameters fast;  // a 0.3 ms first-order drive: the command, a hair late
  fast.tp1 = 3e-4;
  r.model.drive = cs::lti::ProcessModel("P1", fast);
  r.moves = {20.0};
  r.max_duration_s = 2.0 * kT;  // carry, dip, recover
  const auto d = st::design_take_up(r);
  ASSERT_EQ(d.moves.size(), 1u);
  const auto& v = d.moves[0].slot_velocity_deg_s;
  ASSERT_EQ(v.size(), 3u);
  const double carry = (20.0 + 1.0) / (3.0 * kT);  // (θ + 2β)/(3T), header
  EXPECT_NEAR(v[0], carry, 0.01 * carry);
  EXPECT_NEAR(v[1], carry - 1.0 / kT, 0.01 * carry);  // (v_c − v_d)·T = 2β
  EXPECT_NEAR(v[2], carry, 0.01 * carry);
}

TEST(TakeUp, PositiveShaperOnTheGridThatSumsToTheMoveForEitherSign) {
  st::TakeUpRequest r;
  r.model = large_play_model();
  r.moves = {10.0, -10.0, 20.0};
  const auto d = st::design_take_up(r);
  ASSERT_EQ(d.moves.size(), 3u);
  for (const auto& m : d.moves) {
    EXPECT_TRUE(m.shaper.is_positive());
    EXPECT_NEAR(m.shaper.amplitude_sum(), 1.0, 1e-12);
    EXPECT_LE(m.shaper.duration_s(), r.max_duration_s + 1e-12);
    for (const auto& i : m.shaper.impulses()) EXPECT_NEAR(i.time_s / kT, std::round(i.time_s / kT), 1e-12);
    ASSERT_EQ(m.slot_velocity_deg_s.size(), 4u);                 // lead, carry, dip, recover
    EXPECT_NEAR(m.slot_velocity_deg_s[0], 1.0 / kT, 1e-9);         // lead 2β/T
    EXPECT_LT(m.slot_velocity_deg_s[2], m.slot_velocity_deg_s[1]);  // the dip
    EXPECT_NEAR(m.take_up_deg, 1.0, 1e-3);
    EXPECT_NEAR(m.contact_relative_rate_deg_s, 0.0, 1e-3 * std::abs(m.move_deg) / kT);
    EXPECT_LT(m.reversal_deg_s, 1e-6);  // the thesis drive (ζ ≈ 1) never reverses
  }
  for (std::size_t k = 0; k < d.moves[0].shaper.size(); ++k) {
    EXPECT_DOUBLE_EQ(d.moves[0].shaper.impulses()[k].amplitude, d.moves[1].shaper.impulses()[k].amplitude);
  }
  EXPECT_NEAR(d.flank_keeping_deceleration_rad_s2, 0.4, 1e-12);
  EXPECT_NEAR(d.flank_keeping_move_time_s[2], 2.0 * std::sqrt(cs::deg_to_rad(20.0) / 0.4), 1e-12);
}

TEST(TakeUp, InTheModelTheLinkGainsThePlayInTheDipAndRidesTheBrakingFlankToRest) {
  st::TakeUpRequest r;
  r.model = large_play_model();
  r.moves = {20.0};
  const auto d = st::design_take_up(r);
  const auto& m = d.moves[0];
  const double start_s = 0.2;
  // On the rear flank at the start (the lead slot's pick-up is then a contact, not an impact).
  const auto resp = respond(r.model, 20.0, m.shaper, start_s, 1.5, -1.0);
  const double beta = 0.5;
  std::vector<double> phi(resp.link_angle_deg.size());  // link − motor, deg, −β at rest
  for (std::size_t i = 0; i < phi.size(); ++i) phi[i] = resp.link_angle_deg[i] - resp.motor_angle_deg[i] - beta;
  const double slot0 = start_s;
  const double t1 = slot0 + m.separation_s, t2 = slot0 + m.contact_s;
  EXPECT_NEAR(at(phi, t1), -beta, 0.02);  // still on the rear flank when the motor peaks
  // The take-up: the relative displacement over the dip is the play, within what the design's
  // kinematics leave out — the loaded flank springs back as the motor peaks and the link leaves
  // about 1 deg/s faster than the motor's peak (≈ 0.05° over the 0.06 s dip).
  EXPECT_NEAR(at(phi, t2) - at(phi, t1), 1.0, 0.08);
  // From contact on, the link stays on the braking flank: no excursion into the play.
  double lowest = 1e9;
  for (double t = t2 + 0.01; t < 1.5; t += kTs) lowest = std::min(lowest, at(phi, t));
  EXPECT_GT(lowest, beta - 0.06);
  // The residual vibration Eq. 5.1 on the link angle: the unshaped step leaves the link moving in
  // the play; the take-up leaves the drive's own approach.
  cs::metrics::MeanDeviationOptions o;
  o.search_from_s = start_s;
  const auto md = [&](const st::ModelResponse& x) {
    return cs::metrics::mean_deviation(cs::UniformSeries{0.0, x.sample_time_s, x.link_angle_deg}, o).mean_deviation;
  };
  const auto unshaped = respond(r.model, 20.0, cs::shaping::Shaper("none", {{0.0, 1.0}}), start_s, 1.5, -1.0);
  EXPECT_LT(md(resp), 0.25 * md(unshaped)) << md(resp) << " vs " << md(unshaped);
}

TEST(TakeUp, FlankKeepingHoldsBelowFrictionOverInertiaAndSeparatesAbove) {
  st::ClearanceModel m = large_play_model();
  // A drive that integrates a velocity command through a 20 ms lag (P1I): the motor's
  // acceleration is smooth, its ripple under the 1 ms held command far below α (a position
  // staircase through a fast drive would shake the link off the flank by itself).
  cs::lti::ProcessParameters p;
  p.tp1 = 0.02;
  m.drive = cs::lti::ProcessModel("P1I", p);
  m.friction_regularization_rad_s = 1e-4;  // closer to a true Coulomb law than the default 1e-3
  const double alpha = st::flank_keeping_deceleration_rad_s2(m);
  ASSERT_NEAR(alpha, 0.4, 1e-12);
  // Accelerate at 2 rad/s² for 0.2 s (the rear flank drives the link), then decelerate at `a`.
  const auto run = [&](double a) {
    const double ts = 1e-3, accel = 2.0, v = 0.4, t_acc = 0.2, t_dec = v / a, duration = t_acc + t_dec + 0.1;
    const auto n = static_cast<std::size_t>(duration / ts) + 1;
    cs::UniformSeries rate{0.0, ts, std::vector<double>(n)};
    for (std::size_t k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) * ts;
      rate.values[k] = cs::rad_to_deg(t < t_acc ? accel * t : std::max(0.0, v - a * (t - t_acc)));
    }
    const auto resp = st::simulate_drive_command(m, rate, duration, -1.0);
    double most = -1e9;  // the largest link − motor angle during the deceleration (deg, −0.5 on the flank)
    for (std::size_t k = static_cast<std::size_t>((t_acc + 0.05) / ts); k < resp.link_angle_deg.size(); ++k) {
      most = std::max(most, resp.link_angle_deg[k] - resp.motor_angle_deg[k] - 0.5);
    }
    return most;
  };
  // Below α the link stays on the driving flank (it creeps only as far as the regularized
  // Coulomb law and the drive's residual ripple let it); above α it leaves it and crosses the play.
  EXPECT_LT(run(0.5 * alpha), -0.5 + 0.05);
  EXPECT_GT(run(2.0 * alpha), 0.0);
}

TEST(TakeUp, RefusesWhatItCannotDesign) {
  st::TakeUpRequest r;
  r.model = large_play_model();
  r.moves = {1.0};  // shorter than twice the play: the dip would have to reverse
  try {
    (void)st::design_take_up(r);
    FAIL() << "a 1 deg move with 1 deg of play was designed";
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("shortest move"), std::string::npos) << e.what();
  }
  r.moves = {10.0};
  r.max_duration_s = kT;
  EXPECT_THROW((void)st::design_take_up(r), cs::InvalidArgument);
  r.max_duration_s = 0.1;
  r.model.mode = cs::rig::CommandMode::speed;
  EXPECT_THROW((void)st::design_take_up(r), cs::InvalidArgument);
  r.model.mode = cs::rig::CommandMode::position;
  r.model.play_rad = 0.0;
  EXPECT_THROW((void)st::design_take_up(r), cs::InvalidArgument);
}
