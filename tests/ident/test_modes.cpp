// Residual-mode identification on synthetic link-sensor records whose modes are known:
// a free decay of two lightly damped modes plus a drifting real pole and a sensor offset, with
// and without noise; the reported 1σ must describe the scatter over seeded trials; and modes of
// an input/output record. Frequencies from z = e^(sT) are exact for a sampled free decay.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/lti/discretize.hpp"
#include "free_decay.hpp"

namespace ident = clearshape::ident;
using clearshape::UniformSeries;

namespace {

using clearshape::testing::free_decay;
using clearshape::testing::TrueMode;
constexpr double kPi = std::numbers::pi;

const std::vector<TrueMode> kModes = {{6.2, 0.03, 40.0, 0.4}, {17.5, 0.012, 15.0, -1.0}};

}  // namespace

// A window cut from a longer record keeps its time: the fitted free response starts where the
// window does (a fit drawn from t = 0 would sit 0.55 s before the decay it describes).
TEST(Modes, FittedResponseStartsWithTheWindow) {
  UniformSeries window = free_decay(kModes, 1e-3, 2000, 0.0, 1);
  window.start_s = 0.55;
  ident::ModeOptions o;
  o.modes = 2;
  const auto r = ident::identify_free_response_modes(window, o);
  EXPECT_DOUBLE_EQ(r.fitted.start_s, 0.55);
  EXPECT_DOUBLE_EQ(r.fitted.sample_time_s, 1e-3);
  ASSERT_EQ(r.fitted.values.size(), window.values.size());
  EXPECT_NEAR(r.fitted.values.front(), window.values.front(), 1e-6);
}

TEST(Modes, FreeDecayNoiseFreeIsExact) {
  ident::ModeOptions o;
  o.modes = 2;
  const auto r = ident::identify_free_response_modes(free_decay(kModes, 1e-3, 3000, 0.0, 1), o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_GT(r.fit_percent, 99.9999);
  EXPECT_EQ(r.method, "era+ls");
  for (std::size_t i = 0; i < 2; ++i) {  // dominant (larger RMS) first: the 6.2 Hz mode
    EXPECT_NEAR(r.modes[i].natural_frequency_hz(), kModes[i].fn_hz, 1e-8 * kModes[i].fn_hz);
    EXPECT_NEAR(r.modes[i].damping_ratio, kModes[i].zeta, 1e-8);
    EXPECT_NEAR(r.modes[i].amplitude, kModes[i].amplitude, 1e-6 * kModes[i].amplitude);
  }
}

TEST(Modes, UncertaintyDescribesTheScatter) {
  ident::ModeOptions o;
  o.modes = 2;
  std::vector<double> z;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto r = ident::identify_free_response_modes(free_decay(kModes, 1e-3, 2500, 2.0, seed), o);
    ASSERT_EQ(r.modes.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      z.push_back((r.modes[i].natural_frequency_hz() - kModes[i].fn_hz) / r.modes[i].natural_frequency_std_hz());
      z.push_back((r.modes[i].damping_ratio - kModes[i].zeta) / r.modes[i].damping_ratio_std);
      z.push_back((r.modes[i].amplitude - kModes[i].amplitude) / r.modes[i].amplitude_std);
    }
  }
  double s = 0.0, worst = 0.0;
  int beyond3 = 0;
  for (double v : z) {
    s += v * v;
    worst = std::max(worst, std::abs(v));
    beyond3 += std::abs(v) > 3.0 ? 1 : 0;
  }
  const double rms = std::sqrt(s / static_cast<double>(z.size()));
  EXPECT_GT(rms, 0.6);
  EXPECT_LT(rms, 1.5);
  EXPECT_LE(beyond3, 1);
  EXPECT_LT(worst, 4.5);
}

TEST(Modes, PerSampleFrequenciesWithoutSampleTime) {
  const auto y = free_decay({{0.05, 0.01, 1.0, 0.0}}, 1.0, 600, 0.0, 1, 0.0, 0.0);
  const auto r = ident::identify_free_response_modes(y);
  ASSERT_EQ(r.modes.size(), 1u);
  EXPECT_NEAR(r.modes[0].natural_frequency_hz(), 0.05, 1e-9);  // cycles/sample when T = 1
  EXPECT_EQ(r.sample_time_s, 1.0);
}

TEST(Modes, InputOutputRecord) {
  // Two resonances excited by a random input (ZOH discretization of a continuous model).
  const double w1 = 2 * kPi * 4.0, z1 = 0.02, w2 = 2 * kPi * 11.0, z2 = 0.05;
  const auto d = clearshape::testing::two_resonances(w1, z1, w2, z2, 0.005);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> nd;
  std::vector<double> u(2000);
  for (auto& v : u) v = nd(rng);
  const auto y = clearshape::lti::simulate(d, u);
  ident::ModeOptions o;
  o.modes = 2;
  const auto r = ident::identify_modes(ident::Experiment{"io", 0.005, u, y}, o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_EQ(r.method, "n4sid+oe");
  std::vector<std::pair<double, double>> found;
  for (const auto& m : r.modes) found.emplace_back(m.natural_frequency_rad_s, m.damping_ratio);
  std::sort(found.begin(), found.end());
  EXPECT_NEAR(found[0].first, w1, 1e-7 * w1);
  EXPECT_NEAR(found[0].second, z1, 1e-7);
  EXPECT_NEAR(found[1].first, w2, 1e-7 * w2);
  EXPECT_NEAR(found[1].second, z2, 1e-7);
}

TEST(Modes, RejectsBadRequests) {
  ident::ModeOptions o;
  o.modes = 0;
  EXPECT_THROW(ident::identify_free_response_modes(free_decay(kModes, 1e-3, 500, 0.0, 1), o), clearshape::InvalidArgument);
  EXPECT_THROW(ident::identify_free_response_modes(free_decay(kModes, 1e-3, 20, 0.0, 1)), clearshape::InvalidArgument);
  // A pure exponential has no oscillatory mode.
  const auto flat = free_decay({}, 1e-3, 500, 0.0, 1, 0.0, 1.0, 0.1);
  EXPECT_THROW(ident::identify_free_response_modes(flat), clearshape::RuntimeError);
}
