// The measurement floor and "what a command can reach here" (study/measurement_floor.hpp, issue 12):
//   * physical law: on a noise-free rig nothing moves in a rest trial, so Eq. 5.1 reads 0;
//   * with noise the floor is > 0 and equals Eq. 5.1 recomputed here from the rest trials' CSV files
//     (bias removal, trapezoidal integration, the window from the median steady-state start of the
//     table's trials, M and the root mean square written out again in this file);
//   * the verdict flips where the numbers say it must;
//   * a bad rig_tests.floor_trials is refused with file, line and key before any output exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/measurement_floor.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/recordings.hpp"
#include "clearshape/study/run_source.hpp"
#include "clearshape/study/runner.hpp"
#include "protocol_fixtures.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace st = clearshape::study;
using json = nlohmann::ordered_json;

namespace {

// One 5° step, 2 s records, two trials of the unshaped column, three rest trials.
std::string floor_protocol(const std::string& floor_line) {
  return std::string(R"(format = "clearshape-study-protocol/1"
[study]
name = "floor"
mode = "position"
seed = 11
record_s = 2.0
repetitions = 2
[[input]]
name = "step"
label = "Step 5°"
type = "step"
amplitude_deg = 5.0
start_s = 0.5
[rig_tests]
)") + floor_line + R"(
[[rig_tests.table]]
id = "T"
input = "step"
[[rig_tests.table.column]]
shaper = "none"
)";
}

st::StudyResult run_floor_study(const std::filesystem::path& out, st::RigFactory rig) {
  st::StudyOptions options;
  options.out_dir = out;
  options.fresh = true;
  options.threads = 2;
  options.rig = std::move(rig);
  return st::run_study(st::parse_protocol(floor_protocol("floor_trials = 3"), "floor.toml"), options);
}

// A column of a CSV file by name (written here, not with the library's reader).
std::vector<double> csv_column(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  const auto at = static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  EXPECT_LT(at, header.size()) << name << " not in " << file;
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::string cell;
    for (std::size_t i = 0; i <= at; ++i) std::getline(ls, cell, ',');
    v.push_back(std::stod(cell));
  }
  return v;
}

const json& floor_of(const st::StudyResult& r) { return r.results.at("sections").at("measurement_floor").at("tables").at("T"); }

}  // namespace

TEST(MeasurementFloor, NoiseFreeRestTrialsReadZero) {
  // No motion and no noise: the gyro reads a constant (its quantized zero), the bias removal takes
  // it out exactly, the integrated angle is 0 and so is every deviation from its mean.
  clearshape::rig::RigTruth truth = clearshape::rig::thesis_rig_truth();
  truth.gyro.noise_density_dps_per_rthz = 0.0;
  st::RigFactory quiet;
  quiet.description = "sim (thesis truth, noise-free gyroscope; test)";
  quiet.kind = "simulated-noise-free";
  quiet.parallel_runs = 4;
  quiet.make = [truth](clearshape::rig::CommandMode mode, double rate_hz, std::uint64_t seed) {
    clearshape::rig::SimRigOptions o;
    o.mode = mode;
    o.sample_rate_hz = rate_hz;
    o.seed = seed;
    return std::unique_ptr<clearshape::rig::Rig>(clearshape::rig::make_sim_rig_with_truth(o, truth));
  };
  const auto out = clearshape::testing::fresh_temp_dir("clearshape_floor_quiet");
  const st::StudyResult r = run_floor_study(out, quiet);
  const json& f = floor_of(r);
  ASSERT_EQ(f.at("ours").size(), 3u);
  for (const auto& v : f.at("ours")) EXPECT_LT(v.get<double>(), 1e-12);
  EXPECT_LT(f.at("ours_mean").get<double>(), 1e-12);
  // The same rig does move on a step: the zero is the rest, not a dead sensor.
  const json& row = r.table("reach").at("headline").at("T");
  EXPECT_GT(row.at("unshaped_mean").get<double>(), 1e-4);
  EXPECT_EQ(row.at("verdict"), "reachable");  // a floor of 0 hides nothing; no shaped column reaches it
  std::filesystem::remove_all(out);
}

