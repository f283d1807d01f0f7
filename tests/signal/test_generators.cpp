// Command signals against closed forms (thesis §4.1, §5.2.1).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/signal/generators.hpp"
#include "clearshape/signal/signal.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

TEST(Rise, LinearAndSCurveEndpointsAndSymmetry) {
  for (auto shape : {sig::RiseShape::linear, sig::RiseShape::s_curve}) {
    EXPECT_EQ(sig::rise_fraction(shape, -0.5), 0.0);
    EXPECT_EQ(sig::rise_fraction(shape, 0.0), 0.0);
    EXPECT_EQ(sig::rise_fraction(shape, 1.0), 1.0);
    EXPECT_EQ(sig::rise_fraction(shape, 2.0), 1.0);
    EXPECT_NEAR(sig::rise_fraction(shape, 0.5), 0.5, 1e-15);
    for (double u = 0.0; u <= 1.0; u += 0.01) {  // point symmetry about (½, ½)
      EXPECT_NEAR(sig::rise_fraction(shape, u) + sig::rise_fraction(shape, 1.0 - u), 1.0, 1e-14);
    }
  }
}

TEST(Rise, SCurveHasContinuousVelocityAndAccelerationAndBoundedJerk) {
  // Finite differences of s(u): velocity and acceleration vanish at both ends, the jerk is
  // ±32 (piecewise constant) and the peak velocity is 2 (twice the linear ramp's).
  const auto s = [](double u) { return sig::rise_fraction(sig::RiseShape::s_curve, u); };
  const double h = 1e-4;
  EXPECT_NEAR((s(h) - s(0.0)) / h, 0.0, 1e-6);
  EXPECT_NEAR((s(1.0) - s(1.0 - h)) / h, 0.0, 1e-6);
  EXPECT_NEAR((s(0.5 + h) - s(0.5 - h)) / (2 * h), 2.0, 1e-6);
  for (double u : {0.1, 0.2, 0.3, 0.45, 0.6, 0.7, 0.8, 0.9}) {
    const double jerk = (s(u + 2 * h) - 3 * s(u + h) + 3 * s(u) - s(u - h)) / (h * h * h);
    EXPECT_NEAR(std::abs(jerk), 32.0, 0.05) << "u = " << u;
  }
  // Peak acceleration 8 at u = 1/4 (a_p = 8A/T²); the second difference at the corner of the
  // acceleration triangle is low by jerk·h/3 ≈ 1.1e-3.
  const double u = 0.25;
  EXPECT_NEAR((s(u + h) - 2 * s(u) + s(u - h)) / (h * h), 8.0, 32.0 * h / 3.0 + 1e-6);
}

TEST(Rise, ShapeNames) {
  EXPECT_EQ(sig::rise_shape_from_string("linear"), sig::RiseShape::linear);
  EXPECT_EQ(sig::rise_shape_from_string("s-curve"), sig::RiseShape::s_curve);
  EXPECT_EQ(sig::to_string(sig::RiseShape::s_curve), "s-curve");
  EXPECT_THROW(sig::rise_shape_from_string("cubic"), cs::InvalidArgument);
}

TEST(Step, IdealAndFiniteRise) {
  const sig::Step ideal{.amplitude = 2.0, .start_s = 0.5};
  EXPECT_EQ(ideal.value_at(0.4999), 0.0);
  EXPECT_EQ(ideal.value_at(0.5), 2.0);  // right-continuous
  EXPECT_EQ(ideal.value_at(0.5 - 1e-10), 2.0);  // within the 1 ns switching tolerance
  const sig::Step ramped{.amplitude = 4.0, .start_s = 1.0, .rise_s = 0.5};
  EXPECT_DOUBLE_EQ(ramped.value_at(1.25), 2.0);
  EXPECT_NEAR(ramped.value_at(1.1), 0.8, 1e-14);
  EXPECT_EQ(ramped.value_at(3.0), 4.0);
  const sig::Step s{.amplitude = 3.0, .start_s = 0.0, .rise_s = 1.0, .rise_shape = sig::RiseShape::s_curve};
  EXPECT_NEAR(s.value_at(0.25), 3.0 / 12.0, 1e-15);  // s(¼) = 1/12
}

