// The last link's gyroscope and accelerometer (docs/arm.md §1, "Sensors") against independent
// references: the planar closed form of tests/golden/gen_arm_imu.py; on a three-axis chain, the
// body rate R(t)ᵀṘ(t) and the second difference of the mount point's position, both from forward
// kinematics along a known path and along a simulated move; gravity at rest; noise and range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "clearshape/arm/simulation.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

constexpr double kStandardGravity_m_s2 = 9.80665;

std::string sci(double x) {  // a measured error for the test's XML report
  std::ostringstream o;
  o << std::scientific << std::setprecision(2) << x;
  return o.str();
}

// Three joints about z, y and x with tilted origins and a tilted tool: every axis of the IMU moves.
std::string three_axis_urdf() {
  const auto link = [](const char* name, double mass_kg) {
    return std::string("<link name=\"") + name + "\"><inertial><origin xyz=\"0.1 0 0\"/><mass value=\"" +
           std::to_string(mass_kg) +
           "\"/><inertia ixx=\"0.002\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n";
  };
  const auto joint = [](const char* name, const char* parent, const char* child, const char* xyz, const char* rpy,
                        const char* axis) {
    return std::string("<joint name=\"") + name + "\" type=\"continuous\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/><axis xyz=\"" + axis +
           "\"/></joint>\n";
  };
  return "<robot name=\"three-axis\"><link name=\"base\"/>\n" + joint("yaw", "base", "l1", "0 0 0.3", "0 0 0", "0 0 1") +
         link("l1", 1.5) + joint("pitch", "l1", "l2", "0.2 0 0.05", "0.3 0 0", "0 1 0") + link("l2", 1.0) +
         joint("roll", "l2", "l3", "0.25 0.02 0", "0 0.4 0.2", "1 0 0") + link("l3", 0.5) +
         "<joint name=\"tool_mount\" type=\"fixed\"><parent link=\"l3\"/><child link=\"tool\"/>"
         "<origin xyz=\"0.08 0 0.01\" rpy=\"0.1 -0.2 0.3\"/></joint>\n<link name=\"tool\"/></robot>\n";
}

std::string three_axis_toml(const std::string& imu) {
  std::string toml = imu;
  for (const char* name : {"yaw", "pitch", "roll"}) {
    toml += std::string("[[joint]]\nname = \"") + name +
            "\"\nplay_deg = 0.5\n[joint.drive]\nmodel = \"first-order\"\ntime_constant_s = 0.02\n"
            "[joint.contact]\nlaw = \"kelvin-voigt\"\nstiffness = 2000.0\ndamping = 2.0\n"
            "[joint.friction]\nviscous_n_m_s_per_rad = 0.01\n";
  }
  return toml;
}

// ω in the body frame from R(t)ᵀṘ(t) by a central difference (the skew part's vector).
Eigen::Vector3d body_rate(const Eigen::Isometry3d& before, const Eigen::Isometry3d& at, const Eigen::Isometry3d& after,
                          double h_s) {
  const Eigen::Matrix3d w = at.linear().transpose() * (after.linear() - before.linear()) / (2.0 * h_s);
  const Eigen::Matrix3d s = 0.5 * (w - w.transpose());
  return {s(2, 1), s(0, 2), s(1, 0)};
}

// The mount point's acceleration by a second central difference, minus g, in the body frame.
Eigen::Vector3d specific_force(const Eigen::Isometry3d& before, const Eigen::Isometry3d& at,
                               const Eigen::Isometry3d& after, const Eigen::Vector3d& mount_m, double h_s,
                               const Eigen::Vector3d& gravity) {
  const Eigen::Vector3d a = (before * mount_m - 2.0 * (at * mount_m) + after * mount_m) / (h_s * h_s);
  return at.linear().transpose() * (a - gravity);
}

