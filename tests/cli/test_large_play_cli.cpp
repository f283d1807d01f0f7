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

std::filesystem::path temp(const std::string& name) { return clearshape::testing::process_temp_path(name); }
std::filesystem::path studies() { return clearshape::testing::studies_path(""); }

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

  // Custom impulses (what `shape --method clearance-aware` designs): two halves 1/30 s apart
  // shape the command exactly as the same shaper given to `shape`.
  const auto custom = run_cli("simulate --rig large-play --duration 1 --no-noise --shaper custom "
                              "--shaper-impulses \"0:0.5,0.0333333333333:0.5\" --json");
  ASSERT_EQ(custom.exit_code, 0) << custom.err;
  EXPECT_EQ(nlohmann::json::parse(custom.out)["shaper"], "custom");
  EXPECT_EQ(run_cli("simulate --shaper custom").exit_code, 2);
  EXPECT_EQ(run_cli("simulate --shaper-impulses \"0:1\"").exit_code, 2);

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
  // "What a command can reach": the best design of each input is a design, never a column whose
  // design came out as the identity (the large-play fit keeps the pass-through clearance-aware
  // shaper and designs no take-up: those columns ran the unshaped command).
  for (const auto& table : results["tables"]) {
    if (table["id"] != "reach") continue;
    for (const auto& [id, headline] : table["headline"].items()) {
      SCOPED_TRACE(id);
      for (const auto& rig_table : results["tables"]) {
        if (rig_table["id"] != id) continue;
        for (const auto& col : rig_table["columns"]) {
          if (col["key"] != headline["best_column"]) continue;
          EXPECT_FALSE(col.value("note", std::string()).rfind("identity shaper", 0) == 0) << col.dump();
          ASSERT_TRUE(col.contains("shaper")) << col.dump();
          EXPECT_GT(col["shaper"]["impulses"].size(), 1u) << col.dump();
        }
      }
    }
  }
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

TEST(LargePlayCli, ShapeClearanceAwareFromAFitClearanceDocument) {
  const auto dir = temp("clearshape_cli_clearance_aware");
  std::filesystem::create_directories(dir);
  {
    // What `fit-clearance --json` writes (parameters, drive, link inertia, mode).
    std::ofstream f(dir / "fit.json");
    f << R"({"command": "fit-clearance", "mode": "position", "link_inertia_kg_m2": 0.005,
      "parameters": {"stiffness": {"value": 1e5}, "damping": {"value": 2.0}, "play": {"value": 1.0},
                     "exponent": {"value": 1.5}},
      "drive": {"model": "P3UZ", "parameters": {"Kp": {"value": 0.9959}, "Tz": {"value": 0.0042},
                "Zeta": {"value": 0.9968}, "Tw": {"value": 0.0102}, "Tp3": {"value": 0.0034}}}})";
  }
  const auto r = run_cli("shape --method clearance-aware --model " + (dir / "fit.json").string() +
                         " --moves 10 --max-duration-s 0.07 --max-evaluations 10 --threads 1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "clearance-aware");
  EXPECT_LE(j["duration_s"].get<double>(), 0.07);
  EXPECT_TRUE(j["positive"].get<bool>());
  EXPECT_EQ(j["cases"].size(), 5u);  // one move × five start places in the play
  EXPECT_LE(j["worst_md_deg"].get<double>(), j["worst_unshaped_md_deg"].get<double>() * 1.1 + 1e-9);
  // The impulses as `shape --method custom --impulses` takes them.
  const auto custom = run_cli("shape --method custom --impulses \"" + j["custom_impulses"].get<std::string>() + "\" --json");
  ASSERT_EQ(custom.exit_code, 0) << custom.err;
  EXPECT_EQ(nlohmann::json::parse(custom.out)["impulses"].size(), j["impulses"].size());

  const auto missing = run_cli("shape --method clearance-aware --moves 10 --max-duration-s 0.1");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--model"), std::string::npos) << missing.err;
  const auto stray = run_cli("shape --method zvd -f 3 -z 0.1 --moves 10");
  EXPECT_EQ(stray.exit_code, 2);
  std::filesystem::remove_all(dir);
}

// The clearance-aware design prints impulses; --export and --input with it are refused, never
// silently ignored (before any model is read).
TEST(LargePlayCli, ClearanceAwareWithExportOrInputIsRefused) {
  for (const std::string extra : {" --export json --sample-time 0.001", " --input run.csv"}) {
    const auto r = run_cli("shape --method clearance-aware --model missing.json --moves 5" + extra);
    EXPECT_EQ(r.exit_code, 2) << extra;
    EXPECT_NE(r.err.find("--method custom --impulses"), std::string::npos) << r.err;
  }
}