TEST(Ramp, SlopeAndSaturation) {
  const sig::Ramp r{.slope_per_s = 2.0, .start_s = 1.0, .limit = 3.0};
  EXPECT_EQ(r.value_at(0.5), 0.0);
  EXPECT_DOUBLE_EQ(r.value_at(2.0), 2.0);
  EXPECT_EQ(r.value_at(10.0), 3.0);
  const sig::Ramp down{.slope_per_s = -1.0, .limit = -0.5};
  EXPECT_EQ(down.value_at(4.0), -0.5);
  EXPECT_DOUBLE_EQ(sig::Ramp{.slope_per_s = 1.5}.value_at(4.0), 6.0);
  EXPECT_THROW((sig::Ramp{.slope_per_s = 1.0, .limit = -2.0}.validate()), cs::InvalidArgument);
}

TEST(Sine, PhaseOffsetAndStart) {
  const sig::Sine s{.amplitude = 2.0, .frequency_hz = 0.5, .phase_rad = 0.3, .offset = 1.0, .start_s = 1.0};
  EXPECT_EQ(s.value_at(0.5), 1.0);
  EXPECT_NEAR(s.value_at(1.0), 1.0 + 2.0 * std::sin(0.3), 1e-15);
  EXPECT_NEAR(s.value_at(1.5), 1.0 + 2.0 * std::sin(cs::kPi / 2 + 0.3), 1e-14);
  EXPECT_NEAR(s.value_at(3.0), s.value_at(1.0), 1e-14);  // period 2 s
  EXPECT_THROW((sig::Sine{.frequency_hz = 0.0}.validate()), cs::InvalidArgument);
}