TEST(MeasurementFloor, NoisyFloorIsEquationFiveOneOnTheRestRecords) {
  const auto out = clearshape::testing::fresh_temp_dir("clearshape_floor_noisy");
  const st::StudyResult r = run_floor_study(out, st::sim_rig_factory());
  const json& f = floor_of(r);
  const json& rig_table = r.table("T");
  // The window: the median of every trial's Eq. 5.1 start in the rig table.
  std::vector<double> starts;
  for (const auto& col : rig_table.at("columns")) {
    for (const auto& s : col.at("start_time_s")) starts.push_back(s.get<double>());
  }
  std::sort(starts.begin(), starts.end());
  const double start_s = starts.size() % 2 ? starts[starts.size() / 2]
                                            : 0.5 * (starts[starts.size() / 2 - 1] + starts[starts.size() / 2]);
  EXPECT_DOUBLE_EQ(f.at("start_time_s").get<double>(), start_s);
  std::vector<double> md;
  for (int trial = 1; trial <= 3; ++trial) {
    const auto csv = out / "runs" / ("rest__r0" + std::to_string(trial) + ".csv");
    ASSERT_TRUE(std::filesystem::exists(csv)) << csv;
    const std::vector<double> t = csv_column(csv, "time_s");
    const std::vector<double> w = csv_column(csv, "link_rate_deg_s");
    for (const double c : csv_column(csv, "command_deg")) ASSERT_EQ(c, 0.0);  // a rest trial
    const double ts = t[1] - t[0];
    // Gyro bias: the mean rate over the protocol's bias window (0.4 s, the default).
    const auto nb = static_cast<std::size_t>(std::floor(0.4 / ts));
    double bias = 0.0;
    for (std::size_t k = 0; k < nb; ++k) bias += w[k] / static_cast<double>(nb);
    // Link angle: trapezoidal integral of the bias-free rate.
    std::vector<double> angle(w.size(), 0.0);
    for (std::size_t k = 1; k < w.size(); ++k) angle[k] = angle[k - 1] + 0.5 * ts * (w[k - 1] + w[k] - 2.0 * bias);
    // Eq. 5.1 from the first sample at or after the window start: M the window's mean.
    std::size_t k0 = 0;
    while (k0 < t.size() && t[k0] < start_s - 1e-9) ++k0;
    double m = 0.0;
    for (std::size_t k = k0; k < angle.size(); ++k) m += angle[k];
    m /= static_cast<double>(angle.size() - k0);
    double ss = 0.0;
    for (std::size_t k = k0; k < angle.size(); ++k) ss += (m - angle[k]) * (m - angle[k]);
    md.push_back(std::sqrt(ss / static_cast<double>(angle.size() - k0)));
  }
  ASSERT_EQ(f.at("ours").size(), 3u);
  double mean = 0.0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(md[i], 1e-4);  // a noisy gyro integrates to a wandering angle
    EXPECT_NEAR(f.at("ours")[i].get<double>(), md[i], 1e-12 * md[i] + 1e-15);
    mean += md[i] / 3.0;
  }
  double ss = 0.0;
  for (const double v : md) ss += (v - mean) * (v - mean);
  EXPECT_NEAR(f.at("ours_mean").get<double>(), mean, 1e-12 * mean);
  EXPECT_NEAR(f.at("ours_std").get<double>(), std::sqrt(ss / 2.0), 1e-9 * mean);
  // The report's row: the target is a tenth of the unshaped mean, set against this floor.
  const json& row = r.table("reach").at("headline").at("T");
  const double unshaped = rig_table.at("columns")[0].at("ours_mean").get<double>();
  EXPECT_NEAR(row.at("target").get<double>(), 0.1 * unshaped, 1e-15);
  EXPECT_DOUBLE_EQ(row.at("floor_mean").get<double>(), f.at("ours_mean").get<double>());
  EXPECT_EQ(row.at("verdict"), 0.1 * unshaped < mean ? "below-floor" : "reachable");
  EXPECT_NE(r.tables_markdown.find("What a command can reach here"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out / "data" / "measurement_floor.csv"));
  std::filesystem::remove_all(out);
}

