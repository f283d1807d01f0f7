// `clearshape study --recordings` on recordings with a unit mistake: exit 2 with the file, the
// column and the likely fix, never a report (docs/recordings.md "Unit mistakes the reader
// catches"). The audit's case — a gyro in deg/s declared rad/s — used to exit 0 with an unshaped
// MD of 23.9° and 3° of play. Each case stops at the first stage that reads a run (< 1 s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <fmt/format.h>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Three 20° step recordings (6 s at 1 kHz; the link follows the motor exactly) of the quick
// thesis protocol, written with `format_row` (t, command, motor, link rate in deg/s), the
// manifest's [columns] block `columns`.
std::filesystem::path write_folder(const std::string& name, const std::string& header, const std::string& columns,
                                   const std::function<std::string(double, double, double, double)>& format_row) {
  const auto dir = clearshape::testing::fresh_temp_dir(name);
  std::string manifest = "format = \"clearshape-recordings/1\"\n[columns]\n" + columns;
  for (int r = 1; r <= 3; ++r) {
    const std::string file = fmt::format("step-{}.csv", r);
    std::ofstream out(dir / file);
    out << header << "\n";
    for (int k = 0; k <= 6000; ++k) {
      const double t = 1e-3 * k;
      const double u = std::clamp((t - 0.5) / 0.1, 0.0, 1.0);
      const double angle = 20.0 * 0.5 * (1.0 - std::cos(kPi * u));
      const double rate = (u > 0.0 && u < 1.0) ? 20.0 * 0.5 * kPi / 0.1 * std::sin(kPi * u) : 0.0;
      out << format_row(t, t >= 0.5 ? 20.0 : 0.0, angle, rate) << "\n";
    }
    manifest += fmt::format("[[run]]\nid = \"unshaped/step-20/r0{}\"\nfile = \"{}\"\n", r, file);
  }
  std::ofstream(dir / "manifest.toml") << manifest;
  return dir;
}

std::string study(const std::filesystem::path& dir, int expected_exit) {
  const auto proto = clearshape::testing::studies_path("thesis-position.toml");
  const auto r = run_cli(fmt::format("study {} --quick --recordings {} --out {}", proto.string(), dir.string(),
                                     (dir / "out").string()));
  EXPECT_EQ(r.exit_code, expected_exit) << r.err;
  return r.err;
}

const char* const kHeader = "time_s,command_deg,command_applied_deg,motor_angle_deg,link_rate_deg_s";

std::string plain(double t, double c, double a, double w) { return fmt::format("{},{},{},{},{}", t, c, c, a, w); }

}  // namespace

TEST(RecordingUnitsCli, GyroInDegPerSecondDeclaredRadPerSecondIsExitTwoWithTheFix) {
  const auto dir = write_folder("clearshape_cli_units_gyro", kHeader, "link_rate_unit = \"rad/s\"\n", plain);
  const std::string err = study(dir, 2);
  EXPECT_NE(err.find("step-"), std::string::npos) << err;
  EXPECT_NE(err.find("field 'link_rate_deg_s'"), std::string::npos) << err;
  EXPECT_NE(err.find("ratio 57.2"), std::string::npos) << err;
  EXPECT_NE(err.find("declared rad/s, looks like deg/s: set link_rate_unit = \"deg/s\""), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "results.json"));
  // The same folder declared right is read (the check does not refuse a consistent recording).
  const auto good = write_folder("clearshape_cli_units_good", kHeader, "", plain);
  study(good, 0);
  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(good);
}

TEST(RecordingUnitsCli, TimeInMillisecondsIsExitTwoWithTheFix) {
  const auto dir = write_folder("clearshape_cli_units_ms", kHeader, "",
                                [](double t, double c, double a, double w) { return plain(t * 1e3, c, a, w); });
  const std::string err = study(dir, 2);
  EXPECT_NE(err.find("field 'time_s'"), std::string::npos) << err;
  EXPECT_NE(err.find("declared s, looks like ms: set time_unit = \"ms\""), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

TEST(RecordingUnitsCli, DecimalCommasAreExitTwoWithTheFix) {
  std::string header = kHeader;
  std::replace(header.begin(), header.end(), ',', ';');
  const auto dir = write_folder("clearshape_cli_units_comma", header, "", [](double t, double c, double a, double w) {
    std::string row = fmt::format("{:.3f};{:.1f};{:.1f};{:.6f};{:.6f}", t, c, c, a, w);
    std::replace(row.begin(), row.end(), '.', ',');
    return row;
  });
  const std::string err = study(dir, 2);
  EXPECT_NE(err.find(".csv:2"), std::string::npos) << err;
  EXPECT_NE(err.find("'0,000' uses a decimal comma"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}
