// ZV family (Eq. 2.22–2.26) and MZV: published tables (reference note (c2), (c7), (c8)).
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace cs = clearshape::shaping;

namespace {

void expect_impulses(const cs::Shaper& s, const std::vector<double>& a, const std::vector<double>& t,
                     double tol) {
  ASSERT_EQ(s.size(), a.size()) << s.method();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(s.impulses()[i].amplitude, a[i], tol) << s.method() << " A" << i + 1;
    EXPECT_NEAR(s.impulses()[i].time_s, t[i], tol) << s.method() << " t" << i + 1;
  }
}

const cs::Mode k10Hz0 = cs::Mode::from_hz(10.0, 0.0);
const cs::Mode k10Hz05 = cs::Mode::from_hz(10.0, 0.05);
const cs::Mode k10Hz1 = cs::Mode::from_hz(10.0, 0.1);

}  // namespace

// Eq. 2.22–2.26 written out, at the thesis's speed-mode damping ζ = 0.288 (Tw = 0.0479 s).
TEST(DesignZv, ThesisEquations) {
  const double zeta = 0.2880;
  const cs::Mode mode{1.0 / 0.0479, zeta};
  const double K = std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));  // Eq. 2.24
  const double wd = mode.natural_frequency_rad_s * std::sqrt(1 - zeta * zeta);
  const double h = std::numbers::pi / wd;
  expect_impulses(cs::design_zv(mode), {1 / (1 + K), K / (1 + K)}, {0, h}, 1e-14);  // Eq. 2.22–2.23
  const double d2 = 1 + 2 * K + K * K;                                                  // Eq. 2.25
  expect_impulses(cs::design_zvd(mode), {1 / d2, 2 * K / d2, K * K / d2}, {0, h, 2 * h}, 1e-14);
  const double d3 = 1 + 3 * K + 3 * K * K + K * K * K;                                  // Eq. 2.26
  expect_impulses(cs::design_zvdd(mode), {1 / d3, 3 * K / d3, 3 * K * K / d3, K * K * K / d3},
                  {0, h, 2 * h, 3 * h}, 1e-14);
}

TEST(DesignZv, ReferenceTableUndamped) {  // (c2), ζ = 0, f = 10 Hz
  expect_impulses(cs::design_zv(k10Hz0), {0.5, 0.5}, {0, 0.05}, 1e-12);
  expect_impulses(cs::design_zvd(k10Hz0), {0.25, 0.5, 0.25}, {0, 0.05, 0.1}, 1e-12);
  expect_impulses(cs::design_zvdd(k10Hz0), {0.125, 0.375, 0.375, 0.125}, {0, 0.05, 0.1, 0.15}, 1e-12);
  expect_impulses(cs::design_zvddd(k10Hz0), {0.0625, 0.25, 0.375, 0.25, 0.0625},
                  {0, 0.05, 0.1, 0.15, 0.2}, 1e-12);
  expect_impulses(cs::design_mzv(k10Hz0), {0.292893, 0.414214, 0.292893}, {0, 0.0375, 0.075}, 1e-6);
}

TEST(DesignZv, ReferenceTableDamped) {  // (c2), ζ = 0.1 and 0.05, table values to 6 digits
  expect_impulses(cs::design_zv(k10Hz1), {0.578286, 0.421714}, {0, 0.050252}, 1e-6);
  expect_impulses(cs::design_mzv(k10Hz1), {0.365128, 0.407489, 0.227383}, {0, 0.037689, 0.075378}, 1e-6);
  expect_impulses(cs::design_zvd(k10Hz1), {0.334415, 0.487743, 0.177843}, {0, 0.050252, 0.100504}, 1e-6);
  expect_impulses(cs::design_zvdd(k10Hz1), {0.193388, 0.423082, 0.308532, 0.074999},
                  {0, 0.050252, 0.100504, 0.150756}, 1e-6);
  expect_impulses(cs::design_zvddd(k10Hz1), {0.111833, 0.326217, 0.356839, 0.173483, 0.031628},
                  {0, 0.050252, 0.100504, 0.150756, 0.201008}, 1e-6);
  expect_impulses(cs::design_zv(k10Hz05), {0.539238, 0.460762}, {0, 0.050063}, 1e-6);
  expect_impulses(cs::design_zvd(k10Hz05), {0.290778, 0.496921, 0.212301}, {0, 0.050063, 0.100125}, 1e-6);
  expect_impulses(cs::design_zvdd(k10Hz05), {0.156799, 0.401938, 0.343443, 0.097820},
                  {0, 0.050063, 0.100125, 0.150188}, 1e-6);
  expect_impulses(cs::design_mzv(k10Hz05), {0.328223, 0.412530, 0.259246}, {0, 0.037547, 0.075094}, 1e-6);
}

