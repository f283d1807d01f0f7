// Derived signals of a run, against closed forms: the gyro integrated to an angle (trapezoidal
// rule, bias removed), the settle time, seeds and statistics.
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/study/measures.hpp"

namespace st = clearshape::study;

namespace {

st::Record record_with_rate(const std::vector<double>& rate, double ts) {
  st::Record r;
  r.sample_time_s = ts;
  r.link_rate_deg_s = rate;
  r.time_s.resize(rate.size());
  r.motor_angle_deg.assign(rate.size(), 0.0);
  for (std::size_t k = 0; k < rate.size(); ++k) r.time_s[k] = static_cast<double>(k) * ts;
  return r;
}

}  // namespace

TEST(Measures, LinkAngleIntegratesTheRateAfterRemovingTheBias) {
  // Rate = bias 0.5 deg/s + a 10 deg/s pulse on [1, 2) s: the angle rises by 10 deg (±1 sample).
  const double ts = 1e-3;
  std::vector<double> rate(3001, 0.5);
  for (std::size_t k = 1000; k < 2000; ++k) rate[k] += 10.0;
  const auto angle = st::link_angle_deg(record_with_rate(rate, ts), 0.4);
  EXPECT_DOUBLE_EQ(angle.front(), 0.0);
  EXPECT_NEAR(angle[999], 0.0, 1e-9);          // bias removed exactly
  EXPECT_NEAR(angle.back(), 10.0, 10.0 * ts);  // area of the pulse
  EXPECT_NEAR(angle[1500], 5.0 + 0.5 * 10.0 * ts, 1e-9);  // trapezoid at the edge: half a sample
}

TEST(Measures, LinkAngleOfASineMatchesItsIntegral) {
  const double ts = 1e-3, w = 2.0 * 3.14159265358979323846;
  std::vector<double> rate(2001);
  for (std::size_t k = 0; k < rate.size(); ++k) rate[k] = k < 500 ? 0.0 : w * std::cos(w * (static_cast<double>(k) * ts - 0.5));
  const auto angle = st::link_angle_deg(record_with_rate(rate, ts), 0.4);
  for (std::size_t k = 500; k < rate.size(); k += 97) {
    const double exact = std::sin(w * (static_cast<double>(k) * ts - 0.5));
    EXPECT_NEAR(angle[k], exact, 5e-3) << k;  // trapezoidal error O(w² ts) plus the start sample
  }
}

TEST(Measures, MdSeriesFollowsTheProtocolSignal) {
  const auto r = record_with_rate(std::vector<double>(100, 2.0), 1e-3);
  st::MeasureSpec m;
  m.md_signal = st::MdSignal::link_rate_deg_s;
  EXPECT_DOUBLE_EQ(st::md_series(r, m).values[50], 2.0);
  m.md_signal = st::MdSignal::link_angle_deg;
  m.bias_window_s = 0.01;
  EXPECT_DOUBLE_EQ(st::md_series(r, m).values[50], 0.0);  // a constant rate is all bias
}

TEST(Measures, SettleTimeIsTheLastExitFromTheBand) {
  // 0 until 1 s, then 10 with a 1 deg overshoot that ends at 1.2 s.
  const double ts = 1e-3;
  std::vector<double> y(3001, 0.0);
  for (std::size_t k = 1000; k < y.size(); ++k) y[k] = k < 1200 ? 11.0 : 10.0;
  EXPECT_NEAR(st::settle_time_s(y, ts, 0.5, 0.02), 1.2, 1.5 * ts);
  EXPECT_NEAR(st::settle_time_s(y, ts, 0.5, 0.2), 1.0, 1.5 * ts);   // 11 is inside ±2
  EXPECT_DOUBLE_EQ(st::settle_time_s(std::vector<double>(10, 3.0), ts, 0.0), 0.0);
}

TEST(Measures, MeanStdAndRunSeed) {
  const std::vector<double> v{1.0, 2.0, 3.0, 4.0};
  const auto ms = st::mean_std(v);
  EXPECT_DOUBLE_EQ(ms.mean, 2.5);
  EXPECT_NEAR(ms.std, std::sqrt(5.0 / 3.0), 1e-15);
  EXPECT_EQ(st::run_seed(1, "a/b/r01"), st::run_seed(1, "a/b/r01"));
  EXPECT_NE(st::run_seed(1, "a/b/r01"), st::run_seed(1, "a/b/r02"));
  EXPECT_NE(st::run_seed(1, "a/b/r01"), st::run_seed(2, "a/b/r01"));
}
