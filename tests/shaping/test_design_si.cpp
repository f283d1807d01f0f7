// Specified-insensitivity shapers: closed-form optima, feasibility on the band, validation.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace cs = clearshape::shaping;

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

cs::SiOptions band_hz(double lo, double hi, double vtol = 0.05) {
  cs::SiOptions o;
  o.frequency_low_rad_s = kTwoPi * lo;
  o.frequency_high_rad_s = kTwoPi * hi;
  o.vtol = vtol;
  return o;
}

double max_v_on_band(const cs::Shaper& s, const cs::SiOptions& o, double zeta) {
  double m = 0;
  for (int k = 0; k <= 4000; ++k) {
    const double w = o.frequency_low_rad_s + (o.frequency_high_rad_s - o.frequency_low_rad_s) * k / 4000.0;
    m = std::max(m, cs::residual_vibration(s, cs::Mode{w, zeta}));
  }
  return m;
}

}  // namespace

// Over the exact EI band at 5 % (r = 0.8003 … 1.1997, ζ = 0) the shortest positive shaper is
// EI itself (one period); over the ZV band it is ZV (half a period).
TEST(DesignSi, RecoversClosedFormOptima) {
  const cs::Mode m = cs::Mode::from_hz(10.0, 0.0);
  // The bands are shrunk by 0.1 % so that the optimiser's 1e-4 margin on Vtol leaves room.
  const cs::InsensitivityBand ei_band = cs::insensitivity(cs::design_ei(m), m, 0.05);
  const cs::Shaper si = cs::design_si(m, band_hz(10 * ei_band.ratio_low * 1.001, 10 * ei_band.ratio_high / 1.001));
  EXPECT_EQ(si.size(), 3u);
  EXPECT_NEAR(si.duration_s(), 0.1, 1e-3);
  EXPECT_LE(si.duration_s(), 0.1);
  EXPECT_NEAR(si.impulses()[0].amplitude, 0.2625, 2e-3);
  const cs::InsensitivityBand zv_band = cs::insensitivity(cs::design_zv(m), m, 0.05);
  const cs::Shaper si_zv = cs::design_si(m, band_hz(10 * zv_band.ratio_low * 1.001, 10 * zv_band.ratio_high / 1.001));
  EXPECT_EQ(si_zv.size(), 2u);
  EXPECT_NEAR(si_zv.duration_s(), 0.05, 1e-4);
  EXPECT_LE(si_zv.duration_s(), 0.05);
}

TEST(DesignSi, NeverLongerThanACoveringClosedForm) {
  for (double zeta : {0.0, 0.1, 0.25}) {
    const cs::Mode m = cs::Mode::from_hz(5.0, zeta);
    for (const cs::Shaper& closed : {cs::design_zvd(m), cs::design_ei(m), cs::design_zvdd(m)}) {
      const cs::InsensitivityBand b = cs::insensitivity(closed, m, 0.05);
      const cs::SiOptions o = band_hz(5 * b.ratio_low, 5 * b.ratio_high);
      const cs::Shaper si = cs::design_si(m, o);
      EXPECT_LE(si.duration_s(), closed.duration_s() * (1 + 1e-4)) << closed.method() << " ζ=" << zeta;
      EXPECT_LE(max_v_on_band(si, o, zeta), 0.05 * (1 + 1e-6));
      EXPECT_TRUE(si.is_positive());
    }
  }
}

TEST(DesignSi, FixedImpulseCount) {
  const cs::Mode m = cs::Mode::from_hz(10.0, 0.05);
  cs::SiOptions o = band_hz(8.0, 12.0);
  o.impulses = 5;
  const cs::Shaper s = cs::design_si(m, o);
  EXPECT_LE(s.size(), 5u);  // coincident or empty impulses are merged away
  EXPECT_LE(max_v_on_band(s, o, 0.05), 0.05 * (1 + 1e-6));
  o.impulses = 2;  // two impulses cannot cover a ±20 % band at 5 %
  EXPECT_THROW(cs::design_si(m, o), clearshape::RuntimeError);
}

TEST(DesignSi, Deterministic) {
  const cs::Mode m = cs::Mode::from_hz(3.0, 0.12);
  const cs::SiOptions o = band_hz(2.0, 4.5, 0.03);
  const cs::Shaper a = cs::design_si(m, o);
  const cs::Shaper b = cs::design_si(m, o);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.impulses()[i], b.impulses()[i]);
}

TEST(DesignSi, Validation) {
  const cs::Mode m = cs::Mode::from_hz(10.0, 0.05);
  EXPECT_THROW(cs::design_si(m, band_hz(0.0, 12.0)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_si(m, band_hz(12.0, 8.0)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_si(m, band_hz(8.0, 12.0, 1.0)), clearshape::InvalidArgument);
  EXPECT_THROW(cs::design_si(cs::Mode::from_hz(10.0, 1.0), band_hz(8.0, 12.0)), clearshape::InvalidArgument);
  cs::SiOptions o = band_hz(8.0, 12.0);
  o.impulses = 1;
  EXPECT_THROW(cs::design_si(m, o), clearshape::InvalidArgument);
  o.impulses = 0;
  o.constraint_points = 1;
  EXPECT_THROW(cs::design_si(m, o), clearshape::InvalidArgument);
  try {
    cs::design_si(m, band_hz(0.01, 100.0));
    ADD_FAILURE();
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("too wide"), std::string::npos) << e.what();
  }
}