TEST(ArmImu, PlanarArmsMatchTheClosedForm) {
  const io::Table t = io::read_table(clearshape::testing::golden_path("arm_imu.csv"));
  ASSERT_EQ(t.rows(), 48u);
  const ArmModel arms[] = {builtin_arm("scara-2"), builtin_arm("vertical-2")};
  ChainWorkspace scara(arms[0].chain), vertical(arms[1].chain);
  const char* axes = "xyz";
  double worst_gyro = 0.0, worst_accel = 0.0;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const auto col = [&](const std::string& name) { return t.column(name)[r]; };
    const Eigen::Vector2d q(col("q1_rad"), col("q2_rad")), qd(col("qd1_rad_s"), col("qd2_rad_s"));
    const Eigen::Vector2d qdd(col("qdd1_rad_s2"), col("qdd2_rad_s2"));
    const Eigen::Vector3d mount(col("mount_x_m"), col("mount_y_m"), col("mount_z_m"));
    const ChainWorkspace::Sample s = (col("arm") == 0.0 ? scara : vertical).sample(q, qd, qdd, mount);
    for (int a = 0; a < 3; ++a) {
      const double gyro = col(std::string("gyro_") + axes[a] + "_rad_s");
      const double accel = col(std::string("accel_") + axes[a] + "_m_s2");
      worst_gyro = std::max(worst_gyro, std::abs(s.gyro_rad_s(a) - gyro) / (1.0 + std::abs(gyro)));
      worst_accel = std::max(worst_accel, std::abs(s.accel_m_s2(a) - accel) / (1.0 + std::abs(accel)));
    }
  }
  RecordProperty("gyro_error", sci(worst_gyro));
  RecordProperty("accel_error", sci(worst_accel));
  EXPECT_LT(worst_gyro, 1e-12);
  EXPECT_LT(worst_accel, 1e-9);  // relative to 1 + |reading|, accelerations up to 60 m/s²
}

TEST(ArmImu, ThreeAxisChainMatchesTheToolFrameAlongAKnownPath) {
  const RigidChain chain = RigidChain::from_urdf(three_axis_urdf(), "three-axis.urdf");
  ChainWorkspace ws(chain);
  // q_i(t) = A_i sin(w_i t + p_i): positions, rates and accelerations in closed form
  const Eigen::Vector3d amp(0.9, 0.7, 1.2), w(3.0, 5.0, 7.0), ph(0.2, -0.4, 0.3);
  const auto q_at = [&](double t) { return Eigen::VectorXd((amp.array() * (w * t + ph).array().sin()).matrix()); };
  const Eigen::Vector3d mount(0.015, -0.02, 0.03);
  const double h_s = 2e-4;
  double worst_gyro = 0.0, worst_accel = 0.0, peak_gyro = 0.0, peak_accel = 0.0;
  for (double t = 0.0; t < 1.2; t += 0.01) {
    const Eigen::ArrayXd arg = (w * t + ph).array();
    const Eigen::VectorXd qd = (amp.array() * w.array() * arg.cos()).matrix();
    const Eigen::VectorXd qdd = (-amp.array() * w.array().square() * arg.sin()).matrix();
    const ChainWorkspace::Sample s = ws.sample(q_at(t), qd, qdd, mount);
    const Eigen::Isometry3d before = ws.tip_pose(q_at(t - h_s)), at = ws.tip_pose(q_at(t)), after = ws.tip_pose(q_at(t + h_s));
    EXPECT_LT((s.tip_pose.matrix() - at.matrix()).cwiseAbs().maxCoeff(), 1e-14);
    worst_gyro = std::max(worst_gyro, (s.gyro_rad_s - body_rate(before, at, after, h_s)).norm());
    const Eigen::Vector3d ref = specific_force(before, at, after, mount, h_s, chain.gravity_m_s2());
    worst_accel = std::max(worst_accel, (s.accel_m_s2 - ref).norm());
    peak_gyro = std::max(peak_gyro, s.gyro_rad_s.norm());
    peak_accel = std::max(peak_accel, s.accel_m_s2.norm());
  }
  RecordProperty("gyro_error_relative", sci(worst_gyro / peak_gyro));
  RecordProperty("accel_error_relative", sci(worst_accel / peak_accel));
  EXPECT_GT(peak_gyro, 5.0);  // rad/s: a fast three-axis motion
  EXPECT_GT(peak_accel, 15.0);
  EXPECT_LT(worst_gyro, 2e-6 * peak_gyro) << worst_gyro;     // the difference's own error: O(h²)
  EXPECT_LT(worst_accel, 1e-5 * peak_accel) << worst_accel;
}

ArmSimulationOptions tight_run(double duration_s, double rate_hz) {
  ArmSimulationOptions o;
  o.duration_s = duration_s;
  o.output_rate_hz = rate_hz;
  o.solver.relative_tolerance = 1e-10;
  o.solver.angle_tolerance_rad = 1e-12;
  o.solver.rate_tolerance_rad_s = 1e-10;
  return o;
}

