// The arm's dynamics against physical laws: energy is conserved by the frictionless, undriven
// arm (free, and rattling in elastic plays under gravity); a motor step leaves a link with play
// rattling while a stiff joint without play makes it follow the motor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "clearshape/arm/simulation.hpp"

namespace clearshape::arm {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void make_conservative(ArmModel& arm, double half_play_rad) {
  for (ArmJoint& j : arm.joints) {
    j.friction = {};
    j.half_play_rad = half_play_rad;
    j.law = plant::ContactLaw::kelvin_voigt(j.law.stiffness(), 0.0, plant::DampingPolicy::raw);  // elastic
  }
}

std::vector<double> total_energy(const ArmTrace& tr) {
  std::vector<double> e;
  for (std::size_t k = 0; k < tr.time_s.size(); ++k) e.push_back(tr.kinetic_j[k] + tr.potential_j[k] + tr.contact_energy_j[k]);
  return e;
}

double max_drift(const std::vector<double>& e) {
  double d = 0.0;
  for (double v : e) d = std::max(d, std::abs(v - e.front()));
  return d;
}

ArmSimulationOptions tight(double duration_s) {
  ArmSimulationOptions o;
  o.duration_s = duration_s;
  o.output_rate_hz = 200.0;
  o.solver.relative_tolerance = 1e-10;
  o.solver.angle_tolerance_rad = 1e-12;
  o.solver.rate_tolerance_rad_s = 1e-10;
  return o;
}

TEST(ArmEnergy, FreeDoublePendulumConservesKineticPlusPotential) {
  ArmModel arm = builtin_arm("vertical-2");
  make_conservative(arm, 100.0);  // a play wider than any swing: the links never touch
  ArmSimulationOptions o = tight(3.0);
  o.initial.relative_angle_rad = Eigen::Vector2d(-0.4, 0.9);  // released at rest off the vertical
  const std::vector<plant::Command> still(2, plant::Command::constant(0.0));
  const ArmTrace tr = simulate_arm(arm, still, o);
  EXPECT_TRUE(tr.events.empty());
  const std::vector<double> e = total_energy(tr);
  const double swing = *std::max_element(tr.kinetic_j.begin(), tr.kinetic_j.end());
  EXPECT_GT(swing, 1.0);  // J: the pendulum really swings (several joules exchanged)
  EXPECT_LT(max_drift(e), 1e-7 * swing) << "drift " << max_drift(e) << " J of " << swing << " J";
}

TEST(ArmEnergy, RattlingInElasticPlaysUnderGravityConservesTheTotal) {
  ArmModel arm = builtin_arm("vertical-2");
  make_conservative(arm, 0.25 * kDeg);
  ArmSimulationOptions o = tight(1.0);
  o.initial.link_rate_rad_s = Eigen::Vector2d(0.3, -0.5);  // thrown across the play: impacts
  const std::vector<plant::Command> still(2, plant::Command::constant(0.0));
  const ArmTrace tr = simulate_arm(arm, still, o);
  long onsets = 0;
  for (const ArmEvent& ev : tr.events) onsets += ev.onset ? 1 : 0;
  EXPECT_GT(onsets, 20);  // both joints hit their flanks many times
  const std::vector<double> e = total_energy(tr);
  const double scale = *std::max_element(tr.kinetic_j.begin(), tr.kinetic_j.end());
  EXPECT_LT(max_drift(e), 2e-6 * scale) << "drift " << max_drift(e) << " J of " << scale << " J";
}

struct StepResult {
  ArmTrace trace;
  long late_onsets = 0;       // contact onsets of the shoulder once the motor has settled
  double late_spread = 0.0;   // peak-to-peak of q − θ_m/N at the shoulder after the motor settled
  double final_error = 0.0;   // |q − θ_m/N| at the end
};

StepResult shoulder_step(const ArmModel& arm) {
  const double link_step_deg = 5.0;
  const double gear = arm.joints[0].gear_ratio;
  const std::vector<plant::Command> cmd{plant::Command::step(0.05, link_step_deg * gear), plant::Command::constant(0.0)};
  ArmSimulationOptions o;
  o.duration_s = 0.6;
  o.output_rate_hz = 2000.0;
  StepResult r{simulate_arm(arm, cmd, o)};
  const double settled_s = 0.25;  // the drive (ωn = 94 rad/s, ζ = 0.8) is within 0.1 % by then
  double lo = 1e9, hi = -1e9;
  for (std::size_t k = 0; k < r.trace.time_s.size(); ++k) {
    if (r.trace.time_s[k] < settled_s) continue;
    const double phi = r.trace.link_angle_rad(static_cast<Eigen::Index>(k), 0) - r.trace.output_angle_rad(static_cast<Eigen::Index>(k), 0);
    lo = std::min(lo, phi);
    hi = std::max(hi, phi);
  }
  r.late_spread = hi - lo;
  for (const ArmEvent& ev : r.trace.events) r.late_onsets += (ev.joint == 0 && ev.onset && ev.time_s > settled_s) ? 1 : 0;
  const auto last = r.trace.link_angle_rad.rows() - 1;
  r.final_error = std::abs(r.trace.link_angle_rad(last, 0) - r.trace.output_angle_rad(last, 0));
  EXPECT_NEAR(r.trace.output_angle_rad(last, 0), link_step_deg * kDeg, 1e-4 * kDeg);  // the motor arrived
  return r;
}

TEST(ArmPlay, AMotorStepLeavesALinkWithPlayRattling) {
  const ArmModel arm = builtin_arm("scara-2");  // 0.5° play, Hunt–Crossley e = 0.5
  const StepResult r = shoulder_step(arm);
  const double beta = arm.joints[0].half_play_rad;
  // after the motor stopped the link keeps crossing the play and hitting the flanks
  EXPECT_GE(r.late_onsets, 3);
  EXPECT_GT(r.late_spread, beta);
  EXPECT_LE(r.final_error, beta * 1.05);  // it stays within the play (plus the flank's give)
}

TEST(ArmPlay, AStiffJointWithoutPlayMakesTheLinkFollowTheMotor) {
  ArmModel arm = builtin_arm("scara-2");
  for (ArmJoint& j : arm.joints) {  // no play, a stiff and well-damped flank (ζ ≈ 0.7)
    j.half_play_rad = 0.0;
    j.law = plant::ContactLaw::kelvin_voigt(2e5, 2.0 * 0.7 * std::sqrt(2e5 * 0.2), plant::DampingPolicy::raw);
  }
  const StepResult r = shoulder_step(arm);
  EXPECT_LT(r.late_spread, 1e-3 * kDeg);   // no residual motion between motor and link
  EXPECT_LT(r.final_error, 1e-4 * kDeg);   // the link sits on the gearbox output
  // during the move the link lags by the torque its acceleration needs: |φ| ≈ M11 a / K, with
  // the overshoot of a ζ = 0.7 flank to a jump in acceleration (1 + e^(−ζπ/√(1−ζ²)) = 1.05)
  const Eigen::MatrixXd& out = r.trace.output_angle_rad;
  const double dt = r.trace.time_s[1] - r.trace.time_s[0];
  double a_max = 0.0, worst = 0.0;
  for (Eigen::Index k = 1; k + 1 < out.rows(); ++k) {
    a_max = std::max(a_max, std::abs(out(k + 1, 0) - 2.0 * out(k, 0) + out(k - 1, 0)) / (dt * dt));
    worst = std::max(worst, std::abs(r.trace.link_angle_rad(k, 0) - out(k, 0)));
  }
  ChainWorkspace ws(arm.chain);
  Eigen::MatrixXd m;
  ws.mass_matrix(Eigen::Vector2d::Zero(), m);
  const double static_lag = m(0, 0) * a_max / arm.joints[0].law.stiffness();
  // the flank really gives under the load (a little less than statically: the drive's
  // acceleration decays within the flank's period) …
  EXPECT_GT(worst, 0.7 * static_lag);
  EXPECT_LT(worst, 1.1 * static_lag);   // … by what Newton and Hooke say
}

}  // namespace
}  // namespace clearshape::arm

