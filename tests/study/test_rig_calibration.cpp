// Guards the calibration of the simulated rig (docs/design.md §2): the default rig's unshaped
// responses reproduce the thesis's "without is" means (Tables B.1–B.5) within the stated
// tolerance, and the truth's speed drive seen through the §3.3 chain is the thesis's Eq. 4.2.
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/rig_calibration.hpp"
#include "study_paths.hpp"

namespace st = clearshape::study;
using clearshape::testing::studies_path;

TEST(RigCalibration, DefaultRigReproducesTheUnshapedMeansOfTablesB1ToB5) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-position.toml"));
  const auto res = st::unshaped_residuals(clearshape::rig::thesis_rig_truth(), p, 4, 11, 2);
  ASSERT_EQ(res.size(), 5u);
  for (const auto& r : res) {
    // Tolerance: 20 % of the thesis's mean (the calibration's residuals are 2–14 %).
    EXPECT_LT(std::abs(r.relative_error()), 0.20) << r.table << ": ours " << r.ours_mean << ", thesis " << r.target_mean;
  }
}

TEST(RigCalibration, SpeedMeanIsWithinTwentyPercentOfTable51) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-speed.toml"));
  const auto res = st::unshaped_residuals(clearshape::rig::thesis_rig_truth(), p, 3, 11, 2);
  ASSERT_EQ(res.size(), 1u);
  EXPECT_LT(std::abs(res[0].relative_error()), 0.20) << res[0].ours_mean;
}

TEST(RigCalibration, SpeedDriveThroughTheChainIsEq42) {
  clearshape::lti::ProcessParameters thesis;
  thesis.kp = 25.47;
  thesis.tz = -0.0398;
  thesis.zeta = 0.2880;
  thesis.tw = 0.0479;
  thesis.tp3 = 0.0857;
  const clearshape::lti::ProcessModel eq42("P3UZ", thesis);
  const st::DriveChainFit fit = st::fit_drive_under_chain(eq42, 2.0, 1e-3, 300);
  EXPECT_LT(fit.relative_error, 0.03);  // RMS within 3 % of Kp over 2 s
  EXPECT_DOUBLE_EQ(fit.drive.parameters().kp, 25.47);
  // The drive is not the identified model itself: the filter's lag had to come out of it.
  EXPECT_GT(std::abs(fit.drive.parameters().tw - thesis.tw) + std::abs(fit.drive.parameters().zeta - thesis.zeta), 0.01);
}

TEST(RigCalibration, SearchImprovesOnAPerturbedStart) {
  const st::Protocol position = st::load_protocol(studies_path("thesis-position.toml"));
  const st::Protocol speed = st::load_protocol(studies_path("thesis-speed.toml"));
  clearshape::rig::RigTruth start = clearshape::rig::thesis_rig_truth();
  start.position_contact.stiffness *= 2.0;  // a mode √2 too high
  start.clearance_rad *= 3.0;
  st::RigCalibrationOptions options;
  options.trials = 2;
  options.max_evaluations = 10;
  options.variation_evaluations = 0;  // step 4 is tested below
  options.seed = 3;
  const auto start_res = st::unshaped_residuals(start, position, options.trials, options.seed, 2);
  double start_score = 0.0;
  for (const auto& r : start_res) start_score += std::pow(std::log(r.ours_mean / r.target_mean), 2);
  const st::RigCalibrationResult result = st::calibrate_rig(position, speed, start, options);
  EXPECT_LT(result.objective, start_score);
  EXPECT_EQ(result.evaluations, 10);
  EXPECT_EQ(result.residuals.size(), 6u);  // B.1–B.5 and Table 5.1
  // The speed drive came out of step 1, and the TOML names every calibrated section.
  const std::string toml = st::truth_to_toml(result.truth, "test", &result.speed_drive.drive);
  for (const char* section : {"[joint]", "[contact]", "[link]", "[gyroscope]", "[variation]", "[drive.speed]", "# test"}) {
    EXPECT_NE(toml.find(section), std::string::npos) << section;
  }
  EXPECT_NE(result.to_json().dump().find("relative_error"), std::string::npos);
  EXPECT_EQ(result.truth.variation.speed_gain_rel_sigma, start.variation.speed_gain_rel_sigma);  // kept
}