// A cosine blend from 0 to `to` over [start, start + length] (link degrees × gear ratio 1).
plant::Command blend(double to_deg, double start_s, double length_s) {
  UniformSeries s{0.0, 1e-3, {}};
  for (int k = 0; k <= 1000; ++k) {
    const double x = std::clamp((k * 1e-3 - start_s) / length_s, 0.0, 1.0);
    s.values.push_back(to_deg * (0.5 - 0.5 * std::cos(std::numbers::pi * x)));
  }
  return plant::Command(s, plant::Interpolation::linear);
}

TEST(ArmImu, SimulatedMoveMatchesTheToolFrameOfTheLinkAngles) {
  const ArmModel arm = arm_from_text(three_axis_urdf(), "three-axis.urdf",
                                     three_axis_toml("[imu]\nmount_m = [0.015, -0.02, 0.03]\n"), "three-axis.toml");
  ASSERT_EQ(arm.imu.mount_m, Eigen::Vector3d(0.015, -0.02, 0.03));
  const std::vector<plant::Command> commands{blend(40.0, 0.05, 0.3), blend(-30.0, 0.1, 0.25), blend(60.0, 0.0, 0.2)};
  const double rate_hz = 20000.0;
  const ArmTrace tr = simulate_arm(arm, commands, tight_run(0.6, rate_hz));
  EXPECT_GT(tr.events.size(), 6u);  // the plays close and open during the move
  ChainWorkspace ws(arm.chain);
  std::vector<Eigen::Isometry3d> pose;
  for (Eigen::Index k = 0; k < tr.link_angle_rad.rows(); ++k) {
    pose.push_back(ws.tip_pose(tr.link_angle_rad.row(k).transpose()));
  }
  const double h_s = 1.0 / rate_hz;
  double worst_gyro = 0.0, worst_accel = 0.0, peak_gyro = 0.0, peak_accel = 0.0;
  const auto near_event = [&](double t) {  // a kink of q̇ (an impact) inside the difference's stencil
    return std::any_of(tr.events.begin(), tr.events.end(), [&](const ArmEvent& e) { return std::abs(e.time_s - t) <= 1.5 * h_s; });
  };
  for (std::size_t k = 1; k + 1 < pose.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    if (near_event(tr.time_s[k])) continue;
    const Eigen::Vector3d gyro = tr.gyro_rad_s.row(row).transpose(), accel = tr.accel_m_s2.row(row).transpose();
    worst_gyro = std::max(worst_gyro, (gyro - body_rate(pose[k - 1], pose[k], pose[k + 1], h_s)).norm());
    const Eigen::Vector3d ref = specific_force(pose[k - 1], pose[k], pose[k + 1], arm.imu.mount_m, h_s, arm.chain.gravity_m_s2());
    worst_accel = std::max(worst_accel, (accel - ref).norm());
    peak_gyro = std::max(peak_gyro, gyro.norm());
    peak_accel = std::max(peak_accel, (accel + pose[k].linear().transpose() * arm.chain.gravity_m_s2()).norm());
  }
  RecordProperty("gyro_error_relative", sci(worst_gyro / peak_gyro));
  RecordProperty("accel_error_relative", sci(worst_accel / peak_accel));
  EXPECT_GT(peak_gyro, 3.0);
  EXPECT_GT(peak_accel, 10.0);  // m/s², gravity taken out
  EXPECT_LT(worst_gyro, 1e-4 * peak_gyro) << worst_gyro << " of " << peak_gyro;
  EXPECT_LT(worst_accel, 1e-3 * peak_accel) << worst_accel << " of " << peak_accel;
}

TEST(ArmImu, AtRestOnVertical2ReadsGravityUpAndNoRotation) {
  const ArmModel arm = builtin_arm("vertical-2");
  // links held at 30° and −50° (link degrees × the gear ratio: motor degrees of a Kp = 1 drive)
  const std::vector<plant::Command> commands{plant::Command::constant(30.0 * arm.joints[0].gear_ratio),
                                             plant::Command::constant(-50.0 * arm.joints[1].gear_ratio)};
  ArmSimulationOptions o = tight_run(4.0, 100.0);
  const ArmTrace tr = simulate_arm(arm, commands, o);
  const Eigen::Index last = tr.gyro_rad_s.rows() - 1;
  ChainWorkspace ws(arm.chain);
  const Eigen::Matrix3d r = ws.tip_pose(tr.link_angle_rad.row(last).transpose()).linear();
  const Eigen::Vector3d up = r.transpose() * Eigen::Vector3d::UnitZ();  // the world's up in the link frame
  const Eigen::Vector3d accel = tr.accel_m_s2.row(last).transpose();
  EXPECT_LT(tr.gyro_rad_s.row(last).norm(), 1e-9);
  EXPECT_NEAR(accel.norm(), kStandardGravity_m_s2, 1e-8);
  EXPECT_NEAR(accel.dot(up), kStandardGravity_m_s2, 1e-8);  // +g along up: the specific force holds the link
  EXPECT_GT(std::abs(up.x()), 0.3);  // the link is tilted: up is not its own z axis
}

