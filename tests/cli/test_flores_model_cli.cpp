// The Flores contact law of the identified clearance model as the CLI reads it: a
// `fit-clearance --json` document with contact_law "flores" and its restitution, read by
// `recommend --model`, predicts the unshaped Eq. 5.1 MD that `clearshape simulate` gives for a rig
// configuration with the same drive, play, Flores law and friction (the rig's own plant, contact
// law factory and pulse path: another code path); without the contact_law key the same document
// is a dashpot model (another number); a study's results.json with the same Flores model gives the
// same prediction; a Flores document without its restitution, or with an
// unknown law, is exit 2 naming the file and the key.
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

std::filesystem::path temp(const std::string& name) { return pid_temp_file("flores_model_cli", name); }

// A `fit-clearance --json` document of a 1° play with a Hertz pin; `law` is the text before
// "parameters" (e.g. the contact_law key) and `dissipation` the restitution or damping entry.
std::string fit_json(const std::string& law, const std::string& dissipation) {
  return R"({"command": "fit-clearance", "mode": "position", "link_inertia_kg_m2": 0.005, )" + law +
         R"("parameters": {"stiffness": {"value": 2.0e5}, )" + dissipation + R"(,
                "play": {"value": 1.0}, "exponent": {"value": 1.5}, "coulomb": {"value": 2e-3}},
 "drive": )" + kThesisDriveJson + "}";
}

double simulated_flores(const std::string& move) {
  const auto config = temp("rig.toml");
  write_text(config, R"([joint]
clearance_deg = 1.0
friction_viscous_n_m_s_per_rad = 0.0
friction_coulomb_n_m = 0.002
[contact]
model = "flores"
stiffness = 2.0e5
exponent = 1.5
restitution = 0.6
)" + std::string(kThesisLinkDriveToml));
  const auto s = run_cli("simulate --config " + config.string() + " --signal step" + move + " --duration 3 --no-noise --json");
  EXPECT_EQ(s.exit_code, 0) << s.err;
  std::filesystem::remove(config);
  return nlohmann::json::parse(s.out)["mean_deviation_eq_5_1"]["link_angle_deg"]["mean_deviation"].get<double>();
}

// 2 %: the two paths differ in the pulse train's timing (the rig looks one update ahead and
// interpolates, the model holds with one update of latency), as in test_recommend_friction_cli.
TEST(FloresModelCli, PredictionEqualsSimulateOfTheSameJoint) {
  const std::string move = " --amplitude 10 --start-s 0.2";
  const auto fit = temp("fit.json");
  write_text(fit, fit_json(R"("contact_law": "flores", )", R"("restitution": {"value": 0.6})"));
  const double flores = recommend_unshaped_md(fit, move);
  const double rig = simulated_flores(move);
  EXPECT_NEAR(flores, rig, 0.02 * rig) << "model " << flores << " rig " << rig;
  // Without the key (a file of before the choice): the dashpot with D, another prediction.
  write_text(fit, fit_json("", R"("damping": {"value": 2.0})"));
  const double dashpot = recommend_unshaped_md(fit, move);
  EXPECT_GT(std::abs(dashpot - flores), 0.05 * flores) << "dashpot " << dashpot << " flores " << flores;
  std::filesystem::remove(fit);
}

// A study's results.json (sections.clearance with contact_law "flores") is the same model as the
// fit-clearance document with the same parameters: the same prediction, to the digit.
TEST(FloresModelCli, StudyResultsFormReadsTheSameModel) {
  const std::string move = " --amplitude 10 --start-s 0.2";
  const auto fit = temp("fit_same.json");
  write_text(fit, fit_json(R"("contact_law": "flores", )", R"("restitution": {"value": 0.6})"));
  const auto study = temp("results.json");
  write_text(study, std::string(R"({"protocol": {"mode": "position"}, "sections": {
 "identification": {"selected_input": "step", "models": [{"input": "step", "model": "P3UZ", "parameters":
   {"Kp": 0.9959, "Tz": 0.0042, "Zeta": 0.9968, "Tw": 0.0102, "Tp3": 0.0034}}]},
 "clearance": {"stiffness_n_m_per_rad_pow_n": 2.0e5, "damping_n_m_s_per_rad": 1.0, "exponent": 1.5,
   "play_deg": 1.0, "coulomb_n_m": 2e-3, "viscous_n_m_s_per_rad": 0.0, "link_inertia_kg_m2": 0.005,
   "contact_law": "flores", "restitution": 0.6}}})"));
  const double from_fit = recommend_unshaped_md(fit, move);
  const double from_study = recommend_unshaped_md(study, move);
  EXPECT_DOUBLE_EQ(from_fit, from_study);
  std::filesystem::remove(fit);
  std::filesystem::remove(study);
}

TEST(FloresModelCli, MissingRestitutionOrUnknownLawNamesTheKey) {
  const auto fit = temp("bad.json");
  write_text(fit, fit_json(R"("contact_law": "flores", )", R"("damping": {"value": 2.0})"));
  const std::string args = recommend_spectrum_args() + " --model " + fit.string() + " --move step --amplitude 5 --start-s 0.2";
  auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(fit.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("parameters.restitution"), std::string::npos) << r.err;
  write_text(fit, fit_json(R"("contact_law": "flores", )", R"("restitution": {"value": 1.4})"));
  r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("(0, 1]"), std::string::npos) << r.err;
  write_text(fit, fit_json(R"("contact_law": "hertz", )", R"("damping": {"value": 2.0})"));
  r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("contact_law"), std::string::npos) << r.err;
  std::filesystem::remove(fit);
}

TEST(FloresModelCli, FitClearanceRejectsAnUnknownLaw) {
  const auto r = run_cli("fit-clearance --model P3UZ --param Kp=1 --data x.csv --contact-law hertz");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--contact-law"), std::string::npos) << r.err;
  const auto e = run_cli("fit-clearance --model P3UZ --param Kp=1 --data x.csv --contact-law flores --restitution 1.5");
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("--restitution"), std::string::npos) << e.err;
}

}  // namespace
