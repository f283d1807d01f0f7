#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/rig/offline.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;

namespace {
cs::UniformSeries step_command(double amplitude, double at_s, double duration_s, double ts = 1e-3) {
  cs::UniformSeries s;
  s.sample_time_s = ts;
  const std::size_t n = cs::sample_count(duration_s, ts);
  for (std::size_t k = 0; k < n; ++k) s.values.push_back(static_cast<double>(k) * ts >= at_s - 1e-12 ? amplitude : 0.0);
  return s;
}
rig::RunOptions quiet(double duration_s) {
  rig::RunOptions o;
  o.duration_s = duration_s;
  o.sensor_noise = false;
  return o;
}
double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}
}  // namespace

// Zero clearance: the link rides rigidly on the shaft, and the motor follows the thesis
// Eq. 4.2 model. Reference: lti's exact discretization of the same process model driven by the
// same drive command (an independent integrator: matrix exponential, not CVODE) — first-order
// hold in position mode (the pulse count is interpolated linearly), zero-order hold in speed
// mode (the D/A holds each sample).
TEST(SimulateRun, ZeroClearanceReproducesTheRigidDriveResponsePositionMode) {
  rig::RigTruth truth = rig::thesis_rig_truth();
  truth.clearance_rad = 0.0;
  const auto run = rig::simulate_run(truth, rig::CommandMode::position,
                                     step_command(cs::deg_to_rad(10.0), 0.1, 1.0), quiet(1.0));
  ASSERT_TRUE(run.rigid);
  const auto& s = run.simulation;
  EXPECT_EQ(s.link_angle_rad, s.motor_angle_rad);
  EXPECT_EQ(s.link_rate_rad_s, s.motor_rate_rad_s);
  EXPECT_EQ(s.stats.events, 0);
  const cs::UniformSeries drive_command{0.0, 1e-3, run.command_drive};
  const cs::UniformSeries reference =
      cs::lti::simulate(cs::lti::thesis_position_mode_model(), drive_command, cs::lti::Hold::foh);
  std::vector<double> motor_deg(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) motor_deg[k] = cs::rad_to_deg(s.motor_angle_rad[k]);
  // Tolerance: CVODE at rtol 1e-8 / atol 1e-10 rad on a 10° move.
  EXPECT_LT(max_abs_diff(motor_deg, reference.values), 1e-5);
  EXPECT_NEAR(motor_deg.back(), 0.9959 * run.command_drive.back(), 1e-4);  // Kp = 0.9959
  EXPECT_NEAR(run.command_drive.back(), 10.0, 0.12 + 1e-9);  // whole pulses of 0.12°
}

// Speed mode: the prior's drive is the thesis's Eq. 4.2 speed model itself (the calibrated
// rig's drive is the one whose response through the 30 rad/s chain is Eq. 4.2; see
// tests/study/test_rig_calibration.cpp), so the reference is lti's Eq. 4.2.
TEST(SimulateRun, ZeroClearanceReproducesTheRigidDriveResponseSpeedMode) {
  rig::RigTruth truth = rig::uncalibrated_thesis_rig_prior();
  truth.clearance_rad = 0.0;
  const auto run = rig::simulate_run(truth, rig::CommandMode::speed, step_command(1.0, 0.0, 2.0),
                                     quiet(2.0));
  const auto& s = run.simulation;
  const cs::UniformSeries drive_command{0.0, 1e-3, run.command_drive};
  const cs::UniformSeries reference =
      cs::lti::simulate(cs::lti::thesis_speed_mode_model(), drive_command);  // deg/s
  std::vector<double> link_deg_s(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) link_deg_s[k] = cs::rad_to_deg(s.link_rate_rad_s[k]);
  EXPECT_LT(max_abs_diff(link_deg_s, reference.values), 1e-4);  // of 25.47 °/s
  EXPECT_NEAR(link_deg_s.back(), 25.47 * run.command_drive.back(), 1e-3);
}

// Zero-clearance limit (physics oracle): with a stiff linear contact, the link's deviation
// from the rigid response shrinks with the play, bounded by the half play plus the contact
// compliance.
TEST(SimulateRun, SmallClearanceConvergesToRigid) {
  rig::RigTruth truth = rig::thesis_rig_truth();
  truth.position_contact = rig::ContactSpec::defaults(rig::ContactModel::kelvin_voigt,
                                                      rig::CommandMode::position);
  truth.position_contact.stiffness = 1e5;
  truth.position_contact.restitution = 0.3;
  const auto command = step_command(cs::deg_to_rad(10.0), 0.1, 0.8);
  truth.clearance_rad = 0.0;
  const auto rigid = rig::simulate_run(truth, rig::CommandMode::position, command, quiet(0.8));
  double previous = 1e9;
  for (const double clearance_deg : {1.0, 0.1, 0.01}) {
    truth.clearance_rad = cs::deg_to_rad(clearance_deg);
    const auto run = rig::simulate_run(truth, rig::CommandMode::position, command, quiet(0.8));
    const double deviation_deg =
        cs::rad_to_deg(max_abs_diff(run.simulation.link_angle_rad, rigid.simulation.link_angle_rad));
    SCOPED_TRACE(clearance_deg);
    EXPECT_LT(deviation_deg, previous);
    EXPECT_LT(deviation_deg, clearance_deg / 2 + 0.05);  // 0.05°: compliance at 1e5 N·m/rad
    previous = deviation_deg;
  }
}

