// Position-mode drive command path (thesis §3.2, §4.1.2): 30 Hz held velocity, whole counts,
// 500 kHz pulse cap, quadrature edges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/quadrature.hpp"
#include "clearshape/signal/signal.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

namespace {
cs::UniformSeries trajectory_rad(const sig::Signal& s_deg, double rate_hz, double duration_s) {
  cs::UniformSeries y = sig::sample(s_deg, rate_hz, duration_s);
  for (double& v : y.values) v = cs::deg_to_rad(v);
  return y;
}
}  // namespace

TEST(PulseTrainConfig, ThesisDefaultsAndValidation) {
  const sig::PulseTrainConfig c;
  EXPECT_EQ(c.update_rate_hz, 30.0);
  EXPECT_EQ(c.counts_per_rev, 3000.0);
  EXPECT_EQ(c.max_pulse_frequency_hz, 500e3);
  EXPECT_EQ(c.max_counts_per_update(), 16666);  // floor(500 kHz / 30 Hz)
  EXPECT_NEAR(c.counts_per_rad() * cs::kTwoPi, 3000.0, 1e-9);
  EXPECT_THROW((sig::PulseTrainConfig{.update_rate_hz = 0.0}.validate()), cs::InvalidArgument);
  EXPECT_THROW((sig::PulseTrainConfig{.counts_per_rev = -1.0}.validate()), cs::InvalidArgument);
  EXPECT_THROW((sig::PulseTrainConfig{.gear_ratio = 0.0}.validate()), cs::InvalidArgument);
  EXPECT_THROW((sig::PulseTrainConfig{.max_pulse_frequency_hz = 10.0}.validate()), cs::InvalidArgument);
}

TEST(PositionPath, IdealStepBecomesAHigherSlopedRamp) {
  // §4.1.2: a 10° step at 0.1 s reaches the driver as a ramp over one 30 Hz period ending at the
  // step's instant (lookahead), slope 10°·30 Hz, carried by round(10/360·3000) = 83 pulses.
  const auto p = trajectory_rad(sig::Step{.amplitude = 10.0, .start_s = 0.1}, 1000.0, 1.0);
  const auto r = sig::apply_position_path(p, {});
  ASSERT_EQ(r.pulses_per_update.size(), 31u);  // t_k = k/30 <= 1 s
  for (std::size_t k = 0; k < r.pulses_per_update.size(); ++k) {
    EXPECT_EQ(r.pulses_per_update[k], k == 2 ? 83 : 0) << "update " << k;
  }
  EXPECT_EQ(r.saturated_updates, 0u);
  EXPECT_NEAR(cs::rad_to_deg(r.held_velocity_rad_s.values[2]), 300.0, 1e-9);
  EXPECT_LE(r.max_lag_rad, 0.5 / r.counts_per_rad + 1e-15);  // within half a count
  EXPECT_NEAR(cs::rad_to_deg(r.commanded_rad.values.back()), 83.0 * 360.0 / 3000.0, 1e-12);
  // Inside the ramp the commanded position is a staircase of whole counts under the line.
  for (std::size_t i = 67; i < 100; ++i) {
    const double t = r.commanded_rad.time_s(i);
    const double counts = r.commanded_rad.values[i] * r.counts_per_rad;
    EXPECT_NEAR(counts, std::round(counts), 1e-9);
    const double line = 83.0 * (t - 2.0 / 30.0) * 30.0;
    EXPECT_LE(counts, line + 1e-6);
    EXPECT_GT(counts, line - 1.0);
    EXPECT_EQ(r.pulse_frequency_hz.values[i], 83.0 * 30.0);
  }
  EXPECT_EQ(r.pulse_frequency_hz.values[120], 0.0);
}

TEST(PositionPath, InitialPositionMakesAStepAtTimeZeroAMove) {
  const auto p = trajectory_rad(sig::Step{.amplitude = 20.0}, 1000.0, 1.0);
  const auto from_first = sig::apply_position_path(p, {});
  EXPECT_EQ(from_first.initial_count, 167);  // already there: no pulses
  for (auto n : from_first.pulses_per_update) EXPECT_EQ(n, 0);
  const auto from_zero = sig::apply_position_path(p, {}, 0.0);
  EXPECT_EQ(from_zero.initial_count, 0);
  EXPECT_EQ(from_zero.pulses_per_update[0], 167);  // round(20/360·3000) in the first period
  EXPECT_NEAR(cs::rad_to_deg(from_zero.held_velocity_rad_s.values[0]), 600.0, 1e-9);
  EXPECT_EQ(from_zero.commanded_rad.values[0], 0.0);
  EXPECT_NEAR(cs::rad_to_deg(from_zero.commanded_rad.values[40]), 20.04, 1e-12);
  EXPECT_THROW(sig::apply_position_path(p, {}, NAN), cs::InvalidArgument);
}

