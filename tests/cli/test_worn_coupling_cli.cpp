// The worn-coupling rig from the command line (docs/worn-coupling.md, issue 19): `simulate --rig
// worn-coupling` and its quick study, whose clearance-aware design is scored from every start
// place and says when a case ends worse than unshaped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;

TEST(WornCouplingCli, SimulateSelectsTheTruthByName) {
  const auto r = run_cli("simulate --rig worn-coupling --signal step --amplitude 20 --start-s 0.5 --duration 2 "
                         "--no-noise --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rig"], "worn-coupling");
  EXPECT_NEAR(j["clearance_deg"].get<double>(), 1.0, 1e-12);
  EXPECT_GT(j["events"].get<int>(), 2);  // the link leaves its flank and crosses the play
}

TEST(WornCouplingCli, QuickStudyDesignsFromEveryStartPlace) {
  const auto out = clearshape::testing::process_temp_path("clearshape_cli_worn_coupling_study");
  std::filesystem::remove_all(out);
  const auto r = run_cli("study " + clearshape::testing::studies_path("worn-coupling-position.toml").string() +
                         " --quick --json --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto results = nlohmann::json::parse(std::ifstream(out / "results.json"));
  EXPECT_EQ(results["protocol"]["rig"], "worn-coupling");
  const auto& ca = results["sections"]["clearance_aware"];
  ASSERT_TRUE(ca.contains("cases")) << ca.dump();
  std::set<double> starts;
  std::set<std::string> inputs;
  for (const auto& c : ca["cases"]) {
    starts.insert(c["initial_play_fraction"].get<double>());
    inputs.insert(c["input"].get<std::string>());
    // The flag is the truth of the numbers it summarises.
    if (c["md_shaped_deg"].get<double>() > c["md_unshaped_deg"].get<double>()) {
      EXPECT_TRUE(ca["worse_than_unshaped"].get<bool>());
    }
  }
  EXPECT_EQ(starts, (std::set<double>{-1.0, -0.5, 0.0, 0.5, 1.0}));
  EXPECT_EQ(inputs.size(), 5u);  // every input of the rig tables, each its own profile
  EXPECT_LE(ca["duration_s"].get<double>(), ca["max_duration_s"].get<double>() + 1e-12);
  EXPECT_EQ(ca["worse_than_unshaped"].get<bool>(), ca["worst_ratio"].get<double>() > 1.0);
  // `shape --model results.json` designs on the same uncertainty set as the study's stage: the
  // same model points (play, K, Coulomb and damping factors) from the same start places.
  const auto shape = run_cli("shape --method clearance-aware --model " + (out / "results.json").string() +
                             " --moves 10 --max-evaluations 10 --json");
  ASSERT_EQ(shape.exit_code, 0) << shape.err;
  const auto design = nlohmann::json::parse(shape.out);
  const auto points = [](const nlohmann::json& cases, const nlohmann::json& move) {
    std::set<std::vector<double>> p;
    for (const auto& c : cases) {
      if (!move.is_null() && c.at("input") != move) continue;
      p.insert({c["play_factor"].get<double>(), c["stiffness_factor"].get<double>(), c["coulomb_factor"].get<double>(),
                c["damping_factor"].get<double>(), c["initial_play_fraction"].get<double>()});
    }
    return p;
  };
  EXPECT_EQ(points(design["cases"], nullptr), points(ca["cases"], "step-10"));
  EXPECT_GT(points(design["cases"], nullptr).size(), 5u);  // the quick fit's Coulomb 1σ is over 2 %: corners
  std::filesystem::remove_all(out);
}