TEST(ArmImu, NoiseAndRangeAreSeededAndApplied) {
  ArmModel arm = builtin_arm("scara-2");
  const std::vector<plant::Command> commands{blend(20.0 * arm.joints[0].gear_ratio, 0.0, 0.3),
                                             blend(-30.0 * arm.joints[1].gear_ratio, 0.0, 0.3)};
  ArmSimulationOptions o;
  o.duration_s = 0.8;
  const ArmTrace truth = simulate_arm(arm, commands, o);
  arm.imu.gyro_noise_rad_s = 0.01;
  arm.imu.accel_noise_m_s2 = 0.05;
  arm.imu.seed = 7;
  const ArmTrace noisy = simulate_arm(arm, commands, o);
  const ArmTrace again = simulate_arm(arm, commands, o);
  EXPECT_EQ(noisy.accel_m_s2, again.accel_m_s2);  // seeded: the same run twice
  for (const auto& [measured, exact, sigma] : {std::tuple{&noisy.gyro_rad_s, &truth.gyro_rad_s, 0.01},
                                               std::tuple{&noisy.accel_m_s2, &truth.accel_m_s2, 0.05}}) {
    const Eigen::ArrayXXd e = (*measured - *exact).array();
    const double n = static_cast<double>(e.size());
    const double mean = e.mean(), sd = std::sqrt((e - mean).square().sum() / (n - 1.0));
    EXPECT_NEAR(sd, sigma, 0.05 * sigma);             // 2403 samples: the estimate's 1σ is 1.4 %
    EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(n));
  }
  arm.imu.seed = 8;
  EXPECT_NE(simulate_arm(arm, commands, o).accel_m_s2, noisy.accel_m_s2);
  arm.imu = {};
  arm.imu.accel_range_m_s2 = 5.0;  // below g along z (scara-2's axes are vertical)
  arm.imu.gyro_range_rad_s = 0.5;
  const ArmTrace clipped = simulate_arm(arm, commands, o);
  EXPECT_EQ(clipped.accel_m_s2.col(2).maxCoeff(), 5.0);
  EXPECT_EQ(clipped.gyro_rad_s.cwiseAbs().maxCoeff(), 0.5);
  EXPECT_GT(truth.gyro_rad_s.cwiseAbs().maxCoeff(), 0.5);
  const Eigen::MatrixXd inside = truth.accel_m_s2.leftCols(2).cwiseMax(-5.0).cwiseMin(5.0);
  EXPECT_EQ(clipped.accel_m_s2.leftCols(2), inside);
}

std::string imu_refusal(const std::string& imu) {
  try {
    arm_from_text(three_axis_urdf(), "three-axis.urdf", three_axis_toml(imu), "arm.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(ArmImu, MalformedImuTableIsRefusedNamingTheKey) {
  const std::string mount = imu_refusal("[imu]\nmount_m = [0.1, 0.2]\n");
  EXPECT_NE(mount.find("arm.toml"), std::string::npos) << mount;
  EXPECT_NE(mount.find("imu.mount_m"), std::string::npos) << mount;
  EXPECT_NE(mount.find("allowed: 3"), std::string::npos) << mount;
  const std::string noise = imu_refusal("[imu]\naccel_noise_m_s2 = -1.0\n");
  EXPECT_NE(noise.find("imu.accel_noise_m_s2"), std::string::npos) << noise;
  EXPECT_NE(noise.find("allowed: >= 0"), std::string::npos) << noise;
  const std::string range = imu_refusal("[imu]\ngyro_range_rad_s = 0.0\n");
  EXPECT_NE(range.find("imu.gyro_range_rad_s"), std::string::npos) << range;
  const std::string unknown = imu_refusal("[imu]\nmount = [0, 0, 0]\n");
  EXPECT_NE(unknown.find("mount"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("mount_m"), std::string::npos) << unknown;  // the allowed keys
}

}  // namespace
}  // namespace clearshape::arm
