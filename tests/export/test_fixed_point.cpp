// Q15/Q31 taps: Σq = 2^n exactly after the rounding correction, each tap within one LSB.
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/fixed_point.hpp"

namespace ex = clearshape::exports;

TEST(ExportFixedPoint, HandWorkedThreeTaps) {
  // 1/3 each: 32768/3 = 10922.67 → 10923 ×3 = 32769, one too many; all round up by 0.33, the
  // first (lowest index) gives one back: 10922, 10923, 10923.
  const std::vector<double> w{1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  const ex::FixedPointTaps q = ex::quantize_taps(w, 15);
  ASSERT_TRUE(q.representable) << q.why_not;
  EXPECT_EQ(q.q, (std::vector<std::int64_t>{10922, 10923, 10923}));
  EXPECT_NEAR(q.abs_error_sum, (2.0 / 3.0 + 2 * 1.0 / 3.0) / 32768.0, 1e-15);
}

TEST(ExportFixedPoint, SumIsExactlyOneForRandomTaps) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> count(2, 24);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<double> w(static_cast<std::size_t>(count(rng)));
    for (double& x : w) x = u(rng);
    const double sum = std::accumulate(w.begin(), w.end(), 0.0);
    for (double& x : w) x /= sum;
    for (int bits : {15, 31}) {
      const ex::FixedPointTaps q = ex::quantize_taps(w, bits);
      ASSERT_TRUE(q.representable) << q.why_not;
      EXPECT_EQ(std::accumulate(q.q.begin(), q.q.end(), std::int64_t{0}), std::int64_t{1} << bits);
      double err = 0.0;
      for (std::size_t j = 0; j < w.size(); ++j) {
        const double e = std::abs(static_cast<double>(q.q[j]) - w[j] * std::ldexp(1.0, bits));
        EXPECT_LT(e, 1.0) << "tap " << j << " moved by more than one LSB";
        err += e / std::ldexp(1.0, bits);
      }
      EXPECT_NEAR(q.abs_error_sum, err, 1e-15);
    }
  }
}

TEST(ExportFixedPoint, RefusesNegativeTapsAndATapOfOne) {
  const std::vector<double> um{1.0, -1.0, 1.0};
  const ex::FixedPointTaps a = ex::quantize_taps(um, 15);
  EXPECT_FALSE(a.representable);
  EXPECT_NE(a.why_not.find("negative"), std::string::npos) << a.why_not;
  const std::vector<double> identity{1.0};
  const ex::FixedPointTaps b = ex::quantize_taps(identity, 15);
  EXPECT_FALSE(b.representable);
  EXPECT_NE(b.why_not.find("outside [0, 1"), std::string::npos) << b.why_not;
  const std::vector<double> not_one{0.5, 0.4};
  EXPECT_THROW(ex::quantize_taps(not_one, 15), clearshape::InvalidArgument);
}
