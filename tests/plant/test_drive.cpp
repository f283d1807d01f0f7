// Drive models embedded in the plant ODE against SciPy (tests/golden/gen_plant.py).
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/plant/simulation.hpp"
#include "support/paths.hpp"

namespace cp = clearshape::plant;
using clearshape::rad_to_deg;

namespace {
cp::PlantModel rigid_link(cp::DriveModel drive) {
  cp::PlantModel m;
  m.drive = std::move(drive);
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 0.1;  // the link never reaches the stops: the drive runs alone
  m.joint = j;
  return m;
}
cp::SimulationOptions one_second() {
  cp::SimulationOptions o;
  o.duration_s = 1.0;
  o.output_rate_hz = 1000.0;
  o.solver.relative_tolerance = 1e-10;
  o.solver.angle_tolerance_rad = 1e-12;
  o.solver.rate_tolerance_rad_s = 1e-10;
  return o;
}
}  // namespace

// Thesis Eq. 4.2 position mode: a 10° step; motor angle vs scipy.signal.step, ± 1e-7 deg.
TEST(Drive, ThesisPositionModeMatchesSciPy) {
  const auto golden = clearshape::io::read_table(clearshape::testing::golden_path("plant_drive_step.csv"));
  const auto& ref = golden.column("position_motor_deg");
  auto o = one_second();
  o.initial.drive_state = Eigen::VectorXd::Zero(cp::DriveModel::thesis_position_mode().order());
  const auto r = cp::simulate(rigid_link(cp::DriveModel::thesis_position_mode()),
                              cp::Command::constant(10.0), o);  // a step at t = 0 from rest
  ASSERT_EQ(r.size(), ref.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    worst = std::max(worst, std::abs(rad_to_deg(r.motor_angle_rad[k]) - ref[k]));
  }
  EXPECT_LT(worst, 1e-7);
}

// Speed mode: the TF gives deg/s per command unit; the integrator state gives the angle.
TEST(Drive, ThesisSpeedModeMatchesSciPy) {
  const auto golden = clearshape::io::read_table(clearshape::testing::golden_path("plant_drive_step.csv"));
  const auto& rate = golden.column("speed_motor_deg_s");
  const auto& angle = golden.column("speed_motor_deg");
  auto model = rigid_link(cp::DriveModel::thesis_speed_mode());
  std::get<cp::TorsionalClearance>(model.joint).half_play_rad = 1.0;
  auto o = one_second();
  o.initial.drive_state = Eigen::VectorXd::Zero(model.drive.order());
  const auto r = cp::simulate(model, cp::Command::constant(1.0), o);
  ASSERT_EQ(r.size(), rate.size());
  double worst_rate = 0.0;
  double worst_angle = 0.0;
  for (std::size_t k = 0; k < rate.size(); ++k) {
    worst_rate = std::max(worst_rate, std::abs(rad_to_deg(r.motor_rate_rad_s[k]) - rate[k]));
    worst_angle = std::max(worst_angle, std::abs(rad_to_deg(r.motor_angle_rad[k]) - angle[k]));
  }
  EXPECT_LT(worst_rate, 1e-6);   // deg/s, of a 25.5 deg/s response
  EXPECT_LT(worst_angle, 1e-7);  // deg
}

