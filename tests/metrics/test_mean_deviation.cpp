#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"

namespace cs = clearshape;
namespace m = clearshape::metrics;

namespace {
// Ramp 0, 0.1, …, 1.0 (sample 10 equals 1 exactly), then 2·pairs samples alternating 1 ± a.
cs::UniformSeries ramp_then_ringing(int pairs, double a) {
  cs::UniformSeries s;
  s.sample_time_s = 0.01;
  for (int i = 0; i <= 10; ++i) s.values.push_back(i / 10.0);
  for (int p = 0; p < pairs; ++p) {
    s.values.push_back(1.0 + a);
    s.values.push_back(1.0 - a);
  }
  return s;
}
}  // namespace

TEST(MeanDeviation, HandComputedRampThenRinging) {
  // k = 10 (the ramp meets M = 1 exactly there); n = 2·50 + 1 = 101 samples; the mean over them
  // is (1 + 100·1)/101 = 1, and MD = sqrt((0 + 100·a²)/101) (Eq. 5.1).
  const double a = 0.25;  // exactly representable, so M = 1 exactly
  const auto r = m::mean_deviation(ramp_then_ringing(50, a));
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.start_index, 10u);
  EXPECT_NEAR(r.start_time_s, 0.10, 1e-15);
  EXPECT_EQ(r.samples, 101u);
  EXPECT_NEAR(r.steady_mean, 1.0, 1e-14);
  EXPECT_NEAR(r.mean_deviation, std::sqrt(100.0 * a * a / 101.0), 1e-14);
}

TEST(MeanDeviation, ConstantTailGivesZero) {
  cs::UniformSeries s;
  s.sample_time_s = 1e-3;
  for (int i = 0; i < 20; ++i) s.values.push_back(i < 5 ? 0.25 * i : 2.0);
  const auto r = m::mean_deviation(s);
  EXPECT_EQ(r.steady_mean, 2.0);
  EXPECT_EQ(r.mean_deviation, 0.0);
  EXPECT_EQ(r.start_index, 5u);  // 0, 0.25, …, 1.0, then 2.0: first sample that meets M = 2
}

TEST(MeanDeviation, IterationReachesAFixedPoint) {
  // Ramp to 1 then a tail that sits at 1.2 and ends at 1.0: M₀ (final 20 %) differs from the
  // final M, and k moves. At the fixed point M = mean(s[k:]) and k = first crossing of M.
  cs::UniformSeries s;
  s.sample_time_s = 1e-3;
  for (int i = 0; i <= 100; ++i) s.values.push_back(0.012 * i);         // reaches 1.2
  for (int i = 0; i < 300; ++i) s.values.push_back(1.2 - 0.2 * i / 299.0);  // down to 1.0
  const auto r = m::mean_deviation(s);
  ASSERT_TRUE(r.converged);
  EXPECT_GE(r.iterations, 2);
  double mean = 0.0;
  for (std::size_t i = r.start_index; i < s.size(); ++i) mean += s.values[i];
  mean /= static_cast<double>(s.size() - r.start_index);
  EXPECT_NEAR(r.steady_mean, mean, 1e-14);
  EXPECT_LE(s.values[r.start_index - 1], r.steady_mean);
  EXPECT_GE(s.values[r.start_index], r.steady_mean);
  for (std::size_t i = 0; i + 1 < r.start_index; ++i) EXPECT_LT(s.values[i], r.steady_mean);
}

TEST(MeanDeviation, DownwardStepIsSymmetric) {
  auto up = ramp_then_ringing(40, 0.2);
  auto down = up;
  for (double& v : down.values) v = 5.0 - v;
  const auto ru = m::mean_deviation(up);
  const auto rd = m::mean_deviation(down);
  EXPECT_EQ(ru.start_index, rd.start_index);
  EXPECT_NEAR(ru.mean_deviation, rd.mean_deviation, 1e-13);
  EXPECT_NEAR(rd.steady_mean, 4.0, 1e-13);
}

TEST(MeanDeviation, SearchFromSkipsEarlierCrossings) {
  // 1.5 for 5 samples, 0 for 5, then the ramp + ringing: the first excursion through M
  // (before 0.1 s) is ignored with search_from_s = 0.15 s.
  cs::UniformSeries s;
  s.sample_time_s = 0.01;
  for (int i = 0; i < 10; ++i) s.values.push_back(i < 5 ? 1.5 : 0.0);
  const auto tail = ramp_then_ringing(50, 0.25);
  s.values.insert(s.values.end(), tail.values.begin(), tail.values.end());
  const auto all = m::mean_deviation(s);
  m::MeanDeviationOptions options;
  options.search_from_s = 0.15;  // mid-ramp of the tail
  const auto later = m::mean_deviation(s, options);
  EXPECT_EQ(all.start_index, 5u);  // the drop from 1.5 to 0 crosses M first
  EXPECT_EQ(later.start_index, 20u);
  EXPECT_NEAR(later.steady_mean, 1.0, 1e-15);
  EXPECT_NEAR(later.mean_deviation, std::sqrt(100 * 0.0625 / 101.0), 1e-13);
}

TEST(MeanDeviation, RejectsBadInput) {
  cs::UniformSeries s;
  s.values = {1.0};
  EXPECT_THROW(m::mean_deviation(s), cs::InvalidArgument);
  s.values = {1.0, std::numeric_limits<double>::quiet_NaN(), 2.0};
  EXPECT_THROW(m::mean_deviation(s), cs::InvalidArgument);
  s.values = {0.0, 1.0, 2.0};
  m::MeanDeviationOptions options;
  options.final_window_fraction = 0.0;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
  options = {};
  options.search_from_s = 10.0;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
}
