// Speed-mode drive command path: 12-bit ±10 V D/A (thesis §3.2, Table 3.2).
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

TEST(SpeedPath, QuantizesToTheTwelveBitGrid) {
  const sig::AnalogOutputConfig c;  // 1 V/unit, 12 bit, ±10 V
  EXPECT_EQ(c.lsb_v(), 20.0 / 4096.0);
  double v = 1.0;
  EXPECT_EQ(sig::analog_output_v(c, 0.0, v), cs::Status::ok);
  EXPECT_EQ(v, 0.0);
  sig::analog_output_v(c, 10.0, v);  // top code, in range, not clipped
  EXPECT_EQ(v, 10.0 - c.lsb_v());
  sig::analog_output_v(c, -10.0, v);
  EXPECT_EQ(v, -10.0);
  for (double x = -9.99; x < 9.99; x += 0.0731) {
    ASSERT_EQ(sig::analog_output_v(c, x, v), cs::Status::ok);
    EXPECT_LE(std::abs(v - x), c.lsb_v() / 2 + 1e-15);
    EXPECT_NEAR(v / c.lsb_v(), std::round(v / c.lsb_v()), 1e-9);  // on the grid
  }
}

TEST(SpeedPath, ClipsAndReports) {
  const sig::AnalogOutputConfig c{.volts_per_unit = 0.01};  // e.g. 0.01 V per °/s
  double v = 0.0;
  EXPECT_EQ(sig::analog_output_v(c, 1500.0, v), cs::Status::out_of_range);
  EXPECT_EQ(v, 10.0 - c.lsb_v());
  EXPECT_EQ(sig::analog_output_v(c, -1500.0, v), cs::Status::out_of_range);
  EXPECT_EQ(v, -10.0);
  EXPECT_EQ(sig::analog_output_v(c, NAN, v), cs::Status::not_finite);
  EXPECT_EQ(v, 0.0);

  const auto cmd = sig::sample(sig::Sine{.amplitude = 1200.0, .frequency_hz = 1.0}, 1000.0, 1.0);
  const auto r = sig::apply_speed_path(cmd, c);
  std::size_t expected = 0;
  for (double x : cmd.values) expected += std::abs(x * 0.01) > 10.0 ? 1 : 0;
  EXPECT_EQ(r.clipped_samples, expected);
  EXPECT_GT(r.clipped_samples, 0u);
  for (std::size_t i = 0; i < cmd.size(); ++i) {
    EXPECT_EQ(r.commanded.values[i], r.volts.values[i] / 0.01);
    if (std::abs(cmd.values[i]) < 990.0) {
      EXPECT_NEAR(r.commanded.values[i], cmd.values[i], c.lsb_v() / 2 / 0.01 + 1e-9);
    }
  }
}

TEST(SpeedPath, NegativeScaleAndValidation) {
  const sig::AnalogOutputConfig inv{.volts_per_unit = -0.5};
  double v = 0.0;
  sig::analog_output_v(inv, 5.0, v);
  EXPECT_EQ(v, -2.5);  // 512 LSB
  EXPECT_THROW((sig::AnalogOutputConfig{.volts_per_unit = 0.0}.validate()), cs::InvalidArgument);
  EXPECT_THROW((sig::AnalogOutputConfig{.resolution_bits = 0}.validate()), cs::InvalidArgument);
  EXPECT_THROW((sig::AnalogOutputConfig{.full_scale_v = -1.0}.validate()), cs::InvalidArgument);
  cs::UniformSeries bad{0.0, 1e-3, {0.0, INFINITY}};
  EXPECT_THROW(sig::apply_speed_path(bad, {}), cs::InvalidArgument);
}

TEST(SpeedPath, RealTimeOutputIsAllocationFree) {
  const sig::AnalogOutputConfig c;
  double v = 0.0, sum = 0.0;
  cs::testing::AllocationCounter counter;
  for (int i = 0; i < 10000; ++i) {
    sig::analog_output_v(c, std::sin(i * 1e-3) * 12.0, v);
    sum += v;
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_TRUE(std::isfinite(sum));
}
