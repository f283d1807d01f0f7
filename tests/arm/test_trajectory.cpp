// Commands for the arm (arm/trajectory.hpp): a synchronised move of scara-2's joints; its
// per-joint shaping checked by a physical law (an undamped oscillator at the design mode, driven
// by the shaped command, keeps no residual vibration: |Σ a_k e^{−iωt_k}|·dt/ω → 0 for a ZVD
// shaper, Singer & Seering 1990); the ROS JointTrajectory JSON and the CSV read back.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/arm/simulation.hpp"
#include "clearshape/arm/trajectory.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

const std::vector<signal::AxisLimits> kLimits{{2.0, 10.0, 200.0}, {3.0, 15.0, 300.0}};

JointTrajectory a_move(const ArmModel& arm, double sample_time_s = 1e-3) {
  return plan_move(arm, Eigen::Vector2d(-0.5, 1.2), Eigen::Vector2d(0.6, -0.3), kLimits, sample_time_s);
}

// Residual vibration amplitude (rad) of ẍ = −ω²(x − u) after u comes to rest: |Σ ü e^{−iωt}|·dt/ω.
double residual(const JointTrajectory& t, int joint, double w_rad_s) {
  std::complex<double> s = 0.0;
  for (std::size_t k = 0; k < t.time_s.size(); ++k) {
    s += t.acceleration_rad_s2(static_cast<Eigen::Index>(k), joint) * std::exp(std::complex<double>(0, -w_rad_s * t.time_s[k]));
  }
  return std::abs(s) * (t.time_s[1] - t.time_s[0]) / w_rad_s;
}

TEST(ArmTrajectory, MoveEndsTogetherAtTheTarget) {
  const ArmModel arm = builtin_arm("scara-2");
  const JointTrajectory t = a_move(arm);
  EXPECT_EQ(t.joint_names, (std::vector<std::string>{"shoulder", "elbow"}));
  const auto last = static_cast<Eigen::Index>(t.time_s.size() - 1);
  EXPECT_EQ(t.position_rad(last, 0), 0.6);
  EXPECT_EQ(t.position_rad(last, 1), -0.3);
  EXPECT_EQ(t.velocity_rad_s.row(last).norm(), 0.0);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LE(t.velocity_rad_s.col(i).cwiseAbs().maxCoeff(), kLimits[static_cast<std::size_t>(i)].velocity * (1 + 1e-12));
    EXPECT_LE(t.acceleration_rad_s2.col(i).cwiseAbs().maxCoeff(), kLimits[static_cast<std::size_t>(i)].acceleration * (1 + 1e-12));
    EXPECT_GT(t.velocity_rad_s(last - 1, i) * t.velocity_rad_s(last / 2, i), 0.0);  // both still moving near the end
  }
}

