// `clearshape recommend`: each input format (clearshape CSV, Klipper raw accelerometer CSV,
// Klipper PSD CSV), the --json schema, the deterministic --plot PNG, and each error with its
// exit code and a message naming file, line, field or option.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::golden_path;
using clearshape::testing::read_bytes;
using clearshape::testing::run_cli;

namespace {

std::string golden(const std::string& name) { return golden_path(name).string(); }

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("recommend_cli_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::json json_of(const std::string& args) {
  const auto r = run_cli("recommend " + args + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST(RecommendCli, TableInputPrintsTheTableAndTheChoice) {
  const auto r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --candidates zv,zvd,ei");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("mode 1 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("remaining_%"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("recommended: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("clearshape shape --method"), std::string::npos) << r.out;
}

TEST(RecommendCli, JsonSchema) {
  const auto j = json_of("--data " + golden("recommend_two_modes.csv") + " --column gyro_deg_s --candidates zv,mzv,zv*zv --max-delay-s 0.2");
  EXPECT_TRUE(j.contains("schema_version"));
  EXPECT_EQ(j["command"], "recommend");
  ASSERT_EQ(j["inputs"].size(), 1u);
  EXPECT_EQ(j["inputs"][0]["format"], "table");
  EXPECT_EQ(j["inputs"][0]["column"], "gyro_deg_s");
  ASSERT_EQ(j["modes"].size(), 2u);
  for (const auto& m : j["modes"]) {
    for (const char* k : {"frequency_hz", "frequency_std_hz", "damping_ratio", "damping_ratio_std", "source"}) EXPECT_TRUE(m.contains(k)) << k;
  }
  EXPECT_TRUE(j["free_decay"].contains("used"));
  EXPECT_EQ(j["scoring"]["test_damping_ratios"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["scoring"]["max_delay_s"].get<double>(), 0.2);
  ASSERT_EQ(j["candidates"].size(), 3u);
  for (const auto& c : j["candidates"]) {
    for (const char* k : {"name", "available", "design_frequency_hz", "duration_s", "remaining_worst", "remaining_nominal", "impulses",
                          "within_budget"}) {
      EXPECT_TRUE(c.contains(k)) << c["name"] << " " << k;
    }
  }
  EXPECT_EQ(j["candidates"][2]["design_frequency_hz"].size(), 2u);
  ASSERT_TRUE(j["recommendation"].is_object());
  EXPECT_LE(j["recommendation"]["duration_s"].get<double>(), 0.2);
  EXPECT_FALSE(j["reason"].get<std::string>().empty());
}

TEST(RecommendCli, KlipperRawAndPsdInputs) {
  const auto raw = json_of("--data " + golden("recommend_klipper_raw.csv") + " --column accel_x --modes 1 --candidates zv,mzv");
  EXPECT_EQ(raw["inputs"][0]["format"], "klipper-accelerometer");
  EXPECT_NEAR(raw["modes"][0]["frequency_hz"].get<double>(), 42.0, 3.0 * raw["modes"][0]["frequency_std_hz"].get<double>());
  const auto sum = json_of("--data " + golden("recommend_klipper_raw.csv") + " --candidates zv,mzv");
  EXPECT_EQ(sum["inputs"][0]["column"], "xyz");
  const auto psd = json_of("--data " + golden("recommend_klipper_raw_psd.csv") + " --column psd_xyz --candidates zv,mzv");
  EXPECT_EQ(psd["inputs"][0]["format"], "klipper-psd");
  // The PSD file is SciPy's spectrum of the raw file: the same modes.
  EXPECT_NEAR(psd["modes"][0]["frequency_hz"].get<double>(), sum["modes"][0]["frequency_hz"].get<double>(), 1e-6);
  // Several recordings: the worst case over them.
  const auto both = json_of("--data " + golden("recommend_one_mode.csv") + " --data " + golden("recommend_decay.csv") +
                            " --column gyro_deg_s --candidates zv");
  EXPECT_EQ(both["inputs"].size(), 2u);
}

TEST(RecommendCli, FreeDecayWindowUsesTheFit) {
  const auto j = json_of("--data " + golden("recommend_decay.csv") + " --column gyro_deg_s --from-s 0 --to-s 2 --candidates zv,ei");
  EXPECT_TRUE(j["free_decay"]["used"].get<bool>()) << j["free_decay"]["note"];
  EXPECT_EQ(j["modes"][0]["source"], "free-decay fit");
  EXPECT_NEAR(j["modes"][0]["frequency_hz"].get<double>(), 14.955, 0.1);
}

TEST(RecommendCli, PlotIsAPngAndDeterministic) {
  const auto a = temp("a.png"), b = temp("b.png");
  const std::string args = "recommend --data " + golden("recommend_two_modes.csv") + " --column gyro_deg_s --candidates zv,mzv,ei,zv*zv";
  const auto r1 = run_cli(args + " --plot " + a.string());
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  const auto r2 = run_cli(args + " --plot " + b.string());
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const std::string pa = read_bytes(a), pb = read_bytes(b);
  ASSERT_GT(pa.size(), 1000u);
  EXPECT_EQ(pa.substr(1, 3), "PNG");
  EXPECT_TRUE(pa == pb) << "the PNG differs between two identical runs";
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}

TEST(RecommendCli, ErrorsNameWhatIsWrong) {
  const std::string bad = temp("bad.csv").string();
  std::ofstream(bad) << "#time,accel_x,accel_y,accel_z\n0.000,1,2,3\n0.001,1,x2,3\n";
  auto r = run_cli("recommend --data " + bad + " --column accel_x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("accel_y"), std::string::npos) << r.err;
  std::filesystem::remove(bad);

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--column"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nope"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_klipper_raw.csv") + " --column psd_q");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("accel_x"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --damping-range 0.2,0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--damping-range"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --max-delay-s -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--max-delay-s"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --candidates zv,bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bogus"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --plot out.svg");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--plot"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --from-s 100");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--from-s"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode_psd.csv") + " --column psd_x --from-s 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("PSD file"), std::string::npos) << r.err;

  r = run_cli("recommend --data /nonexistent/file.csv --column x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/file.csv"), std::string::npos) << r.err;

  r = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --modes 3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--modes"), std::string::npos) << r.err;

  // The plot may never overwrite an input.
  const std::string copy = temp("in.png").string();
  std::filesystem::copy_file(golden("recommend_one_mode.csv"), copy, std::filesystem::copy_options::overwrite_existing);
  r = run_cli("recommend --data " + copy + " --column gyro_deg_s --candidates zv --plot " + copy);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(read_bytes(copy), read_bytes(golden("recommend_one_mode.csv")));
  std::filesystem::remove(copy);
}

// Issue 21: a record whose values overflow the power spectrum (here 1e200, a wrong unit) ended
// as "find_peaks: value 0 is not finite (inf)", an internal name; `--max-delay-s ""` was read as
// 0. Both now exit 2 naming the file and column, or the option.
TEST(RecommendCli, ValuesTooLargeForASpectrumAndAnEmptyOptionAreNamed) {
  const auto csv = temp("huge.csv");
  {
    std::ofstream f(csv);
    f << "time_s,gyro_deg_s\n";
    for (int k = 0; k < 2000; ++k) f << k * 1e-3 << "," << (k % 50 < 25 ? 1e200 : -1e200) << "\n";
  }
  const auto r = run_cli("recommend --data " + csv.string() + " --column gyro_deg_s");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(csv.string() + ":2: field 'gyro_deg_s': value 1e+200 at t = 0 s is too large for a power spectrum"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find("allowed: |value| <= "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("find_peaks"), std::string::npos) << r.err;
  std::filesystem::remove(csv);

  const auto empty = run_cli("recommend --data " + golden("recommend_one_mode.csv") + " --column gyro_deg_s --max-delay-s \"\"");
  EXPECT_EQ(empty.exit_code, 2) << empty.err;
  EXPECT_NE(empty.err.find("--max-delay-s: an empty value is not a number"), std::string::npos) << empty.err;
}
