// `clearshape calibrate-rig` and the rig TOML's [variation] section (rig/config.hpp).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {
fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() / ("clearshape_calibrate_rig_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}
fs::path studies(const std::string& name) {
  return clearshape::testing::golden_path("").parent_path().parent_path().parent_path() / "studies" / name;
}
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

// The committed calibration (with its [variation] table) is a valid rig file.
TEST(CalibrateRigCli, CommittedTruthFileLoads) {
  const std::string text = slurp(studies("sim-rig-truth.toml"));
  EXPECT_NE(text.find("[variation]"), std::string::npos);
  const auto r = run_cli("simulate --mode speed --signal step --duration 0.2 --json --config " +
                         studies("sim-rig-truth.toml").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(CalibrateRigCli, VariationKeysAreValidatedWithFileLineAndKey) {
  const fs::path toml = temp_dir() / "variation.toml";
  std::ofstream(toml) << "[variation]\nspeed_gain_rel_sigma = 0.01\nanalog_noise_v = 0.5\n";
  auto r = run_cli("simulate --config " + toml.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("variation.analog_noise_v"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("0.5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(":3"), std::string::npos) << r.err;  // the line
  std::ofstream(toml) << "[variation]\nflank_damping_sigma = 0.1\n";
  r = run_cli("simulate --config " + toml.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("flank_damping_rel_sigma"), std::string::npos) << r.err;  // lists the allowed keys
  std::ofstream(toml) << "[variation]\nstart_latency_max_s = 2e-4\nflank_damping_rel_sigma = 0.1\n";
  r = run_cli("simulate --duration 0.2 --json --config " + toml.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  fs::remove_all(toml.parent_path());
}

// --variation-only keeps the built-in joint and writes a loadable rig file with the fitted
// variation; one evaluation keeps it quick.
TEST(CalibrateRigCli, VariationOnlyWritesALoadableRigFile) {
  const fs::path dir = temp_dir() / "out";
  const auto r = run_cli("calibrate-rig --variation-only --variation-evaluations 1 --out " + dir.string() +
                         " --position " + studies("thesis-position.toml").string() + " --speed " +
                         studies("thesis-speed.toml").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("eq41_mean"), std::string::npos) << r.out;
  const std::string text = slurp(dir / "rig-truth.toml");
  EXPECT_NE(text.find("--variation-only"), std::string::npos);
  EXPECT_NE(text.find("[variation]"), std::string::npos);
  EXPECT_NE(text.find("clearance_deg = 0.032007"), std::string::npos);  // the built-in joint, kept
  EXPECT_EQ(run_cli("simulate --duration 0.2 --json --config " + (dir / "rig-truth.toml").string()).exit_code, 0);
  EXPECT_EQ(run_cli("calibrate-rig --variation-evaluations -1").exit_code, 2);
  fs::remove_all(dir.parent_path());
}
