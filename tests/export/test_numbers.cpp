// Number formatting of exports: shortest round trip for data, stated significant digits for settings.
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/numbers.hpp"

namespace ex = clearshape::exports;

TEST(ExportNumbers, ShortestRoundTripsEveryDouble) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 2000; ++i) {
    const double x = std::pow(10.0, u(rng) * 4.0) * (i % 2 ? 1.0 : -1.0);
    const std::string s = ex::shortest(x);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), x) << s;  // bit for bit
    EXPECT_LE(s.size(), 24u) << s;
  }
  EXPECT_EQ(ex::shortest(0.1), "0.1");
  EXPECT_EQ(ex::shortest(1.0), "1.0");  // a C literal that is not an integer
  EXPECT_EQ(ex::shortest(0.1f), "0.1");
  EXPECT_EQ(ex::shortest(2.0f), "2.0");
}

TEST(ExportNumbers, ShortestFloatRoundTripsAsFloat) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const float x = u(rng);
    const std::string s = ex::shortest(x);
    EXPECT_EQ(std::strtof(s.c_str(), nullptr), x) << s;
    EXPECT_LE(s.size(), 16u) << s;  // at most 9 significant digits, "0.000" or an exponent
  }
}

TEST(ExportNumbers, FixedSignificantDropsTheTwoPiNoise) {
  // 14.955 Hz through rad/s and back is 14.955000000000002 in binary64.
  const double hz = (14.955 * 2.0 * std::numbers::pi) / (2.0 * std::numbers::pi);
  EXPECT_EQ(ex::fixed_significant(hz, 6), "14.955");
  EXPECT_EQ(ex::fixed_significant(0.1, 6), "0.1");
  EXPECT_EQ(ex::fixed_significant(40.0, 6), "40");
  EXPECT_EQ(ex::fixed_significant(0.0, 6), "0");
  EXPECT_EQ(ex::fixed_significant(1234567.0, 6), "1234570");
  EXPECT_EQ(ex::fixed_significant(0.000012345678, 6), "0.0000123457");  // never an exponent
  EXPECT_EQ(ex::fixed_significant(-0.0501, 6), "-0.0501");
  EXPECT_EQ(ex::fixed_significant(9.9999996, 6), "10");
  EXPECT_EQ(ex::fixed_significant(0.0365861, 3), "0.0366");
  EXPECT_THROW(ex::fixed_significant(std::nan(""), 6), clearshape::InvalidArgument);
  EXPECT_THROW(ex::fixed_significant(1.0, 0), clearshape::InvalidArgument);
}

TEST(ExportNumbers, RoundSignificantKeepsThatManyDigits) {
  EXPECT_EQ(ex::round_significant(14.955000000000002, 12), 14.955);
  EXPECT_EQ(ex::round_significant(0.123456789, 3), 0.123);
  EXPECT_EQ(ex::round_significant(-987654.0, 2), -990000.0);
}