TEST(ArmTrajectory, ShapedJointsKeepNoResidualAtTheirDesignMode) {
  const ArmModel arm = builtin_arm("scara-2");
  const JointTrajectory t = a_move(arm, 1e-4);  // 0.1 ms: the impulses' interpolation is exact to < 1 %
  const Eigen::Vector2d end(0.6, -0.3);
  for (const ShaperSchedule schedule : {ShaperSchedule::fixed, ShaperSchedule::end_pose}) {
    const auto shapers = joint_shapers(arm, end, {.schedule = schedule, .method = shaping::Method::zvd});
    const JointTrajectory s = shape_trajectory(t, shapers);
    const ArmModes design = joint_modes(arm, schedule == ShaperSchedule::fixed ? workspace_centre(arm) : Eigen::VectorXd(end));
    const double longest = std::max(shapers[0].duration_s(), shapers[1].duration_s());
    EXPECT_NEAR(s.time_s.back(), t.time_s.back() + longest, 1e-3);
    for (int i = 0; i < 2; ++i) {
      const auto last = static_cast<Eigen::Index>(s.time_s.size() - 1);
      EXPECT_NEAR(s.position_rad(last, i), t.position_rad(static_cast<Eigen::Index>(t.time_s.size() - 1), i), 1e-12);
      const double w = design.joint_mode(i).natural_frequency_rad_s;
      const double before = residual(t, i, w), after = residual(s, i, w);
      ::testing::Test::RecordProperty(std::string(to_string(schedule)) + "_joint" + std::to_string(i),
                                      fmt::format("{:.3g} of {:.3g} rad", after / before, before));
      EXPECT_GT(before, 1e-7) << "joint " << i;  // the unshaped move excites the mode
      EXPECT_LT(after, 0.01 * before) << to_string(schedule) << " joint " << i << ": " << after << " of " << before;
    }
  }
  // every_mode: both modes of the end pose cancelled in both joints
  const auto both = joint_shapers(arm, end, {.schedule = ShaperSchedule::end_pose, .every_mode = true});
  EXPECT_EQ(both[0].size(), 9u);  // ZVD * ZVD
  const JointTrajectory s = shape_trajectory(t, both);
  const ArmModes m = joint_modes(arm, end);
  for (int i = 0; i < 2; ++i) {
    for (int k = 0; k < 2; ++k) {
      const double w = m.natural_frequency_rad_s(k);
      EXPECT_LT(residual(s, i, w), 0.01 * residual(t, i, w) + 1e-12) << "joint " << i << " mode " << k;
    }
  }
  const auto none = joint_shapers(arm, end, {.schedule = ShaperSchedule::none});
  EXPECT_EQ(shape_trajectory(t, none).position_rad, t.position_rad);
}

TEST(ArmTrajectory, AMoveWithoutMotionStaysPut) {
  const ArmModel arm = builtin_arm("scara-2");
  const Eigen::Vector2d q(0.3, -0.4);
  const JointTrajectory t = plan_move(arm, q, q, kLimits, 1e-3);
  ASSERT_EQ(t.time_s.size(), 2u);
  const JointTrajectory s = shape_trajectory(t, joint_shapers(arm, q, {}));
  for (Eigen::Index k = 0; k < s.position_rad.rows(); ++k) {
    EXPECT_LT((s.position_rad.row(k) - q.transpose()).norm(), 1e-15);  // ΣA·q, rounded
    EXPECT_EQ(s.velocity_rad_s.row(k).norm(), 0.0);
  }
  EXPECT_NEAR(drive_commands(arm, s)[1].value(0.5), -0.4 * 30.0 * 180.0 / std::numbers::pi, 1e-12);
}

TEST(ArmTrajectory, DriveCommandsAreMotorDegrees) {
  const ArmModel arm = builtin_arm("scara-2");  // Kp = 1 motor degree per unit, gears 50 and 30
  const JointTrajectory t = a_move(arm);
  const auto u = drive_commands(arm, t);
  ASSERT_EQ(u.size(), 2u);
  EXPECT_NEAR(u[0].value(10.0), 50.0 * 0.6 * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(u[1].value(0.0), 30.0 * 1.2 * 180.0 / std::numbers::pi, 1e-9);
}

TEST(ArmTrajectory, ShapedMoveOntoARestingFlankSimulates) {
  // bench_arm_moves: the move to (0, 1.5) shaped at both end-pose modes leaves the shoulder at
  // rest exactly on a flank (φ = −β, rate ~1e-6 rad/s) at 0.79 s; CVODE then found the root again
  // "at and very near t" and stopped. The drives must reach the targets and the links end within
  // their plays (|q − θ_m/N| ≤ β plus the flank's elastic give).
  const ArmModel arm = builtin_arm("scara-2");
  const std::vector<signal::AxisLimits> limits{{2.0, 20.0, 400.0}, {3.0, 30.0, 600.0}};
  const Eigen::Vector2d end(0.0, 1.5);
  const JointTrajectory t = shape_trajectory(
      plan_move(arm, Eigen::Vector2d(0.9, 2.2), end, limits, 1e-3),
      joint_shapers(arm, end, {.schedule = ShaperSchedule::end_pose, .every_mode = true}));
  ArmSimulationOptions o;
  o.duration_s = t.time_s.back() + 1.5;
  const ArmTrace tr = simulate_arm(arm, drive_commands(arm, t), o);
  const auto last = tr.link_angle_rad.rows() - 1;
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(tr.output_angle_rad(last, i), end(i), 1e-6);
    EXPECT_LE(std::abs(tr.link_angle_rad(last, i) - tr.output_angle_rad(last, i)), arm.joints[static_cast<std::size_t>(i)].half_play_rad + 1e-4);
  }
}

