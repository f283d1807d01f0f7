// TransferFunction: normalization, roots, DC gain, frequency response, realizations.
#include <cmath>
#include <complex>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/modes.hpp"
#include "clearshape/lti/transfer_function.hpp"

namespace lti = clearshape::lti;

TEST(Polynomial, MultiplyEvaluateRoots) {
  const lti::Polynomial p = lti::multiply({1.0, 2.0}, {1.0, 3.0});  // (s+2)(s+3)
  EXPECT_EQ(p, (lti::Polynomial{1.0, 5.0, 6.0}));
  EXPECT_EQ(lti::evaluate(p, {1.0, 0.0}), std::complex<double>(12.0, 0.0));
  const auto r = lti::roots(p);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NEAR(r[0].real(), -3.0, 1e-14);
  EXPECT_NEAR(r[1].real(), -2.0, 1e-14);
  EXPECT_EQ(lti::degree({0.0, 0.0, 1.0, 2.0}), 1);
  EXPECT_TRUE(lti::roots({5.0}).empty());
  const std::complex<double> pair[] = {{-1.0, 2.0}, {-1.0, -2.0}};
  const auto q = lti::from_roots(pair);  // s² + 2s + 5
  EXPECT_NEAR(q[1], 2.0, 1e-15);
  EXPECT_NEAR(q[2], 5.0, 1e-15);
}

TEST(TransferFunction, NormalizesAndValidates) {
  const lti::TransferFunction h({0.0, 4.0, 8.0}, {2.0, 6.0, 4.0});
  EXPECT_EQ(h.denominator(), (lti::Polynomial{1.0, 3.0, 2.0}));
  EXPECT_EQ(h.numerator(), (lti::Polynomial{2.0, 4.0}));
  EXPECT_EQ(h.order(), 2);
  EXPECT_EQ(h.relative_degree(), 1);
  EXPECT_DOUBLE_EQ(h.dc_gain(), 2.0);
  EXPECT_THROW(lti::TransferFunction({1.0, 0.0, 0.0}, {1.0, 1.0}), clearshape::InvalidArgument);
  EXPECT_THROW(lti::TransferFunction({1.0}, {0.0, 0.0}), clearshape::InvalidArgument);
  EXPECT_THROW(lti::TransferFunction({1.0}, {1.0, NAN}), clearshape::InvalidArgument);
  EXPECT_TRUE(std::isinf(lti::TransferFunction({1.0}, {1.0, 0.0}).dc_gain()));
}

TEST(TransferFunction, RightHalfPlaneZeroAndModes) {
  // Thesis speed model zero: 1 + Tz s with Tz = −0.0398 → s = +25.13 rad/s.
  const lti::TransferFunction h({-0.0398, 1.0}, {1.0, 2.0, 100.0});
  const auto z = h.zeros();
  ASSERT_EQ(z.size(), 1u);
  EXPECT_NEAR(z[0].real(), 1.0 / 0.0398, 1e-10);
  const auto modes = h.oscillatory_modes();
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_NEAR(modes[0].natural_frequency_rad_s, 10.0, 1e-12);
  EXPECT_NEAR(modes[0].damping_ratio, 0.1, 1e-12);
  EXPECT_NEAR(modes[0].period_s(), clearshape::kTwoPi / std::sqrt(99.0), 1e-12);
}

TEST(TransferFunction, FrequencyResponseClosedForm) {
  const lti::TransferFunction h({3.0}, {0.5, 1.0});  // 3/(1 + 0.5 s)
  for (double w : {0.0, 0.1, 2.0, 50.0}) {
    const auto ref = 3.0 / std::complex<double>(1.0, 0.5 * w);
    EXPECT_NEAR(std::abs(h.frequency_response(w) - ref), 0.0, 1e-15);
  }
}

TEST(TransferFunction, ZerosPolesGainRoundTrip) {
  const std::complex<double> zeros[] = {{25.0, 0.0}};
  const std::complex<double> poles[] = {{-3.0, 4.0}, {-3.0, -4.0}, {-10.0, 0.0}};
  const auto h = lti::TransferFunction::from_zeros_poles_gain(zeros, poles, 2.0);
  EXPECT_NEAR(h.dc_gain(), 2.0 * -25.0 / (25.0 * 10.0), 1e-14);
  const auto p = h.poles();
  EXPECT_NEAR(p[0].real(), -10.0, 1e-12);
  EXPECT_NEAR(std::abs(p[1] - poles[1]), 0.0, 1e-12);
}

// Balancing is a similarity: same H(jω); the canonical form of a TF whose coefficients span
// decades gets a much smaller norm spread.
TEST(TransferFunction, BalancedRealizationKeepsResponseAndImprovesScaling) {
  // (1+1e-4 s)(1+0.5 s)(1+2 s)(1 + 1e-3 s) denominator: coefficients from 1e-7 to 1.
  lti::Polynomial den{1.0};
  for (double t : {1e-4, 0.5, 2.0, 1e-3}) den = lti::multiply(den, {t, 1.0});
  const lti::TransferFunction h({0.02, 3.0}, den);
  const auto raw = h.controllable_canonical();
  const auto bal = h.state_space();
  for (double w : {0.01, 1.0, 100.0, 1e4, 1e5}) {
    const auto ref = h.frequency_response(w);
    EXPECT_NEAR(std::abs(lti::frequency_response(bal, w) - ref), 0.0, 1e-10 * std::abs(ref)) << w;
  }
  auto spread = [](const Eigen::MatrixXd& a) {
    double lo = INFINITY, hi = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i)
      if (a(i) != 0.0) {
        lo = std::min(lo, std::abs(a(i)));
        hi = std::max(hi, std::abs(a(i)));
      }
    return hi / lo;
  };
  // Measured: entry spread 2.5e7 → 5.9e5, ‖A‖_F 2.9e7 → 1.2e4 (Osborne minimizes the Frobenius norm).
  EXPECT_LT(spread(bal.a), 0.1 * spread(raw.a));
  EXPECT_LT(bal.a.norm(), 1e-2 * raw.a.norm());
}