TEST(PositionPath, RampIsTrackedToHalfACountAtEveryUpdate) {
  const auto p = trajectory_rad(sig::Ramp{.slope_per_s = 90.0}, 1000.0, 2.0);
  const auto r = sig::apply_position_path(p, {});
  const double period = r.update_period_s();
  for (std::size_t k = 1; k < r.pulses_per_update.size(); ++k) {
    const double t_k = static_cast<double>(k) * period;
    const auto i = static_cast<std::size_t>(std::ceil(t_k * 1000.0 - 1e-6));  // first sample at or after t_k
    if (i >= p.size()) break;
    const double t_i = p.time_s(i);
    // commanded(t_i) lies between the count at t_k and that plus the pulses emitted since.
    EXPECT_NEAR(r.commanded_rad.values[i], cs::deg_to_rad(90.0 * t_k),
                0.5 / r.counts_per_rad + std::abs(r.pulse_frequency_hz.values[i]) * (t_i - t_k) / r.counts_per_rad + 1e-12);
  }
  // 90 °/s = 750 counts/s → 25 pulses per update, 750 Hz.
  EXPECT_EQ(r.pulses_per_update[5], 25);
  EXPECT_EQ(r.pulse_frequency_hz.values[500], 750.0);
}

TEST(PositionPath, FrequencyCapMakesTheCommandLagAndIsReported) {
  // Gear 0.02 → 150000 pulses/rev; a 90° step needs 37500 pulses but one update carries at most
  // 16666 (500 kHz / 30 Hz): three updates, two of them saturated, and no pulse is lost.
  const auto p = trajectory_rad(sig::Step{.amplitude = 90.0, .start_s = 0.05}, 1000.0, 0.5);
  sig::PulseTrainConfig c;
  c.gear_ratio = 0.02;
  const auto r = sig::apply_position_path(p, c);
  EXPECT_EQ(r.saturated_updates, 2u);
  EXPECT_EQ(r.pulses_per_update[1], 16666);
  EXPECT_EQ(r.pulses_per_update[2], 16666);
  EXPECT_EQ(r.pulses_per_update[3], 37500 - 2 * 16666);
  EXPECT_NEAR(r.max_lag_rad * r.counts_per_rad, 37500.0 - 16666.0, 1e-6);
  for (double f : r.pulse_frequency_hz.values) EXPECT_LE(std::abs(f), 500e3);
  EXPECT_NEAR(cs::rad_to_deg(r.commanded_rad.values.back()), 90.0, 1e-9);
}

TEST(PositionPath, SampledVelocityMissesAStepBetweenUpdates) {
  // The literal §3.2 reading: dp/dt sampled at 30 Hz sees an ideal step only if it falls in
  // the input sample just before an update instant. At 0.105 s it is missed entirely.
  const auto p = trajectory_rad(sig::Step{.amplitude = 10.0, .start_s = 0.105}, 1000.0, 1.0);
  sig::PulseTrainConfig c;
  c.velocity_hold = sig::VelocityHold::sampled;
  const auto r = sig::apply_position_path(p, c);
  EXPECT_EQ(r.commanded_rad.values.back(), 0.0);
  // A slow S-curve is followed: the held-velocity integral lands near the target.
  const auto q = trajectory_rad(sig::Step{.amplitude = 20.0, .rise_s = 1.0, .rise_shape = sig::RiseShape::s_curve}, 1000.0, 2.0);
  const auto rq = sig::apply_position_path(q, c);
  EXPECT_NEAR(cs::rad_to_deg(rq.commanded_rad.values.back()), 20.0, 0.6);
}

