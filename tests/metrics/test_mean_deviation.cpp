#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

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
  // The ringing crosses M long before it could stay inside the band: the crossing decides.
  EXPECT_EQ(r.start_rule, m::StartRule::crossing);
  // b = 0.5 % of |M₀ − s₀|; M₀ = mean of the last ceil(0.2·111) = 23 samples (12 × (1 − a),
  // 11 × (1 + a)) = 1 − a/23.
  EXPECT_NEAR(r.band_half_width, 0.005 * (1.0 - a / 23.0), 1e-15);
}

namespace {
// 0, 0.25, 0.5, 0.75, 0.875, then 50 × (1 − 1/512) and 50 × (1 + 1/512): a monotone approach
// whose steady state sits 1/512 below and then 1/512 above the final value (a drift), so it
// crosses its mean only at sample 55, half-way through the steady state. Every value is exact.
cs::UniformSeries monotone_approach() {
  cs::UniformSeries s;
  s.sample_time_s = 0.01;
  s.values = {0.0, 0.25, 0.5, 0.75, 0.875};
  for (int i = 0; i < 50; ++i) s.values.push_back(1.0 - 1.0 / 512);
  for (int i = 0; i < 50; ++i) s.values.push_back(1.0 + 1.0 / 512);
  return s;
}
}  // namespace

TEST(MeanDeviation, MonotoneApproachStartsAtBandEntry) {
  // M₀ = mean of the last 21 samples = 1 + 1/512; b = 0.005·M₀ ≈ 0.00502. With M₀ the samples
  // 1 − 1/512 are 1/256 ≈ 0.0039 away: inside the band, and they stay (dwell 0.1 s = 10 samples)
  // → k = 5. Then M = mean(s[5:]) = 1 exactly, the band entry is still sample 5: a fixed point,
  // and every steady-state sample deviates by 1/512, so MD = 1/512 (Eq. 5.1).
  const auto s = monotone_approach();
  const auto r = m::mean_deviation(s);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.start_rule, m::StartRule::band_entry);
  EXPECT_EQ(r.start_index, 5u);
  EXPECT_NEAR(r.band_half_width, 0.005 * (1.0 + 1.0 / 512), 1e-15);
  EXPECT_EQ(r.steady_mean, 1.0);
  EXPECT_EQ(r.mean_deviation, 1.0 / 512);
  EXPECT_EQ(r.samples, 100u);

  // The crossing rule alone (b = 0): the first sample equal to M₀ = 1 + 1/512 is sample 55, the
  // mean from there is the same value, so Eq. 5.1 sees a flat half record and MD = 0 — the
  // unfairness the band removes.
  m::MeanDeviationOptions crossing_only;
  crossing_only.band_half_width = 0.0;
  const auto c = m::mean_deviation(s, crossing_only);
  EXPECT_EQ(c.start_rule, m::StartRule::crossing);
  EXPECT_EQ(c.start_index, 55u);
  EXPECT_EQ(c.mean_deviation, 0.0);

  // A band narrower than 1/256 (0.3 % of the move) is not entered: crossing rule again.
  m::MeanDeviationOptions narrow;
  narrow.band_move_fraction = 0.003;
  EXPECT_EQ(m::mean_deviation(s, narrow).start_index, 55u);
}

