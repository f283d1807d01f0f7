// ProcessModel: structure codes, validation, thesis presets (Eq. 4.2), poles/zeros in closed
// form, realization and transfer-function consistency.
#include <cmath>
#include <complex>
#include <string>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/lti/process_model.hpp"

namespace lti = clearshape::lti;
using clearshape::InvalidArgument;

TEST(ProcessStructure, ParsesMatlabCodesInAnyOrder) {
  const auto s = lti::ProcessStructure::parse("P3UZ");
  EXPECT_EQ(s.pole_count, 3);
  EXPECT_TRUE(s.underdamped);
  EXPECT_TRUE(s.zero);
  EXPECT_FALSE(s.delay);
  EXPECT_FALSE(s.integrator);
  EXPECT_EQ(s.code(), "P3ZU");
  EXPECT_EQ(lti::ProcessStructure::parse("p2diz").code(), "P2DIZ");
  EXPECT_EQ(lti::ProcessStructure::parse("P3UZDI"), lti::ProcessStructure::parse("P3DIZU"));
  EXPECT_EQ(lti::ProcessStructure::parse("P0ID").code(), "P0DI");
}

TEST(ProcessStructure, ParameterNamesFollowMatlab) {
  using V = std::vector<std::string_view>;
  EXPECT_EQ(lti::ProcessStructure::parse("P1D").parameter_names(), (V{"Kp", "Tp1", "Td"}));
  EXPECT_EQ(lti::ProcessStructure::parse("P2").parameter_names(), (V{"Kp", "Tp1", "Tp2"}));
  EXPECT_EQ(lti::ProcessStructure::parse("P2U").parameter_names(), (V{"Kp", "Tw", "Zeta"}));
  EXPECT_EQ(lti::ProcessStructure::parse("P3UZ").parameter_names(), (V{"Kp", "Tp3", "Tw", "Zeta", "Tz"}));
  EXPECT_EQ(lti::ProcessStructure::parse("P3DIZ").parameter_names(),
            (V{"Kp", "Tp1", "Tp2", "Tp3", "Td", "Tz"}));
}

TEST(ProcessStructure, RejectsBadCodes) {
  for (const char* code : {"", "P", "Q1", "P4", "P1U", "P2X", "P1DD", "P0Z"}) {
    EXPECT_THROW(lti::ProcessStructure::parse(code), InvalidArgument) << code;
  }
  try {
    lti::ProcessStructure::parse("P1U");
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("needs 2 or 3 poles"), std::string::npos) << e.what();
  }
}

TEST(ProcessModel, ValidatesRangesWithNamedParameters) {
  lti::ProcessParameters p;
  p.tp1 = -0.1;
  try {
    lti::ProcessModel("P1", p);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("Tp1"), std::string::npos) << e.what();
  }
  p = {};
  p.tw = 0.05;
  p.zeta = -0.1;
  EXPECT_THROW(lti::ProcessModel("P2U", p), InvalidArgument);
  p.zeta = 0.1;
  p.td = -1e-3;
  EXPECT_THROW(lti::ProcessModel("P2DU", p), InvalidArgument);
  p.td = 0.0;
  p.tp1 = 0.3;  // not a parameter of P2U
  try {
    lti::ProcessModel("P2U", p);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("Tp1"), std::string::npos) << e.what();
  }
  p = {};
  p.kp = std::nan("");
  EXPECT_THROW(lti::ProcessModel("P0", p), InvalidArgument);
  p = {};
  p.tz = 0.1;  // zero without a pole: improper
  EXPECT_THROW(lti::ProcessModel("P1Z", p), InvalidArgument);
  p.tp1 = 0.2;
  EXPECT_NO_THROW(lti::ProcessModel("P1Z", p));
}

TEST(ProcessModel, VectorRoundTripInParameterOrder) {
  const auto s = lti::ProcessStructure::parse("P3UZ");
  const std::vector<double> v{25.47, 0.0857, 0.0479, 0.2880, -0.0398};
  const auto m = lti::ProcessModel::from_vector(s, v);
  EXPECT_EQ(m.to_vector(), v);
  EXPECT_DOUBLE_EQ(m.parameters().tz, -0.0398);
  EXPECT_THROW(lti::ProcessModel::from_vector(s, std::vector<double>{1.0}), InvalidArgument);
  EXPECT_DOUBLE_EQ(m.parameters().get("zeta"), 0.2880);
}

