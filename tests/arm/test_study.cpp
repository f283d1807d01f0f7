// The arm study (arm/study.hpp): the study TOML's refusals name the file, the key and the allowed
// values; a quick study's results.json is consistent with itself (each design's Σ and improvement
// recomputed from its per-move rows, Eq. 5.1 as 1 − Σ shaped / Σ unshaped), its mode map is the
// SciPy golden's (tests/golden/gen_arm_modes.py: closed-form M(q), scipy.linalg.eigh) at every grid
// pose, the arm is drawn with the URDF's link lengths, and the result does not depend on the
// number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "clearshape/arm/study.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace arm = clearshape::arm;

namespace {

const std::string kValid = R"([study]
arm = "scara-2"
play_deg = 0.5
[benchmark]
moves = 20
velocity_rad_s = [2.0, 3.0]
acceleration_rad_s2 = [20.0, 30.0]
jerk_rad_s3 = [400.0, 600.0]
[designs]
run = ["fixed", "clearance-aware"]
evaluations = 10
threads = 2
[map]
points = 3
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// The message of the InputError that parsing `text` throws ("" if none).
std::string refusal(const std::string& text) {
  try {
    (void)arm::parse_arm_study(text, "studies/bad.toml");
  } catch (const clearshape::InputError& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const std::string& text, const std::string& key, const std::string& allowed) {
  const std::string m = refusal(text);
  EXPECT_NE(m.find("studies/bad.toml"), std::string::npos) << m;
  EXPECT_NE(m.find(key), std::string::npos) << m;
  EXPECT_NE(m.find(allowed), std::string::npos) << m;
}

}  // namespace

TEST(ArmStudy, ReadsTheShippedStudies) {
  for (const char* name : {"arm-scara2.toml", "arm-vertical2.toml"}) {
    const arm::ArmStudySpec s = arm::read_arm_study(clearshape::testing::studies_path(name));
    EXPECT_GE(s.moves, 20u) << name;
    EXPECT_GE(s.designs.size(), 3u) << name;
    ASSERT_EQ(s.play_deg.size(), 1u) << name;
    EXPECT_EQ(s.play_deg[0], 0.5) << name;
    const arm::ArmModel a = arm::study_arm(s);
    for (const auto& j : a.joints) EXPECT_NEAR(j.half_play_rad, 0.25 * M_PI / 180.0, 1e-15) << name;
  }
}

TEST(ArmStudy, RefusesBadInputNamingTheKeyAndTheAllowedValues) {
  expect_refused("[benchmark]\nmoves = 20\n", "study", "a [study] table");
  expect_refused(replaced(kValid, "\"scara-2\"", "\"delta-3\""), "study.arm", "scara-2, vertical-2");
  expect_refused(replaced(kValid, "moves = 20", "moves = 5"), "benchmark.moves", "20 … 1000");
  expect_refused(replaced(kValid, "play_deg = 0.5", "play_deg = 12"), "study.play_deg", "0 … 10");
  expect_refused(replaced(kValid, "[400.0, 600.0]", "[400.0, 0.0]"), "benchmark.jerk_rad_s3", "> 0");
  expect_refused(replaced(kValid, "[400.0, 600.0]", "[400.0]"), "benchmark.velocity_rad_s", "the same count");
  expect_refused(replaced(kValid, "\"fixed\"", "\"optimal\""), "designs.run", "fixed, scheduled, clearance-aware");
  expect_refused(replaced(kValid, "threads = 2", "threads = 2\nflank_margin = 0"), "designs.flank_margin",
                 "0 < flank_margin <= 1");
  expect_refused(replaced(kValid, "threads = 2", "threads = 2\nflank_floor = 1.5"), "designs.flank_floor",
                 "0 < flank_floor <= 1");
  EXPECT_EQ(refusal(replaced(kValid, "\"fixed\"", "\"flank-scheduled\", \"flank-unshaped\"")), "");
  expect_refused(replaced(kValid, "evaluations = 10", "evaluations = 5"), "designs.evaluations", "10 … 100000");
  expect_refused(replaced(kValid, "points = 3", "points = 1"), "map.points", "2 … 101");
  expect_refused(replaced(kValid, "threads = 2", "threads = 2\nspeed = 3"), "designs.speed", "threads");
  expect_refused(replaced(kValid, "arm = \"scara-2\"", "arm = \"scara-2\"\nurdf = \"a.urdf\""), "study.arm",
                 "not both");
  // One play per joint of a two-joint arm, given three: refused when the arm is known, naming the file.
  const arm::ArmStudySpec three = arm::parse_arm_study(replaced(kValid, "0.5", "[0.5, 0.5, 0.5]"), "studies/bad.toml");
  try {
    (void)arm::study_arm(three);
    ADD_FAILURE() << "three plays for two joints accepted";
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("studies/bad.toml: study.play_deg has 3 values"), std::string::npos) << e.what();
  }
}

