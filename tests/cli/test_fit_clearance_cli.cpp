// `clearshape fit-clearance` on SimRig records with a known truth: three 20° position steps of
// the simulated thesis rig (rig::thesis_rig_truth()), the drive identified by `identify --json`,
// the contact parameters recovered within stated tolerances. Cost ≈ 2 s.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/rig/worn_coupling.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;
namespace cs = clearshape;

namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

std::filesystem::path protocol() {
  return cs::testing::golden_path("").parent_path().parent_path().parent_path() / "studies" / "thesis-position.toml";
}

// A run of one of the protocol's inputs on a simulated rig with `truth`, written like a study's run.
std::string record_run(const std::filesystem::path& dir, const std::string& id, const std::string& input,
                       double record_s, std::uint64_t seed, const cs::rig::RigTruth& truth) {
  const auto p = cs::study::load_protocol(protocol());
  cs::study::RunRequest req;
  req.id = id;
  req.command = cs::signal::sample(p.input(input).signal, p.sample_rate_hz, record_s);
  req.record_s = record_s;
  cs::rig::SimRigOptions o;
  o.mode = cs::rig::CommandMode::position;
  o.sample_rate_hz = p.sample_rate_hz;
  o.seed = seed;
  auto rig = cs::rig::make_sim_rig_with_truth(o, truth);
  const cs::study::Record r = cs::study::execute_run(*rig, req);
  const auto path = dir / (req.id + ".csv");
  cs::io::write_csv(path, cs::study::record_columns(r.mode),
                    {&r.time_s, &r.command, &r.command_applied, &r.encoder_counts, &r.motor_angle_deg, &r.gyro_raw,
                     &r.link_rate_deg_s, &r.flags});
  return path.string();
}

// The protocol's 20° step on the simulated thesis rig (its built-in, calibrated truth).
std::string record_step(const std::filesystem::path& dir, int repetition) {
  return record_run(dir, "step-" + std::to_string(repetition), "step-20", 3.0, static_cast<std::uint64_t>(100 + repetition),
                    cs::rig::thesis_rig_truth());
}

}  // namespace

TEST(FitClearanceCli, RecoversTheSimulatedRigsContactWithinTolerance) {
  const auto dir = temp("clearshape_cli_fit_clearance");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string a = record_step(dir, 1), b = record_step(dir, 2), c = record_step(dir, 3);
  const auto id = run_cli("identify --model P3UZ --data " + a +
                          " --input-column command_applied_deg --output-column motor_angle_deg --json");
  ASSERT_EQ(id.exit_code, 0) << id.err;
  { std::ofstream(dir / "drive.json") << id.out; }

  const auto fit = run_cli("fit-clearance --drive " + (dir / "drive.json").string() + " --data " + a + " --data " + b +
                           " --data " + c + " --json");
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const auto doc = nlohmann::json::parse(fit.out);
  const auto truth = cs::rig::thesis_rig_truth();
  const auto& contact = truth.contact(cs::rig::CommandMode::position);
  const auto& q = doc.at("parameters");
  const auto rel = [](double got, double want) { return std::abs(got / want - 1.0); };
  // Tolerances: K and the play to 5 % and 10 %; D to 25 % (the rig draws the flank damping per
  // run, σ(ln D) 0.18, so three runs pin its mean only to ≈ 10 %); n to 0.05.
  EXPECT_LT(rel(q["stiffness"]["value"].get<double>(), contact.stiffness), 0.05) << fit.out;
  EXPECT_LT(rel(q["damping"]["value"].get<double>(), contact.damping), 0.25) << fit.out;
  EXPECT_LT(rel(q["play"]["value"].get<double>(), cs::rad_to_deg(truth.clearance_rad)), 0.10) << fit.out;
  EXPECT_NEAR(q["exponent"]["value"].get<double>(), contact.exponent, 0.05) << fit.out;
  for (const char* name : {"stiffness", "damping", "play", "exponent"}) {
    EXPECT_TRUE(q[name]["identifiable"].get<bool>()) << name;
    EXPECT_TRUE(std::isfinite(q[name]["std"].get<double>())) << name;
  }
  EXPECT_LT(doc.at("agreement").get<double>(), 0.01);  // Eq. 4.1, the thesis reached ≈ 0.02
  EXPECT_LT(doc.at("agreement").get<double>(), doc.at("start_agreement").get<double>());
  EXPECT_TRUE(doc.at("converged").get<bool>());
  EXPECT_TRUE(doc.at("trusted").get<bool>()) << doc.at("warnings");

  // An exhausted budget is reported: trusted false, a warning on stderr, exit 0.
  const auto short_fit = run_cli("fit-clearance --drive " + (dir / "drive.json").string() + " --data " + a +
                                 " --max-evaluations 5 --json");
  ASSERT_EQ(short_fit.exit_code, 0) << short_fit.err;
  const auto s = nlohmann::json::parse(short_fit.out);
  EXPECT_FALSE(s.at("trusted").get<bool>());
  EXPECT_NE(short_fit.err.find("warning: the search did not converge"), std::string::npos) << short_fit.err;

  // Bad input: exit 2 naming the option or the file.
  EXPECT_EQ(run_cli("fit-clearance --data " + a).exit_code, 2);  // no drive model
  EXPECT_EQ(run_cli("fit-clearance --model P3UZ --param Kp=1 --data " + a + " --gyro-unit rpm").exit_code, 2);
  EXPECT_EQ(run_cli("fit-clearance --drive " + a + " --data " + a).exit_code, 2);  // not JSON
  std::filesystem::remove_all(dir);
}

