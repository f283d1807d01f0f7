// The arm's Jacobian against central differences of its right-hand side, in contact on both
// flanks and in free flight, for scara-2 and vertical-2 (gravity, Coriolis and the plays).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "../../src/arm/arm_system.hpp"

namespace clearshape::arm {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void expect_jacobian_matches(const char* name, const Eigen::Vector2d& phi, const Eigen::Vector2d& rate) {
  const ArmModel arm = builtin_arm(name);
  const std::vector<plant::Command> cmd{plant::Command::constant(300.0), plant::Command::constant(-200.0)};
  detail::ArmSystem sys(arm, cmd);
  const int n = sys.size();
  std::vector<double> y(static_cast<std::size_t>(n));
  std::vector<ArmEvent> events;
  sys.initial_state(ArmInitialState{phi, rate}, y.data(), events);
  y[0] *= 1.0 + 1e-4;  // the drives slightly off rest: their rates enter φ̇
  y[2] *= 1.0 - 1e-4;
  std::vector<double> jac(static_cast<std::size_t>(n * n)), fp(static_cast<std::size_t>(n)), fm(fp);
  ASSERT_EQ(sys.jacobian(0.1, y.data(), jac.data()), 0);
  double scale = 0.0;
  for (double v : jac) scale = std::max(scale, std::abs(v));
  for (int c = 0; c < n; ++c) {
    const double h = 1e-7 * (1.0 + std::abs(y[static_cast<std::size_t>(c)]));
    std::vector<double> yp = y, ym = y;
    yp[static_cast<std::size_t>(c)] += h;
    ym[static_cast<std::size_t>(c)] -= h;
    ASSERT_EQ(sys.rhs(0.1, yp.data(), fp.data()), 0);
    ASSERT_EQ(sys.rhs(0.1, ym.data(), fm.data()), 0);
    for (int r = 0; r < n; ++r) {
      const double diff = (fp[static_cast<std::size_t>(r)] - fm[static_cast<std::size_t>(r)]) / (2.0 * h);
      EXPECT_NEAR(jac[static_cast<std::size_t>(r + n * c)], diff, 1e-5 * scale) << name << " row " << r << " col " << c;
    }
  }
}

TEST(ArmJacobian, MatchesDifferencesInContactOnBothFlanks) {
  expect_jacobian_matches("scara-2", Eigen::Vector2d(0.4 * kDeg, -0.35 * kDeg), Eigen::Vector2d(0.3, -0.2));
  expect_jacobian_matches("vertical-2", Eigen::Vector2d(-0.3 * kDeg, 0.45 * kDeg), Eigen::Vector2d(-0.5, 0.8));
}

TEST(ArmJacobian, MatchesDifferencesInFreeFlight) {
  expect_jacobian_matches("vertical-2", Eigen::Vector2d(0.1 * kDeg, -0.1 * kDeg), Eigen::Vector2d(1.5, -2.0));
}

}  // namespace
}  // namespace clearshape::arm
