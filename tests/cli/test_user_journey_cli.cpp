// The user's whole journey, as README's "Your own machine" walk-through tells it, on ten CSVs
// recorded on a simulated axis (`clearshape simulate` of the calibrated thesis rig, one noise
// seed per run) and exported as plain CSVs with the user's own column names and units (time "t",
// commands in rad, the encoder in counts, the gyro in rad/s): nothing of clearshape's own layout
// is assumed. study --print-manifest → fill the manifest → study --recordings → recommend (with
// the study's model) → shape --export c-header → compile the header with cc and run it on a step
// → the shaped trials' command from the study's shaper.
// Checked against the rig's truth (link mode 14.955 Hz, play 0.032°, K 45.16 N·m/rad) and the
// exported taps (the compiled shaper's output is their convolution with the command).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path repository() { return clearshape::testing::golden_path("").parent_path().parent_path().parent_path(); }

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

// The user's export: t, cmd_rad, drive_rad, enc (counts of a 12000-count encoder), gyro_rad_s.
void export_as_user(const fs::path& simulated, const fs::path& user) {
  std::ifstream in(simulated);
  std::string line;
  std::getline(in, line);
  const auto names = split(line);
  const auto col = [&](const std::string& n) { return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin()); };
  const std::size_t t = col("time_s"), cmd = col("command_deg"), drv = col("drive_command_deg"), enc = col("encoder_deg"), gyro = col("gyro_deg_s");
  ASSERT_LT(gyro, names.size());
  std::ofstream out(user);
  out << "t,cmd_rad,drive_rad,enc,gyro_rad_s\n";
  out.precision(12);
  const double rad = std::numbers::pi / 180.0;
  while (std::getline(in, line)) {
    const auto v = split(line);
    out << v[t] << ',' << std::stod(v[cmd]) * rad << ',' << std::stod(v[drv]) * rad << ','
        << std::llround(std::stod(v[enc]) * 12000.0 / 360.0) << ',' << std::stod(v[gyro]) * rad << '\n';
  }
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

}  // namespace

