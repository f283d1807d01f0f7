// study/axis_calibration.hpp without a board: the analysis of records whose physics is known
// exactly — a linear free decay x(t) = A·e^(−ζωt)·sin(ω_d t) after a step, and a base-excited
// oscillator driven by a chirp (its transmissibility peaks at ω) — and the request's checks.
// The same path against the firmware in the emulator: tests/rig_emulator/test_rig_calibrate.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/study/axis_calibration.hpp"

namespace clearshape::study {
namespace {

constexpr double kDt = 1e-3;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A record of `duration_s` with the command of `excitation`; gyro and motor filled by the caller.
AxisCalibrationRun run_of(const signal::Signal& excitation, double duration_s) {
  AxisCalibrationRun run;
  run.label = std::string(excitation.type());
  run.record.command = signal::sample(excitation, 1.0 / kDt, duration_s).values;
  const std::size_t n = run.record.command.size();
  run.record.time_s.resize(n);
  for (std::size_t k = 0; k < n; ++k) run.record.time_s[k] = static_cast<double>(k) * kDt;
  run.record.motor_deg = run.record.command;
  run.record.gyro_deg_s.assign(n, 0.0);
  return run;
}

TEST(AxisCalibration, TheWindowStartsWhereTheStepEndsOrWhereAChirpStarts) {
  AxisCalibrationRequest q;
  q.excitations = step_excitations({10.0}, 0.5, 0.1);
  const auto step = signal::sample(q.excitations[0], 1000.0, 3.0).values;
  EXPECT_NEAR(analysis_start_s(step, kDt, q), 0.601, 1.5e-3);  // one sample after the ramp ends (0.600 s, ± rounding)
  const auto chirp = signal::sample(signal::Chirp{.amplitude = 1.0, .f0_hz = 2.0, .f1_hz = 40.0, .sweep_s = 8.0,
                                                  .start_s = 0.5},
                                    1000.0, 9.5).values;
  EXPECT_NEAR(analysis_start_s(chirp, kDt, q), 0.5, 2e-3);
  EXPECT_EQ(analysis_start_s(std::vector<double>(100, 1.0), kDt, q), 0.0);
  q.from_s = 1.25;
  EXPECT_EQ(analysis_start_s(step, kDt, q), 1.25);
}

TEST(AxisCalibration, ALinearFreeDecayGivesItsModeAndDamping) {
  const double f_hz = 12.0, zeta = 0.05, wn = kTwoPi * f_hz, wd = wn * std::sqrt(1.0 - zeta * zeta);
  AxisCalibrationRequest q;
  q.excitations = step_excitations({5.0, 10.0}, 0.5, 1.0 / 30.0);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.2);  // deg/s, the ITG-3205's order
  std::vector<AxisCalibrationRun> runs;
  for (const auto& e : q.excitations) {
    AxisCalibrationRun run = run_of(e, 3.0);
    const double a = 20.0 * e.get_if<signal::Step>()->amplitude;
    const double t0 = analysis_start_s(run.record.command, kDt, q);
    for (std::size_t k = 0; k < run.record.size(); ++k) {
      const double t = run.record.time_s[k] - t0;
      run.record.gyro_deg_s[k] = (t >= 0.0 ? a * std::exp(-zeta * wn * t) * std::sin(wd * t) : 0.0) + noise(rng);
    }
    runs.push_back(std::move(run));
  }
  const AxisCalibration c = analyse_calibration(runs, q, kDt);
  ASSERT_FALSE(c.recommendation.modes.empty());
  EXPECT_NEAR(c.recommendation.modes[0].frequency_hz, f_hz, 0.01 * f_hz);
  EXPECT_NEAR(c.recommendation.modes[0].damping_ratio, zeta, 0.2 * zeta);
  ASSERT_TRUE(c.recommendation.chosen);
  const exports::ShaperDesign d = recommended_design(c.recommendation, q.options);
  EXPECT_EQ(std::string(shaping::to_string(d.method)), c.recommendation.candidates[*c.recommendation.chosen].name);
  EXPECT_NEAR(d.mode->natural_frequency_hz(), c.recommendation.candidates[*c.recommendation.chosen].design_frequency_hz[0],
              1e-12);
}

// θ_l'' = 2ζω(θ_m' − θ_l') + ω²(θ_m − θ_l): the link on a spring-damper behind the motor, driven by a
// chirp of the motor's angle (RK4 at 0.1 ms). Its link PSD follows the chirp; its transmissibility
// peaks at ω√(1 − 2ζ²)·(…) ≈ ω for small ζ.
TEST(AxisCalibration, AChirpIsReadThroughTheJointsTransmissibility) {
  const double f_hz = 15.0, zeta = 0.08, wn = kTwoPi * f_hz;
  AxisCalibrationRequest q;
  q.excitations = {signal::Chirp{.amplitude = 1.0, .f0_hz = 2.0, .f1_hz = 40.0, .sweep_s = 8.0, .start_s = 0.5}};
  AxisCalibrationRun run = run_of(q.excitations[0], 9.5);
  const signal::Signal& chirp = q.excitations[0];
  double th = 0.0, om = 0.0;
  const int sub = 10;
  const double h = kDt / sub;
  const auto acc = [&](double t, double x, double v) {
    const double eps = 1e-7;
    const double m = chirp.value_at(t), mv = (chirp.value_at(t + eps) - chirp.value_at(t - eps)) / (2 * eps);
    return 2.0 * zeta * wn * (mv - v) + wn * wn * (m - x);
  };
  for (std::size_t k = 0; k < run.record.size(); ++k) {
    run.record.gyro_deg_s[k] = om;
    for (int i = 0; i < sub; ++i) {
      const double t = static_cast<double>(k) * kDt + i * h;
      const double k1x = om, k1v = acc(t, th, om);
      const double k2x = om + 0.5 * h * k1v, k2v = acc(t + 0.5 * h, th + 0.5 * h * k1x, om + 0.5 * h * k1v);
      const double k3x = om + 0.5 * h * k2v, k3v = acc(t + 0.5 * h, th + 0.5 * h * k2x, om + 0.5 * h * k2v);
      const double k4x = om + h * k3v, k4v = acc(t + h, th + h * k3x, om + h * k3v);
      th += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
      om += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
  }
  const AxisCalibration c = analyse_calibration({run}, q, kDt);
  EXPECT_EQ(c.spectra[0].column, "transmissibility motor_deg → gyro_deg_s");
  EXPECT_GE(c.spectra[0].frequency_hz.front(), 2.0);
  EXPECT_LE(c.spectra[0].frequency_hz.back(), 40.0);
  ASSERT_FALSE(c.recommendation.modes.empty());
  EXPECT_NEAR(c.recommendation.modes[0].frequency_hz, f_hz, 0.03 * f_hz);
}

TEST(AxisCalibration, ADegradedRunIsNeverAnalysed) {
  AxisCalibrationRequest q;
  q.excitations = step_excitations({5.0}, 0.5, 0.0);
  AxisCalibrationRun run = run_of(q.excitations[0], 3.0);
  run.label = "step 5";
  run.outcome.degraded = {"12 samples lost on the link"};
  try {
    analyse_calibration({run}, q, kDt);
    FAIL() << "a degraded run was analysed";
  } catch (const RuntimeError& e) {
    EXPECT_NE(std::string(e.what()).find("the step 5 run is not complete (12 samples lost on the link)"),
              std::string::npos)
        << e.what();
  }
}

TEST(AxisCalibration, BadRequestsNameTheField) {
  AxisCalibrationRequest q;
  EXPECT_THROW(q.validate(), InvalidArgument);  // no excitation
  q.excitations = step_excitations({5.0}, 0.5, 0.0);
  q.duration_s = 0.0;
  EXPECT_THROW(q.validate(), InvalidArgument);
  q.duration_s = 3.0;
  q.from_s = 3.0;
  EXPECT_THROW(q.validate(), InvalidArgument);
  EXPECT_THROW(step_excitations({}, 0.5, 0.0), InvalidArgument);
  EXPECT_THROW(step_excitations({0.0}, 0.5, 0.0), InvalidArgument);
  EXPECT_THROW(recommended_design(advise::Recommendation{}, advise::RecommendOptions{}), RuntimeError);
}

}  // namespace
}  // namespace clearshape::study