TEST(DesignZv, GeneralDerivativesAreBinomial) {
  const cs::Mode mode = cs::Mode::from_hz(4.0, 0.15);
  const double K = std::exp(-std::numbers::pi * 0.15 / std::sqrt(1 - 0.15 * 0.15));
  for (int n = 0; n <= 8; ++n) {
    const cs::Shaper s = cs::design_zv_derivatives(mode, n);
    ASSERT_EQ(s.size(), static_cast<std::size_t>(n + 2));
    const double norm = std::pow(1 + K, n + 1);
    double binom = 1;
    for (int k = 0; k <= n + 1; ++k) {
      EXPECT_NEAR(s.impulses()[static_cast<std::size_t>(k)].amplitude, binom * std::pow(K, k) / norm, 1e-14);
      binom = binom * (n + 1 - k) / (k + 1);
    }
    EXPECT_LT(cs::residual_vibration(s, mode), 1e-13) << n;
  }
  EXPECT_EQ(cs::design_zv_derivatives(mode, 1).method(), "zvd");
  EXPECT_EQ(cs::design_zv_derivatives(mode, 3).method(), "zvddd");
  EXPECT_THROW(cs::design_zv_derivatives(mode, -1), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_zv_derivatives(mode, 39), clearshape::InvalidArgument);
  EXPECT_NO_THROW(cs::design_zv_derivatives(mode, 38));
}

// (c8): the implementation variants seen in peers leave residual vibration; ours leave none.
TEST(DesignZv, PeerBugVariantsAreDetected) {
  const cs::Shaper mzv = cs::design_mzv(k10Hz1);
  EXPECT_LT(cs::residual_vibration(mzv, k10Hz1), 1e-14);
  // RRF: the same impulses in reversed order (smallest first).
  std::vector<cs::Impulse> reversed;
  for (std::size_t i = 0; i < mzv.size(); ++i) {
    reversed.push_back({mzv.impulses()[i].time_s, mzv.impulses()[mzv.size() - 1 - i].amplitude});
  }
  EXPECT_NEAR(cs::residual_vibration(cs::Shaper("rrf-mzv", reversed), k10Hz1), 0.1623, 5e-5);
  // Marlin FT: [1, √2K, K²] with the half-period K.
  const double K = std::exp(-0.1 * std::numbers::pi / std::sqrt(0.99));
  const auto t = mzv.impulses();
  const cs::Shaper marlin_mzv("marlin-mzv", {{0, 1}, {t[1].time_s, std::sqrt(2.0) * K}, {t[2].time_s, K * K}});
  EXPECT_NEAR(cs::residual_vibration(marlin_mzv, k10Hz1), 0.0251, 5e-5);
  // Marlin legacy ZV: 7-bit amplitudes and the delay of half the undamped period.
  const cs::Shaper marlin_zv("marlin-zv", {{0, 74.0 / 128}, {0.05, 54.0 / 128}});
  EXPECT_NEAR(cs::residual_vibration(marlin_zv, k10Hz1), 0.0067, 5e-5);
}

TEST(DesignZv, LargestImpulseFirstAtDamping) {
  // The k-th impulse carries the decay K^k: relative to the undamped pattern the amplitudes
  // fall with time, so the first impulse is larger than the last (the RRF MZV order fails this).
  for (double zeta : {0.02, 0.1, 0.3, 0.6}) {
    const cs::Mode m = cs::Mode::from_hz(7.0, zeta);
    for (const cs::Shaper& s : {cs::design_zv(m), cs::design_zvd(m), cs::design_zvdd(m), cs::design_mzv(m)}) {
      EXPECT_GT(s.impulses().front().amplitude, s.impulses().back().amplitude) << s.method() << zeta;
    }
    EXPECT_GT(cs::design_zv(m).impulses()[0].amplitude, 0.5);
  }
}

TEST(DesignZv, MzvUndampedCurveHasZerosAtOneAndFiveThirds) {  // (c7)
  const cs::Shaper s = cs::design_mzv(k10Hz0);
  for (double r : {0.3, 0.8, 1.0, 1.4, 5.0 / 3.0, 1.9}) {
    const double expected = std::abs((std::sqrt(2.0) - 1) + (2 - std::sqrt(2.0)) * std::cos(0.75 * std::numbers::pi * r));
    EXPECT_NEAR(cs::residual_vibration(s, cs::Mode::from_hz(10.0 * r, 0.0)), expected, 1e-13) << r;
  }
}

TEST(DesignZv, ValidationMessages) {
  // ζ just below 1 (the thesis's position mode) is valid but degenerate: K ≈ 1e-17, A1 ≈ 1.
  EXPECT_NEAR(cs::design_zvdd(cs::Mode::from_hz(2.0, 0.9968)).impulses()[0].amplitude, 1.0, 1e-12);
  try {
    cs::design_zvd(cs::Mode::from_hz(2.0, 1.0));
    ADD_FAILURE() << "expected a throw";
  } catch (const clearshape::InvalidArgument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("damping_ratio = 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[0, 1)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not oscillatory"), std::string::npos) << msg;
    EXPECT_NE(msg.find("identity"), std::string::npos) << msg;
    EXPECT_NE(msg.find("clearshape modes"), std::string::npos) << msg;
  }
  EXPECT_THROW(cs::design_zv(cs::Mode::from_hz(2.0, -0.1)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_zv(cs::Mode::from_hz(0.0, 0.1)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_zv(cs::Mode::from_hz(-3.0, 0.1)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_mzv(cs::Mode{std::nan(""), 0.1}), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_zv(cs::Mode{INFINITY, 0.1}), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_zv(cs::Mode{1.0, std::nan("")}), clearshape::InvalidArgument);
}