TEST(DoubleStep, SumOfTwoStepsAndOrder) {
  const sig::DoubleStep d{.amplitude = 8.0, .start_s = 0.1, .second_amplitude = -3.0,
                          .second_start_s = 1.0, .rise_s = 0.2};
  EXPECT_EQ(d.value_at(0.0), 0.0);
  EXPECT_DOUBLE_EQ(d.value_at(0.2), 4.0);
  EXPECT_EQ(d.value_at(0.5), 8.0);
  EXPECT_DOUBLE_EQ(d.value_at(1.1), 6.5);
  EXPECT_EQ(d.value_at(2.0), 5.0);
  try {
    sig::DoubleStep{.start_s = 1.0, .second_start_s = 1.1, .rise_s = 0.2}.validate();
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("second_start_s = 1.1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(">= start_s + rise_s = 1.2"), std::string::npos) << e.what();
  }
}

TEST(StackedSteps, StaircaseHoldAndRepeat) {
  sig::StackedSteps s{.levels = {1.0, 3.0, -2.0}, .dwell_s = 1.0, .start_s = 0.5};
  EXPECT_EQ(s.value_at(0.0), 0.0);
  EXPECT_EQ(s.value_at(0.5), 1.0);
  EXPECT_EQ(s.value_at(1.6), 3.0);
  EXPECT_EQ(s.value_at(2.5), -2.0);
  EXPECT_EQ(s.value_at(9.0), -2.0);  // holds the last level
  s.repeat = true;
  EXPECT_EQ(s.value_at(3.5), 1.0);   // starts again
  EXPECT_EQ(s.value_at(4.7), 3.0);
  s.rise_s = 0.5;
  EXPECT_DOUBLE_EQ(s.value_at(3.75), -2.0 + 3.0 * 0.5);  // from −2 back to 1, halfway
  EXPECT_DOUBLE_EQ(s.value_at(0.75), 0.5);               // from 0 to 1, halfway
  s.rise_s = 1.5;
  EXPECT_THROW(s.validate(), cs::InvalidArgument);
  EXPECT_THROW((sig::StackedSteps{.levels = {}}.validate()), cs::InvalidArgument);
}

TEST(Parabolic, ConstantAcceleration) {
  const sig::Parabolic p{.acceleration_per_s2 = 4.0, .start_s = 1.0};
  EXPECT_EQ(p.value_at(0.9), 0.0);
  EXPECT_DOUBLE_EQ(p.value_at(3.0), 8.0);
  const double h = 1e-3;  // second difference = acceleration
  EXPECT_NEAR((p.value_at(2.0 + h) - 2 * p.value_at(2.0) + p.value_at(2.0 - h)) / (h * h), 4.0, 1e-6);
}

TEST(Trapezoid, RiseHoldFallAndPulse) {
  const sig::Trapezoid t{.amplitude = 5.0, .start_s = 1.0, .rise_s = 0.5, .hold_s = 1.0, .fall_s = 0.25};
  EXPECT_EQ(t.value_at(0.5), 0.0);
  EXPECT_DOUBLE_EQ(t.value_at(1.25), 2.5);
  EXPECT_EQ(t.value_at(2.0), 5.0);
  EXPECT_DOUBLE_EQ(t.value_at(2.625), 2.5);
  EXPECT_EQ(t.value_at(3.0), 0.0);
  const sig::Trapezoid pulse{.amplitude = 2.0, .start_s = 1.0, .rise_s = 0.0, .hold_s = 0.5, .fall_s = 0.0};
  EXPECT_EQ(pulse.value_at(0.999), 0.0);
  EXPECT_EQ(pulse.value_at(1.0), 2.0);
  EXPECT_EQ(pulse.value_at(1.499), 2.0);
  EXPECT_EQ(pulse.value_at(1.5), 0.0);
  EXPECT_THROW((sig::Trapezoid{.hold_s = -1.0}.validate()), cs::InvalidArgument);
}

TEST(Signal, TypeNamesAndValidation) {
  const sig::Signal s = sig::Step{.amplitude = 1.0};
  EXPECT_EQ(s.type(), "step");
  EXPECT_EQ(sig::Signal(sig::StackedSteps{}).type(), "stacked-steps");
  EXPECT_EQ(sig::Signal(sig::DoubleStep{}).type(), "double-step");
  EXPECT_NE(s.get_if<sig::Step>(), nullptr);
  EXPECT_EQ(s.get_if<sig::Ramp>(), nullptr);
  try {
    sig::Signal bad = sig::Step{.rise_s = -0.1};
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rise_s = -0.1"), std::string::npos) << what;
    EXPECT_NE(what.find("allowed: finite and >= 0"), std::string::npos) << what;
  }
  EXPECT_THROW(sig::Signal(sig::Step{.amplitude = NAN}), cs::InvalidArgument);
}

TEST(Signal, SampleGridIncludesBothEnds) {
  const sig::Signal s = sig::Ramp{.slope_per_s = 2.0};
  const cs::UniformSeries y = sig::sample(s, 1000.0, 5.0);
  ASSERT_EQ(y.size(), 5001u);
  EXPECT_EQ(y.sample_time_s, 1e-3);
  EXPECT_NEAR(y.values.back(), 10.0, 1e-12);
  for (std::size_t i = 0; i < y.size(); i += 97) EXPECT_EQ(y.values[i], s.value_at(y.time_s(i)));
  EXPECT_THROW(sig::sample(s, 0.0, 1.0), cs::InvalidArgument);
  EXPECT_THROW(sig::sample(s, 100.0, -1.0), cs::InvalidArgument);
}

TEST(Signal, StepsLandOnTheIntendedSample) {
  // 0.7 s is not a multiple of 0.001 in binary; the 1 ns tolerance still switches at sample 700.
  const auto y = sig::sample(sig::Step{.amplitude = 1.0, .start_s = 0.7}, 1000.0, 1.0);
  EXPECT_EQ(y.values[699], 0.0);
  EXPECT_EQ(y.values[700], 1.0);
  const auto z = sig::sample(sig::Step{.amplitude = 1.0, .start_s = 0.3}, 10.0, 1.0);
  EXPECT_EQ(z.values[2], 0.0);
  EXPECT_EQ(z.values[3], 1.0);
}
