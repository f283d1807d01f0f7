// `clearshape modes` refuses poles that are no modes (issue 20): a growing oscillation (ζ < 0) and
// a pole near the Nyquist frequency are flagged "stable": false and exit 1, unless
// --allow-unstable; a decaying mode is "stable": true with exit 0.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/units.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::process_temp_path;
using clearshape::testing::run_cli;

namespace {

// y[k] = exp(σ·k·dt)·cos(2π f k dt), 1 kHz, 2 s: σ < 0 decays, σ > 0 grows.
std::string write_oscillation(const std::string& name, double f_hz, double sigma_per_s) {
  const auto path = process_temp_path("modes_stability_" + name + ".csv");
  std::ofstream out(path);
  out << "time_s,rate_deg_s\n";
  const double dt = 1e-3;
  for (int k = 0; k < 2000; ++k) {
    const double t = k * dt;
    out << fmt::format("{:.3f},{:.12g}\n", t, std::exp(sigma_per_s * t) * std::cos(clearshape::kTwoPi * f_hz * t));
  }
  return path.string();
}

}  // namespace

TEST(ModesStabilityCli, ADecayingModeIsStable) {
  const std::string path = write_oscillation("decay", 12.0, -0.08 * clearshape::kTwoPi * 12.0);
  const auto r = run_cli("modes --data " + path + " --output-column rate_deg_s --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["modes"][0]["frequency_hz"].get<double>(), 12.0, 0.05);
  EXPECT_TRUE(j["modes"][0]["stable"].get<bool>());
  EXPECT_TRUE(j["modes"][0]["stability_note"].is_null());
  std::filesystem::remove(path);
}

TEST(ModesStabilityCli, AGrowingOscillationIsNotStable) {
  const std::string path = write_oscillation("growing", 12.0, +0.3);
  const auto r = run_cli("modes --data " + path + " --output-column rate_deg_s --json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("mode 1 is not stable"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--allow-unstable"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["modes"][0]["damping_ratio"].get<double>(), 0.0);
  EXPECT_FALSE(j["modes"][0]["stable"].get<bool>());
  EXPECT_FALSE(j["trusted"].get<bool>());
  const auto allowed = run_cli("modes --data " + path + " --output-column rate_deg_s --allow-unstable");
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
  EXPECT_NE(allowed.out.find("NOT STABLE"), std::string::npos) << allowed.out;
  std::filesystem::remove(path);
}

TEST(ModesStabilityCli, APoleNearNyquistIsNotStable) {
  const std::string path = write_oscillation("nyquist", 470.0, -0.02 * clearshape::kTwoPi * 470.0);  // 94 % of 500 Hz
  const auto r = run_cli("modes --data " + path + " --output-column rate_deg_s --json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("Nyquist"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["modes"][0]["stable"].get<bool>());
  std::filesystem::remove(path);
}

// Issue 21: a record whose values overflow its spectrum (a growth to e^400 here) ended as
// "find_peaks: value 0 is not finite (inf)", an internal name. Now exit 2 naming the sample and
// the bound: √DBL_MAX / n, the largest |y| for which no sum of n products of samples overflows.
TEST(ModesStabilityCli, ValuesTooLargeForASpectrumAreRefusedWithTheBound) {
  const std::string path = write_oscillation("huge", 12.0, 200.0);
  const auto r = run_cli("modes --data " + path + " --output-column rate_deg_s");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is too large: its spectrum would overflow"), std::string::npos) << r.err;
  const std::string bound = fmt::format("allowed: |value| <= {:.3g} for a record of 2000 samples",
                                        std::sqrt(std::numeric_limits<double>::max()) / 2000.0);
  EXPECT_NE(r.err.find(bound), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("find_peaks"), std::string::npos) << r.err;
}
