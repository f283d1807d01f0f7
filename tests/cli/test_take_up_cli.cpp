// `clearshape shape --method take-up` (study/take_up.hpp): from a fit-clearance document, one
// profile per move within ZVDD's delay on the 30 Hz grid, printed as impulses that
// `shape --method custom` accepts; the options it shares with clearance-aware and the ones it
// refuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;

TEST(TakeUpCli, ProfilesPerMoveFromAFitClearanceDocument) {
  const auto dir = clearshape::testing::fresh_temp_dir("clearshape_cli_take_up");
  {
    // What `fit-clearance --json` writes, with the joint's Coulomb friction (2e-3 N·m).
    std::ofstream f(dir / "fit.json");
    f << R"({"command": "fit-clearance", "mode": "position", "link_inertia_kg_m2": 0.005,
      "parameters": {"stiffness": {"value": 1e5}, "damping": {"value": 2.0}, "play": {"value": 1.0},
                     "exponent": {"value": 1.5}, "coulomb": {"value": 0.002}},
      "drive": {"model": "P3UZ", "parameters": {"Kp": {"value": 0.9959}, "Tz": {"value": 0.0042},
                "Zeta": {"value": 0.9968}, "Tw": {"value": 0.0102}, "Tp3": {"value": 0.0034}}}})";
  }
  const std::string model = " --model " + (dir / "fit.json").string();
  // ZVDD of 17.8 Hz, ζ 0.43 lasts 0.093 s: three updates on the 30 Hz grid, so four slots.
  const auto r = run_cli("shape --method take-up" + model + " --moves 10,20 -f 17.8 -z 0.43 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "take-up");
  EXPECT_NEAR(j["max_duration_s"].get<double>(), 0.1, 1e-12);
  EXPECT_NEAR(j["flank_keeping_deceleration_rad_s2"].get<double>(), 0.4, 1e-12);
  ASSERT_EQ(j["moves"].size(), 2u);
  for (const auto& m : j["moves"]) {
    EXPECT_EQ(m["slot_velocity_deg_s"].size(), 4u);
    EXPECT_NEAR(m["take_up_deg"].get<double>(), 1.0, 1e-3);
    const auto custom = run_cli("shape --method custom --impulses \"" + m["custom_impulses"].get<std::string>() + "\" --json");
    ASSERT_EQ(custom.exit_code, 0) << custom.err;
    EXPECT_EQ(nlohmann::json::parse(custom.out)["impulses"].size(), m["impulses"].size());
  }
  // With a bound of two updates: carry, dip, recover only.
  const auto short_bound = run_cli("shape --method take-up" + model + " --moves 10 --max-duration-s 0.07 --json");
  ASSERT_EQ(short_bound.exit_code, 0) << short_bound.err;
  EXPECT_EQ(nlohmann::json::parse(short_bound.out)["moves"][0]["slot_velocity_deg_s"].size(), 3u);

  const auto no_search = run_cli("shape --method take-up" + model + " --moves 10 --max-duration-s 0.1 --threads 2");
  EXPECT_EQ(no_search.exit_code, 2);
  EXPECT_NE(no_search.err.find("--threads"), std::string::npos) << no_search.err;
  const auto too_short = run_cli("shape --method take-up" + model + " --moves 1 --max-duration-s 0.1");
  EXPECT_EQ(too_short.exit_code, 2);
  EXPECT_NE(too_short.err.find("shortest move"), std::string::npos) << too_short.err;
  const auto missing = run_cli("shape --method take-up --moves 10 --max-duration-s 0.1");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--model"), std::string::npos) << missing.err;
  const auto exported = run_cli("shape --method take-up" + model + " --moves 10 --export json --sample-time 0.001");
  EXPECT_EQ(exported.exit_code, 2);
  EXPECT_NE(exported.err.find("--method custom --impulses"), std::string::npos) << exported.err;
  std::filesystem::remove_all(dir);
}
