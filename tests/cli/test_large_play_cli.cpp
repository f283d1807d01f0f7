// The large-play rig from the command line (docs/large-play.md): `simulate --rig large-play`,
// `study --rig NAME` and the protocol's `[study] rig`, with their errors (exit 2, naming the
// option or the file's key and the allowed names).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;

namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

std::filesystem::path studies() {
  return clearshape::testing::golden_path("").parent_path().parent_path().parent_path() / "studies";
}

}  // namespace

TEST(LargePlayCli, SimulateSelectsTheTruthByName) {
  const auto r = run_cli("simulate --rig large-play --signal step --amplitude 20 --start-s 0.5 --rise-s 0.0333333 "
                         "--duration 2 --no-noise --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rig"], "large-play");
  EXPECT_NEAR(j["clearance_deg"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(j["contact"]["model"], "flores");
  EXPECT_NEAR(j["contact"]["stiffness_n_m_per_rad_pow_n"].get<double>(), 1.0167e6, 1e2);
  EXPECT_GT(j["events"].get<int>(), 4);  // the link crosses the play and bounces
  // Flags still override the built-in truth.
  const auto wide = run_cli("simulate --rig large-play --clearance-deg 2 --duration 1 --no-noise --json");
  ASSERT_EQ(wide.exit_code, 0) << wide.err;
  EXPECT_NEAR(nlohmann::json::parse(wide.out)["clearance_deg"].get<double>(), 2.0, 1e-12);

  const auto bad = run_cli("simulate --rig big-play");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--rig"), std::string::npos) << bad.err;
}

TEST(LargePlayCli, QuickStudyRunsOnTheProtocolsRig) {
  const auto out = temp("clearshape_cli_large_play_study");
  std::filesystem::remove_all(out);
  const auto r = run_cli("study " + (studies() / "large-play-position.toml").string() + " --quick --json --out " +
                         out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto results = nlohmann::json::parse(std::ifstream(out / "results.json"));
  EXPECT_EQ(results["rig"]["kind"], "simulated-large-play");
  EXPECT_NE(results["rig"]["description"].get<std::string>().find("large-play"), std::string::npos);
  EXPECT_EQ(results["protocol"]["rig"], "large-play");
  // The clearance fit finds a play of the order of the truth's 1° (the thesis rig's is 0.03°).
  const double play = results["sections"]["clearance"]["play_deg"].get<double>();
  EXPECT_GT(play, 0.3);
  EXPECT_LT(play, 2.0);
  std::filesystem::remove_all(out);
}

TEST(LargePlayCli, UnknownRigNamesAreErrors) {
  const auto r = run_cli("study " + (studies() / "large-play-position.toml").string() + " --quick --rig bigplay");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("thesis, large-play"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("serial:PORT"), std::string::npos) << r.err;

  const auto dir = temp("clearshape_cli_large_play_bad");
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir / "bad.toml");
    f << "format = \"clearshape-study-protocol/1\"\n[study]\nname = \"bad\"\nmode = \"position\"\nrig = \"moon\"\n";
  }
  const auto p = run_cli("study " + (dir / "bad.toml").string());
  EXPECT_EQ(p.exit_code, 2);
  EXPECT_NE(p.err.find("bad.toml"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("rig"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("large-play"), std::string::npos) << p.err;
  std::filesystem::remove_all(dir);
}