// Without variation the motor repeats exactly (Eq. 4.1 = 0 to rounding); with the built-in
// calibrated variation every mean Eq. 4.1 error of Tables 4.1–4.2 and every unshaped trials'
// spread (Tables 5.1, B.1–B.5) is within a factor 4 of the thesis's (the calibration's residuals,
// ×0.49…×3.1, are recorded in studies/sim-rig-truth.toml), on other seeds than the
// calibration's — except the two the modelled variation does not reach (Table 4.2's double step,
// ×0.06, and Table 5.1's spread, ×0.15), which must still be far above the exact repetition.
TEST(RigCalibration, DefaultRigReproducesTheThesisRepeatability) {
  const st::Protocol position = st::load_protocol(studies_path("thesis-position.toml"));
  const st::Protocol speed = st::load_protocol(studies_path("thesis-speed.toml"));
  clearshape::rig::RigTruth still = clearshape::rig::thesis_rig_truth();
  still.variation = clearshape::rig::RunVariation{};
  for (const auto& r : st::variation_residuals(still, position, speed, 3, 21, 2)) {
    if (r.quantity == "eq41_mean") {
      EXPECT_LT(r.ours, 1e-12) << r.table << " " << r.input;
    }
  }
  const auto res = st::variation_residuals(clearshape::rig::thesis_rig_truth(), position, speed, 10, 21, 2);
  int eq41 = 0, spreads = 0;
  for (const auto& r : res) {
    if (r.quantity == "md_mean") continue;
    (r.quantity == "eq41_mean" ? eq41 : spreads) += 1;
    const bool known_miss = (r.table == "4.2" && r.input == "double-step-16") || (r.table == "5.1" && r.quantity == "md_std");
    const double factor = known_miss ? 40.0 : 4.0;
    EXPECT_LT(std::abs(r.log_error()), std::log(factor))
        << r.table << " " << r.input << " " << r.quantity << ": ours " << r.ours << ", thesis " << r.target;
  }
  EXPECT_EQ(eq41, 6);     // Table 4.1: 4 inputs, Table 4.2: 2
  EXPECT_EQ(spreads, 6);  // Table 5.1, B.1–B.5
}

TEST(RigCalibration, VariationSearchImprovesOnAFarStart) {
  const st::Protocol position = st::load_protocol(studies_path("thesis-position.toml"));
  const st::Protocol speed = st::load_protocol(studies_path("thesis-speed.toml"));
  clearshape::rig::RigTruth start = clearshape::rig::thesis_rig_truth();
  start.variation.position_gain_rel_sigma = 0.02;  // far too much scatter everywhere
  start.variation.speed_gain_rel_sigma = 0.04;
  start.variation.start_latency_max_s = 1e-3;
  start.variation.analog_noise_v = 0.03;
  start.variation.analog_offset_sigma_v = 0.03;
  start.variation.flank_damping_rel_sigma = 0.9;
  st::VariationCalibrationOptions options;
  options.repetitions = 2;
  options.final_repetitions = 2;
  options.max_evaluations = 8;
  options.seed = 5;
  options.threads = 2;
  double start_score = 0.0;
  for (const auto& r : st::variation_residuals(start, position, speed, 2, 5, 2)) {
    if (r.target > 0.0) start_score += r.log_error() * r.log_error();
  }
  const st::VariationCalibrationResult result = st::calibrate_variation(position, speed, start, options);
  EXPECT_EQ(result.evaluations, 8);
  EXPECT_LT(result.objective, start_score);
  EXPECT_NO_THROW(result.variation.validate());
  EXPECT_NE(result.to_json().dump().find("eq41_mean"), std::string::npos);
}
