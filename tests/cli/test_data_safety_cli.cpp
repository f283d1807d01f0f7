// The CLI's data-safety contract, one regression per fault found by the hostile-user review:
// inputs never overwritten, outputs whole or absent, --fresh removes only the study's own
// files, failed stdout is a failure, non-finite and negative option values are refused with the
// option's name, unknown subcommands are named, library logs stay quiet. Injected faults (full
// disk, full stdout, a killed study, links to an input) are in test_faults_cli.cpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {
fs::path temp_dir(const std::string& name) { return clearshape::testing::fresh_temp_dir("clearshape_safety_" + name); }
std::string read(const fs::path& p) { return clearshape::testing::read_bytes(p); }
fs::path studies() { return fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies"; }
}  // namespace

TEST(DataSafetyCli, AnOutputEqualToAnInputIsRefusedAndTheInputKept) {
  const fs::path d = temp_dir("input");
  ASSERT_EQ(run_cli("signal --type step --amplitude 1 --duration 0.2 -o " + (d / "in.csv").string()).exit_code, 0);
  const std::string before = read(d / "in.csv");
  auto r = run_cli("shape --method zv --frequency-hz 10 --zeta 0.1 -i " + (d / "in.csv").string() +
                   " --column command -o " + (d / "." / "in.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("inputs are never overwritten"), std::string::npos) << r.err;
  EXPECT_EQ(read(d / "in.csv"), before);

  ASSERT_EQ(run_cli("simulate --duration 0.2 -o " + (d / "run.csv").string()).exit_code, 0);
  const std::string rec = read(d / "run.csv");
  r = run_cli("identify --data " + (d / "run.csv").string() + " --input-column command_deg --output-column motor_deg --model P1 --simulated " +
              (d / "run.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("inputs are never overwritten"), std::string::npos) << r.err;
  EXPECT_EQ(read(d / "run.csv"), rec);

  std::ofstream(d / "rig.toml") << "[contact]\nstiffness = 40\n";
  const std::string cfg = read(d / "rig.toml");
  r = run_cli("simulate --duration 0.1 --config " + (d / "rig.toml").string() + " -o " + (d / "rig.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(read(d / "rig.toml"), cfg);
}

TEST(DataSafetyCli, SimulateRefusesAnOutputNamedLikeItsSidecar) {
  const fs::path d = temp_dir("sidecar");
  const auto r = run_cli("simulate --duration 0.1 -o " + (d / "run.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(d / "run.json"));  // neither half was written
}

TEST(DataSafetyCli, AFailedWriteToStdoutIsAFailure) {
  for (const char* args : {"shape --method zv --frequency-hz 10 --zeta 0.1", "signal --type step --duration 0.1",
                           "shape --method zvd --frequency-hz 5 --zeta 0.05 --json"}) {
    const auto r = run_cli(std::string(args) + " > /dev/full");
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("standard output"), std::string::npos) << r.err;
  }
}

TEST(DataSafetyCli, NonFiniteAndNegativeOptionValuesAreRefusedByName) {
  auto r = run_cli("calibrate-rig --spread-weight nan");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--spread-weight"), std::string::npos) << r.err;
  r = run_cli("shape --method zv --frequency-hz inf --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frequency-hz"), std::string::npos) << r.err;
  r = run_cli("simulate --noise-seed -1 --duration 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--noise-seed: -1 is negative"), std::string::npos) << r.err;
  // The other wrapped counts of the report, and a message that named the internal truth.clearance_rad.
  r = run_cli("identify --data in.csv --input-column u --output-column y --model P1 --starts -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--starts: -1 is negative"), std::string::npos) << r.err;
  r = run_cli("modes --data in.csv --column y --from-sample -5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--from-sample: -5 is negative"), std::string::npos) << r.err;
  r = run_cli("simulate --clearance-deg -1 --duration 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--clearance-deg"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("clearance_rad"), std::string::npos) << r.err;
  // A NaN in a record is named by file, line and column before any algorithm (find_peaks) sees it.
  const fs::path d = temp_dir("nan_record");
  {
    std::ofstream csv(d / "rec.csv");
    csv << "time_s,y\n";
    for (int k = 0; k < 500; ++k) csv << k * 1e-3 << "," << (k == 100 ? "nan" : std::to_string(std::sin(60e-3 * k))) << "\n";
  }
  for (const char* cmd : {"recommend --data ", "modes --output-column y --data "}) {
    r = run_cli(std::string(cmd) + (d / "rec.csv").string() + (std::string(cmd).starts_with("rec") ? " --column y" : ""));
    EXPECT_EQ(r.exit_code, 2) << cmd;
    EXPECT_NE(r.err.find("rec.csv:102: field 'y'"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("find_peaks"), std::string::npos) << r.err;
  }
}

TEST(DataSafetyCli, UnknownSubcommandIsNamed) {
  const auto r = run_cli("bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown subcommand 'bogus'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("simulate"), std::string::npos) << r.err;
}

TEST(DataSafetyCli, ConfigThatIsAFolderIsAnError) {
  const fs::path d = temp_dir("cfgdir");
  const auto r = run_cli("simulate --duration 0.1 --config " + d.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
}

TEST(DataSafetyCli, PositionStepAtTimeZeroGoesThroughThePulseTrainCap) {
  const auto r = run_cli("simulate --amplitude 1e5 --duration 0.5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_GT(doc.at("limited_commands").get<int>(), 0);  // was 0: the step bypassed the 30 Hz updates
}

TEST(DataSafetyCli, FreshStudyKeepsTheUsersFilesAndRemovesStaleTemporaries) {
  const fs::path d = temp_dir("fresh");
  const std::string study = "study " + (studies() / "thesis-position.toml").string() + " --quick --out " + d.string();
  ASSERT_EQ(run_cli(study).exit_code, 0);
  std::ofstream(d / "data" / "my.csv") << "mine\n";
  std::ofstream(d / "runs" / "notes.json") << "{\"mine\": true}\n";
  std::ofstream(d / "runs" / "x.csv.tmp4242-1") << "half-written\n";
  const std::string first = read(d / "results.json");
  const auto r = run_cli(study + " --fresh");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read(d / "data" / "my.csv"), "mine\n");
  EXPECT_EQ(read(d / "runs" / "notes.json"), "{\"mine\": true}\n");
  EXPECT_FALSE(fs::exists(d / "runs" / "x.csv.tmp4242-1"));
  EXPECT_EQ(read(d / "results.json"), first);  // same bytes from scratch
  EXPECT_TRUE(fs::exists(d / "outputs.json"));
}

// Case 8: a protocol value no run accepts is refused before the study creates anything, with the
// file, line and key (it used to fail at the first run, leaving out/, data/ and runs/ behind).
TEST(DataSafetyCli, AProtocolValueNoRunAcceptsIsRefusedBeforeAnythingIsWritten) {
  const fs::path d = temp_dir("late");
  std::string text = read(studies() / "thesis-position.toml");
  const std::size_t at = text.find("sample_rate_hz = 1000.0");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 23, "sample_rate_hz = 0.001 ");
  std::ofstream(d / "p.toml") << text;
  const auto r = run_cli("study " + (d / "p.toml").string() + " --quick --out " + (d / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("p.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("study.sample_rate_hz"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out")) << "the study created its folder before refusing the protocol";
}

// Issue 21: an output folder that is a file (or lies under one) ended in a raw errno text
// ("cannot create directories: Not a directory", exit 1). Now exit 2 naming the file.
TEST(DataSafetyCli, AnOutputFolderThatIsAFileIsNamedAndExitsTwo) {
  const fs::path d = temp_dir("outfile");
  std::ofstream(d / "file") << "keep\n";
  const std::string file = (d / "file").string();
  const auto study = run_cli("study " + (studies() / "thesis-position.toml").string() + " --quick --out " + file);
  EXPECT_EQ(study.exit_code, 2) << study.err;
  EXPECT_NE(study.err.find(file + " is a file, not a folder, so " + file + "/data cannot be made in it"), std::string::npos)
      << study.err;
  const auto sweep = run_cli("sweep " + (studies() / "sweep-play.toml").string() + " --out " + file + "/sub");
  EXPECT_EQ(sweep.exit_code, 2) << sweep.err;
  EXPECT_NE(sweep.err.find("--out " + file + " is a file, not a folder"), std::string::npos) << sweep.err;
  const auto calibrate = run_cli("calibrate-rig --out " + file);
  EXPECT_EQ(calibrate.exit_code, 2) << calibrate.err;
  EXPECT_NE(calibrate.err.find("--out: " + file + " is a file, not a folder"), std::string::npos) << calibrate.err;
  for (const auto* r : {&study, &sweep, &calibrate}) EXPECT_EQ(r->err.find("Not a directory"), std::string::npos) << r->err;
  EXPECT_EQ(read(d / "file"), "keep\n");
}

TEST(DataSafetyCli, CeresLoggingIsQuietUnlessVerbose) {
  const fs::path d = temp_dir("glog");
  ASSERT_EQ(run_cli("simulate --duration 1 -o " + (d / "run.csv").string()).exit_code, 0);
  const auto r = run_cli("identify --data " + (d / "run.csv").string() + " --input-column command_deg --output-column motor_deg --model P3UZ");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("InitGoogleLogging"), std::string::npos) << r.err.substr(0, 400);
  EXPECT_LT(r.err.size(), 4000u) << r.err.substr(0, 400);
}

// Case 9 with an input that makes Ceres log: a P1D fit to a sinusoid drives the time constant
// negative, and Ceres reports every non-finite Jacobian ("Error in evaluating the ResidualBlock",
// ~150 kB here). --verbose shows those reports, so the quiet run's check can fail.
TEST(DataSafetyCli, CeresResidualBlockReportsAppearOnlyWithVerbose) {
  const fs::path d = temp_dir("glog_flood");
  {
    std::ofstream csv(d / "osc.csv");
    csv << "time_s,u,y\n";
    for (int k = 0; k < 1000; ++k) csv << k * 1e-3 << ",1," << std::sin(300.0 * k * 1e-3) << "\n";
  }
  const std::string cmd = "identify --data " + (d / "osc.csv").string() + " --input-column u --output-column y --model P1D";
  const auto quiet = run_cli(cmd);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err.substr(0, 400);
  EXPECT_EQ(quiet.err.find("ResidualBlock"), std::string::npos) << quiet.err.substr(0, 400);
  EXPECT_EQ(quiet.err.find("InitGoogleLogging"), std::string::npos) << quiet.err.substr(0, 400);
  EXPECT_LT(quiet.err.size(), 4000u);
  const auto verbose = run_cli(cmd + " --verbose");
  ASSERT_EQ(verbose.exit_code, 0);
  EXPECT_NE(verbose.err.find("ResidualBlock"), std::string::npos) << "the input no longer makes Ceres log";
}