namespace clearshape::arm {
namespace {

TEST(ArmPlay, GravityDeflectsAJointWithoutPlayByTorqueOverStiffness) {
  ArmModel arm = builtin_arm("vertical-2");  // links horizontal at q = 0: gravity loads both
  for (ArmJoint& j : arm.joints) j.half_play_rad = 0.0;
  ArmSimulationOptions o;
  o.duration_s = 3.0;
  const std::vector<plant::Command> still(2, plant::Command::constant(0.0));
  const ArmTrace tr = simulate_arm(arm, still, o);
  EXPECT_TRUE(tr.events.empty());  // zero play: no flank to cross
  // Hooke: the links hang on the flanks at φ = −K⁻¹ g(q) (the oscillation about it averages out)
  ChainWorkspace ws(arm.chain);
  Eigen::VectorXd g;
  ws.gravity_torque(Eigen::Vector2d::Zero(), g);
  const auto rows = tr.link_angle_rad.rows();
  for (int i = 0; i < 2; ++i) {
    const double mean = (tr.link_angle_rad.col(i) - tr.output_angle_rad.col(i)).tail(rows / 3).mean();
    const double hooke = -g(i) / arm.joints[static_cast<std::size_t>(i)].law.stiffness();
    EXPECT_NEAR(mean, hooke, 1e-3 * std::abs(hooke)) << "joint " << i;
  }
}

}  // namespace
}  // namespace clearshape::arm
