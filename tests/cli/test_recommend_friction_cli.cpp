// The joint friction of the identified nonlinear model (study::ClearanceModel: Coulomb c and
// viscous b on the link–motor relative rate, thesis Eq. 2.9 regularized) as the CLI reads it:
//  - `recommend --model FIT.json` with friction predicts the unshaped Eq. 5.1 MD that
//    `clearshape simulate` gives for a rig configuration with the same drive, play, contact law
//    and joint friction (the rig's own plant and pulse path: another code path);
//  - `--clearance-aware` adds the shaper designed on that model for the move, positive and within
//    its bound, whose predicted MD is what `simulate --shaper custom` gives on the rig's path (to a
//    fraction of the pulse step);
//  - a document written before friction was fitted (no coulomb/viscous keys) still reads, as
//    friction 0; a negative friction is exit 2 naming the file and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"
#include "support/recommend_model.hpp"

using namespace clearshape::testing;  // run_cli and the recommend --model fixtures

namespace {

std::filesystem::path temp(const std::string& name) { return pid_temp_file("recommend_friction_cli", name); }

// A `fit-clearance --json` document of a 1° play with a Hertz-like flank; `friction` is the text of
// the coulomb/viscous entries (with a leading comma) or "".
std::string fit_json(const std::string& friction) {
  return R"({"command": "fit-clearance", "mode": "position", "link_inertia_kg_m2": 0.005,
 "parameters": {"stiffness": {"value": 2.0e5}, "damping": {"value": 2.0},
                "play": {"value": 1.0}, "exponent": {"value": 1.5})" +
         friction + R"(}, "drive": )" + kThesisDriveJson + "}";
}

double simulated(double coulomb, double viscous, const std::string& move, const std::string& shaper = "") {
  const auto config = temp("model.toml");
  write_text(config, "[joint]\nclearance_deg = 1.0\nfriction_viscous_n_m_s_per_rad = " + std::to_string(viscous) +
                    "\nfriction_coulomb_n_m = " + std::to_string(coulomb) + R"(
[contact]
model = "thesis"
stiffness = 2.0e5
exponent = 1.5
damping = 2.0
)" + std::string(kThesisLinkDriveToml));
  const auto s = run_cli("simulate --config " + config.string() + " --signal step" + move + " --duration 3 --no-noise --json" + shaper);
  EXPECT_EQ(s.exit_code, 0) << s.err;
  std::filesystem::remove(config);
  return nlohmann::json::parse(s.out)["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"].get<double>();
}

TEST(RecommendFrictionCli, PredictionWithFrictionEqualsSimulateOfTheSameJoint) {
  const std::string move = " --amplitude 10 --start-s 0.2";
  const auto fit = temp("fit.json");
  write_text(fit, fit_json(R"(, "coulomb": {"value": 2e-3}, "viscous": {"value": 1e-4})"));
  const double with_friction = recommend_unshaped_md(fit, move);
  const double rig = simulated(2e-3, 1e-4, move);
  EXPECT_NEAR(with_friction, rig, 0.02 * rig) << "model " << with_friction << " rig " << rig;
  // The same document without the friction keys (an older fit) reads as friction 0: the model
  // then predicts the frictionless joint, which is another number.
  write_text(fit, fit_json(""));
  const double without = recommend_unshaped_md(fit, move);
  const double rig0 = simulated(0.0, 0.0, move);
  EXPECT_NEAR(without, rig0, 0.02 * rig0) << "model " << without << " rig " << rig0;
  EXPECT_GT(std::abs(without - with_friction), 0.05 * with_friction);
  std::filesystem::remove(fit);
}

TEST(RecommendFrictionCli, NegativeFrictionNamesTheKey) {
  const auto fit = temp("bad.json");
  write_text(fit, fit_json(R"(, "coulomb": {"value": -1e-3})"));
  const auto r = run_cli(recommend_spectrum_args() + " --model " + fit.string() + " --move step --amplitude 5 --start-s 0.2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(fit.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("parameters.coulomb"), std::string::npos) << r.err;
  std::filesystem::remove(fit);
}

TEST(RecommendFrictionCli, ClearanceAwareCandidateBesideTheLinearOnes) {
  const std::string move = " --amplitude 10 --start-s 0.2 --rise-s 0.0333";
  const auto fit = temp("fit_ca.json");
  write_text(fit, fit_json(R"(, "coulomb": {"value": 2e-3}, "viscous": {"value": 1e-4})"));
  const std::string args = recommend_spectrum_args() + " --model " + fit.string() + " --move step" + move + " --move-duration-s 3 --json";
  const auto plain = run_cli(args);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  // The document outlives the loop (a range over a member of a temporary read freed memory: ASan).
  const auto plain_doc = nlohmann::json::parse(plain.out);
  for (const auto& c : plain_doc["candidates"]) EXPECT_NE(c["name"], "clearance-aware");

  const auto r = run_cli(args + " --clearance-aware");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  const nlohmann::json* ca = nullptr;
  for (const auto& c : doc["candidates"]) {
    if (c["name"] == "clearance-aware") ca = &c;
  }
  ASSERT_NE(ca, nullptr) << r.out;
  EXPECT_LE((*ca)["duration_s"].get<double>(), (*ca)["max_duration_s"].get<double>() + 1e-9);
  double sum = 0.0;
  std::string impulses;
  for (const auto& i : (*ca)["impulses"]) {
    EXPECT_GE(i["amplitude"].get<double>(), 0.0);
    sum += i["amplitude"].get<double>();
    if (!impulses.empty()) impulses += ',';
    impulses += nlohmann::json(i["time_s"].get<double>()).dump();
    impulses += ':';
    impulses += nlohmann::json(i["amplitude"].get<double>()).dump();
  }
  EXPECT_NEAR(sum, 1.0, 1e-9);
  // Its predicted MD is the rig path's MD under the same impulses to a tenth of the unshaped MD,
  // and on the rig's own path (another plant and pulse train) it removes most of the vibration.
  // (The model's pulse path once lagged by 33 whole samples instead of the 33.3 ms period: its
  // update instants sat 0.3 ms off the rig's, and a design that exploited them predicted 0.0026°
  // where the rig gave 0.028°.)
  const double predicted = (*ca)["predicted_md"].get<double>();
  const double rig = simulated(2e-3, 1e-4, move, " --shaper custom --shaper-impulses " + impulses);
  const double rig_unshaped = simulated(2e-3, 1e-4, move);
  EXPECT_NEAR(predicted, rig, 0.1 * rig_unshaped) << "model " << predicted << " rig " << rig << " impulses " << impulses;
  EXPECT_LT(rig, 0.25 * rig_unshaped) << "rig shaped " << rig << " unshaped " << rig_unshaped;
  EXPECT_LT(predicted, 0.25 * doc["model"]["unshaped_md"].get<double>());  // the design helps on its own model

  const auto bad = run_cli(recommend_spectrum_args() + " --clearance-aware");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--clearance-aware needs --model"), std::string::npos) << bad.err;
  std::filesystem::remove(fit);
}

}  // namespace
