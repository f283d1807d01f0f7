// Guards the calibration of the simulated rig (DESIGN.md §2): the default rig's unshaped
// responses reproduce the thesis's "without is" means (Tables B.1–B.5) within the stated
// tolerance, and the truth's speed drive seen through the §3.3 chain is the thesis's Eq. 4.2.
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/study/calibrated_truth.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/rig_calibration.hpp"
#include "study_paths.hpp"

namespace st = clearshape::study;
using clearshape::testing::studies_path;

TEST(RigCalibration, DefaultRigReproducesTheUnshapedMeansOfTablesB1ToB5) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-position.toml"));
  const auto res = st::unshaped_residuals(st::calibrated_thesis_rig_truth(), p, 4, 11, 2);
  ASSERT_EQ(res.size(), 5u);
  for (const auto& r : res) {
    // Tolerance: 20 % of the thesis's mean (the calibration's residuals are 2–14 %).
    EXPECT_LT(std::abs(r.relative_error()), 0.20) << r.table << ": ours " << r.ours_mean << ", thesis " << r.target_mean;
  }
}

TEST(RigCalibration, SpeedMeanIsWithinTwentyPercentOfTable51) {
  const st::Protocol p = st::load_protocol(studies_path("thesis-speed.toml"));
  const auto res = st::unshaped_residuals(st::calibrated_thesis_rig_truth(), p, 3, 11, 2);
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
  clearshape::rig::RigTruth start = st::calibrated_thesis_rig_truth();
  start.position_contact.stiffness *= 2.0;  // a mode √2 too high
  start.clearance_rad *= 3.0;
  st::RigCalibrationOptions options;
  options.trials = 2;
  options.max_evaluations = 10;
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
  for (const char* section : {"[joint]", "[contact]", "[link]", "[gyroscope]", "[drive.speed]", "# test"}) {
    EXPECT_NE(toml.find(section), std::string::npos) << section;
  }
  EXPECT_NE(result.to_json().dump().find("relative_error"), std::string::npos);
}
