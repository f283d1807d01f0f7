// The guard rails of `identify` on the command line: a speed-mode model fitted to an angle is
// flagged (stderr, "trusted": false, the suggested options), --derivative --butterworth fit the
// speed instead; a good fit says "trusted": true. Exit status 0 either way (docs/recordings.md).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;
namespace lti = clearshape::lti;
using clearshape::testing::run_cli;

namespace {

// The thesis speed model (Eq. 4.2, V → deg/s) under a 1 V step; its speed and its angle.
std::string write_speed_run() {
  const double dt = 1e-3;
  std::vector<double> u(3001, 0.0);
  for (std::size_t k = 200; k < u.size(); ++k) u[k] = 1.0;
  const auto y = lti::simulate(lti::thesis_speed_mode_model(), clearshape::UniformSeries{0.0, dt, u});
  std::vector<double> angle(u.size(), 0.0), time = y.times_s();
  for (std::size_t k = 1; k < u.size(); ++k) angle[k] = angle[k - 1] + dt * y.values[k];
  const fs::path p = fs::temp_directory_path() / ("clearshape_guard_rails_" + std::to_string(::getpid()) + ".csv");
  clearshape::io::write_csv(p, {"time_s", "command_v", "motor_speed_deg_s", "motor_angle_deg"}, {&time, &u, &y.values, &angle});
  return p.string();
}

}  // namespace

TEST(GuardRailsCli, SpeedModelOnAnAngleIsFlaggedAndTheDerivativeFixesIt) {
  const std::string run = write_speed_run();
  const auto good = run_cli("identify --model P3UZ --data " + run + " --input-column command_v --output-column motor_speed_deg_s --json");
  ASSERT_EQ(good.exit_code, 0) << good.err;
  EXPECT_TRUE(nlohmann::json::parse(good.out).at("trusted").get<bool>()) << good.out;
  EXPECT_EQ(good.err.find("warning"), std::string::npos) << good.err;

  const auto angle = run_cli("identify --model P3UZ --data " + run + " --input-column command_v --output-column motor_angle_deg --json");
  ASSERT_EQ(angle.exit_code, 0) << angle.err;  // done, but flagged
  const auto j = nlohmann::json::parse(angle.out);
  EXPECT_FALSE(j.at("trusted").get<bool>());
  EXPECT_NE(angle.err.find("fitted to an angle"), std::string::npos) << angle.err;
  EXPECT_NE(angle.err.find("--derivative --butterworth 30rad/s"), std::string::npos) << angle.err;
  EXPECT_NE(angle.err.find("NOT to be trusted"), std::string::npos) << angle.err;

  // The thesis's chain on the angle: the speed model again (the filter's lag is in the model).
  const auto fixed = run_cli("identify --model P3UZ --data " + run +
                             " --input-column command_v --output-column motor_angle_deg --derivative --butterworth 30rad/s --json");
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  const auto f = nlohmann::json::parse(fixed.out);
  EXPECT_EQ(fixed.err.find("fitted to an angle"), std::string::npos) << fixed.err;
  EXPECT_GT(f.at("fit_percent").get<double>(), 90.0);
  EXPECT_EQ(run_cli("identify --model P3UZ --data " + run + " --derivative --butterworth 30").exit_code, 2);  // no unit
  fs::remove(run);
}

namespace {

// A 5 Hz, ζ = 0.05 free decay from 0.5 s at 1 kHz with white noise of `noise` (seeded).
std::string write_decay(const std::string& name, double noise) {
  std::vector<double> t(3001), y(3001);
  std::uint64_t state = 12345;
  for (std::size_t k = 0; k < t.size(); ++k) {
    t[k] = static_cast<double>(k) * 1e-3;
    const double tau = t[k] - 0.5;
    const double wn = 2.0 * M_PI * 5.0;
    y[k] = tau >= 0.0 ? std::exp(-0.05 * wn * tau) * std::cos(wn * std::sqrt(1.0 - 0.0025) * tau) : 0.0;
    // Uniform noise from a 64-bit LCG (Knuth MMIX constants), variance noise²/3.
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    y[k] += noise * (2.0 * static_cast<double>(state >> 11) / 9007199254740992.0 - 1.0);
  }
  const fs::path p = fs::temp_directory_path() / ("clearshape_guard_rails_" + name + std::to_string(::getpid()) + ".csv");
  clearshape::io::write_csv(p, {"Time", "rate_deg_s"}, {&t, &y});
  return p.string();
}

}  // namespace

TEST(GuardRailsCli, ModesWindowInSecondsAndAPoorFitFlagged) {
  const std::string clean = write_decay("clean", 0.002);
  const auto r = run_cli("modes --data " + clean + " --output-column rate_deg_s --from-s 0.5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("window").at("from_sample"), 500);  // "Time" is found by the shared time-column defaults
  EXPECT_NEAR(j.at("modes")[0].at("frequency_hz").get<double>(), 5.0, 0.01);
  EXPECT_TRUE(j.at("trusted").get<bool>()) << j.at("warnings");

  const std::string noisy = write_decay("noisy", 1.0);
  const auto n = run_cli("modes --data " + noisy + " --output-column rate_deg_s --from-s 0.5 --to-s 3 --json");
  ASSERT_EQ(n.exit_code, 0) << n.err;  // done, but flagged
  EXPECT_FALSE(nlohmann::json::parse(n.out).at("trusted").get<bool>());
  EXPECT_NE(n.err.find("poor fit"), std::string::npos) << n.err;
  // Seconds and samples together, or seconds without a time base: exit 2.
  EXPECT_EQ(run_cli("modes --data " + clean + " --output-column rate_deg_s --from-s 0.5 --from-sample 3").exit_code, 2);
  EXPECT_EQ(run_cli("modes --data " + clean + " --output-column rate_deg_s --from-s 9").exit_code, 2);
  fs::remove(clean);
  fs::remove(noisy);
}

TEST(GuardRailsCli, IdentifyWindowInSeconds) {
  const std::string run = write_speed_run();
  // The step starts at 0.2 s; the window from 0.1 s to 2.5 s keeps it and fits the model again.
  const auto r = run_cli("identify --model P3UZ --data " + run +
                         " --input-column command_v --output-column motor_speed_deg_s --from-s 0.1 --to-s 2.5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("experiments")[0].at("samples"), 2400);
  EXPECT_NEAR(j.at("parameters").at("Kp").at("value").get<double>(), 25.47, 0.05);
  EXPECT_EQ(run_cli("identify --model P3UZ --data " + run + " --from-s 2 --to-s 1").exit_code, 2);
  fs::remove(run);
}