TEST(ArmStudy, QuickStudyIsConsistentAndItsMapIsTheGoldens) {
  arm::ArmStudySpec spec = arm::parse_arm_study(kValid, "quick.toml");
  arm::make_quick(spec);
  spec.moves = 2;
  const arm::ArmModel a = arm::study_arm(spec);
  const arm::ArmStudyResult r = arm::run_arm_study(spec, a);
  const auto doc = arm::arm_study_json(spec, a, r);
  ASSERT_EQ(doc["designs"].size(), 3u);
  ASSERT_EQ(doc["moves"].size(), 2u);
  std::vector<double> sums(3, 0.0);
  for (const auto& m : doc["moves"]) {
    for (std::size_t d = 0; d < 3; ++d) {
      sums[d] += m["designs"][doc["designs"][d]["name"].get<std::string>()]["residual_mm"].get<double>();
    }
  }
  EXPECT_GT(sums[0], 0.0);
  for (std::size_t d = 0; d < 3; ++d) {
    const auto& row = doc["designs"][d];
    EXPECT_NEAR(row["total_residual_mm"].get<double>(), sums[d], 1e-12 * sums[0]);
    EXPECT_NEAR(row["improvement"].get<double>(), 1.0 - sums[d] / sums[0], 1e-12);
    EXPECT_EQ(row["worse_than_unshaped"].get<bool>(), sums[d] > sums[0]);
  }
  // The map: 3 × 3 poses over ±2.6 rad, each the golden's modes at its elbow angle (scara-2's modes
  // do not depend on the shoulder angle: M depends on q2 only).
  const auto golden = clearshape::io::read_table(clearshape::testing::golden_path("arm_scara_modes.csv"));
  ASSERT_EQ(doc["mode_map"]["poses"].size(), 9u);
  for (const auto& p : doc["mode_map"]["poses"]) {
    const double q2 = p["pose_rad"][1].get<double>();
    std::size_t row = golden.rows();
    for (std::size_t k = 0; k < golden.rows(); ++k) row = std::abs(golden.column("q2_rad")[k] - q2) < 1e-12 ? k : row;
    ASSERT_LT(row, golden.rows()) << "no golden row at q2 = " << q2;
    EXPECT_NEAR(p["natural_frequency_hz"][0].get<double>() / golden.column("f1_hz")[row], 1.0, 1e-9);
    EXPECT_NEAR(p["natural_frequency_hz"][1].get<double>() / golden.column("f2_hz")[row], 1.0, 1e-9);
  }
  // The drawing at the centre (0, 0): base, shoulder, elbow 0.25 m out, tool 0.45 m out (docs/arm.md §3).
  const auto& pts = doc["drawing"]["points_m"];
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_NEAR(pts[2][0].get<double>() - pts[1][0].get<double>(), 0.25, 1e-12);
  EXPECT_NEAR(pts[3][0].get<double>() - pts[1][0].get<double>(), 0.45, 1e-12);
  EXPECT_NEAR(std::hypot(pts[3][0].get<double>(), pts[3][1].get<double>()), 0.45, 1e-12);
  // One thread gives the same document, bit for bit.
  spec.threads = 1;
  EXPECT_EQ(arm::arm_study_json(spec, a, arm::run_arm_study(spec, a)).dump(), doc.dump());
}
