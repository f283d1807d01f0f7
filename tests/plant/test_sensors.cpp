// Sensor models (docs/design.md §5): encoder, ITG-3205 gyroscope, MF-614 converters.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/daq.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "support/alloc_counter.hpp"

namespace cp = clearshape::plant;
using clearshape::deg_to_rad;
using clearshape::kTwoPi;

TEST(Encoder, ThesisConventionAndQuantization) {
  const cp::Encoder x4;  // 3000 lines decoded x4
  EXPECT_EQ(x4.counts_per_revolution(), 12000);
  EXPECT_DOUBLE_EQ(x4.resolution_rad(), kTwoPi / 12000.0);
  const cp::Encoder x1({3000, cp::Decoding::x1, 0.0});
  EXPECT_EQ(x1.counts_per_revolution(), 3000);
  const double delta = kTwoPi / 3000.0;
  EXPECT_EQ(x1.count(0.0), 0);
  EXPECT_EQ(x1.count(0.5 * delta), 0);
  EXPECT_EQ(x1.count(1.5 * delta), 1);
  EXPECT_EQ(x1.count(-0.5 * delta), -1);  // floor, not truncation
  EXPECT_EQ(x1.count(kTwoPi + 0.5 * delta), 3000);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-20.0, 20.0);
  for (int i = 0; i < 10000; ++i) {
    const double a = angle(rng);
    EXPECT_EQ(x1.count(a), static_cast<std::int64_t>(std::floor(a / delta)));
    const double err = a - x1.measure(a);
    ASSERT_GE(err, -1e-12);
    ASSERT_LT(err, delta + 1e-12);
  }
  const cp::Encoder zeroed({3000, cp::Decoding::x4, 1.0});
  EXPECT_EQ(zeroed.count(1.0 + 2.5 * x4.resolution_rad()), 2);
  EXPECT_THROW(cp::Encoder({0, cp::Decoding::x4, 0.0}), clearshape::InvalidArgument);
}

TEST(Gyroscope, QuantizationAndSaturationExact) {
  cp::GyroscopeConfig cfg;
  cfg.noise_density_dps_per_rthz = 0.0;
  cp::Gyroscope g(cfg);
  EXPECT_EQ(g.quantize(deg_to_rad(1.0)), 14);        // 14.375 LSB per °/s, rounded
  EXPECT_EQ(g.quantize(deg_to_rad(-1.0)), -14);
  EXPECT_EQ(g.quantize(deg_to_rad(7.0)), 101);       // 100.625 → 101
  EXPECT_EQ(g.quantize(deg_to_rad(2000.0)), 28750);  // full scale
  EXPECT_EQ(g.quantize(deg_to_rad(5000.0)), 28750);  // saturated at ±2000 °/s
  EXPECT_EQ(g.quantize(deg_to_rad(-5000.0)), -28750);
  const auto s = g.sample(deg_to_rad(3000.0));
  EXPECT_TRUE(s.saturated);
  EXPECT_EQ(s.raw, 28750);
  EXPECT_NEAR(s.rate_rad_s, deg_to_rad(2000.0), 1e-12);
  const auto t = g.sample(deg_to_rad(50.0));
  EXPECT_FALSE(t.saturated);
  EXPECT_EQ(t.raw, static_cast<std::int16_t>(std::nearbyint(50.0 * 14.375)));
  // the quantization error is at most half an LSB inside the range
  for (double dps = -1999.0; dps < 1999.0; dps += 0.37) {
    const auto q = g.sample(deg_to_rad(dps));
    ASSERT_LE(std::abs(clearshape::rad_to_deg(q.rate_rad_s) - dps), 0.5 / 14.375 + 1e-12);
  }
}