TEST(PositionPath, ReverseMotionAndGearRatio) {
  sig::PulseTrainConfig c;
  c.gear_ratio = 2.0;  // each command pulse turns the motor two counts: 1500 pulses/rev
  const auto p = trajectory_rad(sig::Trapezoid{.amplitude = 36.0, .start_s = 0.1, .rise_s = 0.2, .hold_s = 0.2, .fall_s = 0.3}, 1000.0, 1.5);
  const auto r = sig::apply_position_path(p, c);
  std::int64_t up = 0, down = 0;
  for (auto n : r.pulses_per_update) {
    (n > 0 ? up : down) += n;
  }
  EXPECT_EQ(up, 150);    // 36° of 1500 pulses/rev
  EXPECT_EQ(down, -150);
  EXPECT_EQ(r.commanded_rad.values.back(), 0.0);
}

TEST(PositionPath, RejectsBadInput) {
  EXPECT_THROW(sig::apply_position_path(cs::UniformSeries{}, {}), cs::InvalidArgument);
  cs::UniformSeries y{0.0, 1e-3, {0.0, NAN, 1.0}};
  EXPECT_THROW(sig::apply_position_path(y, {}), cs::InvalidArgument);
}

TEST(PulseTrain, RealTimePathIsAllocationFreeAndReportsStatus) {
  sig::PulseTrain train(sig::PulseTrainConfig{});
  train.reset(0.0);
  std::int64_t sum = 0;
  cs::testing::AllocationCounter counter;
  for (int k = 0; k < 300; ++k) {
    const cs::Status s = train.program(0.01 * k);
    EXPECT_EQ(s, cs::Status::ok);
    for (int j = 0; j < 33; ++j) sum += train.count_at(j * 1e-3);
  }
  EXPECT_EQ(train.program(1e3), cs::Status::out_of_range);
  EXPECT_EQ(train.program(NAN), cs::Status::not_finite);
  EXPECT_EQ(train.pulses(), 0);
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_GT(sum, 0);
}

TEST(Quadrature, X4DecodingMatchesTheCountsAtEveryUpdate) {
  sig::PulseTrainConfig c;
  c.update_rate_hz = 25.0;
  c.counts_per_rev = 2500.0;
  const auto p = trajectory_rad(sig::Trapezoid{.amplitude = 20.0, .start_s = 0.1, .rise_s = 0.2, .hold_s = 0.2, .fall_s = 0.3}, 800.0, 1.5);
  const auto r = sig::apply_position_path(p, c);
  const double period = r.update_period_s();
  const double end = static_cast<double>(r.pulses_per_update.size()) * period;
  const auto trace = sig::quadrature_trace(r, 0.0, end + 1e-6);
  std::size_t expected_edges = 0;
  for (auto n : r.pulses_per_update) expected_edges += static_cast<std::size_t>(4 * std::abs(n));
  ASSERT_EQ(trace.edges.size(), expected_edges);
  EXPECT_EQ(trace.start_edges, 4 * r.initial_count);

  sig::QuadratureDecoder decoder(trace.a_high, trace.b_high, trace.start_edges);
  std::size_t e = 0;
  std::int64_t count = r.initial_count;
  for (std::size_t k = 0; k < r.pulses_per_update.size(); ++k) {
    const double t_end = static_cast<double>(k + 1) * period;
    for (; e < trace.edges.size() && trace.edges[e].time_s <= t_end + 1e-12; ++e) {
      ASSERT_EQ(decoder.apply(trace.edges[e]), cs::Status::ok);
      if (e > 0) {
        ASSERT_GE(trace.edges[e].time_s, trace.edges[e - 1].time_s);
      }
    }
    count += r.pulses_per_update[k];
    EXPECT_EQ(decoder.count(), 4 * count) << "update " << k;
    EXPECT_FALSE(decoder.a_high());  // whole pulses: both channels low between periods
    EXPECT_FALSE(decoder.b_high());
  }
  // Against the sampled commanded position: |×4 count − 4·commanded counts| <= 3 anywhere.
  sig::QuadratureDecoder d2(false, false, 4 * r.initial_count);
  e = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (; e < trace.edges.size() && trace.edges[e].time_s <= p.time_s(i); ++e) d2.apply(trace.edges[e]);
    const double counts = r.commanded_rad.values[i] * r.counts_per_rad;
    EXPECT_LE(std::abs(static_cast<double>(d2.count()) - 4.0 * counts), 3.0 + 1e-6) << "t = " << p.time_s(i);
  }
}

