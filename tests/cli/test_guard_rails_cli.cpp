// The guard rails of `identify` on the command line: a speed-mode model fitted to an angle is
// flagged (stderr, "trusted": false, the suggested options), --derivative --butterworth fit the
// speed instead; a good fit says "trusted": true. Exit status 0 either way (docs/recordings.md).
#include <unistd.h>

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
