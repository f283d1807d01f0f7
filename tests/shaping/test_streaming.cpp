// StreamingShaper: equals shape_offline to rounding, allocation-free, holds non-finite input.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/streaming.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace sh = clearshape::shaping;

namespace {

// ZVD closed form (Singer & Seering 1990; reference note (c7)): [1, 2K, K²]/(1+K)² at
// [0, Td/2, Td], K = exp(−ζπ/√(1−ζ²)).
sh::Shaper zvd(const sh::Mode& mode) {
  const double zeta = mode.damping_ratio;
  const double k = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
  const double half_td = std::numbers::pi / mode.damped_frequency_rad_s();
  return sh::Shaper("zvd", {{0.0, 1.0}, {half_td, 2.0 * k}, {2.0 * half_td, k * k}});
}

// Feeds u (history resting at u[0]) then `extra` samples of u's last value.
std::vector<double> run_streaming(sh::StreamingShaper& s, const std::vector<double>& u,
                                  std::size_t extra) {
  std::vector<double> y;
  y.reserve(u.size() + extra);
  for (double v : u) y.push_back(s.step(v));
  for (std::size_t i = 0; i < extra; ++i) y.push_back(s.step(u.back()));
  return y;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace

static_assert(noexcept(std::declval<sh::StreamingShaper&>().step(1.0)));
static_assert(noexcept(std::declval<sh::StreamingShaper&>().step(1.0, std::declval<double&>())));
static_assert(noexcept(std::declval<sh::StreamingShaper&>().reset(0.0)));

TEST(StreamingShaper, HistoryIsAPowerOfTwoCoveringTheShaper) {
  const sh::Shaper s = zvd(sh::Mode::from_hz(10.0, 0.1));  // Td = 100.504 samples at 1 ms
  const sh::StreamingShaper stream(s, 1e-3);
  EXPECT_EQ(stream.history_samples(), 128u);
  EXPECT_TRUE(std::has_single_bit(stream.history_samples()));
  EXPECT_EQ(stream.tap_count(), 5u);  // 0 | 50, 51 | 100, 101
  EXPECT_EQ(sh::max_delay_samples(stream.taps()), 101u);
  EXPECT_DOUBLE_EQ(stream.sample_time_s(), 1e-3);
  // Td/2 = 64 samples exactly → one tap each, delay 128 → 256-sample history.
  const sh::Shaper grid("zv", {{0.0, 0.5}, {0.064, 0.5}, {0.128, 0.25}});
  EXPECT_EQ(sh::StreamingShaper(grid, 1e-3).history_samples(), 256u);
}

TEST(StreamingShaper, MatchesOfflineOverSeededRandomShapersAndSignals) {
  std::mt19937_64 rng(20240607);
  std::uniform_int_distribution<int> impulse_count(1, 12), length(50, 3000);  // up to 24 taps
  std::uniform_real_distribution<double> gap_s(1e-4, 0.05), amplitude(-0.5, 1.5),
      sample_time_s(1e-4, 5e-3), unit(-1.0, 1.0);
  std::bernoulli_distribution jump(0.02);
  double worst_relative = 0.0;
  int many_taps = 0;  // trials past shape_offline's 16-tap unrolled kernels (generic path)
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<sh::Impulse> impulses;
    double t = 0.0;
    for (int i = impulse_count(rng); i > 0; --i) {
      impulses.push_back({t, amplitude(rng)});
      t += gap_s(rng);
    }
    double sum = 0.0;
    for (const auto& p : impulses) sum += p.amplitude;
    if (std::abs(sum) < 0.05) impulses.front().amplitude += 1.0;  // keep ΣA away from 0
    const sh::Shaper shaper("random", impulses);

    // Random walk with occasional jumps, non-zero start.
    cs::UniformSeries u{0.0, sample_time_s(rng), {}};
    double level = 5.0 * unit(rng);
    for (int k = length(rng); k > 0; --k) {
      level += jump(rng) ? 10.0 * unit(rng) : 0.1 * unit(rng);
      u.values.push_back(level);
    }
    const cs::UniformSeries offline = sh::shape_offline(shaper, u);
    sh::StreamingShaper stream(shaper, u.sample_time_s, u.values.front());
    const std::vector<double> y = run_streaming(stream, u.values, offline.size() - u.size());
    ASSERT_EQ(y.size(), offline.size());
    many_taps += stream.tap_count() > 16 ? 1 : 0;
    const double scale = std::max(1.0, max_abs(offline.values));
    for (std::size_t k = 0; k < y.size(); ++k) {
      worst_relative = std::max(worst_relative, std::abs(y[k] - offline.values[k]) / scale);
    }
  }
  EXPECT_LT(worst_relative, 1e-12);
  EXPECT_GT(many_taps, 10);
}

TEST(StreamingShaper, ExactAtModeTapsMatchOffline) {
  const sh::Mode mode = sh::Mode::from_hz(13.7, 0.07);
  const auto taps = sh::discretize(zvd(mode), 1e-3, sh::Discretization::exact_at_mode, mode);
  cs::UniformSeries u{0.0, 1e-3, {}};
  for (int k = 0; k < 500; ++k) u.values.push_back(std::sin(0.05 * k) + (k > 200 ? 1.0 : 0.0));
  const auto offline = sh::shape_offline(taps, u);
  sh::StreamingShaper stream(taps, 1e-3, u.values.front());
  const auto y = run_streaming(stream, u.values, offline.size() - u.size());
  for (std::size_t k = 0; k < y.size(); ++k) EXPECT_NEAR(y[k], offline.values[k], 1e-12);
}

TEST(StreamingShaper, StepIsAllocationFree) {
  sh::StreamingShaper stream(zvd(sh::Mode::from_hz(10.0, 0.1)), 1e-3);  // allocates here only
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double sink = 0.0;
  cs::testing::AllocationCounter counter;
  for (int k = 0; k < 100000; ++k) {
    double out = 0.0;
    const double input = (k % 997 == 0) ? nan : std::sin(1e-3 * k);
    (void)stream.step(input, out);
    sink += out + stream.step(0.5 * input);
    if (k % 50000 == 0) stream.reset(0.25);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

TEST(StreamingShaper, NonFiniteInputIsHeldAndReported) {
  const sh::Shaper s = zvd(sh::Mode::from_hz(10.0, 0.1));
  std::vector<double> u(400);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = std::cos(0.02 * static_cast<double>(k));
  std::vector<double> held = u;
  sh::StreamingShaper stream(s, 1e-3, u[0]);
  std::vector<double> y;
  for (std::size_t k = 0; k < u.size(); ++k) {
    double input = u[k];
    if (k == 120) input = std::numeric_limits<double>::quiet_NaN();
    if (k == 121) input = std::numeric_limits<double>::infinity();
    if (k == 300) input = -std::numeric_limits<double>::infinity();
    if (k == 120 || k == 121) held[k] = u[119];
    if (k == 300) held[k] = u[299];
    double out = 0.0;
    const cs::Status status = stream.step(input, out);
    EXPECT_EQ(status, std::isfinite(input) ? cs::Status::ok : cs::Status::not_finite) << k;
    ASSERT_TRUE(std::isfinite(out)) << k;
    y.push_back(out);
  }
  // The output is the shaped command with the bad samples replaced by the previous input.
  const auto expected = sh::shape_offline(s, cs::UniformSeries{0.0, 1e-3, held}, false);
  for (std::size_t k = 0; k < y.size(); ++k) EXPECT_NEAR(y[k], expected.values[k], 1e-12) << k;
}

TEST(StreamingShaper, ResetAndInitialValueFillTheHistory) {
  const sh::Shaper s = zvd(sh::Mode::from_hz(10.0, 0.1));
  sh::StreamingShaper stream(s, 1e-3, 2.0);
  EXPECT_NEAR(stream.step(2.0), 2.0, 1e-15);
  for (int k = 0; k < 30; ++k) stream.step(7.0);
  stream.reset(-1.0);
  EXPECT_NEAR(stream.step(-1.0), -1.0, 1e-15);
  // A step from rest reaches the final value exactly when the shaper has passed.
  stream.reset(0.0);
  double last = 0.0;
  for (int k = 0; k < 102; ++k) last = stream.step(1.0);
  EXPECT_NEAR(last, 1.0, 1e-15);
}

TEST(StreamingShaper, ConstructionValidates) {
  const sh::Shaper s = zvd(sh::Mode::from_hz(10.0, 0.1));
  EXPECT_THROW(sh::StreamingShaper(s, 0.0), cs::InvalidArgument);
  EXPECT_THROW(sh::StreamingShaper(s, -1e-3), cs::InvalidArgument);
  EXPECT_THROW(sh::StreamingShaper(s, 1e-3, std::nan("")), cs::InvalidArgument);
  EXPECT_THROW(sh::StreamingShaper(std::vector<sh::DiscreteTap>{}, 1e-3), cs::InvalidArgument);
  EXPECT_THROW(sh::StreamingShaper(std::vector<sh::DiscreteTap>{{0, std::nan("")}}, 1e-3),
               cs::InvalidArgument);
  EXPECT_THROW(sh::StreamingShaper(std::vector<sh::DiscreteTap>{{std::size_t{1} << 40, 1.0}}, 1e-3),
               cs::InvalidArgument);
}
