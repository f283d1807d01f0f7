// clearshape identify / modes: JSON fields and values on synthetic runs of the thesis speed model
// (Eq. 4.2) and a synthetic gyro free decay, cross-validation, column choice and file formats,
// per-sample frequencies, the DaISy robot arm (../shared/data) with a two-mode shaper designed
// from its identified resonances, and bad input → exit 2 with a clear message.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
namespace lti = clearshape::lti;
using clearshape::testing::run_cli;

namespace {

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("clearshape_identify_cli_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::json parse(const std::string& text) { return nlohmann::json::parse(text); }

// A run of the thesis speed model (time_s, command, speed_deg_s) with 1 % noise.
std::string write_run(const std::string& name, const std::vector<double>& u, std::uint64_t seed) {
  const double dt = 1e-3;
  const auto y = lti::simulate(lti::thesis_speed_mode_model(), clearshape::UniformSeries{0.0, dt, u});
  std::vector<double> out = y.values, time = y.times_s();
  double rms = 0.0;
  for (double v : out) rms += v * v;
  rms = std::sqrt(rms / static_cast<double>(out.size()));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  for (double& v : out) v += 0.01 * rms * nd(rng);
  const fs::path p = temp_path(name + ".csv");
  clearshape::io::write_csv(p, {"time_s", "command", "speed_deg_s"}, {&time, &u, &out});
  return p.string();
}

std::vector<double> step(std::size_t n) { return std::vector<double>(n, 1.0); }
std::vector<double> sine(std::size_t n) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = std::sin(2.0 * M_PI * 2.0 * static_cast<double>(k) * 1e-3);
  return u;
}
std::vector<double> prbs(std::size_t n) {
  std::mt19937_64 rng(5);
  std::vector<double> u(n);
  double level = 1.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k % 20 == 0 && (rng() & 1U)) level = -level;
    u[k] = level;
  }
  return u;
}

// Gyro rate after a move: 0.3 + 40 e^(−ζωn t) cos(ωd t + 0.4) + noise, 6.2 Hz, ζ = 0.03.
std::string write_gyro(bool with_time) {
  const fs::path p = temp_path(with_time ? "gyro.csv" : "gyro.dat");
  std::ofstream f(p);
  if (with_time) f << "time_s,link_rate_deg_s\n";
  std::mt19937_64 rng(2);
  std::normal_distribution<double> nd;
  const double wn = 2 * M_PI * 6.2, z = 0.03, wd = wn * std::sqrt(1 - z * z);
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 1e-3;
    const double v = 0.3 + 40 * std::exp(-z * wn * t) * std::cos(wd * t + 0.4) + nd(rng);
    if (with_time) {
      f << t << "," << v << "\n";
    } else {
      f << "  " << v << "\n";
    }
  }
  return p.string();
}

}  // namespace

