// Offline shaping and discretisation: golden data from NumPy (tests/golden/gen_apply.py),
// closed-form ZV/ZVD shapers and an exactly simulated 2nd-order plant.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/shaping/apply.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace sh = clearshape::shaping;

namespace {

constexpr double kPi = std::numbers::pi;

// ZV-family closed form (Singer & Seering 1990; reference note (c7)): C(n,k)·K^k/(1+K)^n at
// k·π/ωd, K = exp(−ζπ/√(1−ζ²)); n = 1 ZV, 2 ZVD, 3 ZVDD, 4 ZVDDD.
sh::Shaper zv_family(int n, const sh::Mode& mode) {
  const double zeta = mode.damping_ratio;
  const double k = std::exp(-zeta * kPi / std::sqrt(1.0 - zeta * zeta));
  std::vector<sh::Impulse> impulses;
  double binomial = 1.0;
  for (int i = 0; i <= n; ++i) {
    impulses.push_back({i * kPi / mode.damped_frequency_rad_s(), binomial * std::pow(k, i)});
    binomial = binomial * (n - i) / (i + 1);
  }
  return sh::Shaper("zv" + std::string(static_cast<std::size_t>(n - 1), 'd'), impulses);
}

// Residual vibration of on-grid taps (reference note (c1); Singer & Seering 1990):
// V = e^{−ζωn·t_N}·|Σ w_j·e^{ζωn·t_j}·e^{jωd·t_j}| / Σ w_j with t_j = d_j·Ts.
double residual_of_taps(const std::vector<sh::DiscreteTap>& taps, double ts, const sh::Mode& m) {
  const double sigma = m.damping_ratio * m.natural_frequency_rad_s;
  const double wd = m.damped_frequency_rad_s();
  const double t_last = static_cast<double>(sh::max_delay_samples(taps)) * ts;
  std::complex<double> sum{0.0, 0.0};
  double weight_sum = 0.0;
  for (const auto& tap : taps) {
    const double t = static_cast<double>(tap.delay_samples) * ts;
    sum += tap.weight * std::exp(sigma * (t - t_last)) * std::polar(1.0, wd * t);
    weight_sum += tap.weight;
  }
  return std::abs(sum) / weight_sum;
}

// Exact response of ωn²/(s² + 2ζωn s + ωn²) to the piecewise-linear interpolation of the
// samples u (held at both ends, plant at rest at u[0] before), as a superposition of unit-ramp
// responses r(t) = t − 2ζ/ωn + e^{−σt}[(2ζ/ωn)cos ωd t + ((2ζ²−1)/ωd) sin ωd t] (r(0) = 0,
// r' = the unit-step response 1 − e^{−σt}(cos ωd t + (σ/ωd) sin ωd t)).
class SecondOrderPlant {
 public:
  SecondOrderPlant(const sh::Mode& mode, const cs::UniformSeries& u) : mode_(mode), u0_(u.values[0]) {
    double previous_slope = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
      const double slope =
          k + 1 < u.size() ? (u.values[k + 1] - u.values[k]) / u.sample_time_s : 0.0;
      if (slope != previous_slope) kinks_.push_back({u.time_s(k), slope - previous_slope});
      previous_slope = slope;
    }
  }
  double output(double t) const {
    const double wn = mode_.natural_frequency_rad_s;
    const double zeta = mode_.damping_ratio;
    const double sigma = zeta * wn;
    const double wd = mode_.damped_frequency_rad_s();
    double y = u0_;
    for (const Kink& kink : kinks_) {
      const double tau = t - kink.time_s;
      if (tau <= 0.0) break;
      const double ramp = tau - 2.0 * zeta / wn +
                          std::exp(-sigma * tau) * (2.0 * zeta / wn * std::cos(wd * tau) +
                                                    (2.0 * zeta * zeta - 1.0) / wd * std::sin(wd * tau));
      y += kink.slope_change * ramp;
    }
    return y;
  }
  double last_kink_s() const { return kinks_.empty() ? 0.0 : kinks_.back().time_s; }

