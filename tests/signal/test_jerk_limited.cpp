// Jerk-limited point-to-point moves (signal/jerk_limited.hpp) against:
//   - tests/golden/gen_jerk_limited.py (SciPy; minimum time from a peak-velocity
//     parametrisation solved with brentq, the profile integrated with PPoly): duration, peaks and
//     positions at T/10 steps to 1e-12 relative;
//   - the physical law of a synchronised move: every axis within its velocity, acceleration and
//     jerk limits at every sample, velocity the derivative of position, all axes start at rest
//     and end together, at rest, exactly at the target;
//   - rise.hpp's S-curve, the special case without constant phases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/signal/jerk_limited.hpp"
#include "clearshape/signal/rise.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {

double rel(double a, double b) { return std::abs(a - b) / std::max(1.0, std::abs(b)); }

}  // namespace

TEST(JerkLimited, MinimumTimeMatchesScipyGolden) {
  const auto t = cs::io::read_table(cs::testing::golden_path("signal_jerk_limited.csv"));
  ASSERT_EQ(t.rows(), 12u);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const double d = t.column("distance")[r];
    const sig::AxisLimits lim{t.column("v_max")[r], t.column("a_max")[r], t.column("j_max")[r]};
    const auto p = sig::JerkLimitedProfile::minimum_time(0.3, 0.3 + d, lim);
    const double duration = t.column("duration_s")[r];
    EXPECT_LE(std::abs(p.duration_s() - duration) / duration, 1e-12) << "case " << r;
    EXPECT_LE(std::abs(p.peak_velocity() / t.column("peak_velocity")[r] - 1.0), 1e-12) << "case " << r;
    EXPECT_LE(std::abs(p.peak_acceleration() / t.column("peak_acceleration")[r] - 1.0), 1e-12) << "case " << r;
    for (int k = 0; k <= 10; ++k) {
      std::string column = "p";
      column += std::to_string(k);
      const double golden = t.column(column)[r];
      const double ours = p.at(duration * k / 10.0).position - 0.3;
      EXPECT_LE(std::abs(ours - golden), 1e-12 * std::max(1.0, d)) << "case " << r << " p" << k;
    }
  }
}

TEST(JerkLimited, SCurveRiseIsTheCaseWithoutConstantPhases) {
  // rise.hpp: jerk ±32/T³ over four quarters. Unreachable v and a, j = 32·D/T³ give Tj = T/4.
  const double rise_s = 0.6, distance = 2.5;
  const auto p = sig::JerkLimitedProfile::minimum_time(
      0.0, distance, {1e9, 1e9, 32.0 * distance / (rise_s * rise_s * rise_s)});
  ASSERT_NEAR(p.duration_s(), rise_s, 1e-15);
  EXPECT_EQ(p.cruise_time_s(), 0.0);
  for (int k = 0; k <= 60; ++k) {
    const double time_s = rise_s * k / 60.0;
    EXPECT_NEAR(p.at(time_s).position, distance * sig::rise_fraction(sig::RiseShape::s_curve, k / 60.0), 1e-14);
  }
}