TEST(MeanDeviation, DwellIgnoresABriefVisitToTheBand) {
  // The monotone approach with sample 2 raised to 1 − 1/512: that lone visit lasts one sample,
  // shorter than the dwell (10 samples), so the entry is still sample 5. With a dwell of one
  // sample the visit counts: k = 2 and MD takes in samples 3 and 4 (0.25 and 0.125 below M).
  auto s = monotone_approach();
  s.values[2] = 1.0 - 1.0 / 512;
  const auto r = m::mean_deviation(s);
  EXPECT_EQ(r.start_index, 5u);
  EXPECT_EQ(r.start_rule, m::StartRule::band_entry);
  m::MeanDeviationOptions no_dwell;
  no_dwell.band_dwell_s = 0.0;
  const auto q = m::mean_deviation(s, no_dwell);
  ASSERT_TRUE(q.converged);
  EXPECT_EQ(q.start_index, 2u);
  double mean = 0.0;
  for (std::size_t i = 2; i < s.size(); ++i) mean += s.values[i];
  mean /= static_cast<double>(s.size() - 2);
  double ss = 0.0;
  for (std::size_t i = 2; i < s.size(); ++i) ss += (s.values[i] - mean) * (s.values[i] - mean);
  EXPECT_NEAR(q.steady_mean, mean, 1e-15);
  EXPECT_NEAR(q.mean_deviation, std::sqrt(ss / static_cast<double>(s.size() - 2)), 1e-15);
}

TEST(MeanDeviation, NoisyApproach) {
  // Hand case: alternate ±e on the steady part of the monotone approach. e = 1/1024 keeps every
  // sample within 1/512 + 1/1024 ≈ 0.0029 < b of M: band entry at 5, M = 1, and MD² = mean of
  // (±1/512 ± 1/1024)² = (1/512)² + (1/1024)² (the cross terms cancel over each 50-sample half).
  auto s = monotone_approach();
  for (std::size_t i = 5; i < s.size(); ++i) s.values[i] += ((i % 2) ? 1.0 : -1.0) / 1024;
  const auto r = m::mean_deviation(s);
  EXPECT_EQ(r.start_rule, m::StartRule::band_entry);
  EXPECT_EQ(r.start_index, 5u);
  EXPECT_NEAR(r.steady_mean, 1.0, 1e-15);
  EXPECT_NEAR(r.mean_deviation, std::hypot(1.0 / 512, 1.0 / 1024), 1e-15);

  // e = 1/64 > b: the noise carries the response over its mean at once — the first sign change,
  // sample 5 (sample 4 = 0.875 lies below M ≈ 1, sample 5 = 1 − 1/512 + 1/64 above), and the
  // band (never stayed in: every other sample is 1/64 away) plays no part.
  auto loud = monotone_approach();
  for (std::size_t i = 5; i < loud.size(); ++i) loud.values[i] += ((i % 2) ? 1.0 : -1.0) / 64;
  const auto q = m::mean_deviation(loud);
  EXPECT_EQ(q.start_rule, m::StartRule::crossing);
  EXPECT_EQ(q.start_index, 5u);

  // Seeded Gaussian noise, σ = b/10, on an exponential approach with a slow drift: the start is
  // the band entry near where 1 − e^{−t/τ} comes within b of M, not the late crossing of the
  // drift, and MD ≈ the RMS of drift + noise about M (statistical tolerance: 5 %).
  cs::UniformSeries e;
  e.sample_time_s = 1e-3;
  std::mt19937_64 rng(20151101);
  std::normal_distribution<double> noise(0.0, 0.0005);
  const double tau_s = 0.05;
  for (int i = 0; i < 4000; ++i) {
    const double t = i * 1e-3;
    e.values.push_back(1.0 - std::exp(-t / tau_s) + 0.004 * t / 4.0 + noise(rng));
  }
  const auto g = m::mean_deviation(e);
  EXPECT_EQ(g.start_rule, m::StartRule::band_entry);
  // b ≈ 0.005·1.0036; 1 − e^{−t/τ} + drift reaches M − b ≈ 1.0018 − 0.005 near t = τ·ln(1/0.0032).
  EXPECT_NEAR(g.start_time_s, tau_s * std::log(1.0 / 0.0032), 0.03);
  const double drift_rms = 0.004 * (4.0 - g.start_time_s) / 4.0 / std::sqrt(12.0);  // uniform ramp
  EXPECT_NEAR(g.mean_deviation, std::hypot(drift_rms, 0.0005), 0.05 * std::hypot(drift_rms, 0.0005) + 2e-4);
  m::MeanDeviationOptions crossing_only;
  crossing_only.band_half_width = 0.0;
  EXPECT_GT(m::mean_deviation(e, crossing_only).start_time_s, g.start_time_s + 0.2);
}