namespace {

// The protocol's 5° step on the worn-coupling rig (1° of play, the link anywhere in it, the flank
// damping drawn per run).
std::string record_worn_step(const std::filesystem::path& dir, int repetition) {
  return record_run(dir, "worn-" + std::to_string(repetition), "step-5", 2.0, static_cast<std::uint64_t>(200 + repetition),
                    cs::rig::worn_coupling_rig_truth());
}

}  // namespace

// --per-run: each record its own run (its own start place and flank damping), never averaged —
// the fit that finds a worn joint's play (issue 19). Its document carries model_sigma with the
// damping's run spread, and `shape --model` designs on that set. Cost ≈ 10 s.
TEST(FitClearanceCli, PerRunFindsTheWornPlayAndCarriesTheSetToShape) {
  const auto dir = temp("clearshape_cli_fit_clearance_per_run");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::string data;
  for (int k = 1; k <= 6; ++k) data += " --data " + record_worn_step(dir, k);
  const auto truth = cs::rig::worn_coupling_rig_truth();
  // P2U: the 5° step does not pin the thesis's third pole (P3UZ fits a near-zero Tp3 here, which
  // the fit then integrates with CVODE: ×4 the time).
  const auto id = run_cli("identify --model P2U --data " + (dir / "worn-1.csv").string() +
                          " --input-column command_applied_deg --output-column motor_angle_deg --json");
  ASSERT_EQ(id.exit_code, 0) << id.err;
  { std::ofstream(dir / "drive.json") << id.out; }
  const auto fit = run_cli("fit-clearance --per-run --drive " + (dir / "drive.json").string() + data +
                           " --fit stiffness damping play coulomb viscous --play-deg 0.5 --stiffness 30 --json");
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  { std::ofstream(dir / "fit.json") << fit.out; }
  const auto doc = nlohmann::json::parse(fit.out);
  const auto& q = doc.at("parameters");
  const auto rel = [](double got, double want) { return std::abs(got / want - 1.0); };
  // The goal: play and K within 10 %, the Coulomb torque within 25 %.
  EXPECT_LT(rel(q["play"]["value"].get<double>(), cs::rad_to_deg(truth.clearance_rad)), 0.10) << fit.out;
  EXPECT_LT(rel(q["stiffness"]["value"].get<double>(), truth.position_contact.stiffness), 0.10) << fit.out;
  EXPECT_LT(rel(q["coulomb"]["value"].get<double>(), truth.joint_friction.coulomb), 0.25) << fit.out;
  EXPECT_EQ(q["exponent"]["value"].get<double>(), 1.0);
  ASSERT_EQ(doc.at("runs").size(), 6u);
  const double spread = doc.at("model_sigma").at("damping_spread").get<double>();
  EXPECT_GT(spread, 0.0);  // the rig draws D per run (σ(ln D) 0.18)
  // shape reads the set: five start places at the nominal model and at D × e^(∓spread) at least.
  const auto shape = run_cli("shape --method clearance-aware --model " + (dir / "fit.json").string() +
                             " --moves 5 --max-duration-s 0.2 --max-evaluations 10 --json");
  ASSERT_EQ(shape.exit_code, 0) << shape.err;
  bool lower = false, upper = false;
  const auto design = nlohmann::json::parse(shape.out);  // outlives the loop (not a temporary's member)
  for (const auto& c : design.at("cases")) {
    lower = lower || std::abs(c["damping_factor"].get<double>() - std::exp(-spread)) < 1e-12;
    upper = upper || std::abs(c["damping_factor"].get<double>() - std::exp(spread)) < 1e-12;
  }
  EXPECT_TRUE(lower && upper) << "spread " << spread << "\n" << shape.out;
  // What it cannot fit is refused by option.
  EXPECT_EQ(run_cli("fit-clearance --per-run --mode speed --model P1 --param Kp=1" + data).exit_code, 2);
  EXPECT_EQ(run_cli("fit-clearance --per-run --drive " + (dir / "drive.json").string() + data + " --rest-s 5").exit_code, 2);
  std::filesystem::remove_all(dir);
}
