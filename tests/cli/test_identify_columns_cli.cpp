// `clearshape identify` says which columns it used and refuses a pair whose output only converts
// the input (issue 20): a recording's command and applied command (the pulse train's 30 Hz hold,
// 0.12° steps) give exit 2 naming the other columns; the motor angle is identified.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/io/table.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace lti = clearshape::lti;
using clearshape::testing::process_temp_path;
using clearshape::testing::run_cli;

namespace {

// time_s, command_deg (a 20° step ramped over 33 ms at 0.5 s), command_applied_deg (held at the
// 30 Hz updates, quantised to 0.12°), motor_angle_deg (the thesis position model's response).
std::string write_recording() {
  const double dt = 1e-3;
  const std::size_t n = 3000;
  std::vector<double> u(n), applied(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = 20.0 * std::clamp((static_cast<double>(k) - 500.0) / 33.0, 0.0, 1.0);
  for (std::size_t k = 0; k < n; ++k) applied[k] = 0.12 * std::round(u[(k / 33) * 33] / 0.12);
  const auto y = lti::simulate(lti::thesis_position_mode_model(), clearshape::UniformSeries{0.0, dt, applied});
  std::vector<double> time = y.times_s(), angle = y.values;
  const auto p = process_temp_path("identify_columns.csv");
  clearshape::io::write_csv(p, {"time_s", "command_deg", "command_applied_deg", "motor_angle_deg"}, {&time, &u, &applied, &angle});
  return p.string();
}

}  // namespace

TEST(IdentifyColumnsCli, TheAppliedCommandIsRefusedAndTheMappingPrinted) {
  const std::string path = write_recording();
  const auto r = run_cli("identify --data " + path);
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("input 'command_deg' (column 2), output 'command_applied_deg' (column 3), time 'time_s' (column 1)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("output 'command_applied_deg' is input 'command_deg' through a converter"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("motor_angle_deg"), std::string::npos) << r.err;  // the column to give instead

  const auto ok = run_cli("identify --model P2U --data " + path + " --output-column motor_angle_deg --json");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.err.find("output 'motor_angle_deg' (column 4)"), std::string::npos) << ok.err;
  std::filesystem::remove(path);
}