// Thesis §4.2: ωn = 1/Tw, ζ = Zeta; Eq. 4.2 factors give the poles and the zero.
TEST(ProcessModel, ThesisSpeedModeFigures) {
  const auto m = lti::thesis_speed_mode_model();
  EXPECT_EQ(m.code(), "P3ZU");
  EXPECT_NEAR(m.natural_frequency_rad_s(), 20.8768267, 1e-6);
  EXPECT_DOUBLE_EQ(m.damping_ratio(), 0.2880);
  EXPECT_DOUBLE_EQ(m.dc_gain(), 25.47);
  const auto z = m.zeros();
  ASSERT_EQ(z.size(), 1u);
  EXPECT_NEAR(z[0].real(), 25.1256281, 1e-6);  // RHP zero, s = −1/Tz = +25.13 rad/s
  const auto p = m.poles();
  ASSERT_EQ(p.size(), 3u);
  EXPECT_NEAR(p[0].real(), -1.0 / 0.0857, 1e-12);
  const auto modes = m.oscillatory_modes();
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_NEAR(modes[0].natural_frequency_rad_s, 1.0 / 0.0479, 1e-10);
  EXPECT_NEAR(modes[0].damping_ratio, 0.2880, 1e-12);
  EXPECT_NEAR(modes[0].damped_frequency_rad_s(), 19.992, 1e-3);  // docs/design.md §5
  // The transfer function's numeric roots agree with the closed form.
  const auto tf = m.transfer_function();
  const auto tp = tf.poles();
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(std::abs(tp[i] - p[i]), 0.0, 1e-10 * std::abs(p[i]));
  EXPECT_NEAR(tf.dc_gain(), 25.47, 1e-12);
}

TEST(ProcessModel, ThesisPositionModeFigures) {
  const auto m = lti::thesis_position_mode_model();
  EXPECT_NEAR(m.natural_frequency_rad_s(), 98.0392157, 1e-6);
  EXPECT_DOUBLE_EQ(m.damping_ratio(), 0.9968);
  EXPECT_NEAR(m.zeros()[0].real(), -238.095238, 1e-5);
  const auto modes = m.oscillatory_modes();
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_NEAR(modes[0].damping_ratio, 0.9968, 1e-12);
  EXPECT_NEAR(modes[0].damped_frequency_rad_s(), 7.84, 1e-2);  // docs/design.md §5
}

TEST(ProcessModel, OverdampedPairGivesRealPolesWithProductOneOverTw2) {
  lti::ProcessParameters p;
  p.tw = 0.1;
  p.zeta = 3.0;
  const lti::ProcessModel m("P2U", p);
  const auto poles = m.poles();
  ASSERT_EQ(poles.size(), 2u);
  EXPECT_EQ(poles[0].imag(), 0.0);
  EXPECT_NEAR(poles[0].real() * poles[1].real(), 100.0, 1e-10);
  EXPECT_NEAR(poles[0].real() + poles[1].real(), -60.0, 1e-10);
  EXPECT_TRUE(m.oscillatory_modes().empty());
  EXPECT_THROW(lti::ProcessModel("P2", lti::ProcessParameters{}).natural_frequency_rad_s(), InvalidArgument);
}

TEST(ProcessModel, IntegratorDcGainIsInfinite) {
  lti::ProcessParameters p;
  p.kp = -2.0;
  p.tp1 = 0.1;
  const lti::ProcessModel m("P1I", p);
  EXPECT_TRUE(std::isinf(m.dc_gain()));
  EXPECT_LT(m.dc_gain(), 0.0);
  EXPECT_EQ(m.poles().back(), std::complex<double>(0.0, 0.0));
}

// The cascade realization, the expanded transfer function and the factored frequency response
// describe the same G(s).
TEST(ProcessModel, RealizationsAgreeInFrequency) {
  std::vector<lti::ProcessModel> models{lti::thesis_speed_mode_model(), lti::thesis_position_mode_model()};
  lti::ProcessParameters p;
  p.kp = 3.0;
  p.tp1 = 0.5;
  p.tp2 = 1e-4;  // widely separated
  p.tp3 = 2.0;
  p.tz = 0.02;
  models.emplace_back("P3IZ", p);
  p = {};
  p.kp = 1.5;
  p.tp1 = 0.2;
  p.tz = -0.4;  // biproper with RHP zero: nonzero D
  models.emplace_back("P1Z", p);
  for (const auto& m : models) {
    const auto ss = m.state_space();
    const auto tf = m.transfer_function();
    for (double w : {0.01, 0.3, 1.0, 7.0, 20.0, 100.0, 1e3, 1e4}) {
      const auto ref = m.frequency_response(w);
      EXPECT_NEAR(std::abs(lti::frequency_response(ss, w) - ref), 0.0, 1e-12 * std::abs(ref)) << m.code() << " " << w;
      EXPECT_NEAR(std::abs(tf.frequency_response(w) - ref), 0.0, 1e-10 * std::abs(ref)) << m.code() << " " << w;
    }
    const auto sp = lti::poles(ss);
    const auto mp = m.poles();
    ASSERT_EQ(sp.size(), mp.size());
    for (std::size_t i = 0; i < sp.size(); ++i) EXPECT_NEAR(std::abs(sp[i] - mp[i]), 0.0, 1e-9 * (1.0 + std::abs(mp[i])));
  }
}

TEST(ProcessModel, DelayIsAPurePhaseFactor) {
  lti::ProcessParameters p;
  p.kp = 2.0;
  p.tp1 = 0.1;
  p.td = 0.05;
  const lti::ProcessModel m("P1D", p);
  const double w = 10.0;
  const auto g = m.frequency_response(w);
  const auto g0 = 2.0 / std::complex<double>(1.0, w * 0.1);
  EXPECT_NEAR(std::abs(g), std::abs(g0), 1e-14);
  EXPECT_NEAR(std::arg(g / g0), -w * 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(m.delay_s(), 0.05);
}
