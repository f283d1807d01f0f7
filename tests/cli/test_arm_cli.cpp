// clearshape arm: modes at a pose against the SciPy eigh golden (tests/golden/gen_arm_modes.py),
// the identified mode map against those, a shaped move's JSON and CSV (the ZVD's length is one
// damped period, Singer & Seering 1990), a move played by the simulation ends where it was sent
// (no play: the position drives' steady state), help text, a failure → exit 1, and bad input →
// exit 2 naming the option.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/arm/arm.hpp"
#include "clearshape/io/table.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

/// The golden row of scara-2's modes at elbow angle q2 (rad).
std::pair<double, double> golden_modes_hz(double q2) {
  const auto t = clearshape::io::read_table(clearshape::testing::golden_path("arm_scara_modes.csv"));
  for (std::size_t r = 0; r < t.rows(); ++r) {
    if (std::abs(t.column("q2_rad")[r] - q2) < 1e-9) return {t.column("f1_hz")[r], t.column("f2_hz")[r]};
  }
  ADD_FAILURE() << "no golden row at q2 = " << q2;
  return {NAN, NAN};
}

TEST(ArmCli, ModesAtAPoseMatchTheScipyGolden) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_modes");
  const auto r = run_cli("arm modes --pose 0.7,0.6 -o " + (dir / "modes.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = read_json(dir / "modes.json");
  const auto [f1, f2] = golden_modes_hz(0.6);
  ASSERT_EQ(doc["modes"].size(), 2u);
  EXPECT_NEAR(doc["modes"][0]["linear_frequency_hz"].get<double>() / f1, 1.0, 1e-9);
  EXPECT_NEAR(doc["modes"][1]["linear_frequency_hz"].get<double>() / f2, 1.0, 1e-9);
  EXPECT_NE(r.out.find("frequency_hz"), std::string::npos) << r.out;
}

// The identified first mode beside the linearised one written in the same file (joint_modes, itself
// checked against the golden in tests/arm) and, on the elbow-straight poses, beside the golden.
void write_text(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// Your own arm: scara-2's URDF and TOML as files give the golden modes; a TOML with a bad key is
// refused naming the file and the key.
TEST(ArmCli, OwnUrdfAndConfigWorkTheSameWay) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_own");
  const auto text = clearshape::arm::builtin_arm_text("scara-2");
  write_text(dir / "arm.urdf", text.urdf);
  write_text(dir / "arm.toml", text.toml);
  const std::string files = " --urdf " + (dir / "arm.urdf").string() + " --config " + (dir / "arm.toml").string();
  auto r = run_cli("arm modes --pose 0.7,0.6 --json" + files);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_NEAR(doc["modes"][0]["linear_frequency_hz"].get<double>() / golden_modes_hz(0.6).first, 1.0, 1e-9);
  write_text(dir / "bad.toml", text.toml + "\n[bogus]\nx = 1\n");
  r = run_cli("arm modes --urdf " + (dir / "arm.urdf").string() + " --config " + (dir / "bad.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bogus"), std::string::npos) << r.err;
  r = run_cli("arm modes --urdf " + (dir / "arm.urdf").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--urdf requires --config"), std::string::npos) << r.err;
}

TEST(ArmCli, IdentifiedMapWithoutPlayAgreesWithTheLinearisedModes) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_map");
  const auto r = run_cli("arm modes --identify --grid 3 --play-deg 0 -o " + (dir / "map.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = clearshape::io::read_table(dir / "map.csv");
  int first_modes = 0, straight = 0;
  for (std::size_t k = 0; k < t.rows(); ++k) {
    if (t.column("linear_mode")[k] != 0.0 || t.column("harmonic")[k] != 0.0) continue;
    ++first_modes;
    EXPECT_NEAR(t.column("frequency_hz")[k] / t.column("linear_frequency_hz")[k], 1.0, 1e-3) << k;
    EXPECT_GT(t.column("frequency_std_hz")[k], 0.0);
    if (t.column("elbow_rad")[k] != 0.0) continue;
    ++straight;
    EXPECT_NEAR(t.column("frequency_hz")[k] / golden_modes_hz(0.0).first, 1.0, 1e-3) << k;
  }
  EXPECT_EQ(first_modes, 9);
  EXPECT_EQ(straight, 3);
}

// With the built-in 0.5° play the loaded ramp keeps the flanks loaded: the first mode within 0.5 %
// of the linearised one at every pose, and no run without a mode in the JSON.
TEST(ArmCli, IdentifiedMapWithPlayUnderALoadedRamp) {
  const auto r = run_cli("arm modes --identify --grid 2 --excitation loaded-ramp --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_TRUE(doc["failures"].empty()) << doc["failures"].dump();
  int first_modes = 0;
  for (const auto& m : doc["modes"]) {
    if (m["linear_mode"] != 0 || m["harmonic"] != 0) continue;
    ++first_modes;
    EXPECT_LT(std::abs(m["relative_frequency_error"].get<double>()), 0.005) << m.dump();
  }
  EXPECT_EQ(first_modes, 4);
}

TEST(ArmCli, ShapedMoveWritesJointTrajectoryJsonAndCsv) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_move");
  const std::string move = "arm move --from 0,1.5 --to 1.2,0.6 ";
  auto r = run_cli(move + "-o " + (dir / "plain.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli(move + "--shaper scheduled -o " + (dir / "shaped.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli(move + "--shaper scheduled -o " + (dir / "shaped.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto plain = read_json(dir / "plain.json"), shaped = read_json(dir / "shaped.json");
  EXPECT_EQ(shaped["joint_names"], nlohmann::json::parse(R"(["shoulder", "elbow"])"));
  const auto end_s = [](const nlohmann::json& d) {
    const auto& t = d["points"].back()["time_from_start"];
    return t["sec"].get<double>() + 1e-9 * t["nanosec"].get<double>();
  };
  // ZVD at the end pose's shoulder mode lasts one damped period (golden f1 at q2 = 0.6; ζ < 1e-3)
  const double period_s = 1.0 / golden_modes_hz(0.6).first;
  EXPECT_NEAR(end_s(shaped) - end_s(plain), period_s, 1.5e-3);
  const auto& last = shaped["points"].back()["positions"];
  EXPECT_DOUBLE_EQ(last[0].get<double>(), 1.2);
  EXPECT_DOUBLE_EQ(last[1].get<double>(), 0.6);
  const auto csv = clearshape::io::read_table(dir / "shaped.csv");
  EXPECT_EQ(csv.rows(), shaped["points"].size());
  EXPECT_DOUBLE_EQ(csv.column("shoulder_rad").back(), 1.2);
}

// Limits per joint (issue 24 item 4, "limits per axis"): the elbow held to 0.5 rad/s sets the
// move's length; the synchronised shoulder then stays below its own 2 rad/s, and the elbow reaches
// exactly its limit (a trapezoid's cruise). One value still means every joint.
TEST(ArmCli, LimitsPerJointBindTheSlowerJoint) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_limits");
  const std::string move = "arm move --from 0,0 --to 1,0.5 --acceleration 20 --jerk 400 ";
  auto r = run_cli(move + "--velocity 2,0.5 -o " + (dir / "per-joint.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli(move + "--velocity 0.5 -o " + (dir / "every.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto peak = [](const nlohmann::json& d, int joint) {
    double v = 0.0;
    for (const auto& p : d["points"]) v = std::max(v, std::abs(p["velocities"][joint].get<double>()));
    return v;
  };
  const auto per_joint = read_json(dir / "per-joint.json"), every = read_json(dir / "every.json");
  EXPECT_NEAR(peak(per_joint, 1), 0.5, 1e-9);
  EXPECT_GT(peak(per_joint, 0), 0.5);  // the shoulder is allowed more than the elbow …
  EXPECT_LT(peak(per_joint, 0), 2.0);  // … and is slowed to end with it
  EXPECT_NEAR(peak(every, 0), 0.5, 1e-9);  // one value: the shoulder held to 0.5 too, a longer move
  EXPECT_GT(every["points"].size(), per_joint["points"].size());
}

TEST(ArmCli, SimulatedMoveWithoutPlayEndsAtItsTarget) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_cli_simulate");
  auto r = run_cli("arm move --from 0,1.5 --to 1.2,0.6 --shaper fixed -o " + (dir / "m.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("arm simulate --play-deg 0 --trajectory " + (dir / "m.json").string() + " -o " + (dir / "run.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("residual"), std::string::npos) << r.out;
  const auto t = clearshape::io::read_table(dir / "run.csv");
  EXPECT_NEAR(t.column("shoulder_link_deg").back(), 1.2 * 180 / M_PI, 0.01);
  EXPECT_NEAR(t.column("elbow_link_deg").back(), 0.6 * 180 / M_PI, 0.01);
  // the motor's encoder (3000 lines × 4 per motor turn) over the gear ratio is the gearbox output
  EXPECT_NEAR(t.column("shoulder_encoder_deg").back() / 50.0, t.column("shoulder_output_deg").back(), 0.03 / 50.0);
  // the last link's IMU at rest: no rotation, +g along z (scara-2's axes are vertical)
  EXPECT_NEAR(t.column("gyro_z_rad_s").back(), 0.0, 1e-6);
  EXPECT_NEAR(t.column("accel_z_m_s2").back(), 9.80665, 1e-9);
  // the move (0.75 s), 1 s of settling, and the ZVD at the centre's shoulder mode: one period
  const double zvd_s = 1.0 / golden_modes_hz(0.0).first;
  EXPECT_NEAR(t.column("time_s").back() - t.column("time_s").front(), 0.75 + 1.0 + zvd_s, 2e-3);
}

TEST(ArmCli, HelpNamesTheSubcommandsAndOptions) {
  auto r = run_cli("arm --help");
  ASSERT_EQ(r.exit_code, 0);
  for (const char* s : {"simulate", "modes", "move"}) EXPECT_NE(r.out.find(s), std::string::npos) << s;
  r = run_cli("arm move --help");
  ASSERT_EQ(r.exit_code, 0);
  for (const char* s : {"--shaper", "--from", "--to", "--velocity", "--urdf"}) EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

TEST(ArmCli, AFailureExits1) {  // standard output that cannot be written is a run-time failure
  const auto r = run_cli("arm modes --pose 0,0 > /dev/full");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("cannot write to standard output"), std::string::npos) << r.err;
}

TEST(ArmCli, BadInputExits2NamingTheOption) {
  const std::pair<const char*, const char*> cases[] = {
      {"arm move --from 1,2,3 --to 0,0", "--from = '1,2,3' has 3 angles; allowed: 2"},
      {"arm move --from 0,0 --to 0,x", "--to = '0,x': 'x' is not an angle"},
      {"arm move --from 0,0 --to 0,1 --shaper bogus", "--shaper"},
      {"arm move --from 0,0 --to 0,1 -o t.txt", "-o = 't.txt': allowed a file name ending in .json or .csv"},
      {"arm modes --identify --grid 0", "--grid: Value 0 not in range 1 to 10"},
      {"arm modes --play-deg 20", "--play-deg"},
      {"arm modes --arm nope", "--arm: nope not in {scara-2,vertical-2}"},
      {"arm simulate", "give either --trajectory FILE or --from and --to"},
      {"arm move --from 0,0 --to 1,0 --velocity 2,0.5,1", "--velocity = '2,0.5,1' has 3 values; allowed: one value for every joint or 2"},
      {"arm move --from 0,0 --to 1,0 --jerk 0", "--jerk = '0': 0 is out of range; allowed: one value for every joint or 2 comma-separated, each in [1e-06, 1e+07] rad/s³"},
      {"arm move --from 0,0 --to 1,0 --acceleration 1,x", "--acceleration = '1,x': 'x' is not a number"},
      {"arm move --from 0,0 --to 1,0 --flank-margin 1.5", "--flank-margin: Value 1.5 not in range 0"},
      {"arm move --from 0,0 --to 1,0 --flank-margin -0.1", "--flank-margin: Value -0.1 not in range 0"},
      {"arm move --from 0,0 --to 1,0 --flank-margin 0.5 --flank-floor 0", "--flank-floor = 0; allowed: (0, 1]"},
      {"arm move --from 0,0 --to 1,0 --flank-floor 1.5", "--flank-floor = 1.5; allowed: (0, 1]"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