 private:
  struct Kink {
    double time_s;
    double slope_change;
  };
  sh::Mode mode_;
  double u0_;
  std::vector<Kink> kinks_;
};

cs::UniformSeries sampled_step(double ts, double duration_s, std::size_t step_sample) {
  cs::UniformSeries u;
  u.sample_time_s = ts;
  u.values.assign(cs::sample_count(duration_s, ts), 0.0);
  std::fill(u.values.begin() + static_cast<std::ptrdiff_t>(step_sample), u.values.end(), 1.0);
  return u;
}

// max |y(t) − 1| over t in [from_s, from_s + 0.5 s], 0.1 ms steps.
double max_residual_after(const SecondOrderPlant& plant, double from_s) {
  double worst = 0.0;
  for (int i = 0; i <= 5000; ++i) worst = std::max(worst, std::abs(plant.output(from_s + i * 1e-4) - 1.0));
  return worst;
}

const sh::Mode kPlant = sh::Mode::from_hz(10.0, 0.1);  // reference note (c5)

}  // namespace

// ---------------------------------------------------------------------------------------------
// discretize

TEST(Discretize, OnGridImpulsesBecomeSingleTaps) {
  const sh::Shaper s("custom", {{0.0, 0.5}, {0.004, 0.5}});
  const auto taps = sh::discretize(s, 1e-3);
  ASSERT_EQ(taps.size(), 2u);
  EXPECT_EQ(taps[0], (sh::DiscreteTap{0, 0.5}));
  EXPECT_EQ(taps[1], (sh::DiscreteTap{4, 0.5}));
}

TEST(Discretize, LinearSplitOverNeighbouringSamples) {
  // t = 2.25·Ts → A(1−f) = 0.75·A at 2 and f·A = 0.25·A at 3 (first-order hold).
  const sh::Shaper s("custom", {{0.0, 0.6}, {0.00225, 0.4}});
  const auto taps = sh::discretize(s, 1e-3);
  ASSERT_EQ(taps.size(), 3u);
  EXPECT_EQ(taps[1].delay_samples, 2u);
  EXPECT_EQ(taps[2].delay_samples, 3u);
  EXPECT_NEAR(taps[1].weight, 0.4 * 0.75, 1e-15);
  EXPECT_NEAR(taps[2].weight, 0.4 * 0.25, 1e-15);
}

TEST(Discretize, EqualDelaysAreMergedAndSumKept) {
  // Impulses at 0 and 0.5·Ts share sample 0: weights 0.5 + 0.5·0.5 at 0 and 0.5·0.5 at 1.
  const sh::Shaper s("custom", {{0.0, 0.5}, {0.0005, 0.5}});
  const auto taps = sh::discretize(s, 1e-3);
  ASSERT_EQ(taps.size(), 2u);
  EXPECT_EQ(taps[0].delay_samples, 0u);
  EXPECT_NEAR(taps[0].weight, 0.75, 1e-15);
  EXPECT_NEAR(taps[1].weight, 0.25, 1e-15);
}

TEST(Discretize, ThreeImpulsesInOneSampleGiveSortedMergedTaps) {
  // A shaper shorter than Ts (issue 21): 0.25 at 0, 0.5 at 0.2·Ts, 0.25 at 0.4·Ts. First-order
  // hold: sample 1 gets 0.5·0.2 + 0.25·0.4 = 0.2, sample 0 the rest, 0.8 (was 4 unsorted taps).
  const sh::Shaper s("custom", {{0.0, 0.25}, {0.0002, 0.5}, {0.0004, 0.25}});
  const auto taps = sh::discretize(s, 1e-3);
  ASSERT_EQ(taps.size(), 2u);
  EXPECT_EQ(taps[0].delay_samples, 0u);
  EXPECT_EQ(taps[1].delay_samples, 1u);
  EXPECT_NEAR(taps[0].weight, 0.8, 1e-15);
  EXPECT_NEAR(taps[1].weight, 0.2, 1e-15);
}

