// The study end to end on the physical-rig path without hardware: `clearshape study
// tests/rig/study-emulator.toml --rig serial:PTY` against clearshape-rig-emulator (the firmware
// ELF in simavr, the thesis plant behind its pins), compared with the same protocol on the
// simulated thesis rig (`--rig thesis`, the emulator's plant). Skipped when the emulator was
// not built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "emulator_process.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path protocol_path() { return fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path() / "rig" / "study-emulator.toml"; }

json load(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

const json* find_table(const json& results, const std::string& id) {
  for (const json& t : results.at("tables")) {
    if (t.at("id") == id) return &t;
  }
  return nullptr;
}

const json* find_column(const json& table, const std::string& key) {
  for (const json& c : table.at("columns")) {
    if (c.at("key") == key) return &c;
  }
  return nullptr;
}

TEST(StudyOnTheEmulator, MatchesTheSimulatedRigWithinTheTrialsSpread) {
  if (!fs::exists(clearshape::test::emulator_path())) GTEST_SKIP() << "clearshape-rig-emulator was not built";
  const fs::path dir = fs::temp_directory_path() / ("clearshape-study-emulator-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Gyro noise on (seeded), as on the simulated rig. Paced at real time, as a board runs: a
  // free-running board gets ahead of the host by more than the study's 100 ms command
  // watchdog. (Before the board applied COMMANDs by their tick, COMMAND_LATENCY_TICKS in
  // firmware/main.c, a shaper impulse on the 30 Hz update grid made its update or the next one
  // depending on the host's sub-millisecond round trip: Eq. 5.1 with ZVDD 0.1–0.2° instead of
  // 0.02° in some trials.)
  // A run is degraded beyond 1 % of samples later than 5 ms on the host's clock (issue 21); the
  // emulator on a loaded host runs slower than real time, so the host's clock sees its samples
  // late although the commands answer them in time on the board's own clock: a wider tolerance
  // (serial:PORT?max_late_fraction=F) keeps this comparison about the firmware.
  clearshape::test::EmulatorProcess emulator({"--speed", "1", "--seed", "7"});
  ASSERT_FALSE(emulator.path().empty());
  const auto physical = clearshape::testing::run_cli("study '" + protocol_path().string() + "' --rig 'serial:" +
                                                     emulator.path() + "?max_late_fraction=0.5' --out '" +
                                                     (dir / "emulator").string() + "'");
  ASSERT_EQ(physical.exit_code, 0) << physical.err;
  const auto simulated = clearshape::testing::run_cli("study '" + protocol_path().string() + "' --rig thesis --out '" +
                                                      (dir / "sim").string() + "'");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;

  const json a = load(dir / "emulator" / "results.json");
  const json b = load(dir / "sim" / "results.json");
  EXPECT_EQ(a.at("rig").at("kind"), "physical");
  EXPECT_NE(a.at("rig").at("description").get<std::string>().find("serial:"), std::string::npos);
  EXPECT_EQ(b.at("rig").at("kind"), "simulated-thesis");

  // The link's residual mode: the same plant, so the same frequency and damping within 2 %.
  const json* ma = find_table(a, "link-mode");
  const json* mb = find_table(b, "link-mode");
  ASSERT_TRUE(ma && mb);
  const double fa = ma->at("columns").at(0).at("ours").at(0), fb = mb->at("columns").at(0).at("ours").at(0);
  EXPECT_NEAR(fa, fb, 0.02 * fb);

  // Eq. 5.1 per column: the means differ by less than the trials' spread (twice the larger
  // standard deviation of the two sets of three trials, and at least 0.5 % of the mean).
  const json* ta = find_table(a, "T.1");
  const json* tb = find_table(b, "T.1");
  ASSERT_TRUE(ta && tb);
  for (const std::string key : {"none", "zvdd@link-mode"}) {
    const json* ca = find_column(*ta, key);
    const json* cb = find_column(*tb, key);
    ASSERT_TRUE(ca && cb) << key;
    ASSERT_EQ(ca->at("ours").size(), 3u) << key;
    const double mean_a = ca->at("ours_mean"), mean_b = cb->at("ours_mean");
    const double spread = std::max({2.0 * ca->at("ours_std").get<double>(), 2.0 * cb->at("ours_std").get<double>(),
                                    0.005 * mean_b});
    EXPECT_NEAR(mean_a, mean_b, spread) << key;
    for (const json& v : ca->at("ours")) EXPECT_NEAR(v.get<double>(), mean_b, spread + 3.0 * cb->at("ours_std").get<double>()) << key;
    std::printf("%s: Eq. 5.1 mean emulator %.4f deg (std %.4f), simulated %.4f deg (std %.4f)\n", key.c_str(), mean_a,
                ca->at("ours_std").get<double>(), mean_b, cb->at("ours_std").get<double>());
  }
  // Shaping must still pay off on the firmware path (the thesis's point, Table B.1).
  EXPECT_GT(find_column(*ta, "zvdd@link-mode")->at("improvement_percent").get<double>(), 80.0);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
