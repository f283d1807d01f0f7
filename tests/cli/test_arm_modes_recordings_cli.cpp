// clearshape arm modes --recordings: the simulated loaded-ramp runs (scara-2, 0.5° play, 3×3
// grid) written by --identify --write-recordings and identified from the files give the --identify
// map row for row, with the first mode within 0.5 % of the linearised one (joint_modes, checked
// against SciPy's eigh in tests/arm); a step played by `arm simulate -o` (its columns are a
// recording's) listed by hand gives the linearised modes; the options --recordings excludes, and a
// bad manifest → exit 2 naming the file, the line and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

nlohmann::json modes_of(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in)["modes"];
}

TEST(ArmModesRecordingsCli, RecordedRunsGiveTheIdentifiedMap) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_modes_recordings_cli");
  const auto sim = run_cli("arm modes --identify --grid 3 --excitation loaded-ramp --write-recordings " +
                           (dir / "rec").string() + " -o " + (dir / "sim.json").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_NE(sim.err.find("wrote the runs as recordings"), std::string::npos) << sim.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "rec" / "pose09-loaded-ramp.csv"));
  const auto rec = run_cli("arm modes --recordings " + (dir / "rec" / "manifest.toml").string() + " -o " +
                           (dir / "rec.json").string());
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  const auto a = modes_of(dir / "sim.json"), b = modes_of(dir / "rec.json");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 9u);
  for (std::size_t r = 0; r < a.size(); ++r) {
    EXPECT_EQ(a[r], b[r]) << "row " << r;  // the same samples: the same numbers
    if (b[r]["linear_mode"] == 0) {
      EXPECT_NEAR(b[r]["frequency_hz"].get<double>() / b[r]["linear_frequency_hz"].get<double>(), 1.0, 0.005) << b[r];
    }
  }
}

// No play: a 1° step of the shoulder to (0.0175, 1.2) rad rings at the linearised modes (17.921 and
// 46.232 Hz); measured +0.000 % and −0.02 % from the window 0.2 s to the end.
TEST(ArmModesRecordingsCli, ASimulatedRunIsARecording) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_modes_recordings_cli_simulate");
  const auto sim = run_cli("arm simulate --play-deg 0 --from 0,1.2 --to 0.0175,1.2 --velocity 2 --acceleration 40 "
                           "--jerk 4000 --settle-s 0.75 -o " + (dir / "step.csv").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  std::ofstream(dir / "step.toml") << "format = \"clearshape-arm-recordings-1\"\n[[run]]\nfile = \"step.csv\"\n"
                                      "pose_rad = [0.0175, 1.2]\nexcitation = \"step\"\njoint = \"shoulder\"\n"
                                      "window_start_s = 0.2\n";
  const auto r = run_cli("arm modes --play-deg 0 --recordings " + (dir / "step.toml").string() + " -o " +
                         (dir / "map.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto modes = modes_of(dir / "map.json");
  ASSERT_EQ(modes.size(), 2u) << modes;
  for (const auto& m : modes) {
    EXPECT_NEAR(m["frequency_hz"].get<double>() / m["linear_frequency_hz"].get<double>(), 1.0, 0.001) << m;
  }
  EXPECT_EQ(modes[1]["linear_mode"], 1);
}

TEST(ArmModesRecordingsCli, RefusesWhatDoesNotApply) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_modes_recordings_cli_bad");
  auto r = run_cli("arm modes --recordings m.toml --grid 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--grid excludes --recordings"), std::string::npos) << r.err;
  r = run_cli("arm modes --recordings m.toml --identify");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("arm modes --write-recordings " + (dir / "w").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--write-recordings requires --identify"), std::string::npos) << r.err;
  r = run_cli("arm modes --recordings " + (dir / "none.toml").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cannot read the arm recordings manifest"), std::string::npos) << r.err;
  std::ofstream(dir / "m.toml") << "format = \"clearshape-arm-recordings-1\"\n\n[[run]]\nfile = \"m.toml\"\n"
                                   "pose_rad = [0.5]\nexcitation = \"loaded-ramp\"\n";
  r = run_cli("arm modes --recordings " + (dir / "m.toml").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("m.toml:5: field 'run[0].pose_rad': has 1 angles; allowed: 2"), std::string::npos) << r.err;
}

}  // namespace