TEST(IdentifyCli, JsonForTheThesisSpeedModel) {
  const std::string run = write_run("step", step(3001), 1);
  const auto r = run_cli("identify --model P3UZ --data " + run + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_TRUE(j.contains("schema_version"));
  EXPECT_EQ(j["model"], "P3UZ");
  const auto& p = j["parameters"];
  for (const char* name : {"Kp", "Tz", "Zeta", "Tw", "Tp3"}) {
    ASSERT_TRUE(p.contains(name)) << name;
    EXPECT_TRUE(p[name]["std"].is_number()) << name;
  }
  // Truth (Eq. 4.2) within 4σ of the estimate.
  const std::vector<std::pair<const char*, double>> truth = {
      {"Kp", 25.47}, {"Tz", -0.0398}, {"Zeta", 0.288}, {"Tw", 0.0479}, {"Tp3", 0.0857}};
  for (const auto& [name, value] : truth) {
    EXPECT_LT(std::abs(double(p[name]["value"]) - value), 4.0 * double(p[name]["std"])) << name;
  }
  EXPECT_GT(double(j["fit_percent"]), 90.0);
  EXPECT_NEAR(double(j["wn_rad_s"]), 1.0 / double(p["Tw"]["value"]), 1e-12);  // ωn = 1/Tw
  EXPECT_EQ(double(j["zeta"]), double(p["Zeta"]["value"]));                     // ζ = Zeta
  EXPECT_GT(double(j["poles_rad_s"][0]["re"]), -1e9);
  ASSERT_EQ(j["experiments"].size(), 1u);
  EXPECT_EQ(j["experiments"][0]["samples"], 3001);
  fs::remove(run);
}

TEST(IdentifyCli, TableFixAndSimulatedCsv) {
  const std::string run = write_run("fix", step(2001), 2);
  const std::string sim = temp_path("sim.csv").string();
  const auto r = run_cli("identify --data " + run + " --fix Tz=-0.04 --simulated " + sim);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Tz"), std::string::npos);
  EXPECT_NE(r.out.find("fixed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wn = 1/Tw"), std::string::npos) << r.out;
  const auto table = clearshape::io::read_table(sim);
  EXPECT_EQ(table.names, (std::vector<std::string>{"time_s", "input", "measured", "simulated"}));
  EXPECT_EQ(table.rows(), 2001u);
  fs::remove(run);
  fs::remove(sim);
}

TEST(IdentifyCli, CrossValidationMatrix) {
  const std::string a = write_run("cv_step", step(2001), 3), b = write_run("cv_sine", sine(2001), 4),
                    c = write_run("cv_prbs", prbs(2001), 5);
  const auto r = run_cli("identify --crossval --model P3UZ --data " + a + " --data " + b + " --data " + c + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  ASSERT_EQ(j["fit_percent_matrix"].size(), 3u);
  for (const auto& row : j["fit_percent_matrix"]) {
    ASSERT_EQ(row.size(), 3u);
    for (const auto& f : row) EXPECT_GT(double(f), 90.0);
  }
  EXPECT_LT(int(j["best"]["index"]), 3);
  EXPECT_EQ(j["models"].size(), 3u);
  EXPECT_TRUE(j.contains("joint"));
  // The human table marks the best row.
  const auto t = run_cli("identify --crossval --data " + a + " --data " + b);
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("<- best"), std::string::npos) << t.out;
  for (const auto& f : {a, b, c}) fs::remove(f);
}

TEST(IdentifyCli, WhitespaceWithoutHeaderNeedsSampleTime) {
  const fs::path p = temp_path("plain.dat");
  {
    const auto y = lti::simulate(lti::thesis_speed_mode_model(), clearshape::UniformSeries{0.0, 1e-3, prbs(1500)});
    const auto u = prbs(1500);
    std::ofstream f(p);
    for (std::size_t k = 0; k < u.size(); ++k) f << u[k] << "\t" << y.values[k] << "\n";
  }
  const auto no_time = run_cli("identify --data " + p.string());
  EXPECT_EQ(no_time.exit_code, 2);
  EXPECT_NE(no_time.err.find("--sample-time"), std::string::npos) << no_time.err;
  const auto r = run_cli("identify --data " + p.string() + " --sample-time 0.001 --input-column 1 --output-column 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_NEAR(double(j["parameters"]["Tw"]["value"]), 0.0479, 1e-6);  // noise-free
  EXPECT_NEAR(double(j["parameters"]["Tz"]["value"]), -0.0398, 1e-6);
  fs::remove(p);
}

TEST(IdentifyCli, BadInputExitsTwo) {
  const std::string run = write_run("bad", step(500), 6);
  const std::vector<std::string> cases = {"identify --data /nonexistent/run.csv", "identify --data " + run + " --fix Tz",
                                 "identify --data " + run + " --fix Tp1=0.1", "identify --data " + run + " --model Q3",
                                 "identify --data " + run + " --initial-state maybe",
                                 "identify --data " + run + " --output-column nope"};
  for (const std::string& args : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << args;
  }
  fs::remove(run);
}

TEST(ModesCli, FreeDecayWithTimeColumn) {
  const std::string g = write_gyro(true);
  const auto r = run_cli("modes --data " + g + " --output-column link_rate_deg_s --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_EQ(j["frequency_unit"], "Hz");
  EXPECT_NEAR(double(j["sample_time_s"]), 1e-3, 1e-12);
  ASSERT_EQ(j["modes"].size(), 1u);
  const auto& m = j["modes"][0];
  EXPECT_LT(std::abs(double(m["frequency_hz"]) - 6.2), 4.0 * double(m["frequency_std_hz"]));
  EXPECT_LT(std::abs(double(m["damping_ratio"]) - 0.03), 4.0 * double(m["damping_ratio_std"]));
  EXPECT_LT(std::abs(double(m["amplitude"]) - 40.0), 4.0 * double(m["amplitude_std"]));
  EXPECT_TRUE(j["shape_command"].get<std::string>().find("clearshape shape --method zvd --frequency-hz 6.") == 0)
      << j["shape_command"];
  fs::remove(g);
}

TEST(ModesCli, PerSampleWithoutSampleTime) {
  const std::string g = write_gyro(false);
  const auto r = run_cli("modes --data " + g + " --output-column 1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_EQ(j["frequency_unit"], "cycles/sample");
  EXPECT_TRUE(j["sample_time_s"].is_null());
  EXPECT_TRUE(j.contains("note"));
  EXPECT_NEAR(double(j["modes"][0]["frequency_cycles_per_sample"]), 6.2e-3, 1e-5);
  EXPECT_FALSE(j["modes"][0].contains("frequency_hz"));
  const auto table = run_cli("modes --data " + g + " --output-column 1");
  EXPECT_NE(table.out.find("cycles/sample"), std::string::npos) << table.out;
  // With the sample time the same record gives Hz.
  const auto hz = run_cli("modes --data " + g + " --output-column 1 --sample-time 0.001 --json");
  ASSERT_EQ(hz.exit_code, 0) << hz.err;
  EXPECT_NEAR(double(parse(hz.out)["modes"][0]["frequency_hz"]), 6.2, 0.01);
  const auto bad = run_cli("modes --data " + g + " --output-column 1 --modes 0");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  fs::remove(g);
}

// DaISy 96-009 (docs/design.md §5): two lightly damped resonances at 0.0582 and 0.1267
// cycles/sample; a two-mode shaper (ZVD ∗ ZVD, Crain et al. 1996) designed from them leaves no
// residual vibration at either mode (time unit: one sample).
TEST(ModesCli, DaisyRobotArmTwoModesAndTwoModeShaper) {
  const fs::path data = clearshape::testing::shared_path("data/daisy_robot_arm.dat");
  if (!fs::exists(data)) GTEST_SKIP() << data << " is absent (third-party data, not in the repository)";
  const auto r = run_cli("modes --data " + data.string() + " --input-column 1 --output-column 2 --modes 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  ASSERT_EQ(j["modes"].size(), 2u);
  EXPECT_EQ(j["frequency_unit"], "cycles/sample");
  std::vector<clearshape::shaping::Mode> modes;
  for (const auto& m : j["modes"]) {
    EXPECT_LT(double(m["damping_ratio"]), 0.01);
    modes.push_back({double(m["natural_frequency_rad_per_sample"]), double(m["damping_ratio"])});
  }
  std::sort(modes.begin(), modes.end(), [](auto& a, auto& b) { return a.natural_frequency_rad_s < b.natural_frequency_rad_s; });
  EXPECT_NEAR(modes[0].natural_frequency_hz(), 0.0582, 0.0006);
  EXPECT_NEAR(modes[1].natural_frequency_hz(), 0.1267, 0.0013);
  namespace sh = clearshape::shaping;
  const sh::Shaper two = sh::convolve(sh::design_zvd(modes[0]), sh::design_zvd(modes[1]));
  EXPECT_EQ(two.size(), 9u);
  for (const auto& m : modes) EXPECT_LT(sh::residual_vibration(two, m), 1e-9);
  // Unshaped, a step excites each mode fully (V = 1); ±5 % frequency error still leaves V small.
  for (const auto& m : modes) {
    EXPECT_LT(sh::residual_vibration(two, {m.natural_frequency_rad_s * 1.05, m.damping_ratio}), 0.05);
  }
}
