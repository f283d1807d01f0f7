// Method names, custom impulse lists, UM-ZV, convolution (multi-mode) and the dispatcher.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace cs = clearshape::shaping;

TEST(DesignMisc, MethodNamesRoundTrip) {
  const std::vector<std::string_view> names = cs::method_names();
  ASSERT_EQ(names.size(), 11u);
  EXPECT_EQ(names.front(), "zv");
  EXPECT_EQ(names[9], "um-zv");
  for (std::string_view n : names) EXPECT_EQ(cs::to_string(cs::method_from_string(n)), n);
  try {
    cs::method_from_string("zvdx");
    ADD_FAILURE();
  } catch (const clearshape::InvalidArgument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'zvdx'"), std::string::npos);
    EXPECT_NE(msg.find("zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, si, um-zv, custom"), std::string::npos) << msg;
  }
}

TEST(DesignMisc, ParseImpulses) {
  const auto p = cs::parse_impulses("0:0.5, 0.05:0.5");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].time_s, 0.05);
  EXPECT_EQ(p[1].amplitude, 0.5);
  EXPECT_EQ(cs::parse_impulses("0.0:1e0")[0].amplitude, 1.0);
  for (const char* bad : {"", "0:0.5,", "0;0.5", "x:1", "0:1:2", "0:nan", "0:0.5,,0.1:0.5"}) {
    EXPECT_THROW(cs::parse_impulses(bad), clearshape::InvalidArgument) << bad;
  }
  try {
    cs::parse_impulses("0:0.5,0.05:abc");
    ADD_FAILURE();
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("entry 2"), std::string::npos) << e.what();
  }
}

TEST(DesignMisc, ParseImpulsesRefusesAZeroAmplitude) {
  // Found by fuzz_impulses: "0:2,5:0,52:0,250:0" was one unit impulse that claimed V = 0 (the
  // zero impulses moved t_N to 250 s, where the mode had decayed) and a 10-s insensitivity walk.
  for (const char* bad : {"0:2,5:0,52:0,250:0", "0:0", "0:1, 0.1:-0"}) {
    try {
      cs::parse_impulses(bad);
      ADD_FAILURE() << bad;
    } catch (const clearshape::InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("amplitude 0"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(cs::parse_impulses("0:1,0.1:-1e-300").size(), 2u);  // tiny but not zero
}

TEST(DesignMisc, CustomThroughDispatcher) {
  cs::DesignRequest req;
  req.method = cs::Method::custom;
  req.impulses = {{0.0, 1.0}, {0.05, 1.0}};
  const cs::Shaper s = cs::design(req);
  EXPECT_EQ(s.method(), "custom");
  EXPECT_DOUBLE_EQ(s.impulses()[0].amplitude, 0.5);  // normalised (Eq. 2.21)
  req.impulses = {{0.05, 1.0}, {0.0, 1.0}};
  EXPECT_THROW(cs::design(req), clearshape::InvalidArgument);  // times must increase
  req.impulses = {{-0.01, 1.0}};
  EXPECT_THROW(cs::design(req), clearshape::InvalidArgument);  // times >= 0
  req.impulses.clear();
  EXPECT_THROW(cs::design(req), clearshape::InvalidArgument);
  req.method = cs::Method::si;
  req.mode = cs::Mode::from_hz(5.0, 0.1);
  EXPECT_THROW(cs::design(req), clearshape::InvalidArgument);  // si without a band
}

TEST(DesignMisc, UnityMagnitudeZv) {
  const cs::Shaper u0 = cs::design_um_zv(cs::Mode::from_hz(10.0, 0.0));  // (c2): [1,−1,1] at [0,T/6,T/3]
  ASSERT_EQ(u0.size(), 3u);
  EXPECT_NEAR(u0.impulses()[1].time_s, 0.1 / 6, 1e-15);
  EXPECT_NEAR(u0.impulses()[2].time_s, 0.1 / 3, 1e-15);
  EXPECT_EQ(u0.impulses()[1].amplitude, -1.0);
  EXPECT_FALSE(u0.is_positive());
  EXPECT_LT(cs::residual_vibration(u0, cs::Mode::from_hz(10.0, 0.0)), 1e-15);
  // Vaughan's cubic fit for t2 (in undamped periods) at ζ = 0.1: 0.16658 + 0.29277ζ + …
  const double z = 0.1;
  const cs::Shaper u1 = cs::design_um_zv(cs::Mode::from_hz(1.0, z));
  EXPECT_NEAR(u1.impulses()[1].time_s, 0.16658 + 0.29277 * z + 0.075438 * z * z + 0.21335 * z * z * z, 1e-4);
  for (double zeta : {0.05, 0.2, 0.5, 0.8}) {
    const cs::Mode m = cs::Mode::from_hz(3.0, zeta);
    const cs::Shaper u = cs::design_um_zv(m);
    EXPECT_LT(cs::residual_vibration(u, m), 1e-11) << zeta;
    EXPECT_LT(u.duration_s(), cs::design_zv(m).duration_s()) << zeta;  // shorter than ZV
  }
}

TEST(DesignMisc, ConvolutionCancelsBothModes) {
  const cs::Mode m1 = cs::Mode::from_hz(4.0, 0.05);
  const cs::Mode m2 = cs::Mode::from_hz(11.0, 0.02);
  const cs::Shaper a = cs::design_zvd(m1);
  const cs::Shaper b = cs::design_zv(m2);
  const cs::Shaper c = cs::convolve(a, b);
  EXPECT_EQ(c.method(), "zvd*zv");
  EXPECT_EQ(c.size(), 6u);
  EXPECT_NEAR(c.amplitude_sum(), 1.0, 1e-15);
  EXPECT_LT(cs::residual_vibration(c, m1), 1e-13);
  EXPECT_LT(cs::residual_vibration(c, m2), 1e-13);
  EXPECT_NEAR(c.duration_s(), a.duration_s() + b.duration_s(), 1e-15);
  // V of a convolution is the product of the V's (multiplicative phasors).
  for (double w : {10.0, 33.0, 80.0}) {
    const cs::Mode m{w, 0.07};
    EXPECT_NEAR(cs::residual_vibration(c, m), cs::residual_vibration(a, m) * cs::residual_vibration(b, m), 1e-14);
  }
  // Coincident times merge: ZV(10 Hz) * ZV(10 Hz) = ZVD(10 Hz).
  const cs::Mode m = cs::Mode::from_hz(10.0, 0.1);
  const cs::Shaper zz = cs::convolve(cs::design_zv(m), cs::design_zv(m));
  const cs::Shaper zvd = cs::design_zvd(m);
  ASSERT_EQ(zz.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(zz.impulses()[i].amplitude, zvd.impulses()[i].amplitude, 1e-15);
    EXPECT_NEAR(zz.impulses()[i].time_s, zvd.impulses()[i].time_s, 1e-15);
  }
  // Dispatcher with a second mode.
  cs::DesignRequest req;
  req.method = cs::Method::ei;
  req.mode = m1;
  req.second_mode = m2;
  const cs::Shaper two = cs::design(req);
  EXPECT_EQ(two.size(), 9u);
  EXPECT_NEAR(cs::residual_vibration(two, m1), 0.05 * cs::residual_vibration(cs::design_ei(m2), m1), 1e-12);
  req.method = cs::Method::custom;
  req.impulses = {{0, 1}};
  EXPECT_THROW(cs::design(req), clearshape::InvalidArgument);
}
