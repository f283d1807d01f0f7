// Degenerate and boundary process models: static gain, pure delay, integrator with zero,
// pole-zero cancellation, zero time constants; consistency of the stepper with discretize().
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/simulate.hpp"

namespace lti = clearshape::lti;
using clearshape::UniformSeries;

namespace {
UniformSeries sequence(std::size_t n) {
  UniformSeries u{0.0, 1e-3, std::vector<double>(n)};
  for (std::size_t i = 0; i < n; ++i) u.values[i] = std::sin(0.3 * static_cast<double>(i)) + 0.1 * static_cast<double>(i % 7);
  return u;
}
}  // namespace

// P0D: y(t) = Kp u(t − Td). Td = 2.5 T: ZOH holds u[k−3]; FOH interpolates halfway.
TEST(EdgeCases, PureDelayStaticGain) {
  lti::ProcessParameters p;
  p.kp = 2.0;
  p.td = 0.0025;
  const lti::ProcessModel m("P0D", p);
  EXPECT_EQ(m.state_space().order(), 0);
  const auto u = sequence(50);
  const auto yz = lti::simulate(m, u, lti::Hold::zoh);
  const auto yf = lti::simulate(m, u, lti::Hold::foh);
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double u3 = k >= 3 ? u.values[k - 3] : 0.0;
    const double u2 = k >= 2 ? u.values[k - 2] : 0.0;
    EXPECT_DOUBLE_EQ(yz.values[k], 2.0 * u3) << k;
    EXPECT_NEAR(yf.values[k], 2.0 * (0.5 * u2 + 0.5 * u3), 1e-15) << k;
  }
}

// P0IZ: Kp (1 + Tz s)/s; step → Kp (t + Tz) (the zero gives a direct feedthrough Kp Tz).
TEST(EdgeCases, IntegratorWithZero) {
  lti::ProcessParameters p;
  p.kp = 3.0;
  p.tz = 0.2;
  const lti::ProcessModel m("P0IZ", p);
  const auto y = lti::step_response(m, 0.5, 1e-3);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(y.values[i], 3.0 * (y.time_s(i) + 0.2), 1e-13);
  EXPECT_TRUE(m.zeros().size() == 1 && std::abs(m.zeros()[0].real() + 5.0) < 1e-15);
}

// Tz = Tp1 cancels the pole: the output is Kp u exactly.
TEST(EdgeCases, PoleZeroCancellation) {
  lti::ProcessParameters p;
  p.kp = 1.7;
  p.tp1 = 0.05;
  p.tz = 0.05;
  const lti::ProcessModel m("P1Z", p);
  const auto u = sequence(40);
  const auto y = lti::simulate(m, u, lti::Hold::zoh);
  for (std::size_t k = 0; k < u.size(); ++k) EXPECT_NEAR(y.values[k], 1.7 * u.values[k], 1e-14);
}

// A zero time constant removes its factor: P2 with Tp2 = 0 behaves as P1.
TEST(EdgeCases, ZeroTimeConstantRemovesFactor) {
  lti::ProcessParameters p;
  p.kp = 1.0;
  p.tp1 = 0.1;
  const lti::ProcessModel two("P2", p), one("P1", p);
  EXPECT_EQ(two.state_space().order(), 1);
  EXPECT_EQ(two.poles().size(), 1u);
  const auto a = lti::step_response(two, 0.3, 1e-3), b = lti::step_response(one, 0.3, 1e-3);
  EXPECT_EQ(a.values, b.values);
}

// Undamped pair (Zeta = 0) is allowed and oscillates forever: y = 1 − cos(t/Tw).
TEST(EdgeCases, UndampedPair) {
  lti::ProcessParameters p;
  p.tw = 0.01;
  const lti::ProcessModel m("P2U", p);
  const auto y = lti::step_response(m, 1.0, 1e-3);
  for (std::size_t i = 0; i < y.size(); i += 37) EXPECT_NEAR(y.values[i], 1.0 - std::cos(y.time_s(i) / 0.01), 1e-11);
  EXPECT_EQ(m.oscillatory_modes().at(0).damping_ratio, 0.0);
}

// Without delay the stepper's Φ and taps are the ZOH/FOH discretization's matrices.
TEST(EdgeCases, SampledModelMatchesDiscretize) {
  const auto ss = lti::thesis_speed_mode_model().state_space();
  const lti::SampledModel zoh(ss, 1e-3, lti::Hold::zoh);
  const auto d = lti::discretize(ss, 1e-3, lti::Hold::zoh);
  EXPECT_LE((zoh.phi() - d.a).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((zoh.input_taps().col(1) - d.b.col(0)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(zoh.input_taps().col(0).norm(), 0.0);
  EXPECT_EQ(zoh.input_taps().col(2).norm(), 0.0);
}

// FOH discrete state: ξ[k] = x(kT) − M13 u[k] (scipy convention) — starting from x0 ≠ 0 the
// discrete model reproduces the continuous simulation when ξ0 = x0 − M13 u[0].
TEST(EdgeCases, FohDiscreteStateConvention) {
  const auto ss = lti::thesis_position_mode_model().state_space();
  const double dt = 1e-3;
  const auto d = lti::discretize(ss, dt, lti::Hold::foh);
  // Recover M13 from b = Γ − Λ + ΦΛ and the ZOH Γ: (Φ − I) Λ = b − Γ.
  const auto z = lti::discretize(ss, dt, lti::Hold::zoh);
  const Eigen::VectorXd lambda =
      (d.a - Eigen::MatrixXd::Identity(ss.order(), ss.order())).partialPivLu().solve(d.b - z.b);
  auto u = sequence(200);
  u.values[0] = 0.7;
  Eigen::VectorXd x0(ss.order());
  x0 << 0.3, -0.2, 0.1;
  const auto yc = lti::simulate(ss, u, lti::Hold::foh, 0.0, x0);
  const auto yd = lti::simulate(d, u.values, Eigen::VectorXd(x0 - lambda * u.values[0]));
  for (std::size_t k = 0; k < u.size(); ++k) EXPECT_NEAR(yd[k], yc.values[k], 1e-12) << k;
}

TEST(EdgeCases, ParameterAccessByName) {
  lti::ProcessParameters p;
  p.set("TP2", 0.4);
  EXPECT_EQ(p.tp2, 0.4);
  EXPECT_THROW(p.set("Tq", 1.0), clearshape::InvalidArgument);
  EXPECT_THROW((void)p.get("K"), clearshape::InvalidArgument);
}
