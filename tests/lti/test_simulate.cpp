// Simulation against closed-form responses (step, ramp, delayed), the real-time stepper's
// allocation-freedom, discretization identities and the ODE right-hand side.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/simulate.hpp"
#include "support/alloc_counter.hpp"

namespace lti = clearshape::lti;
using clearshape::Status;
using clearshape::UniformSeries;

namespace {
lti::ProcessModel first_order(double kp, double tp, double td = 0.0) {
  lti::ProcessParameters p;
  p.kp = kp;
  p.tp1 = tp;
  p.td = td;
  return lti::ProcessModel(td > 0.0 ? "P1D" : "P1", p);
}
UniformSeries ramp(double duration_s, double dt, double slope) {
  UniformSeries u{0.0, dt, std::vector<double>(clearshape::sample_count(duration_s, dt))};
  for (std::size_t i = 0; i < u.size(); ++i) u.values[i] = slope * u.time_s(i);
  return u;
}
}  // namespace

// y(t) = K (1 − e^(−(t−Td)/T)) for t ≥ Td: exact with a held step for any delay.
TEST(Simulate, FirstOrderStepWithIntegerAndFractionalDelay) {
  for (double td : {0.0, 0.003, 0.0025, 0.0137}) {
    const auto y = lti::step_response(first_order(2.0, 0.05, td), 0.3, 1e-3);
    ASSERT_EQ(y.size(), 301u);
    for (std::size_t i = 0; i < y.size(); ++i) {
      const double t = y.time_s(i);
      const double ref = t >= td ? 2.0 * (1.0 - std::exp(-(t - td) / 0.05)) : 0.0;
      EXPECT_NEAR(y.values[i], ref, 1e-13) << "td " << td << " t " << t;
    }
  }
}

// Ramp r = a t through K/(1+Ts): y = K a (t − T + T e^(−t/T)); FOH reconstructs a ramp exactly,
// also when delayed by a fractional number of samples.
TEST(Simulate, FirstOrderRampFohExactWithFractionalDelay) {
  const double k = 1.5, tp = 0.02, a = 3.0;
  for (double td : {0.0, 0.002, 0.0004, 0.0071}) {
    const auto y = lti::simulate(first_order(k, tp, td), ramp(0.2, 1e-3, a), lti::Hold::foh);
    for (std::size_t i = 0; i < y.size(); ++i) {
      const double t = y.time_s(i) - td;
      const double ref = t > 0.0 ? k * a * (t - tp + tp * std::exp(-t / tp)) : 0.0;
      EXPECT_NEAR(y.values[i], ref, 1e-13) << "td " << td << " t " << y.time_s(i);
    }
  }
}

// Underdamped pair: y = 1 − e^(−ζωn t)(cos ωd t + ζ/√(1−ζ²) sin ωd t).
TEST(Simulate, UnderdampedStepClosedForm) {
  lti::ProcessParameters p;
  p.tw = 0.0479;
  p.zeta = 0.288;
  const lti::ProcessModel m("P2U", p);
  const auto y = lti::step_response(m, 1.0, 5e-4);
  const double wn = 1.0 / p.tw, z = p.zeta, wd = wn * std::sqrt(1.0 - z * z);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = y.time_s(i);
    const double ref = 1.0 - std::exp(-z * wn * t) * (std::cos(wd * t) + z / std::sqrt(1.0 - z * z) * std::sin(wd * t));
    EXPECT_NEAR(y.values[i], ref, 1e-12) << t;
  }
}

// Integrator: P1I step → Kp (t − T (1 − e^(−t/T))).
TEST(Simulate, IntegratingModelStep) {
  lti::ProcessParameters p;
  p.kp = 4.0;
  p.tp1 = 0.1;
  const auto y = lti::step_response(lti::ProcessModel("P1I", p), 1.0, 1e-3);
  for (std::size_t i = 0; i < y.size(); i += 10) {
    const double t = y.time_s(i);
    EXPECT_NEAR(y.values[i], 4.0 * (t - 0.1 * (1.0 - std::exp(-t / 0.1))), 1e-12) << t;
  }
}