// The prior's stiff thesis law (K = 1e4 N·m/rad^1.5): impacts, and the link stays in the play.
TEST(SimulateRun, ClearanceProducesImpactsAndKeepsTheLinkInThePlay) {
  const rig::RigTruth truth = rig::uncalibrated_thesis_rig_prior();
  const auto run = rig::simulate_run(truth, rig::CommandMode::position,
                                     step_command(cs::deg_to_rad(20.0), 0.1, 1.5), quiet(1.5));
  const auto& s = run.simulation;
  EXPECT_GT(s.stats.events, 0);
  const double beta = truth.half_play_rad();
  for (std::size_t k = 0; k < s.size(); ++k) {
    // |φ| ≤ β + penetration; the thesis law's penetration stays well below 0.1°.
    EXPECT_LE(std::abs(s.relative_angle_rad[k]), beta + cs::deg_to_rad(0.1)) << k;
  }
  EXPECT_NEAR(cs::rad_to_deg(s.link_angle_rad.back()), cs::rad_to_deg(s.motor_angle_rad.back()),
              cs::rad_to_deg(beta) + 0.1);
  // Sensors: the encoder reads the motor to one count (0.03°).
  for (std::size_t k = 0; k < s.size(); ++k) {
    EXPECT_LE(s.motor_angle_rad[k] - run.encoder_angle_rad[k], cs::deg_to_rad(0.03) + 1e-12);
    EXPECT_GE(s.motor_angle_rad[k] - run.encoder_angle_rad[k], -1e-12);
  }
}

TEST(SimulateRun, DeterministicAndSeededNoise) {
  const rig::RigTruth truth = rig::thesis_rig_truth();
  const auto command = step_command(1.0, 0.05, 0.5);
  rig::RunOptions options;
  options.duration_s = 0.5;
  const auto a = rig::simulate_run(truth, rig::CommandMode::speed, command, options);
  const auto b = rig::simulate_run(truth, rig::CommandMode::speed, command, options);
  EXPECT_EQ(a.gyro_raw, b.gyro_raw);
  EXPECT_EQ(a.simulation.link_rate_rad_s, b.simulation.link_rate_rad_s);
  options.seed = 2;
  const auto c = rig::simulate_run(truth, rig::CommandMode::speed, command, options);
  EXPECT_NE(a.gyro_raw, c.gyro_raw);
  EXPECT_EQ(a.simulation.link_rate_rad_s, c.simulation.link_rate_rad_s);
}

TEST(SimulateRun, RejectsBadInput) {
  const rig::RigTruth truth = rig::thesis_rig_truth();
  EXPECT_THROW(rig::simulate_run(truth, rig::CommandMode::speed, cs::UniformSeries{}, quiet(1.0)),
               cs::InvalidArgument);
  rig::RunOptions bad = quiet(1.0);
  bad.initial_play_fraction = 2.0;
  EXPECT_THROW(rig::simulate_run(truth, rig::CommandMode::speed, step_command(1, 0, 1), bad),
               cs::InvalidArgument);
}

// The calibrated rig's flank is compliant (linear, K = 45 N·m/rad): the link lags the shaft
// by the flank's deflection. Physics bound (linear spring–damper driven through its support,
// dynamic amplification <= 2): |φ| <= β + 2·J·max|α_motor|/K; and the deflection is far
// beyond the stiff prior's 0.1°.
TEST(SimulateRun, CalibratedFlankDeflectionIsBoundedByTheMotorAcceleration) {
  const rig::RigTruth truth = rig::thesis_rig_truth();
  const auto run = rig::simulate_run(truth, rig::CommandMode::position,
                                     step_command(cs::deg_to_rad(20.0), 0.1, 1.5), quiet(1.5));
  const auto& s = run.simulation;
  double max_accel = 0.0, max_phi = 0.0;
  for (std::size_t k = 1; k < s.size(); ++k) {
    max_accel = std::max(max_accel, std::abs(s.motor_rate_rad_s[k] - s.motor_rate_rad_s[k - 1]) / 1e-3);
    max_phi = std::max(max_phi, std::abs(s.relative_angle_rad[k]));
  }
  const double bound = truth.half_play_rad() +
                       2.0 * truth.link.inertia_kg_m2 * max_accel / truth.position_contact.stiffness;
  EXPECT_LE(max_phi, bound);
  EXPECT_GT(max_phi, truth.half_play_rad() + cs::deg_to_rad(0.1));
  EXPECT_GT(s.stats.events, 0);
  // At rest the link settles against the shaft within the play.
  EXPECT_NEAR(cs::rad_to_deg(s.link_angle_rad.back()), cs::rad_to_deg(s.motor_angle_rad.back()),
              cs::rad_to_deg(truth.half_play_rad()) + 0.01);
}