TEST(Discretize, GoldenExactSplitMatchesNumpyLinearSolve) {
  // apply_exact_taps.csv: Murphy–Watanabe weights solved as a 2×2 system with numpy.linalg.solve.
  const auto golden = cs::io::read_table(cs::testing::golden_path("apply_exact_taps.csv"));
  const std::vector<std::string> names{"zv", "zvd", "zvdd", "ei"};
  const sh::Mode mode = sh::Mode::from_hz(13.7, 0.07);  // gen_apply.py F_HZ, ZETA
  for (std::size_t i = 0; i < names.size(); ++i) {
    SCOPED_TRACE(names[i]);
    const auto imp = cs::io::read_table(cs::testing::golden_path("apply_" + names[i] + "_impulses.csv"));
    std::vector<sh::Impulse> impulses;
    for (std::size_t r = 0; r < imp.rows(); ++r) impulses.push_back({imp.columns[0][r], imp.columns[1][r]});
    const auto taps = sh::discretize(sh::Shaper(names[i], impulses), 1e-3,
                                     sh::Discretization::exact_at_mode, mode);
    std::vector<sh::DiscreteTap> expected;
    for (std::size_t r = 0; r < golden.rows(); ++r) {
      if (golden.columns[0][r] != static_cast<double>(i)) continue;
      expected.push_back({static_cast<std::size_t>(golden.columns[1][r]), golden.columns[2][r]});
    }
    ASSERT_EQ(taps.size(), expected.size());
    for (std::size_t j = 0; j < taps.size(); ++j) {
      EXPECT_EQ(taps[j].delay_samples, expected[j].delay_samples);
      EXPECT_NEAR(taps[j].weight, expected[j].weight, 1e-12);
    }
  }
}

TEST(Discretize, ExactAtModeCancelsTheModeWhereLinearLeavesResidual) {
  // ZVD for 10 Hz, ζ = 0.1 at Ts = 1 ms: Td/2 = 50.252 samples, between samples.
  const double ts = 1e-3;
  const sh::Shaper zvd = zv_family(2, kPlant);
  const double v_linear = residual_of_taps(sh::discretize(zvd, ts), ts, kPlant);
  const double v_exact = residual_of_taps(
      sh::discretize(zvd, ts, sh::Discretization::exact_at_mode, kPlant), ts, kPlant);
  std::printf("ZVD 10 Hz ζ=0.1, Ts=1 ms: V(design) linear split = %.3e, exact split = %.3e\n",
              v_linear, v_exact);
  EXPECT_LT(v_exact, 1e-13);
  EXPECT_GT(v_linear, 1e-5);  // small but clearly non-zero: O((ωd·Ts)²)
  EXPECT_LT(v_linear, 1e-2);
}

TEST(Discretize, ExactAtModePropertyOverSeededModes) {
  std::mt19937_64 rng(1992);
  std::uniform_real_distribution<double> freq_hz(0.5, 40.0), zeta(0.0, 0.5), ts(2e-4, 4e-3);
  std::uniform_int_distribution<int> order(1, 4);
  for (int trial = 0; trial < 200; ++trial) {
    const sh::Mode mode = sh::Mode::from_hz(freq_hz(rng), zeta(rng));
    const double sample_time_s = ts(rng);
    const sh::Shaper s = zv_family(order(rng), mode);
    const auto taps = sh::discretize(s, sample_time_s, sh::Discretization::exact_at_mode, mode);
    double sum = 0.0;
    for (const auto& t : taps) sum += t.weight;
    EXPECT_NEAR(sum, 1.0, 1e-13);
    EXPECT_LT(residual_of_taps(taps, sample_time_s, mode), 1e-11) << "trial " << trial;
  }
}