// The thesis speed model has an RHP zero: the step response starts in the wrong direction
// (initial curvature K·Tz/(Tw²·Tp3) < 0) and settles at Kp.
TEST(Simulate, ThesisSpeedModelUndershootsThenSettles) {
  const auto y = lti::step_response(lti::thesis_speed_mode_model(), 3.0, 1e-3);
  EXPECT_EQ(y.values[0], 0.0);
  EXPECT_LT(y.values[5], 0.0);
  const double curvature = 25.47 * -0.0398 / (0.0479 * 0.0479 * 0.0857);
  EXPECT_NEAR(y.values[1], 0.5 * curvature * 1e-6, 0.02 * std::abs(0.5 * curvature * 1e-6));
  EXPECT_NEAR(y.values.back(), 25.47, 1e-6 * 25.47);
}

TEST(Simulate, ZeroInputFreeResponseFromInitialState) {
  const auto model = first_order(1.0, 0.1).state_space();
  UniformSeries u{0.0, 1e-3, std::vector<double>(200, 0.0)};
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(1, 2.0);
  for (auto hold : {lti::Hold::zoh, lti::Hold::foh}) {
    const auto y = lti::simulate(model, u, hold, 0.0, x0);
    for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(y.values[i], 2.0 * std::exp(-y.time_s(i) / 0.1), 1e-13);
  }
  EXPECT_THROW(lti::simulate(model, u, lti::Hold::zoh, 0.0, Eigen::VectorXd::Zero(3)), clearshape::InvalidArgument);
}

TEST(Simulate, RejectsBadInput) {
  const lti::SampledModel sm(first_order(1.0, 0.1), 1e-3);
  UniformSeries u{0.0, 2e-3, {0.0, 1.0}};
  EXPECT_THROW(lti::simulate(sm, u), clearshape::InvalidArgument);  // wrong sample time
  u.sample_time_s = 1e-3;
  u.values[1] = NAN;
  EXPECT_THROW(lti::simulate(sm, u), clearshape::InvalidArgument);
  EXPECT_THROW(lti::SampledModel(first_order(1.0, 0.1), 0.0), clearshape::InvalidArgument);
  EXPECT_THROW(lti::SampledModel(first_order(1.0, 0.1).state_space(), 1e-3, lti::Hold::zoh, -1.0),
               clearshape::InvalidArgument);
}

TEST(SampledModel, SplitsDelayIntoWholeAndFraction) {
  const lti::SampledModel a(first_order(1.0, 0.1, 0.003), 1e-3);
  EXPECT_EQ(a.delay_samples(), 3u);  // 0.003/0.001 = 2.9999999999999996 is snapped to 3
  EXPECT_EQ(a.delay_fraction(), 0.0);
  const lti::SampledModel b(first_order(1.0, 0.1, 0.0125), 1e-3);
  EXPECT_EQ(b.delay_samples(), 12u);
  EXPECT_NEAR(b.delay_fraction(), 0.5, 1e-12);
}

// The stepper produces the offline result, without allocating and without throwing.
TEST(Simulator, StepIsAllocationFreeAndMatchesOffline) {
  lti::ProcessParameters p = lti::thesis_speed_mode_model().parameters();
  p.td = 0.0123;
  const lti::ProcessModel m("P3DZU", p);
  const lti::SampledModel sm(m, 1e-3, lti::Hold::foh);
  const auto u = ramp(0.5, 1e-3, 2.0);
  const auto offline = lti::simulate(sm, u);
  lti::Simulator sim(sm);
  std::vector<double> y(u.size());
  {
    clearshape::testing::AllocationCounter counter;
    for (std::size_t i = 0; i < u.size(); ++i) ASSERT_EQ(sim.step(u.values[i], y[i]), Status::ok);
    sim.reset();
    const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(sm.order());
    EXPECT_EQ(sim.reset(x0), Status::ok);
    EXPECT_EQ(counter.allocations(), 0u);
  }
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_EQ(y[i], offline.values[i]);
  EXPECT_EQ(sim.steps(), 0u);
}

TEST(Simulator, NonFiniteInputHoldsPreviousAndReportsIt) {
  lti::Simulator sim(lti::SampledModel(first_order(1.0, 0.01), 1e-3));
  lti::Simulator ref(lti::SampledModel(first_order(1.0, 0.01), 1e-3));
  double y = 0.0;
  EXPECT_EQ(sim.step(1.0, y), Status::ok);
  ref.step(1.0);
  EXPECT_EQ(sim.step(NAN, y), Status::not_finite);
  EXPECT_EQ(y, ref.step(1.0));
  EXPECT_EQ(sim.reset(Eigen::VectorXd::Zero(4)), Status::out_of_range);
}