TEST(MeasurementFloor, RecordedRestTrialsGiveTheSameFloor) {
  // A physical rig's rest trials arrive as recordings: the manifest template lists them, and the
  // floor read from the files is the floor the simulated runs gave.
  const auto sim = clearshape::testing::fresh_temp_dir("clearshape_floor_sim");
  const st::StudyResult a = run_floor_study(sim, st::sim_rig_factory());
  const st::Protocol p = st::parse_protocol(floor_protocol("floor_trials = 3"), "floor.toml");
  const std::string manifest = st::recordings_manifest_template(p);
  EXPECT_NE(manifest.find("id = \"rest/r03\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("rest trial (zero command"), std::string::npos);
  const auto rec = clearshape::testing::fresh_temp_dir("clearshape_floor_rec");
  for (const auto& e : std::filesystem::directory_iterator(sim / "runs")) {
    if (e.path().extension() == ".csv") std::filesystem::copy_file(e.path(), rec / e.path().filename());
  }
  std::ofstream(rec / "manifest.toml") << manifest;
  st::StudyOptions options;
  options.out_dir = rec / "out";
  options.threads = 2;
  options.source = st::recordings_run_source(st::load_recordings_manifest(rec, p), p);
  const st::StudyResult b = st::run_study(p, options);
  EXPECT_EQ(floor_of(b).at("ours"), floor_of(a).at("ours"));
  EXPECT_EQ(b.table("reach").at("headline"), a.table("reach").at("headline"));
  std::filesystem::remove_all(sim);
  std::filesystem::remove_all(rec);
}

TEST(MeasurementFloor, VerdictFollowsTheNumbers) {
  st::ReachNumbers n;
  n.unshaped_mean = 0.03;  // target 0.003
  n.floor_mean = 0.018;
  n.floor_std = 0.01;
  n.best_label = "ZVDD";
  n.best_mean = 0.02;
  st::ReachVerdict v = st::reach_verdict(n, "deg");
  EXPECT_EQ(v.reach, st::Reach::below_floor);
  EXPECT_NEAR(v.target, 0.003, 1e-15);
  EXPECT_NE(v.sentence.find("the 90 % target 0.003 deg is below the measurement floor 0.018"), std::string::npos)
      << v.sentence;
  EXPECT_NE(v.sentence.find("no command can show it"), std::string::npos);
  EXPECT_NEAR(v.floor_improvement_percent, 40.0, 1e-9);  // 1 − 0.018/0.03
  EXPECT_NE(v.sentence.find("40 % improvement"), std::string::npos) << v.sentence;
  // The floor just below the target: no longer hidden; the best design is far from it.
  n.floor_mean = 0.0029;
  v = st::reach_verdict(n, "deg");
  EXPECT_EQ(v.reach, st::Reach::reachable);
  EXPECT_NE(v.sentence.find("reachable in principle"), std::string::npos) << v.sentence;
  EXPECT_NE(v.sentence.find("the command, not the sensor, is the limit"), std::string::npos);
  // … and the best design at or below the target reaches it.
  n.best_mean = 0.0029;
  EXPECT_EQ(st::reach_verdict(n, "deg").reach, st::Reach::reached);
  n.best_mean = 0.0031;
  EXPECT_EQ(st::reach_verdict(n, "deg").reach, st::Reach::reachable);
  // Without a shaped column nothing is reached, whatever the floor.
  n.best_label.clear();
  v = st::reach_verdict(n, "deg");
  EXPECT_EQ(v.reach, st::Reach::reachable);
  EXPECT_NE(v.sentence.find("no shaped command was tested"), std::string::npos);
  EXPECT_EQ(st::to_string(st::Reach::below_floor), "below-floor");
}

TEST(MeasurementFloor, FixedStartEquationAndMedian) {
  clearshape::UniformSeries s;
  s.sample_time_s = 0.5;
  s.values = {0.0, 0.0, 1.0, 3.0};  // from t = 1 s: M = 2, deviations ±1
  EXPECT_DOUBLE_EQ(st::fixed_start_mean_deviation(s, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(st::fixed_start_mean_deviation(s, 0.9), 1.0);  // the first sample at or after
  EXPECT_DOUBLE_EQ(st::fixed_start_mean_deviation(s, 9.0), 0.0);  // the last sample alone
  EXPECT_DOUBLE_EQ(st::median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(st::median({4.0, 1.0, 2.0, 3.0}), 2.5);
  EXPECT_TRUE(std::isnan(st::median({})));
}

TEST(MeasurementFloor, RestTrialsArePlannedAndCappedByQuick) {
  const st::Protocol p = st::parse_protocol(floor_protocol("floor_trials = 3"), "floor.toml");
  EXPECT_EQ(p.rig_tests.floor_trials, 3);
  int rest = 0;
  for (const auto& run : st::distinct_runs(p)) rest += run.stage == "rest" ? 1 : 0;
  EXPECT_EQ(rest, 3);
  EXPECT_EQ(st::rest_run_id(3), "rest/r03");
  EXPECT_EQ(st::quick_variant(p).rig_tests.floor_trials, 3);  // [quick] repetitions default 3
  EXPECT_EQ(st::to_json(p)["rig_tests"]["floor_trials"], 3);
  // Without the key nothing changes in the effective protocol (its hash keeps finished runs).
  EXPECT_FALSE(st::to_json(st::parse_protocol(floor_protocol(""), "floor.toml"))["rig_tests"].contains("floor_trials"));
}

TEST(MeasurementFloor, BadFloorTrialsNamesFileLineAndKey) {
  // floor_trials is on line 15 of the fixture.
  for (const std::string bad : {"floor_trials = -1", "floor_trials = 1001", "floor_trials = nan", "floor_trials = 2.5",
                                "floor_trials = \"10\""}) {
    const std::string e = clearshape::testing::protocol_error_of(floor_protocol(bad));
    EXPECT_NE(e.find("mini.toml:15"), std::string::npos) << bad << ": " << e;
    EXPECT_NE(e.find("rig_tests.floor_trials"), std::string::npos) << bad << ": " << e;
  }
  const std::string no_table = std::string(clearshape::testing::kMiniProtocol) + "[rig_tests]\nfloor_trials = 2\n";
  EXPECT_NE(clearshape::testing::protocol_error_of(no_table).find("needs at least one"), std::string::npos);
  // From the command line: exit 2 with file, line and key, and no output folder.
  const auto dir = clearshape::testing::fresh_temp_dir("clearshape_floor_bad");
  {
    std::ofstream f(dir / "bad.toml");
    f << floor_protocol("floor_trials = -4");
  }
  const auto r = clearshape::testing::run_cli("study " + (dir / "bad.toml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.toml:15"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rig_tests.floor_trials"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  std::filesystem::remove_all(dir);
}
