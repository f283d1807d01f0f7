// clearshape signal: success, CSV header and contents, JSON summary, bad input → exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {
fs::path temp_csv(const std::string& name) {
  return fs::temp_directory_path() / ("clearshape_signal_cli_" + std::to_string(::getpid()) + "_" + name);
}
std::string first_line(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  return line;
}
}  // namespace

TEST(SignalCli, PrintsASummaryTable) {
  const auto r = run_cli("signal --type step --amplitude 10 --start-s 0.5 --rise-s 0.2 --rise-shape s-curve --duration 1 --rate 100");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("signal                step"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("101 (100 Hz, 0 ... 1 s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max                   10"), std::string::npos) << r.out;
}

TEST(SignalCli, WritesCsvWithUnitSuffixedHeader) {
  const auto plain = temp_csv("plain.csv");
  auto r = run_cli("signal --type ramp --slope 2 --limit 1.5 --duration 1 --rate 10 -o " + plain.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(first_line(plain), "time_s,command");
  const auto t = clearshape::io::read_table(plain);
  ASSERT_EQ(t.rows(), 11u);
  EXPECT_DOUBLE_EQ(t.column("command")[5], 1.0);
  EXPECT_DOUBLE_EQ(t.column("command")[10], 1.5);

  const auto pos = temp_csv("position.csv");
  r = run_cli("signal --type step --amplitude 10 --start-s 0.1 --duration 1 --path position -o " + pos.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(first_line(pos), "time_s,command_deg,commanded_deg,pulse_frequency_hz");
  const auto tp = clearshape::io::read_table(pos);
  EXPECT_NEAR(tp.column("commanded_deg").back(), 83 * 360.0 / 3000.0, 1e-12);  // whole counts
  EXPECT_EQ(tp.column("pulse_frequency_hz")[80], 83 * 30.0);

  const auto spd = temp_csv("speed.csv");
  r = run_cli("signal --type sine --amplitude 1500 --frequency-hz 2 --unit deg_s --path speed --daq-scale 0.008 --duration 1 -o " + spd.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(first_line(spd), "time_s,command_deg_s,commanded_deg_s,daq_v");
  EXPECT_NE(r.err.find("372 sample(s) clipped"), std::string::npos) << r.err;
  for (const auto& p : {plain, pos, spd}) fs::remove(p);
}

TEST(SignalCli, JsonSummaryReportsSaturatedUpdates) {
  const auto r = run_cli("signal --type step --amplitude 90 --start-s 0.05 --duration 0.5 --path position --gear-ratio 0.02 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["type"], "step");
  EXPECT_EQ(doc["samples"], 501);
  EXPECT_DOUBLE_EQ(doc["sample_time_s"].get<double>(), 0.001);
  EXPECT_EQ(doc["max"], 90.0);
  EXPECT_EQ(doc["final"], 90.0);
  EXPECT_EQ(doc["path"]["saturated_updates"], 2);
  EXPECT_EQ(doc["path"]["final_count"], 37500);
  EXPECT_TRUE(doc.contains("schema_version"));
  EXPECT_NE(r.err.find("pulse cap"), std::string::npos) << r.err;

  const auto p = run_cli("signal --type prbs --order 7 --bit-period-s 0.02 --amplitude 50 --seed 3 --unit deg_s --json");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const auto d = nlohmann::json::parse(p.out);
  EXPECT_EQ(d["min"], -50.0);
  EXPECT_EQ(d["max"], 50.0);
  EXPECT_EQ(d["parameters"]["order"], 7.0);
  EXPECT_EQ(d["path"], "none");
}

TEST(SignalCli, BadInputExitsWithTwoAndNamesTheOption) {
  const struct {
    const char* args;
    const char* message;
  } cases[] = {
      {"signal --type sawtooth", "sawtooth"},
      {"signal --type step --rise-s -1", "--rise-s = -1 is out of range; allowed: finite and >= 0"},
      {"signal --type step --slope 2", "--slope does not apply to --type step; it takes: --amplitude"},
      {"signal --type prbs --order 40", "order = 40"},
      {"signal --type prbs --order 4 --seed 16", "allowed: an integer in [1, 15]"},
      {"signal --type stacked-steps --levels 1,x,3", "item 'x' is not a number"},
      {"signal --type step --path position --unit V", "--unit V cannot drive --path position"},
      {"signal --type step --path position --daq-scale 2", "--daq-scale applies to --path speed only"},
      {"signal --type step --update-hz 30", "--update-hz applies to --path position only"},
      {"signal --type step --path position --update-hz -5", "--update-hz = -5"},
      {"signal --type step --rate 0", "--rate = 0"},
      {"signal --type step --rate 1e6 --duration 100", "<= 1e7 samples"},
      {"signal --type step --amplitude abc", "amplitude"},
      {"signal --amplitude 1", "--type"},
  };
  for (const auto& c : cases) {
    const auto r = run_cli(std::string(c.args) + " --output /nonexistent_dir_should_not_be_written/x.csv");
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args;
  }
}