TEST(MeanDeviation, NoiseMultipleWidensTheBand) {
  // Alternating ±1/64 on a flat 1.0 tail after a ramp: σ_n (successive differences 2/64) is
  // 1/64·√2; with band_noise_multiple = 3, b = 3·σ_n = 0.066 and the ramp sample 0.95 (0.05
  // from M = 1) starts a stay inside the band.
  cs::UniformSeries s;
  s.sample_time_s = 0.01;
  s.values = {0.0, 0.5, 0.95};
  for (int i = 0; i < 100; ++i) s.values.push_back(1.0 + ((i % 2) ? 1.0 : -1.0) / 64);
  m::MeanDeviationOptions options;
  options.band_noise_multiple = 3.0;
  const auto r = m::mean_deviation(s, options);
  EXPECT_NEAR(r.noise_floor, std::sqrt(2.0) / 64, 1e-15);
  EXPECT_NEAR(r.band_half_width, 3.0 * std::sqrt(2.0) / 64, 1e-15);
  EXPECT_EQ(r.start_index, 2u);
  EXPECT_EQ(r.start_rule, m::StartRule::band_entry);
  // Default: no noise term, b = 0.005, and the first crossing is sample 4 (sample 3 = 1 − 1/64).
  EXPECT_EQ(m::mean_deviation(s).start_index, 4u);
  EXPECT_EQ(m::mean_deviation(s).start_rule, m::StartRule::crossing);
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

TEST(MeanDeviation, ARateThatRestsOnItsMeanMeetsItOnTheReturn) {
  // A quantized rate during a position move: 0 (exactly the steady mean) at rest, a pulse, then
  // ringing ±1. M₀ = mean of the last 2 samples = 0; the largest |s − M| is 8, so the departure
  // is sample 3 (|4| >= 4) and the first crossing after it is sample 6 (4 → −1). M = mean of
  // −1, 1, −1, 1 = 0: a fixed point, MD = 1 (Eq. 5.1). Without the departure the rest at
  // sample 0 "met" M, the iteration moved M to the mean of the pulse (16/7) and k to its
  // rising edge (sample 3): MD measured the move.
  cs::UniformSeries s;
  s.sample_time_s = 0.01;
  s.values = {0.0, 0.0, 0.0, 4.0, 8.0, 4.0, -1.0, 1.0, -1.0, 1.0};
  const auto r = m::mean_deviation(s);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.start_index, 6u);
  EXPECT_EQ(r.start_rule, m::StartRule::crossing);
  EXPECT_EQ(r.steady_mean, 0.0);
  EXPECT_EQ(r.mean_deviation, 1.0);
  // A response that never leaves its mean has no meeting: the final window.
  cs::UniformSeries flat;
  flat.sample_time_s = 0.01;
  flat.values.assign(10, 0.5);
  const auto f = m::mean_deviation(flat);
  EXPECT_EQ(f.start_rule, m::StartRule::window_start);
  EXPECT_EQ(f.mean_deviation, 0.0);
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
  options = {};
  options.band_move_fraction = 1.0;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
  options = {};
  options.band_noise_multiple = -1.0;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
  options = {};
  options.band_dwell_s = -0.1;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
  options = {};
  options.band_half_width = -1e-3;
  EXPECT_THROW(m::mean_deviation(s, options), cs::InvalidArgument);
}

TEST(MeanDeviation, StartRuleNames) {
  EXPECT_EQ(m::to_string(m::StartRule::crossing), "crossing");
  EXPECT_EQ(m::to_string(m::StartRule::band_entry), "band-entry");
  EXPECT_EQ(m::to_string(m::StartRule::window_start), "window-start");
}