TEST(ArmTrajectory, RosJsonHasTheFieldsAndReadsBack) {
  const ArmModel arm = builtin_arm("scara-2");
  const JointTrajectory t = shape_trajectory(a_move(arm), joint_shapers(arm, Eigen::Vector2d(0.6, -0.3), {}));
  const auto dir = testing::fresh_temp_dir("arm_trajectory");
  write_trajectory_json(dir / "move.json", t);
  const nlohmann::json doc = nlohmann::json::parse(io::read_text_file(dir / "move.json"));
  EXPECT_EQ(doc.at("joint_names"), nlohmann::json::array({"shoulder", "elbow"}));
  ASSERT_EQ(doc.at("points").size(), t.time_s.size());
  const nlohmann::json& p = doc.at("points").at(734);
  EXPECT_EQ(p.at("positions").size(), 2u);
  EXPECT_EQ(p.at("velocities").size(), 2u);
  EXPECT_EQ(p.at("accelerations").size(), 2u);
  EXPECT_EQ(p.at("time_from_start").at("sec").get<long long>(), 0);
  EXPECT_EQ(p.at("time_from_start").at("nanosec").get<long long>(), 734000000);
  const JointTrajectory back = read_trajectory_json(dir / "move.json");
  EXPECT_EQ(back.joint_names, t.joint_names);
  EXPECT_EQ(back.position_rad, t.position_rad);
  EXPECT_EQ(back.velocity_rad_s, t.velocity_rad_s);
  EXPECT_EQ(back.acceleration_rad_s2, t.acceleration_rad_s2);
  for (std::size_t k = 0; k < t.time_s.size(); ++k) ASSERT_NEAR(back.time_s[k], t.time_s[k], 1e-9);
  write_trajectory_csv(dir / "move.csv", t);
  const JointTrajectory csv = read_trajectory_csv(dir / "move.csv");
  EXPECT_EQ(csv.time_s, t.time_s);
  EXPECT_EQ(csv.position_rad, t.position_rad);
  EXPECT_EQ(io::read_text_file(dir / "move.csv").substr(0, 32), "time_s,shoulder_rad,elbow_rad\n0,");
  EXPECT_EQ(drive_commands(arm, back)[0].value(5.0), drive_commands(arm, t)[0].value(5.0));
}

TEST(ArmTrajectory, RefusesMalformedTrajectories) {
  const nlohmann::json no_positions = {{"joint_names", {"a"}},
                                       {"points", {{{"time_from_start", {{"sec", 0}, {"nanosec", 0}}}}}}};
  try {
    trajectory_from_json(no_positions, "t.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "points[0].positions");
  }
  const nlohmann::json wrong_size = {
      {"joint_names", {"a", "b"}},
      {"points", {{{"positions", {1.0}}, {"velocities", {}}, {"accelerations", {}}, {"time_from_start", {{"sec", 0}, {"nanosec", 0}}}}}}};
  EXPECT_THROW(trajectory_from_json(wrong_size, "t.json"), InputError);
  const nlohmann::json bad_time = {
      {"joint_names", {"a"}},
      {"points", {{{"positions", {1.0}}, {"velocities", {}}, {"accelerations", {}}, {"time_from_start", {{"sec", 0}, {"nanosec", 2000000000}}}}}}};
  EXPECT_THROW(trajectory_from_json(bad_time, "t.json"), InputError);
  JointTrajectory t = a_move(builtin_arm("scara-2"));
  t.time_s[3] = t.time_s[2];
  EXPECT_THROW(t.validate(), InvalidArgument);
  EXPECT_THROW(plan_move(builtin_arm("scara-2"), Eigen::Vector3d::Zero(), Eigen::Vector2d::Zero(), kLimits, 1e-3),
               InvalidArgument);
}

}  // namespace
}  // namespace clearshape::arm
