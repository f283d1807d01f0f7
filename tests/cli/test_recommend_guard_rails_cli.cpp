// `clearshape recommend`'s guard rails (issue 20): a record of pure noise is refused with exit 1
// and what to record instead; the same record with time in ms gives the same design; a pick
// leaving more than --max-remaining is warned about in the table, the JSON and on stderr.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::golden_path;
using clearshape::testing::process_temp_path;
using clearshape::testing::run_cli;

namespace {

std::string golden(const std::string& name) { return golden_path(name).string(); }

// The golden one-mode record (400 Hz) rewritten with its time column multiplied by `scale`.
std::string one_mode_with_time_scale(double scale, const std::string& time_name) {
  const auto path = process_temp_path("recommend_guard_" + time_name + ".csv");
  std::ifstream in(golden_path("recommend_one_mode.csv"));
  std::ofstream out(path);
  std::string line;
  std::getline(in, line);
  out << time_name << ",gyro_deg_s\n";
  for (std::size_t k = 0; std::getline(in, line); ++k) {
    out << fmt::format("{:.17g},{}\n", static_cast<double>(k) * 0.0025 * scale, line.substr(line.find(',') + 1));
  }
  return path.string();
}

}  // namespace

TEST(RecommendGuardRailsCli, PureNoiseIsRefusedWithWhatToRecord) {
  const auto path = process_temp_path("recommend_guard_noise.csv");
  {
    std::ofstream out(path);
    out << "time_s,gyro_deg_s\n";
    std::mt19937_64 rng(20);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int k = 0; k < 3000; ++k) out << fmt::format("{:.3f},{:.6f}\n", k * 0.001, noise(rng));
  }
  const auto r = run_cli("recommend --data " + path.string() + " --column gyro_deg_s");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.err.find("no usable resonance in " + path.string() + ": "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("free decay"), std::string::npos) << r.err;
  std::filesystem::remove(path);
}

TEST(RecommendGuardRailsCli, TimeInMillisecondsGivesTheSameDesign) {
  const std::string s = one_mode_with_time_scale(1.0, "time_s"), ms = one_mode_with_time_scale(1000.0, "time_ms");
  const auto a = run_cli("recommend --data " + s + " --column gyro_deg_s --json");
  const auto b = run_cli("recommend --data " + ms + " --column gyro_deg_s --time-column time_ms --json");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  ASSERT_TRUE(ja["recommendation"].is_object());
  EXPECT_EQ(ja["recommendation"]["name"], jb["recommendation"]["name"]);
  const double fa = ja["recommendation"]["design_frequency_hz"][0].get<double>();
  const double fb = jb["recommendation"]["design_frequency_hz"][0].get<double>();
  EXPECT_NEAR(fb * 1000.0, fa, 1e-6 * fa);
  EXPECT_NEAR(jb["recommendation"]["duration_s"].get<double>() / 1000.0, ja["recommendation"]["duration_s"].get<double>(),
              1e-6 * ja["recommendation"]["duration_s"].get<double>());
  std::filesystem::remove(s);
  std::filesystem::remove(ms);
}

TEST(RecommendGuardRailsCli, APickBeyondMaxRemainingIsWarnedAbout) {
  const std::string base = "recommend --data " + golden("recommend_two_modes.csv") + " --column gyro_deg_s --candidates zv";
  const auto j = run_cli(base + " --max-remaining 0.001 --json");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_NE(j.err.find("warning: ZV leaves"), std::string::npos) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_TRUE(doc["candidates"][0]["leaves_too_much"].get<bool>());
  EXPECT_TRUE(doc["recommendation"]["warning"].is_string());
  EXPECT_DOUBLE_EQ(doc["scoring"]["max_remaining"].get<double>(), 0.001);
  const auto t = run_cli(base + " --max-remaining 0.001");
  EXPECT_NE(t.out.find("warning: ZV leaves"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find(" !"), std::string::npos) << t.out;
  const auto ok = run_cli(base + " --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto fine = nlohmann::json::parse(ok.out);
  EXPECT_EQ(fine["recommendation"]["warning"].is_null(), fine["recommendation"]["remaining_worst"].get<double>() <= 0.2);
  const auto bad = run_cli(base + " --max-remaining 1.5");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--max-remaining"), std::string::npos) << bad.err;
}
