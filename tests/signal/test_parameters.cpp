// Building signals from a type name and named parameters (CLI, study protocols).
#include <gtest/gtest.h>

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/parameters.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

TEST(Parameters, BuildsEachTypeWithDefaultsForMissingValues) {
  for (const auto type : sig::signal_types()) {
    const sig::Signal s = sig::make_signal(type, {});
    EXPECT_EQ(s.type(), type);
  }
  const auto s = sig::make_signal("step", {{"amplitude", 10.0}, {"rise_s", 0.2}, {"rise_shape", std::string("s-curve")}});
  const auto* step = s.get_if<sig::Step>();
  ASSERT_NE(step, nullptr);
  EXPECT_EQ(step->amplitude, 10.0);
  EXPECT_EQ(step->start_s, 0.0);
  EXPECT_EQ(step->rise_shape, sig::RiseShape::s_curve);
}

TEST(Parameters, RoundTripsThroughParametersOf) {
  const std::vector<sig::Signal> signals = {
      sig::Step{.amplitude = 2.0, .start_s = 0.1, .rise_s = 0.3, .rise_shape = sig::RiseShape::s_curve},
      sig::Ramp{.slope_per_s = -2.0, .start_s = 0.5, .limit = -4.0},
      sig::Ramp{.slope_per_s = 3.0},
      sig::Sine{.amplitude = 2.0, .frequency_hz = 3.0, .phase_rad = 0.2, .offset = 1.0, .start_s = 0.4},
      sig::Prbs{.order = 11, .bit_period_s = 0.03, .amplitude = 2.0, .offset = -1.0, .seed = 1234, .start_s = 0.2},
      sig::DoubleStep{.amplitude = 8.0, .start_s = 0.1, .second_amplitude = 8.0, .second_start_s = 2.0, .rise_s = 0.4},
      sig::StackedSteps{.levels = {1.0, 2.0, 4.0}, .dwell_s = 0.5, .start_s = 0.2, .rise_s = 0.1, .repeat = true},
      sig::Parabolic{.acceleration_per_s2 = 3.0, .start_s = 0.7},
      sig::Trapezoid{.amplitude = -3.0, .start_s = 0.2, .rise_s = 0.1, .hold_s = 0.4, .fall_s = 0.3}};
  for (const auto& s : signals) {
    const sig::Signal back = sig::make_signal(s.type(), sig::parameters_of(s));
    EXPECT_EQ(back.type(), s.type());
    for (double t = 0.0; t < 4.0; t += 0.0137) ASSERT_EQ(back.value_at(t), s.value_at(t)) << s.type() << " t=" << t;
  }
}

TEST(Parameters, ErrorsNameTheProblem) {
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const cs::InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([] { sig::make_signal("sawtooth", {}); }).find("allowed: step, ramp, sine, prbs"), std::string::npos);
  const auto foreign = message([] { sig::make_signal("step", {{"slope_per_s", 1.0}}); });
  EXPECT_NE(foreign.find("'slope_per_s' does not apply to signal type 'step'"), std::string::npos) << foreign;
  EXPECT_NE(foreign.find("it takes: amplitude, start_s, rise_s, rise_shape"), std::string::npos) << foreign;
  EXPECT_NE(message([] { sig::make_signal("prbs", {{"order", 7.5}}); }).find("order = 7.5"), std::string::npos);
  EXPECT_NE(message([] { sig::make_signal("prbs", {{"order", 40.0}}); }).find("[2, 31]"), std::string::npos);
  EXPECT_NE(message([] { sig::make_signal("prbs", {{"order", 3.0}, {"seed", 8.0}}); }).find("[1, 7]"), std::string::npos);
  EXPECT_NE(message([] { sig::make_signal("step", {{"amplitude", std::string("big")}}); }).find("must be a number"), std::string::npos);
  EXPECT_NE(message([] { sig::make_signal("trapezoid", {{"rise_shape", std::string("cubic")}}); }).find("linear, s-curve"), std::string::npos);
  EXPECT_NE(message([] { sig::make_signal("sine", {{"frequency_hz", -1.0}}); }).find("frequency_hz = -1"), std::string::npos);
  EXPECT_THROW(sig::parameter_names("nope"), cs::InvalidArgument);
}
