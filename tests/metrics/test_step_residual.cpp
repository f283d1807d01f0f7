#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/residual.hpp"
#include "clearshape/metrics/step_info.hpp"

namespace cs = clearshape;
namespace m = clearshape::metrics;

namespace {
cs::UniformSeries first_order(double tau_s, double duration_s, double ts) {
  cs::UniformSeries s;
  s.sample_time_s = ts;
  for (double t = 0.0; t <= duration_s + 1e-12; t += ts) s.values.push_back(1.0 - std::exp(-t / tau_s));
  return s;
}
}  // namespace

TEST(StepInfo, FirstOrderClosedForm) {
  // 1 − e^{−t/τ}: rise 10–90 % = τ·ln 9; 2 % settling = τ·ln 50; no overshoot.
  const double tau = 0.1;
  const auto s = first_order(tau, 3.0, 1e-4);
  m::StepInfoOptions options;
  options.final_value = 1.0;
  const auto info = m::step_info(s, options);
  EXPECT_NEAR(info.rise_time_s, tau * std::log(9.0), 1e-6);  // linear interpolation error
  EXPECT_NEAR(info.settling_time_s, tau * std::log(50.0), 1e-6);
  EXPECT_EQ(info.overshoot_percent, 0.0);
  EXPECT_EQ(info.undershoot_percent, 0.0);
}

TEST(StepInfo, NeverSettlesIsNaNAndStepTimeShifts) {
  cs::UniformSeries s;
  s.sample_time_s = 0.1;
  s.start_s = 1.0;
  s.values = {0.0, 0.5, 1.0, 1.5, 0.5, 1.5};
  m::StepInfoOptions options;
  options.final_value = 1.0;
  options.step_time_s = 0.5;
  const auto info = m::step_info(s, options);
  EXPECT_TRUE(std::isnan(info.settling_time_s));
  EXPECT_NEAR(info.rise_time_s, 0.16, 1e-12);       // 0.1 at 0.02 s, 0.9 at 0.18 s
  EXPECT_NEAR(info.peak_time_s, 0.8, 1e-12);        // sample 3 at 1.3 s, step at 0.5 s
  EXPECT_NEAR(info.overshoot_percent, 50.0, 1e-12);
  EXPECT_NEAR(info.settling_min, 0.5, 1e-12);
  options.final_value = 0.0;
  EXPECT_THROW(m::step_info(s, options), cs::InvalidArgument);
}

TEST(Residual, SineAboutFinalValue) {
  // 2 + 0.5·sin(2π·5t) after 1 s, whole periods: p-p = 1, RMS = 0.5/√2.
  cs::UniformSeries s;
  s.sample_time_s = 1e-3;
  for (int i = 0; i <= 2000; ++i) {
    const double t = i * 1e-3;
    s.values.push_back(t < 1.0 ? 0.0 : 2.0 + 0.5 * std::sin(2 * M_PI * 5 * t));
  }
  s.values.pop_back();  // 1000 samples after 1 s = 5 whole periods
  const auto r = m::residual_vibration(s, 1.0, 2.0);
  EXPECT_EQ(r.samples, 1000u);
  EXPECT_NEAR(r.peak_to_peak, 1.0, 1e-6);
  EXPECT_NEAR(r.rms_about_final, 0.5 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.max_abs_deviation, 0.5, 1e-6);
  EXPECT_THROW(m::residual_vibration(s, 5.0), cs::InvalidArgument);
}

TEST(Residual, DelayOfADelayedCopy) {
  // A response delayed by 0.137 s reaches 50 % exactly 0.137 s later.
  const auto a = first_order(0.05, 2.0, 1e-3);
  cs::UniformSeries b = a;
  b.values.assign(a.size(), 0.0);
  for (std::size_t i = 137; i < a.size(); ++i) b.values[i] = a.values[i - 137];
  EXPECT_NEAR(m::time_to_fraction_s(a, 0.5, 0.0, 1.0), 0.05 * std::log(2.0), 5e-6);  // interpolation error ~Ts²·y''/8
  EXPECT_NEAR(m::shaping_delay_s(a, b), 0.137, 1e-9);
  EXPECT_NEAR(m::final_value(a, 0.1), 1.0, 1e-12);
}
