// The C-header export per axis (arm/shaper_export.hpp): each joint's header holds the taps of a
// ZVD at that joint's mode, checked against the closed form (Singer & Seering 1990: amplitudes
// 1, 2K, K² over (1 + K)² at 0, Td/2, Td, K = exp(−ζπ/√(1−ζ²))) discretised here by first-order
// hold (an impulse at (m + f)·Ts split as (1 − f) at m and f at m + 1).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>

#include "clearshape/arm/shaper_export.hpp"
#include "clearshape/core/error.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

std::vector<double> define_list(const std::string& text, const std::string& name) {
  const std::regex re("#define " + name + " \\{ ([^}]*) \\}");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return {};
  std::vector<double> out;
  std::stringstream ss(std::regex_replace(m[1].str(), std::regex("u"), ""));
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stod(item));
  return out;
}

std::map<long, double> zvd_taps(const shaping::Mode& mode, double ts) {
  const double z = mode.damping_ratio, wd = mode.natural_frequency_rad_s * std::sqrt(1 - z * z);
  const double k = std::exp(-z * std::numbers::pi / std::sqrt(1 - z * z)), td = 2 * std::numbers::pi / wd;
  const double amp[3] = {1 / ((1 + k) * (1 + k)), 2 * k / ((1 + k) * (1 + k)), k * k / ((1 + k) * (1 + k))};
  std::map<long, double> taps;
  for (int j = 0; j < 3; ++j) {
    const double x = j * td / 2 / ts;
    const long m = static_cast<long>(std::floor(x));
    taps[m] += amp[j] * (1 - (x - m));
    if (x > m) taps[m + 1] += amp[j] * (x - m);
  }
  return taps;
}

TEST(ArmShaperExport, EachJointHeaderHoldsItsZvdTaps) {
  const ArmModel arm = builtin_arm("scara-2");
  const auto files = joint_shaper_headers(arm, Eigen::Vector2d(1.0, 1.0),
                                          {.schedule = ShaperSchedule::fixed, .method = shaping::Method::zvd}, 1e-3);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].file_name, "cs_shoulder.h");
  EXPECT_EQ(files[1].c_name, "cs_elbow");
  const ArmModes centre = joint_modes(arm, Eigen::Vector2d(0.0, 0.0));  // fixed: the workspace centre
  for (int i = 0; i < 2; ++i) {
    const std::string upper = i == 0 ? "CS_SHOULDER" : "CS_ELBOW";
    const std::vector<double> delays = define_list(files[i].text, upper + "_DELAYS");
    const std::vector<double> weights = define_list(files[i].text, upper + "_TAPS_DOUBLE");
    const std::map<long, double> expected = zvd_taps(centre.joint_mode(i), 1e-3);
    ASSERT_EQ(delays.size(), expected.size()) << files[i].text.substr(0, 600);
    ASSERT_EQ(weights.size(), expected.size());
    std::size_t j = 0;
    for (const auto& [delay, weight] : expected) {
      EXPECT_EQ(delays[j], static_cast<double>(delay));
      EXPECT_NEAR(weights[j], weight, 1e-12);
      ++j;
    }
    EXPECT_NE(files[i].text.find("fixed shapers (zvd) at q = (0, 0) rad"), std::string::npos);
  }
  const auto dir = testing::fresh_temp_dir("arm_shaper_export");
  write_joint_shaper_headers(dir, files);
  EXPECT_TRUE(std::filesystem::exists(dir / "cs_shoulder.h") && std::filesystem::exists(dir / "cs_elbow.h"));
}

TEST(ArmShaperExport, BothModesAndRefusals) {
  const ArmModel arm = builtin_arm("scara-2");
  const auto both = joint_shaper_headers(arm, Eigen::Vector2d(1.2, 0.6),
                                         {.schedule = ShaperSchedule::end_pose, .every_mode = true}, 1e-3, "arm");
  EXPECT_NE(both[0].text.find("second mode"), std::string::npos);
  EXPECT_EQ(both[0].c_name, "arm_shoulder");
  EXPECT_THROW(joint_shaper_headers(arm, Eigen::Vector2d(0, 0), {.schedule = ShaperSchedule::none}, 1e-3),
               InvalidArgument);
  EXPECT_THROW(joint_shaper_headers(arm, Eigen::Vector2d(0, 0), {}, 1e-3, "9x"), InvalidArgument);
}

// Given shapers (the clearance-aware design's kind: impulses between samples): each joint's header
// holds its own shaper's taps by the first-order hold split of the header comment above.
TEST(ArmShaperExport, GivenShapersGiveTheirFirstOrderHoldTaps) {
  const ArmModel arm = builtin_arm("scara-2");
  const std::vector<shaping::Shaper> shapers{shaping::Shaper("a", {{0.0, 0.25}, {0.0125, 0.75}}),
                                             shaping::Shaper("b", {{0.0, 0.5}, {0.002, 0.5}})};
  const auto files = joint_shaper_headers(arm, shapers, 5e-3, "cs", "a test");
  ASSERT_EQ(files.size(), 2u);
  // 0.0125 s = 2.5 samples: 0.75 split half and half between delays 2 and 3
  EXPECT_EQ(define_list(files[0].text, "CS_SHOULDER_DELAYS"), (std::vector<double>{0, 2, 3}));
  const std::vector<double> w = define_list(files[0].text, "CS_SHOULDER_TAPS_DOUBLE");
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w[0], 0.25, 1e-15);
  EXPECT_NEAR(w[1], 0.375, 1e-15);
  EXPECT_NEAR(w[2], 0.375, 1e-15);
  // 0.002 s = 0.4 samples: 0.5·0.6 joins the first impulse at 0, 0.5·0.4 goes to delay 1
  const std::vector<double> elbow = define_list(files[1].text, "CS_ELBOW_TAPS_DOUBLE");
  ASSERT_EQ(elbow.size(), 2u);
  EXPECT_NEAR(elbow[0], 0.8, 1e-15);
  EXPECT_NEAR(elbow[1], 0.2, 1e-15);
  EXPECT_NE(files[1].text.find("a test"), std::string::npos);
  EXPECT_THROW(joint_shaper_headers(arm, std::span(shapers).first(1), 5e-3, "cs", "x"), InvalidArgument);
}

}  // namespace
}  // namespace clearshape::arm