TEST(Gyroscope, NoiseIsSeededAndHasTheDatasheetLevel) {
  cp::GyroscopeConfig cfg;  // 0.03 °/s/√Hz at 1 kHz: σ = 0.03·√500 = 0.671 °/s
  cfg.sensitivity_lsb_per_dps = 1e4;  // fine quantization to see the noise itself
  cfg.full_scale_dps = 3.0;
  cp::Gyroscope a(cfg);
  cp::Gyroscope b(cfg);
  const int n = 100000;
  double sum = 0.0;
  double sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto sa = a.sample(0.0);
    const auto sb = b.sample(0.0);
    ASSERT_EQ(sa.raw, sb.raw);  // same seed, same sequence
    const double dps = clearshape::rad_to_deg(sa.rate_rad_s);
    sum += dps;
    sum2 += dps * dps;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(a.noise_std_dps(), 0.03 * std::sqrt(500.0), 1e-12);
  EXPECT_NEAR(sd / a.noise_std_dps(), 1.0, 0.02);
  EXPECT_NEAR(mean, 0.0, 5.0 * a.noise_std_dps() / std::sqrt(n));
  cfg.seed = 2;
  cp::Gyroscope c(cfg);
  a.reset();
  int same = 0;
  for (int i = 0; i < 100; ++i) same += a.sample(0.0).raw == c.sample(0.0).raw;
  EXPECT_LT(same, 20);
}

TEST(Gyroscope, LowPassBiasAndLatencyExact) {
  cp::GyroscopeConfig cfg;
  cfg.noise_density_dps_per_rthz = 0.0;
  cfg.sensitivity_lsb_per_dps = 1e3;
  cfg.low_pass = cp::GyroLowPass::hz42;
  cfg.sample_rate_hz = 1000.0;
  cfg.bias_dps = 0.5;
  cfg.latency_samples = 3;
  cp::Gyroscope g(cfg);
  const double a = 1.0 - std::exp(-kTwoPi * 42.0 / 1000.0);
  double y = 0.5;  // the filter starts at the bias (reset to zero rate)
  double expected[12];
  for (int k = 0; k < 12; ++k) {
    y += a * (10.5 - y);
    expected[k] = std::nearbyint(y * 1e3) / 1e3;
  }
  for (int k = 0; k < 12; ++k) {
    const auto s = g.sample(deg_to_rad(10.0));
    const double want = k < 3 ? 0.5 : expected[k - 3];  // three samples late
    EXPECT_NEAR(clearshape::rad_to_deg(s.rate_rad_s), want, 1e-12) << "k = " << k;
  }
}

TEST(Gyroscope, SampleIsAllocationFree) {
  cp::GyroscopeConfig cfg;
  cfg.low_pass = cp::GyroLowPass::hz98;
  cfg.latency_samples = 5;
  cp::Gyroscope g(cfg);
  const cp::Encoder enc;
  const cp::Converter adc;
  clearshape::testing::AllocationCounter counter;
  double acc = 0.0;
  for (int i = 0; i < 1000; ++i) {
    acc += g.sample(0.01 * i).rate_rad_s;
    acc += static_cast<double>(enc.count(0.001 * i));
    acc += adc.quantize(0.01 * i);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_TRUE(std::isfinite(acc));
}

TEST(Converter, TwelveBitPlusMinusTenVolts) {
  const cp::Converter c;  // MF-614: 12 bit, ±10 V
  EXPECT_DOUBLE_EQ(c.lsb_v(), 20.0 / 4096.0);
  EXPECT_EQ(c.max_code(), 4095);
  EXPECT_EQ(c.code(0.0), 2048);
  EXPECT_EQ(c.code(-10.0), 0);
  EXPECT_EQ(c.code(-11.0), 0);
  EXPECT_EQ(c.code(10.0), 4095);  // saturates at +10 V − 1 LSB
  EXPECT_DOUBLE_EQ(c.volts(4095), 10.0 - 20.0 / 4096.0);
  EXPECT_EQ(c.code(std::nan("")), 2048);
  EXPECT_TRUE(c.saturates(10.0));
  EXPECT_FALSE(c.saturates(9.99));
  for (double v = -9.99; v < 9.99; v += 0.0123) {
    ASSERT_LE(std::abs(c.quantize(v) - v), 0.5 * c.lsb_v() + 1e-12);
  }
  EXPECT_THROW(cp::Converter({12, 1.0, -1.0}), clearshape::InvalidArgument);
  EXPECT_THROW(cp::Converter({0, -10.0, 10.0}), clearshape::InvalidArgument);
}