TEST(Discretize, RejectsBadArguments) {
  const sh::Shaper zv = zv_family(1, kPlant);
  EXPECT_THROW(sh::discretize(zv, 0.0), cs::InvalidArgument);
  EXPECT_THROW(sh::discretize(zv, std::nan("")), cs::InvalidArgument);
  EXPECT_THROW(sh::discretize(zv, 1e-12), cs::InvalidArgument);  // 5e10 samples: unit mistake
  // exact_at_mode needs a valid, sub-Nyquist mode.
  EXPECT_THROW(sh::discretize(zv, 1e-3, sh::Discretization::exact_at_mode), cs::InvalidArgument);
  EXPECT_THROW(sh::discretize(zv, 1e-3, sh::Discretization::exact_at_mode, sh::Mode::from_hz(10, 1.0)),
               cs::InvalidArgument);
  EXPECT_THROW(sh::discretize(zv, 0.06, sh::Discretization::exact_at_mode, kPlant),
               cs::InvalidArgument);  // ωd·Ts = 3.75 rad > π
  try {
    sh::discretize(zv, -1.0);
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("sample_time_s"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// shape_offline

TEST(ShapeOffline, GoldenAgainstNumpyInterpAndConvolve) {
  // Tolerance 1e-12 absolute on O(1) signals (both sides are a few rounded products).
  const auto input = cs::io::read_table(cs::testing::golden_path("apply_input.csv"));
  const double ts = cs::io::uniform_sample_time(input, "time_s", 1e-9);
  for (const std::string name : {"zv", "zvd", "zvdd", "ei"}) {
    const auto imp = cs::io::read_table(cs::testing::golden_path("apply_" + name + "_impulses.csv"));
    std::vector<sh::Impulse> impulses;
    for (std::size_t r = 0; r < imp.rows(); ++r) impulses.push_back({imp.columns[0][r], imp.columns[1][r]});
    const sh::Shaper shaper(name, impulses);
    const auto expected = cs::io::read_table(cs::testing::golden_path("apply_" + name + ".csv"));
    for (const std::string signal : {"step", "ramp", "prbs", "sine"}) {
      SCOPED_TRACE(name + "/" + signal);
      cs::UniformSeries u{input.column("time_s")[0], ts, input.column(signal)};
      const cs::UniformSeries y = sh::shape_offline(shaper, u);
      const auto& want = expected.column(signal);
      ASSERT_EQ(y.size(), want.size());
      EXPECT_DOUBLE_EQ(y.start_s, u.start_s);
      double worst = 0.0;
      for (std::size_t k = 0; k < y.size(); ++k) worst = std::max(worst, std::abs(y.values[k] - want[k]));
      EXPECT_LT(worst, 1e-12);
      // Without extension: the same samples, cut at the input's length.
      const cs::UniformSeries cut = sh::shape_offline(shaper, u, false);
      ASSERT_EQ(cut.size(), u.size());
      for (std::size_t k = 0; k < cut.size(); ++k) EXPECT_EQ(cut.values[k], y.values[k]);
    }
  }
}

TEST(ShapeOffline, ImpulseBetweenSamplesIsLinearInterpolationOfInput) {
  // A pure delay of 2.5 samples on a ramp shifts it by exactly 2.5·Ts·slope (never rounded).
  const sh::Shaper delay("delay", {{0.0025, 1.0}});
  cs::UniformSeries u;
  u.sample_time_s = 1e-3;
  for (int k = 0; k < 20; ++k) u.values.push_back(3.0 * k);
  const auto y = sh::shape_offline(delay, u);
  for (std::size_t k = 3; k < u.size(); ++k) EXPECT_NEAR(y.values[k], 3.0 * (static_cast<double>(k) - 2.5), 1e-12);
  EXPECT_NEAR(y.values[0], 0.0, 1e-12);  // held at the first value before the start
  EXPECT_EQ(y.size(), u.size() + 3);     // extended by ceil(2.5) samples
  EXPECT_NEAR(y.values.back(), 3.0 * 19, 1e-12);
}

TEST(ShapeOffline, ConstantInputIsUnchangedAndEmptyGivesEmpty) {
  const sh::Shaper zvd = zv_family(2, kPlant);
  cs::UniformSeries u{1.5, 1e-3, std::vector<double>(300, -2.75)};
  for (double v : sh::shape_offline(zvd, u).values) EXPECT_NEAR(v, -2.75, 1e-14);
  EXPECT_TRUE(sh::shape_offline(zvd, cs::UniformSeries{0.0, 1e-3, {}}).values.empty());
  EXPECT_THROW(sh::shape_offline(zvd, cs::UniformSeries{0.0, 0.0, {1.0}}), cs::InvalidArgument);
  EXPECT_THROW(sh::shape_offline(std::vector<sh::DiscreteTap>{}, u), cs::InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// End to end on an exact 2nd-order plant (reference note (c5) and (e) 5–6)

TEST(ShapeOfflinePlant, UnshapedStepOvershootIs72Point92Percent) {
  const auto u = sampled_step(1e-5, 0.3, 1);  // a 10 µs ramp: overshoot lower by ~(ωTs)²/24
  const SecondOrderPlant plant(kPlant, u);
  double peak = 0.0;
  for (int i = 0; i < 30000; ++i) peak = std::max(peak, plant.output(i * 1e-5));
  const double k = std::exp(-0.1 * kPi / std::sqrt(1.0 - 0.01));
  EXPECT_NEAR(peak - 1.0, 0.7292, 5e-5);
  EXPECT_NEAR(peak - 1.0, k, 1e-6);
}

TEST(ShapeOfflinePlant, ZvAndZvdOnGridLeaveNoResidual) {
  for (int n : {1, 2}) {
    const sh::Shaper s = zv_family(n, kPlant);
    const double ts = (kPi / kPlant.damped_frequency_rad_s()) / 50.0;  // Td/2 = 50 samples
    const auto y = sh::shape_offline(s, sampled_step(ts, 0.3, 20));
    const SecondOrderPlant plant(kPlant, y);
    const double after_s = 20 * ts + s.duration_s();
    EXPECT_NEAR(plant.last_kink_s(), after_s, 1e-9);
    const double residual = max_residual_after(plant, after_s);
    std::printf("%s on grid (Ts = Td/100): max |y-1| after the last impulse = %.2e\n",
                s.method().c_str(), residual);
    EXPECT_LT(residual, 1e-9);
    // Positive shaper, exact mode: no overshoot anywhere.
    for (int i = 0; i < 4000; ++i) EXPECT_LE(plant.output(i * 1e-4), 1.0 + 1e-9);
  }
}

TEST(ShapeOfflinePlant, OffGridExactSplitLeavesNoResidualLinearSplitSmall) {
  const double ts = 1e-3;  // Td/2 = 50.252 samples
  const auto u = sampled_step(ts, 0.5, 20);
  for (int n : {1, 2}) {
    const sh::Shaper s = zv_family(n, kPlant);
    const auto exact = sh::discretize(s, ts, sh::Discretization::exact_at_mode, kPlant);
    const SecondOrderPlant plant_exact(kPlant, sh::shape_offline(exact, u));
    const SecondOrderPlant plant_linear(kPlant, sh::shape_offline(s, u));
    const double r_exact = max_residual_after(plant_exact, plant_exact.last_kink_s());
    const double r_linear = max_residual_after(plant_linear, plant_linear.last_kink_s());
    std::printf("%s off grid (Ts = 1 ms): max |y-1| after the last impulse: exact split %.2e, "
                "linear split %.2e\n", s.method().c_str(), r_exact, r_linear);
    EXPECT_LT(r_exact, 1e-9);
    EXPECT_GT(r_linear, 1e-6);
    EXPECT_LT(r_linear, 1e-2);
  }
}
