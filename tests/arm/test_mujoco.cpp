// The arm's rigid-body layer (arm/chain.hpp: Orocos KDL) against MuJoCo 2.2.2 (Debian's
// libmujoco-dev, an independent implementation) on the same URDF: the joint-space inertia M(q), the
// bias torque C(q, q̇)q̇ + g(q) at seeded states of both built-in arms, and a 2 s trajectory of the
// rigid scara-2 (play 0) under the same joint torques, both integrated by RK4 at 0.1 ms
// (issue 24 item 6).
#include <gtest/gtest.h>

#ifdef CLEARSHAPE_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>

#include "clearshape/arm/arm.hpp"
#include "clearshape/arm/chain.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

#ifdef CLEARSHAPE_HAVE_MUJOCO

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

// MuJoCo's own URDF import of the built-in arm's URDF, with KDL's gravity and RK4.
struct MjArm {
  std::unique_ptr<mjModel, MjDeleter> model;
  std::unique_ptr<mjData, MjDeleter> data;
};

MjArm load_in_mujoco(const std::string& name, const RigidChain& chain) {
  const std::filesystem::path dir = clearshape::testing::fresh_temp_dir("clearshape_mujoco");
  const std::filesystem::path urdf = dir / (name + ".urdf");
  std::ofstream(urdf) << builtin_arm_text(name).urdf;
  char error[1000] = "";
  MjArm a;
  a.model.reset(mj_loadXML(urdf.c_str(), nullptr, error, sizeof error));
  std::filesystem::remove_all(dir);
  if (!a.model) ADD_FAILURE() << "MuJoCo could not load " << name << ": " << error;
  if (!a.model) return a;
  for (int i = 0; i < 3; ++i) a.model->opt.gravity[i] = chain.gravity_m_s2()(i);
  a.model->opt.integrator = mjINT_RK4;
  a.model->opt.timestep = 1e-4;
  a.data.reset(mj_makeData(a.model.get()));
  return a;
}

Eigen::MatrixXd mujoco_mass_matrix(const MjArm& a) {
  const int n = a.model->nv;
  Eigen::Matrix<mjtNum, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(n, n);
  mj_fullM(a.model.get(), m.data(), a.data->qM);
  return m;
}

class MujocoArm : public ::testing::TestWithParam<std::string> {};

TEST_P(MujocoArm, InertiaAndBiasTorqueAgreeWithKdl) {
  const ArmModel arm = builtin_arm(GetParam());
  const MjArm mj = load_in_mujoco(GetParam(), arm.chain);
  ASSERT_TRUE(mj.model);
  ASSERT_EQ(mj.model->nv, arm.chain.dof());
  ChainWorkspace ws(arm.chain);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pose(-2.5, 2.5), rate(-6.0, 6.0);
  const int n = arm.chain.dof();
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(n), qd(n);
    for (int i = 0; i < n; ++i) {
      q(i) = pose(rng);
      qd(i) = rate(rng);
      mj.data->qpos[i] = q(i);
      mj.data->qvel[i] = qd(i);
    }
    mj_forward(mj.model.get(), mj.data.get());
    Eigen::MatrixXd m;
    ws.mass_matrix(q, m);
    const Eigen::MatrixXd m_mj = mujoco_mass_matrix(mj);
    EXPECT_LT((m - m_mj).norm(), 1e-9 * m.norm()) << "M(q) at trial " << trial << "\nKDL\n" << m << "\nMuJoCo\n" << m_mj;
    Eigen::VectorXd bias;
    ws.bias_torque(q, qd, bias);
    const Eigen::Map<const Eigen::VectorXd> bias_mj(mj.data->qfrc_bias, n);
    EXPECT_LT((bias - bias_mj).norm(), 1e-9 * (1.0 + bias.norm())) << "bias at trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(BuiltinArms, MujocoArm, ::testing::Values("scara-2", "vertical-2"),
                         [](const auto& param_info) { return param_info.param == "scara-2" ? "scara2" : "vertical2"; });

// τ(t) = (0.08 sin 3t, 0.04 cos 5t) N·m on the rigid, frictionless scara-2 from rest at the
// workspace's centre: q̈ = M(q)⁻¹(τ − C(q, q̇)q̇ − g(q)) from KDL, RK4 at 0.1 ms, against MuJoCo's
// mj_step with RK4 at the same step.
TEST(MujocoArm, ARigidTrajectoryUnderTheSameTorquesAgrees) {
  const ArmModel arm = builtin_arm("scara-2");
  const MjArm mj = load_in_mujoco("scara-2", arm.chain);
  ASSERT_TRUE(mj.model);
  ChainWorkspace ws(arm.chain);
  const auto torque = [](double t) {
    Eigen::Vector2d tau(0.08 * std::sin(3.0 * t), 0.04 * std::cos(5.0 * t));
    return tau;
  };
  const double h = 1e-4;
  const int steps = 20000;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2), qd = Eigen::VectorXd::Zero(2);
  for (int i = 0; i < 2; ++i) mj.data->qpos[i] = mj.data->qvel[i] = 0.0;
  double max_gap = 0.0, max_angle = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double t = k * h;
    // MuJoCo's RK4 holds qfrc_applied over the step: the same zero-order hold here.
    const Eigen::Vector2d tau = torque(t);
    const auto f = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
      Eigen::MatrixXd m;
      Eigen::VectorXd bias;
      ws.mass_matrix(x, m);
      ws.bias_torque(x, v, bias);
      return Eigen::VectorXd(m.ldlt().solve(tau - bias));
    };
    const Eigen::VectorXd a1 = f(q, qd);
    const Eigen::VectorXd a2 = f(q + 0.5 * h * qd, qd + 0.5 * h * a1);
    const Eigen::VectorXd a3 = f(q + 0.5 * h * (qd + 0.5 * h * a1), qd + 0.5 * h * a2);
    const Eigen::VectorXd a4 = f(q + h * (qd + 0.5 * h * a2), qd + h * a3);
    q += h / 6.0 * (qd + 2.0 * (qd + 0.5 * h * a1) + 2.0 * (qd + 0.5 * h * a2) + (qd + h * a3));
    qd += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    for (int i = 0; i < 2; ++i) mj.data->qfrc_applied[i] = tau(i);
    mj_step(mj.model.get(), mj.data.get());
    for (int i = 0; i < 2; ++i) {
      max_gap = std::max(max_gap, std::abs(q(i) - mj.data->qpos[i]));
      max_angle = std::max(max_angle, std::abs(q(i)));
    }
  }
  std::printf("scara-2, 2 s under the same torques: largest |q_KDL - q_MuJoCo| %.3g rad, largest |q| %.3g rad\n", max_gap,
              max_angle);
  EXPECT_GT(max_angle, 0.3);      // the arm moved well away from its start …
  EXPECT_LT(max_angle, 2.5);      // … and stayed inside its URDF limits (no limit force in MuJoCo)
  EXPECT_LT(max_gap, 1e-7);
}

#else

TEST(MujocoArm, Unavailable) { GTEST_SKIP() << "MuJoCo (libmujoco-dev) was not found at configure time"; }

#endif

}  // namespace
}  // namespace clearshape::arm
