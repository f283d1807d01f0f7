// `clearshape frf` (H1 and coherence, MATLAB tfestimate/mscohere) on a record of a known resonance,
// its option errors, and `identify`'s residual tests (MATLAB resid) on the thesis's PRBS record:
// the true structure passes, a structure short of a pole and a zero fails independence; and the compare figure
// python/plot_compare.py draws from its output (issue 20).
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/units.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/io/table.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
using clearshape::testing::golden_path;
using clearshape::testing::process_temp_path;
using clearshape::testing::read_bytes;
using clearshape::testing::run_cli;

namespace {

constexpr double kFs = 1000.0, kFnHz = 40.0, kZeta = 0.05, kGain = 2.0;

// time_s, command (seeded white noise), command_applied (the command itself, a D/A copy), response:
// K·ωn²/(s² + 2ζωn s + ωn²) by the bilinear transform prewarped at ωn, so the digital response at
// fn is the analytic K/(2ζ) = 20 at −90° (Oppenheim & Schafer §7.1.2).
std::string write_resonance_record() {
  const double wn = cs::kTwoPi * kFnHz;
  const double c = wn / std::tan(wn / (2.0 * kFs));
  const double num = kGain * wn * wn;
  const cs::dsp::SosDesign design({cs::dsp::Section{num, 2.0 * num, num, c * c + 2.0 * kZeta * wn * c + wn * wn,
                                                    2.0 * (wn * wn - c * c), c * c - 2.0 * kZeta * wn * c + wn * wn}},
                                  kFs);
  std::mt19937_64 rng(40);
  std::normal_distribution<double> white(0.0, 1.0);
  std::vector<double> u(60000), time(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    u[i] = white(rng);
    time[i] = static_cast<double>(i) / kFs;
  }
  const auto y = cs::dsp::sosfilt(design, u);
  const auto p = process_temp_path("frf_resonance.csv");
  cs::io::write_csv(p, {"time_s", "command", "command_applied", "response"}, {&time, &u, &u, &y});
  return p.string();
}

}  // namespace

TEST(FrfCli, ResonanceMatchesTheAnalyticResponse) {
  const std::string rec = write_resonance_record();
  const auto out = process_temp_path("frf_out.csv");
  const auto r = run_cli("frf --in " + rec + " --output response --segment-s 4 --out " + out.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("input 'command' (column 2), output 'response' (column 4)"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["segment_samples"].get<int>(), 4000);
  EXPECT_EQ(j["overlap_samples"].get<int>(), 2000);
  EXPECT_NEAR(j["peak"]["frequency_hz"].get<double>(), kFnHz, 0.25);
  // At fn: analytic 20 and −90°; 2 % and 1° (resolution bias −0.3 %, random error ≈ 1.3 % with 29
  // segments: Bendat & Piersol, Random Data, 4th ed., ch. 9; docs/frf.md).
  const std::size_t k = 160;  // 40 Hz at 0.25 Hz bins
  ASSERT_DOUBLE_EQ(j["frequency_hz"][k].get<double>(), kFnHz);
  EXPECT_NEAR(j["magnitude"][k].get<double>(), kGain / (2.0 * kZeta), 0.02 * kGain / (2.0 * kZeta));
  EXPECT_NEAR(j["phase_deg"][k].get<double>(), -90.0, 1.0);
  EXPECT_GT(j["coherence"][k].get<double>(), 0.99);  // no noise
  const std::string csv = read_bytes(out);
  EXPECT_EQ(csv.rfind("frequency_hz,magnitude,phase_deg,coherence\n", 0), 0u) << csv.substr(0, 80);
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), 2001u + 1u);  // 4000/2 + 1 bins + header
  std::filesystem::remove(out);
  std::filesystem::remove(rec);
}

TEST(FrfCli, TheDaCopyAndBadOptionsAreRefusedNamingTheOption) {
  const std::string rec = write_resonance_record();
  const auto copy = run_cli("frf --in " + rec);  // default pair: command and command_applied
  EXPECT_EQ(copy.exit_code, 2);
  EXPECT_NE(copy.err.find("output 'command_applied' is input 'command' through a converter"), std::string::npos) << copy.err;
  EXPECT_NE(copy.err.find("give the response with --output (other columns: response)"), std::string::npos) << copy.err;
  const std::string base = "frf --in " + rec + " --output response ";
  const auto seg = run_cli(base + "--segment-s 100");
  EXPECT_EQ(seg.exit_code, 2);
  EXPECT_NE(seg.err.find("--segment-s = 100 is out of range; allowed: 0.008 … 60 s"), std::string::npos) << seg.err;
  const auto ov = run_cli(base + "--overlap 1");
  EXPECT_EQ(ov.exit_code, 2);
  EXPECT_NE(ov.err.find("--overlap = 1 is out of range; allowed: 0 ≤ overlap < 1"), std::string::npos) << ov.err;
  const auto win = run_cli(base + "--window kaiser");
  EXPECT_EQ(win.exit_code, 2);
  EXPECT_NE(win.err.find("--window = 'kaiser' is not valid; allowed: hann, hamming, rectangular"), std::string::npos) << win.err;
  const auto col = run_cli(base + "--input nothing");
  EXPECT_EQ(col.exit_code, 2);
  EXPECT_NE(col.err.find("nothing"), std::string::npos) << col.err;
  const auto self = run_cli(base + "--out " + rec);  // an output never replaces its input
  EXPECT_EQ(self.exit_code, 2) << self.err;
  std::filesystem::remove(rec);
}