// ZOH discretization of 1/(1+Ts) (B = 1/T): a = e^(−h/T), b = 1 − e^(−h/T).
TEST(Discretize, ZohFirstOrderClosedForm) {
  const auto d = lti::discretize(first_order(1.0, 0.05).state_space(), 0.01);
  EXPECT_NEAR(d.a(0, 0), std::exp(-0.2), 1e-15);
  EXPECT_NEAR(d.b(0, 0), 1.0 - std::exp(-0.2), 1e-15);
  EXPECT_THROW(lti::discretize(first_order(1.0, 0.05).state_space(), -1.0), clearshape::InvalidArgument);
}

// dlsim of the ZOH and FOH discretizations equals the stepping simulator (two derivations of
// the same exact solution).
TEST(Discretize, DiscreteModelsReproduceTheSimulator) {
  const auto m = lti::thesis_speed_mode_model();
  const auto ss = m.state_space();
  UniformSeries u{0.0, 2e-3, std::vector<double>(400)};
  for (std::size_t i = 0; i < u.size(); ++i) u.values[i] = std::sin(0.05 * static_cast<double>(i)) + (i > 50 ? 1.0 : 0.0);
  for (auto hold : {lti::Hold::zoh, lti::Hold::foh}) {
    const auto d = lti::discretize(ss, 2e-3, hold);
    const auto yd = lti::simulate(d, u.values);
    const auto ys = lti::simulate(ss, u, hold);
    for (std::size_t i = 0; i < u.size(); ++i) EXPECT_NEAR(yd[i], ys.values[i], 1e-11 * 25.47) << i;
  }
}

// derivative() is ẋ = A x + B u and is allocation-free; RK4 with it converges to the exact step.
TEST(StateSpace, DerivativeDrivesAnOdeToTheExactSolution) {
  const auto ss = lti::thesis_position_mode_model().state_space();
  const auto n = static_cast<std::size_t>(ss.order());
  std::vector<double> x(n, 0.0), k1(n), k2(n), k3(n), k4(n), tmp(n);
  const double h = 1e-4;
  {
    clearshape::testing::AllocationCounter counter;
    for (int step = 0; step < 500; ++step) {
      auto stage = [&](const std::vector<double>& k, double c) {
        for (std::size_t i = 0; i < n; ++i) tmp[i] = x[i] + c * h * k[i];
      };
      lti::derivative(ss, x, 1.0, k1);
      stage(k1, 0.5);
      lti::derivative(ss, tmp, 1.0, k2);
      stage(k2, 0.5);
      lti::derivative(ss, tmp, 1.0, k3);
      stage(k3, 1.0);
      lti::derivative(ss, tmp, 1.0, k4);
      for (std::size_t i = 0; i < n; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    EXPECT_EQ(counter.allocations(), 0u);
  }
  const auto exact = lti::step_response(lti::thesis_position_mode_model(), 0.05, 1e-4);
  EXPECT_NEAR(lti::output(ss, x, 1.0), exact.values.back(), 1e-9);
}

TEST(Discretize, ContinuousEquivalentInvertsZoh) {
  lti::StateSpace c;
  c.a.resize(3, 3);
  c.a << 0, 1, 0, -400, -4, 20, 0, 0, -30;
  c.b.resize(3, 1);
  c.b << 0, 2, 1;
  c.c.resize(1, 3);
  c.c << 1, 0.1, -0.5;
  c.d = Eigen::MatrixXd::Constant(1, 1, 0.3);
  const auto d = lti::discretize(c, 0.005);
  const auto back = lti::continuous_equivalent(d);
  EXPECT_LT((back.a - c.a).cwiseAbs().maxCoeff(), 1e-9 * c.a.cwiseAbs().maxCoeff());
  EXPECT_LT((back.b - c.b).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(back.d(0, 0), 0.3);
  // A pole on the negative real axis has no real logarithm.
  lti::DiscreteStateSpace neg = d;
  neg.a = -Eigen::MatrixXd::Identity(3, 3) * 0.5;
  EXPECT_THROW(lti::continuous_equivalent(neg), clearshape::RuntimeError);
}