TEST(JerkLimited, SynchronizedMovesKeepEveryLimitAndEndTogether) {
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<double> pos(-3.0, 3.0), lim(0.5, 5.0);
  for (int trial = 0; trial < 40; ++trial) {
    const std::size_t n = 2 + static_cast<std::size_t>(trial % 5);
    std::vector<double> q0(n), q1(n);
    std::vector<sig::AxisLimits> limits(n);
    for (std::size_t i = 0; i < n; ++i) {
      q0[i] = pos(rng);
      q1[i] = trial % 7 == 0 && i == 0 ? q0[i] : pos(rng);  // sometimes an axis that stays
      limits[i] = {lim(rng), 4.0 * lim(rng), 40.0 * lim(rng)};
    }
    const auto move = sig::synchronized_move(q0, q1, limits);
    const auto& slowest = move.axes[move.limiting_axis];
    EXPECT_DOUBLE_EQ(move.duration_s, sig::JerkLimitedProfile::minimum_time(
                                          q0[move.limiting_axis], q1[move.limiting_axis],
                                          limits[move.limiting_axis]).duration_s());
    EXPECT_DOUBLE_EQ(slowest.duration_s(), move.duration_s);
    const double dt = 1e-4;
    const auto samples = sig::sample_move(move, dt);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& a = move.axes[i];
      EXPECT_EQ(a.duration_s(), move.duration_s);
      const auto& s = samples[i];
      EXPECT_EQ(s.position.values.front(), q0[i]);
      EXPECT_EQ(s.position.values.back(), q1[i]);  // exactly the target
      EXPECT_EQ(a.at(move.duration_s).position, q1[i]);
      EXPECT_EQ(s.velocity.values.back(), 0.0);
      EXPECT_EQ(s.acceleration.values.back(), 0.0);
      EXPECT_EQ(a.at(0.0).velocity, 0.0);
      const double tol = 1.0 + 1e-12;
      for (std::size_t k = 0; k < s.position.size(); ++k) {
        const auto st = a.at(static_cast<double>(k) * dt);
        ASSERT_LE(std::abs(st.velocity), limits[i].velocity * tol) << trial << " axis " << i;
        ASSERT_LE(std::abs(st.acceleration), limits[i].acceleration * tol) << trial << " axis " << i;
        ASSERT_LE(std::abs(st.jerk), limits[i].jerk * tol) << trial << " axis " << i;
        if (k == 0 || k + 1 >= s.position.size()) continue;
        // v = dp/dt (central difference, error ≤ j·dt²/6 + rounding) and a = dv/dt (≤ j·dt)
        const double dp = (s.position.values[k + 1] - s.position.values[k - 1]) / (2 * dt);
        ASSERT_NEAR(dp, s.velocity.values[k], limits[i].jerk * dt * dt + 1e-9) << trial;
        const double dv = (s.velocity.values[k + 1] - s.velocity.values[k - 1]) / (2 * dt);
        ASSERT_NEAR(dv, s.acceleration.values[k], limits[i].jerk * dt + 1e-9) << trial;
      }
    }
    // the limiting axis is time-optimal: it reaches its velocity or acceleration limit, or else
    // it is all jerk phases (±j throughout, no constant acceleration, no cruise)
    const auto& l = limits[move.limiting_axis];
    if (q0[move.limiting_axis] != q1[move.limiting_axis]) {
      const bool all_jerk = slowest.cruise_time_s() == 0.0 &&
                            rel(slowest.acceleration_time_s(), 2.0 * slowest.jerk_time_s()) < 1e-12;
      EXPECT_TRUE(rel(slowest.peak_velocity(), l.velocity) < 1e-12 ||
                  rel(slowest.peak_acceleration(), l.acceleration) < 1e-12 || all_jerk);
    }
  }
}

TEST(JerkLimited, TimeScalingDividesVelocityAccelerationAndJerk) {
  const auto p = sig::JerkLimitedProfile::minimum_time(1.0, -1.0, {1.0, 2.0, 10.0});
  const auto slow = p.time_scaled(2.0 * p.duration_s());
  EXPECT_DOUBLE_EQ(slow.peak_velocity(), p.peak_velocity() / 2.0);
  EXPECT_DOUBLE_EQ(slow.peak_acceleration(), p.peak_acceleration() / 4.0);
  const double t = 0.3 * p.duration_s();
  const auto fast_state = p.at(t), slow_state = slow.at(2.0 * t);
  EXPECT_DOUBLE_EQ(slow_state.position, fast_state.position);
  EXPECT_DOUBLE_EQ(slow_state.velocity, fast_state.velocity / 2.0);
  EXPECT_DOUBLE_EQ(slow_state.jerk, fast_state.jerk / 8.0);
  EXPECT_LT(fast_state.velocity, 0.0);  // moving down
  EXPECT_EQ(slow.at(1e3).position, -1.0);
}

TEST(JerkLimited, RefusesBadInput) {
  EXPECT_THROW(sig::JerkLimitedProfile::minimum_time(0, 1, {0.0, 1, 1}), cs::InvalidArgument);
  EXPECT_THROW(sig::JerkLimitedProfile::minimum_time(0, NAN, {1, 1, 1}), cs::InvalidArgument);
  const auto p = sig::JerkLimitedProfile::minimum_time(0, 1, {1, 1, 1});
  EXPECT_THROW((void)p.time_scaled(0.5 * p.duration_s()), cs::InvalidArgument);
  const std::vector<double> two{0, 1}, one{1};
  const std::vector<sig::AxisLimits> lim2(2);
  EXPECT_THROW(sig::synchronized_move(two, one, lim2), cs::InvalidArgument);
  try {
    sig::synchronized_move(two, two, std::vector<sig::AxisLimits>{{1, 1, 1}, {1, -1, 1}});
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("axis[1].limits.acceleration"), std::string::npos) << e.what();
  }
}