TEST(Quadrature, WindowStateMatchesDecodingFromTheStart) {
  const auto p = trajectory_rad(sig::Step{.amplitude = 10.0, .start_s = 0.2, .rise_s = 0.3}, 1000.0, 1.0);
  const auto r = sig::apply_position_path(p, {});
  const auto all = sig::quadrature_trace(r, 0.0, 1.1);
  for (double from : {0.0, 0.21, 0.2345, 0.31, 0.6, 1.05}) {
    const auto w = sig::quadrature_trace(r, from, 1.1);
    sig::QuadratureDecoder d(false, false, 4 * r.initial_count);
    std::size_t n_before = 0;
    for (const auto& edge : all.edges) {
      if (edge.time_s >= from) break;
      d.apply(edge);
      ++n_before;
    }
    EXPECT_EQ(w.start_edges, d.count()) << "from " << from;
    EXPECT_EQ(w.a_high, d.a_high()) << "from " << from;
    EXPECT_EQ(w.b_high, d.b_high()) << "from " << from;
    EXPECT_EQ(w.edges.size() + n_before, all.edges.size()) << "from " << from;
  }
  EXPECT_THROW(sig::quadrature_trace(r, 0.5, 0.5), cs::InvalidArgument);
  EXPECT_THROW(sig::quadrature_trace(r, 0.0, 1.0, 10), cs::InvalidArgument);
}

TEST(Quadrature, DecoderDirectionAndInvalidEdges) {
  sig::QuadratureDecoder d(false, false, 0);
  // Forward: A↑ B↑ A↓ B↓ → +4; reverse: B↑ A↑ B↓ A↓ → −4.
  for (auto [ch, lvl] : {std::pair{sig::Channel::a, true}, {sig::Channel::b, true}, {sig::Channel::a, false}, {sig::Channel::b, false}}) {
    EXPECT_EQ(d.apply({0.0, ch, lvl}), cs::Status::ok);
  }
  EXPECT_EQ(d.count(), 4);
  for (auto [ch, lvl] : {std::pair{sig::Channel::b, true}, {sig::Channel::a, true}, {sig::Channel::b, false}, {sig::Channel::a, false}}) {
    d.apply({0.0, ch, lvl});
  }
  EXPECT_EQ(d.count(), 0);
  EXPECT_EQ(d.apply({0.0, sig::Channel::a, false}), cs::Status::out_of_range);
  EXPECT_EQ(d.count(), 0);
}

// The real-time path (the rig's loop): a step written at t = 10.5 ms is taken at the first tick at
// or after the next update instant (33.3 ms → the 34 ms tick) and reached, to a whole count, by
// the update after (66.7 ms → held from the 67 ms tick); nothing moves before 34 ms. With a 0.5 ms
// latency the instants move to 0.5, 33.8, 67.2 ms: taken at 34 ms, reached from the 68 ms tick.
TEST(RealtimePositionPath, TakesTheCommandAtTheTickOfEachUpdate) {
  const clearshape::signal::PulseTrainConfig config;
  clearshape::UniformSeries step{0.0, 1e-3, std::vector<double>(120, 0.0)};
  for (std::size_t k = 11; k < step.values.size(); ++k) step.values[k] = 0.1;  // rad
  const double reached = std::round(0.1 * config.counts_per_rad()) / config.counts_per_rad();
  const auto d = clearshape::signal::apply_realtime_position_path(step, config);
  EXPECT_EQ(d.values[33], 0.0);
  EXPECT_GT(d.values[35], 0.0);
  EXPECT_LT(d.values[66], reached);
  EXPECT_DOUBLE_EQ(d.values[67], reached);
  EXPECT_DOUBLE_EQ(d.values.back(), reached);
  const auto late = clearshape::signal::apply_realtime_position_path(step, config, 0.5e-3);
  EXPECT_EQ(late.values[33], 0.0);
  EXPECT_LT(late.values[67], reached);
  EXPECT_DOUBLE_EQ(late.values[68], reached);
  EXPECT_THROW(clearshape::signal::apply_realtime_position_path(step, config, -1e-3), clearshape::InvalidArgument);
  step.values[50] = std::nan("");
  EXPECT_THROW(clearshape::signal::apply_realtime_position_path(step, config), clearshape::InvalidArgument);
}