TEST(IdentifyResidualsCli, TheTrueStructurePassesAndAMissingPoleFailsIndependence) {
  // tests/golden/ident_position_prbs.csv: the thesis position model P3UZ, ±1 PRBS, 2 % noise.
  const std::string data = golden_path("ident_position_prbs.csv").string();
  const auto good = run_cli("identify --data " + data + " --json");
  ASSERT_EQ(good.exit_code, 0) << good.err;
  const auto g = nlohmann::json::parse(good.out)["residual_tests"];
  EXPECT_EQ(g["max_lag"].get<int>(), 25);
  EXPECT_DOUBLE_EQ(g["confidence"].get<double>(), 0.99);
  EXPECT_TRUE(g["experiments"][0]["whiteness"]["white"].get<bool>());
  EXPECT_TRUE(g["experiments"][0]["independence"]["independent"].get<bool>());
  EXPECT_EQ(g["experiments"][0]["independence"]["lags"].size(), 51u);
  EXPECT_EQ(good.err.find("depends on the input"), std::string::npos) << good.err;

  const auto poor = run_cli("identify --model P2U --data " + data);
  ASSERT_EQ(poor.exit_code, 0) << poor.err;
  EXPECT_NE(poor.out.find("NOT independent"), std::string::npos) << poor.out;
  EXPECT_NE(poor.err.find("warning: residual of 'ident_position_prbs' depends on the input"), std::string::npos) << poor.err;

  const auto lags = run_cli("identify --data " + data + " --resid-lags 1000");
  EXPECT_EQ(lags.exit_code, 2);
  EXPECT_NE(lags.err.find("--resid-lags = 1000 is out of range; allowed: 1 … 666"), std::string::npos) << lags.err;
  const auto conf = run_cli("identify --data " + data + " --resid-confidence 1");
  EXPECT_EQ(conf.exit_code, 2);
  EXPECT_NE(conf.err.find("--resid-confidence = 1 is out of range; allowed: (0, 1)"), std::string::npos) << conf.err;
}

TEST(IdentifyResidualsCli, CompareFigureIsDrawnDeterministically) {
  // python/plot_compare.py: measured vs simulated, the residual, and the two correlation panels.
  const std::string data = golden_path("ident_position_prbs.csv").string();
  const auto dir = clearshape::testing::fresh_temp_dir("compare_figure");
  const auto json = dir / "identify.json", sim = dir / "sim.csv", png = dir / "compare.png";
  const auto r = run_cli("identify --model P2U --data " + data + " --simulated " + sim.string() + " --json > " + json.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto script = golden_path("").parent_path().parent_path().parent_path() / "python" / "plot_compare.py";
  const std::string draw = "/usr/bin/python3 " + script.string() + " " + json.string() + " " + sim.string() + " ";
  ASSERT_EQ(std::system((draw + png.string()).c_str()), 0);
  const std::string first = read_bytes(png);
  ASSERT_GT(first.size(), 10000u);
  EXPECT_EQ(first.substr(1, 3), "PNG");
  ASSERT_EQ(std::system((draw + (dir / "again.png").string()).c_str()), 0);
  EXPECT_EQ(read_bytes(dir / "again.png"), first);  // same data, same bytes
  // A JSON without residual tests (a cross-validation) is refused with exit 2 and no file.
  const std::string bad = "/usr/bin/python3 " + script.string() + " " + sim.string() + " " + sim.string() + " " +
                          (dir / "bad.png").string() + " 2>/dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.png"));
  std::filesystem::remove_all(dir);
}

// Issue 21 (the overflow behind "find_peaks: value 0 is not finite"): a record of 1e200 values
// gave frf columns of -nan with exit 0. The bound is √DBL_MAX / n (core/error.hpp): no sum of n
// products of samples can then overflow. Now exit 2 naming the file, line and column.
TEST(FrfCli, ValuesThatWouldOverflowAreRefusedByFileLineAndColumn) {
  const auto path = process_temp_path("frf_huge.csv");
  {
    std::ofstream f(path);
    f << "time_s,u,y\n";
    for (int k = 0; k < 2000; ++k) f << k * 1e-3 << "," << (k % 40 < 20 ? 1.0 : -1.0) << "," << (k == 7 ? 1e200 : 0.5) << "\n";
  }
  const auto r = run_cli("frf --in " + path.string() + " --input u --output y");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  const std::string bound = fmt::format("{:.3g}", std::sqrt(std::numeric_limits<double>::max()) / 2000.0);
  EXPECT_NE(r.err.find(path.string() + ":9: field 'y': value 1e+200 is too large"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("allowed: |value| <= " + bound + " for a record of 2000 rows"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  std::filesystem::remove(path);
}