TEST(UserJourneyCli, TenRecordedCsvsToAReportARecommendationAndACompiledHeader) {
  const fs::path dir = fs::temp_directory_path() / ("user_journey_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sim");
  fs::create_directories(dir / "my-axis");
  const std::string proto = (repository() / "studies" / "thesis-position.toml").string();

  // Ten runs on the axis: the quick protocol's 3 s records at 1 kHz, moves at 0.5 s.
  struct Run { std::string id, file, signal; };
  std::vector<Run> runs;
  for (int r = 1; r <= 3; ++r) {
    runs.push_back({"unshaped/step-20/r0" + std::to_string(r), "step20_" + std::to_string(r) + ".csv", "step --amplitude 20 --start-s 0.5"});
    runs.push_back({"unshaped/double-step-16/r0" + std::to_string(r), "dstep16_" + std::to_string(r) + ".csv",
                    "double-step --amplitude 16 --start-s 0.5 --second-amplitude 16 --second-start-s 1.0"});
  }
  for (int r = 1; r <= 2; ++r) {
    runs.push_back({"rig/B.2/none/r0" + std::to_string(r), "step10_" + std::to_string(r) + ".csv", "step --amplitude 10 --start-s 0.5"});
    runs.push_back({"rig/B.3/none/r0" + std::to_string(r), "step5_" + std::to_string(r) + ".csv", "step --amplitude 5 --start-s 0.5"});
  }
  ASSERT_EQ(runs.size(), 10u);
  int seed = 1;
  for (const auto& run : runs) {
    const fs::path sim = dir / "sim" / run.file;
    const auto r = run_cli("simulate --signal " + run.signal + " --duration 3 --noise-seed " + std::to_string(seed++) + " -o " + sim.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    export_as_user(sim, dir / "my-axis" / run.file);
  }

  // 1. The template, 2. filled in: the user's columns and units, one entry per recorded file.
  const auto t = run_cli("study " + proto + " --quick --print-manifest");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  std::string manifest = t.out.substr(0, t.out.find("[[run]]"));
  replace(manifest, "time = \"time_s\"", "time = \"t\"");
  replace(manifest, "command = \"command_deg\"", "command = \"cmd_rad\"");
  replace(manifest, "command_unit = \"deg\"", "command_unit = \"rad\"");
  replace(manifest, "command_applied = \"command_applied_deg\"", "command_applied = \"drive_rad\"");
  replace(manifest, "motor_angle = \"motor_angle_deg\"", "motor_angle = \"enc\"");
  replace(manifest, "motor_angle_unit = \"deg\"", "motor_angle_unit = \"counts\"");
  replace(manifest, "link_rate = \"link_rate_deg_s\"", "link_rate = \"gyro_rad_s\"");
  replace(manifest, "link_rate_unit = \"deg/s\"", "link_rate_unit = \"rad/s\"");
  for (const auto& run : runs) {
    ASSERT_NE(t.out.find("id = \"" + run.id + "\""), std::string::npos) << run.id << " is not in the template";
    manifest += "[[run]]\nid = \"" + run.id + "\"\nfile = \"" + run.file + "\"\n\n";
  }
  {
    std::ofstream(dir / "my-axis" / "manifest.toml") << manifest;
  }

  // 3. The study on the recordings.
  const fs::path out = dir / "out";
  const auto s = run_cli("study " + proto + " --quick --recordings " + (dir / "my-axis").string() + " --out " + out.string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_NE(s.err.find("stage rig-tests SKIPPED"), std::string::npos) << s.err;  // no shaped trials yet: said, not silent
  std::ifstream results_in(out / "results.json");
  const json results = json::parse(results_in);
  EXPECT_EQ(results["rig"]["kind"], "recordings");
  const auto& clearance = results["sections"]["clearance"];
  EXPECT_NEAR(clearance["play_deg"].get<double>(), 0.0320, 0.1 * 0.0320) << clearance.dump();
  EXPECT_NEAR(clearance["stiffness_n_m_per_rad_pow_n"].get<double>(), 45.16, 0.05 * 45.16);
  EXPECT_NEAR(results["sections"]["link_mode"]["natural_frequency_hz"].get<double>(), 14.955, 0.3);

  // 4. The recommendation: the free decays after the 20° steps, scored with the study's model.
  // Forgetting the window (the spectrum of the whole move) is answered by a hint naming it.
  const auto whole = run_cli("recommend --data " + (dir / "my-axis" / "step20_1.csv").string() + " --column gyro_rad_s");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_NE(whole.err.find("hint:"), std::string::npos) << whole.err;
  EXPECT_NE(whole.err.find("--from-s 0.6"), std::string::npos) << whole.err;
  std::string data;
  for (int r = 1; r <= 3; ++r) data += " --data " + (dir / "my-axis" / ("step20_" + std::to_string(r) + ".csv")).string();
  const auto rec = run_cli("recommend" + data + " --column gyro_rad_s --from-s 0.6 --max-delay-s 0.1 --model " + (out / "results.json").string() +
                           " --move step --amplitude 20 --start-s 0.5 --json");
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  const json advice = json::parse(rec.out);
  EXPECT_NEAR(advice["modes"][0]["frequency_hz"].get<double>(), 14.955, 0.3);
  ASSERT_FALSE(advice["recommendation"].is_null()) << advice["reason"];
  const double md = advice["recommendation"]["predicted_md"].get<double>();
  EXPECT_LT(md, 0.2 * advice["model"]["unshaped_md"].get<double>()) << advice["reason"];
  std::string shape = advice["recommendation"]["shape_command"];
  ASSERT_EQ(shape.rfind("clearshape shape ", 0), 0u) << shape;
  shape = shape.substr(std::string("clearshape ").size());

  // 5. The header for a 1 kHz loop (and the same taps as JSON, to check the compiled output).
  const fs::path header = dir / "shaper.h";
  const auto h = run_cli(shape + " --export c-header --sample-time 0.001 -o " + header.string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  const auto j = run_cli(shape + " --export json --sample-time 0.001");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const json taps = json::parse(j.out)["discrete"]["taps"];

  // 6. Compiled with the system C compiler, run on a 20° step at sample 10.
  {
    std::ofstream(dir / "main.c") << "#include <stdio.h>\n#include \"shaper.h\"\n"
                                     "int main(void) {\n  cs_shaper_state_double s;\n  cs_shaper_reset_double(&s, 0.0);\n"
                                     "  for (int k = 0; k < 300; ++k) printf(\"%.17g\\n\", cs_shaper_step_double(&s, k < 10 ? 0.0 : 20.0));\n"
                                     "  return 0;\n}\n";
  }
  const std::string exe = (dir / "controller").string();
  ASSERT_EQ(std::system(("cc -std=c99 -Wall -Wextra -Werror -pedantic -o " + exe + " " + (dir / "main.c").string() + " -lm 2> " +
                         (dir / "cc.log").string()).c_str()),
            0);
  ASSERT_EQ(std::system((exe + " > " + (dir / "controller.out").string()).c_str()), 0);
  std::ifstream outputs(dir / "controller.out");
  double y = 0.0;
  for (int k = 0; k < 300; ++k) {
    ASSERT_TRUE(outputs >> y) << k;
    double expected = 0.0;
    for (const auto& tap : taps) {
      const int i = k - tap["delay_samples"].get<int>();
      expected += tap["weight"].get<double>() * (i >= 10 ? 20.0 : 0.0);
    }
    ASSERT_NEAR(y, expected, 1e-12) << "sample " << k;
  }
  EXPECT_NEAR(y, 20.0, 1e-12);  // the move arrives, delayed by the shaper

  // 7. The shaped trials' command: the study's zvdd@link-mode impulses through `shape --input`.
  std::string impulses;
  for (const auto& sh : results["sections"]["shapers"]) {
    if (sh["key"] != "zvdd@link-mode") continue;
    for (const auto& i : sh["impulses"]) {
      impulses += (impulses.empty() ? "" : ",") + json(i["time_s"]).dump() + ":" + json(i["amplitude"]).dump();
    }
  }
  ASSERT_FALSE(impulses.empty()) << results["sections"]["shapers"].dump();
  const fs::path command = dir / "step20-command.csv", shaped = dir / "step20-zvdd-command.csv";
  ASSERT_EQ(run_cli("signal --type step --amplitude 20 --start-s 0.5 --duration 3 -o " + command.string()).exit_code, 0);
  const auto sc = run_cli("shape --method custom --impulses \"" + impulses + "\" -i " + command.string() + " --column command -o " +
                          shaped.string());
  ASSERT_EQ(sc.exit_code, 0) << sc.err;
  std::ifstream shaped_in(shaped);
  std::string line, last;
  std::getline(shaped_in, line);
  EXPECT_EQ(line, "time_s,command,command_shaped");
  while (std::getline(shaped_in, line)) last = line;
  EXPECT_NEAR(std::stod(split(last).back()), 20.0, 1e-9) << last;
  fs::remove_all(dir);
}