TEST(Drive, PresetsAndValidation) {
  const auto pos = cp::DriveModel::thesis_position_mode();
  EXPECT_EQ(pos.mode(), cp::DriveMode::position);
  EXPECT_NEAR(pos.dc_gain(), clearshape::deg_to_rad(0.9959), 1e-12);
  const auto spd = cp::DriveModel::thesis_speed_mode();
  EXPECT_EQ(spd.mode(), cp::DriveMode::speed);
  EXPECT_EQ(spd.order(), 4);  // three TF states + the angle integrator
  EXPECT_NEAR(spd.dc_gain(), clearshape::deg_to_rad(25.47), 1e-12);
  // rest state: position drive at a constant command
  const auto x = pos.rest_state(5.0);
  EXPECT_NEAR(pos.angle_rad(x), clearshape::deg_to_rad(5.0 * 0.9959), 1e-12);
  EXPECT_NEAR(pos.rate_rad_s(x, 5.0), 0.0, 1e-12);
  EXPECT_THROW((void)spd.rest_state(1.0), clearshape::InvalidArgument);  // moving, not at rest
  // a biproper position TF would let the angle jump
  clearshape::lti::StateSpace ss;
  ss.a = Eigen::MatrixXd::Constant(1, 1, -1.0);
  ss.b = Eigen::MatrixXd::Constant(1, 1, 1.0);
  ss.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
  ss.d = Eigen::MatrixXd::Constant(1, 1, 0.5);
  EXPECT_THROW((void)cp::DriveModel::position_mode(ss), clearshape::InvalidArgument);
  EXPECT_NO_THROW((void)cp::DriveModel::speed_mode(ss));
  EXPECT_THROW((void)cp::DriveModel::first_order_position(0.0), clearshape::InvalidArgument);
}

// A process-model delay Td shifts the command in time exactly.
TEST(Drive, DelayShiftsTheCommand) {
  const auto plain = cp::DriveModel::first_order_position(0.05);
  const auto delayed = cp::DriveModel::position_mode(
      [] {
        clearshape::lti::StateSpace ss;
        ss.a = Eigen::MatrixXd::Constant(1, 1, -20.0);
        ss.b = Eigen::MatrixXd::Constant(1, 1, 20.0);
        ss.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
        ss.d = Eigen::MatrixXd::Zero(1, 1);
        return ss;
      }(),
      clearshape::deg_to_rad(1.0), 0.1);
  auto o = one_second();
  const auto a = cp::simulate(rigid_link(plain), cp::Command::step(0.2, 1.0), o);
  const auto b = cp::simulate(rigid_link(delayed), cp::Command::step(0.1, 1.0), o);
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_NEAR(a.motor_angle_rad[k], b.motor_angle_rad[k], 1e-11) << "t = " << a.time_s[k];
  }
  // exact first-order response after the step at 0.2 s
  const double t = 0.5;
  EXPECT_NEAR(rad_to_deg(a.motor_angle_rad[500]), 1.0 - std::exp(-(t - 0.2) / 0.05), 1e-8);
}

// A realization copied out and back in is the same model, bit for bit (what a Python pickle of a
// RigTruth relies on); a malformed one is refused naming the field.
TEST(DriveModel, RealizationRoundTripsBitForBitAndRefusesMalformed) {
  for (const auto& drive : {cp::DriveModel::thesis_position_mode(), cp::DriveModel::thesis_speed_mode()}) {
    const auto r = drive.realization();
    const auto back = cp::DriveModel::from_realization(r);
    EXPECT_EQ(back.mode(), drive.mode());
    EXPECT_EQ(back.a(), drive.a());
    EXPECT_EQ(back.b(), drive.b());
    EXPECT_EQ(back.angle_output(), drive.angle_output());
    EXPECT_EQ(back.rate_output(), drive.rate_output());
    EXPECT_EQ(back.rate_feedthrough(), drive.rate_feedthrough());
    EXPECT_EQ(back.delay_s(), drive.delay_s());
    const auto o = one_second();
    const auto a = cp::simulate(rigid_link(drive), cp::Command::step(0.1, 1.0), o);
    const auto b = cp::simulate(rigid_link(back), cp::Command::step(0.1, 1.0), o);
    EXPECT_EQ(a.motor_angle_rad, b.motor_angle_rad);
  }
  auto r = cp::DriveModel::thesis_position_mode().realization();
  auto short_b = r;
  short_b.b.resize(r.b.size() - 1);
  EXPECT_THROW((void)cp::DriveModel::from_realization(short_b), clearshape::InvalidArgument);
  r.delay_s = -1.0;
  try {
    (void)cp::DriveModel::from_realization(r);
    FAIL() << "a negative delay was accepted";
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("drive.delay_s"), std::string::npos) << e.what();
  }
}
