// The shapers Klipper and RRF build, checked against physical facts (V = 0 at the mode for the
// zero-vibration family, the 5 % humps of the EI fits) and the RRF documentation's custom example.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "clearshape/export/firmware_shapers.hpp"
#include "clearshape/shaping/residual.hpp"

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;

namespace {

double max_v(const sh::Shaper& s, const sh::Mode& m, double r0, double r1) {
  double worst = 0.0;
  for (int i = 0; i <= 400; ++i) {
    const double r = r0 + (r1 - r0) * i / 400.0;
    worst = std::max(worst, sh::residual_vibration(s, {r * m.natural_frequency_rad_s, m.damping_ratio}));
  }
  return worst;
}

}  // namespace

TEST(FirmwareShapers, ZeroVibrationFamilyCancelsTheMode) {
  for (double zeta : {0.0, 0.1, 0.3}) {
    const sh::Mode mode = sh::Mode::from_hz(40.0, zeta);
    for (const char* t : {"zv", "mzv", "zvd"}) {
      const auto s = ex::klipper_shaper(t, 40.0, zeta);
      ASSERT_TRUE(s);
      EXPECT_LT(sh::residual_vibration(*s, mode), 1e-12) << t << " ζ=" << zeta;
      EXPECT_NEAR(s->amplitude_sum(), 1.0, 1e-15);
    }
    for (const char* t : {"zvd", "zvdd", "zvddd"}) {
      EXPECT_LT(sh::residual_vibration(*ex::rrf_shaper(t, 40.0, zeta), mode), 1e-12) << t;
    }
  }
  // Durations on the damped period: ZV is half of it, ZVD the whole, MZV three quarters.
  const double td = 1.0 / (40.0 * std::sqrt(1.0 - 0.01));
  EXPECT_NEAR(ex::klipper_shaper("zv", 40.0, 0.1)->duration_s(), 0.5 * td, 1e-15);
  EXPECT_NEAR(ex::klipper_shaper("zvd", 40.0, 0.1)->duration_s(), td, 1e-15);
  EXPECT_NEAR(ex::klipper_shaper("mzv", 40.0, 0.1)->duration_s(), 0.75 * td, 1e-15);
}

TEST(FirmwareShapers, EiCurveFitsKeepTheirFivePercentHumps) {
  // Singhose's fits: EI has V(1) ≈ 5 %; 2-hump EI V(1) ≈ 0 with humps ≈ 5 %; 3-hump V(1) ≈ 5 %.
  const double zeta = 0.1;
  const sh::Mode mode = sh::Mode::from_hz(50.0, zeta);
  EXPECT_NEAR(sh::residual_vibration(*ex::klipper_shaper("ei", 50.0, zeta), mode), 0.05, 0.005);
  EXPECT_LT(sh::residual_vibration(*ex::klipper_shaper("2hump_ei", 50.0, zeta), mode), 0.005);
  EXPECT_NEAR(max_v(*ex::klipper_shaper("2hump_ei", 50.0, zeta), mode, 0.7, 1.3), 0.05, 0.005);
  EXPECT_NEAR(sh::residual_vibration(*ex::klipper_shaper("3hump_ei", 50.0, zeta), mode), 0.05, 0.005);
  EXPECT_NEAR(max_v(*ex::klipper_shaper("3hump_ei", 50.0, zeta), mode, 0.6, 1.4), 0.05, 0.006);
}

TEST(FirmwareShapers, RrfTimesItsEiFitsOnTheDampedPeriod) {
  const double zeta = 0.2;
  const auto klipper = ex::klipper_shaper("2hump_ei", 30.0, zeta);
  const auto rrf = ex::rrf_shaper("ei2", 30.0, zeta);
  EXPECT_NEAR(rrf->duration_s() * std::sqrt(1.0 - zeta * zeta), klipper->duration_s(), 1e-15);
}

TEST(FirmwareShapers, RrfMzvIsKlippersReversed) {
  // Equal at ζ = 0; reversed amplitudes leave a large V at the mode once ζ > 0.
  const auto k0 = ex::klipper_shaper("mzv", 40.0, 0.0);
  const auto r0 = ex::rrf_shaper("mzv", 40.0, 0.0);
  EXPECT_LT(ex::residual_difference(*k0, *r0, sh::Mode::from_hz(40.0, 0.0)).max_abs, 1e-12);
  const sh::Mode damped = sh::Mode::from_hz(40.0, 0.1);
  EXPECT_GT(sh::residual_vibration(*ex::rrf_shaper("mzv", 40.0, 0.1), damped), 0.1);
  EXPECT_NEAR(ex::rrf_shaper("mzv", 40.0, 0.1)->impulses()[0].amplitude,
              ex::klipper_shaper("mzv", 40.0, 0.1)->impulses()[2].amplitude, 1e-15);
}

TEST(FirmwareShapers, RrfCustomFormFromTheDocumentationExample) {
  // M593 P"custom" H0.4:0.7 T0.0135:0.0135 (Duet3D G-code dictionary): H is cumulative.
  const sh::Shaper s = ex::rrf_custom_shaper({0.4, 0.7}, {0.0135, 0.0135});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(s.impulses()[0].amplitude, 0.4, 1e-15);
  EXPECT_NEAR(s.impulses()[1].amplitude, 0.3, 1e-15);
  EXPECT_NEAR(s.impulses()[2].amplitude, 0.3, 1e-15);
  EXPECT_NEAR(s.impulses()[2].time_s, 0.027, 1e-15);
  EXPECT_FALSE(ex::klipper_shaper("zvdd", 40.0, 0.1));
  EXPECT_FALSE(ex::rrf_shaper("zv", 40.0, 0.1));
}
