// clearshape shape --export FORMAT: each format end to end (file and stdout), and every bad
// option → exit 2 with a message naming the option and its allowed values.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("clearshape_export_cli_" + std::to_string(::getpid()) + "_" + name);
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(ShapeExportCli, CHeaderToFile) {
  const fs::path out = temp_path("zvd.h");
  const auto r = run_cli("shape -m zvd -f 13.7 -z 0.07 --export c-header --sample-time 0.001 --export-name axis_x -o " +
                         out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(contains(r.err, "wrote " + out.string())) << r.err;
  const std::string h = read_file(out);
  EXPECT_TRUE(contains(h, "#define AXIS_X_TAPS 5u")) << h;
  EXPECT_TRUE(contains(h, "static inline double axis_x_step_double(")) << h;
  EXPECT_TRUE(contains(h, "clearshape shape --method zvd --frequency-hz 13.7 --zeta 0.07 --export c-header "
                          "--sample-time 0.001 --export-name axis_x")) << h;
  // A second export replaces the file whole (atomic writer).
  ASSERT_EQ(run_cli("shape -m zv -f 13.7 -z 0.07 --export c-header --sample-time 0.001 -o " + out.string()).exit_code, 0);
  EXPECT_TRUE(contains(read_file(out), "#define CS_SHAPER_TAPS 3u"));
  fs::remove(out);
}

TEST(ShapeExportCli, JsonToStdout) {
  const auto r = run_cli("shape -m ei -f 14.955 -z 0.1 --export json --sample-time 0.002 --discretization exact");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["design"]["method"], "ei");
  EXPECT_EQ(j["design"]["vtol"], 0.05);
  EXPECT_EQ(j["design"]["mode"]["frequency_hz"], 14.955);
  EXPECT_EQ(j["discrete"]["sample_time_s"], 0.002);
  EXPECT_EQ(j["discrete"]["discretization"], "exact");
  // EI leaves V = Vtol at the mode; the exact split keeps each impulse's vibration there, and the
  // rescale of the taps to ΣA = 1 changes V by the ratio of the sums (about 1 % at 2 ms).
  EXPECT_NEAR(double(j["residual_vibration"]["at_design"]["continuous"]), 0.05, 1e-9);
  EXPECT_NEAR(double(j["residual_vibration"]["at_design"]["discrete"]), 0.05, 0.002);
  EXPECT_GE(j["discrete"]["taps"].size(), 3u);
}

TEST(ShapeExportCli, KlipperAndRrfLines) {
  const auto k = run_cli("shape -m mzv -f 14.955 -z 0.1 --export klipper --export-axis x");
  ASSERT_EQ(k.exit_code, 0) << k.err;
  EXPECT_TRUE(contains(k.out, "[input_shaper]\nshaper_type_x: mzv\nshaper_freq_x: 14.955\ndamping_ratio_x: 0.1\n")) << k.out;
  EXPECT_FALSE(contains(k.out, "_y:")) << k.out;
  const auto r = run_cli("shape -m zvd -f 40.5 -z 0.1 --export rrf");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\nM593 P\"zvd\" F40.5 S0.1\n")) << r.out;
  // RRF has no zv: the custom form, with a note on stderr saying why.
  const auto c = run_cli("shape -m zv -f 40 -z 0 --export rrf");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_TRUE(contains(c.out, "M593 P\"custom\" H0.5 T0.0125\n")) << c.out;
  EXPECT_TRUE(contains(c.err, "RRF has no zv type")) << c.err;
}

TEST(ShapeExportCli, BadFormatAndSampleTime) {
  const auto f = run_cli("shape -m zvd -f 10 -z 0.1 --export yaml --sample-time 0.001");
  EXPECT_EQ(f.exit_code, 2);
  EXPECT_TRUE(contains(f.err, "--export = 'yaml' is not a known format; allowed: json, c-header, klipper, rrf")) << f.err;
  const auto missing = run_cli("shape -m zvd -f 10 -z 0.1 --export c-header");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.err, "needs --sample-time")) << missing.err;
  for (const char* bad : {"0", "-0.001"}) {
    const auto r = run_cli(std::string("shape -m zvd -f 10 -z 0.1 --export json --sample-time ") + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(contains(r.err, "--sample-time = ")) << r.err;
    EXPECT_TRUE(contains(r.err, "allowed: finite and > 0")) << r.err;
  }
  const auto nan = run_cli("shape -m zvd -f 10 -z 0.1 --export json --sample-time nan");
  EXPECT_EQ(nan.exit_code, 2);
  EXPECT_TRUE(contains(nan.err, "--sample-time")) << nan.err;
  EXPECT_TRUE(contains(nan.err, "not a finite number")) << nan.err;
  // A sample time so small that the shaper would need more than 2^26 samples of history.
  const auto tiny = run_cli("shape -m zvd -f 10 -z 0.1 --export json --sample-time 1e-12");
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_TRUE(contains(tiny.err, "2^26")) << tiny.err;
}

TEST(ShapeExportCli, OptionsThatDoNotApply) {
  const auto k = run_cli("shape -m zvd -f 40 -z 0.1 --export klipper --sample-time 0.001");
  EXPECT_EQ(k.exit_code, 2);
  EXPECT_TRUE(contains(k.err, "--sample-time and --discretization apply to --export json and c-header")) << k.err;
  const auto n = run_cli("shape -m zvd -f 40 -z 0.1 --export json --sample-time 0.001 --export-name x");
  EXPECT_EQ(n.exit_code, 2);
  EXPECT_TRUE(contains(n.err, "--export-name applies to --export c-header")) << n.err;
  const auto a = run_cli("shape -m zvd -f 40 -z 0.1 --export rrf --export-axis x");
  EXPECT_EQ(a.exit_code, 2);
  const auto s = run_cli("shape -m zvd -f 40 -z 0.1 --sample-time 0.001");
  EXPECT_EQ(s.exit_code, 2);
  EXPECT_TRUE(contains(s.err, "apply to --export FORMAT")) << s.err;
  const auto j = run_cli("shape -m zvd -f 40 -z 0.1 --export json --sample-time 0.001 --json");
  EXPECT_EQ(j.exit_code, 2);
  const auto name = run_cli("shape -m zvd -f 40 -z 0.1 --export c-header --sample-time 0.001 --export-name 9x");
  EXPECT_EQ(name.exit_code, 2);
  EXPECT_TRUE(contains(name.err, "--export-name = '9x' is not a C identifier")) << name.err;
}

TEST(ShapeExportCli, WhatAFirmwareLacks) {
  const auto k = run_cli("shape -m zvdd -f 40 -z 0.1 --export klipper");
  EXPECT_EQ(k.exit_code, 2);
  EXPECT_TRUE(contains(k.err, "Klipper has no zvdd shaper")) << k.err;
  EXPECT_TRUE(contains(k.err, "use zvd")) << k.err;
  const auto v = run_cli("shape -m ei -f 40 -z 0.1 --vtol 0.02 --export klipper");
  EXPECT_EQ(v.exit_code, 2);
  EXPECT_TRUE(contains(v.err, "fixes the tolerable vibration at 5 %")) << v.err;
  const auto u = run_cli("shape -m um-zv -f 40 -z 0.1 --export rrf");
  EXPECT_EQ(u.exit_code, 2);
  EXPECT_TRUE(contains(u.err, "negative impulses")) << u.err;
}

TEST(ShapeExportCli, NeverWithAnInputAndFailedWritesExitOne) {
  const fs::path in = temp_path("in.csv");
  {
    std::ofstream f(in);
    f << "time_s,u\n0,0\n0.001,1\n";
  }
  const auto r = run_cli("shape -m zvd -f 40 -z 0.1 --export json --sample-time 0.001 --input " + in.string() +
                         " --column u -o " + in.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "separate call")) << r.err;
  EXPECT_EQ(read_file(in), "time_s,u\n0,0\n0.001,1\n");  // untouched
  fs::remove(in);
  // A folder where the file should go: refused by name before anything is written (exit 2,
  // issue 21: an output is never anything but a regular file), nothing left behind.
  const fs::path dir = temp_path("dir");
  fs::create_directories(dir);
  const auto w = run_cli("shape -m zvd -f 40 -z 0.1 --export rrf -o " + dir.string());
  EXPECT_EQ(w.exit_code, 2) << w.err;
  EXPECT_TRUE(contains(w.err, "is a folder, not a regular file")) << w.err;
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// Issue 21: a valid shaper shorter than the sample time (ZVD at 100 kHz, Ts = 1 ms) was refused
// with an internal message ("shaper 'taps': impulse times must increase strictly"): the linear
// split put an impulse's tap at m+1 before the next impulse's tap at m. Reference: the ZVD
// impulses (Singer & Seering 1990: 1, 2K, K² over (1+K)² at 0, Td/2, Td) split linearly (Vaughan's
// digseq: A·(1−f) at 0, A·f at 1 with f = t/Ts), computed here independently of the library.
TEST(ShapeExportCli, AShaperShorterThanTheSampleTimeIsExported) {
  const double f_hz = 1e5, zeta = 0.1, ts = 0.001;
  const double root = std::sqrt(1.0 - zeta * zeta);
  const double k = std::exp(-zeta * std::numbers::pi / root);
  const double td = 1.0 / (f_hz * root);
  const double norm = (1.0 + k) * (1.0 + k);
  const double tap1 = (2.0 * k * (td / 2.0) / ts + k * k * td / ts) / norm;
  const auto r = run_cli("shape -m zvd -f 1e5 -z 0.1 --export json --sample-time 0.001");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto taps = nlohmann::json::parse(r.out)["discrete"]["taps"];
  ASSERT_EQ(taps.size(), 2u) << taps;
  EXPECT_EQ(taps[0]["delay_samples"], 0);
  EXPECT_EQ(taps[1]["delay_samples"], 1);
  EXPECT_NEAR(double(taps[0]["weight"]), 1.0 - tap1, 1e-12);
  EXPECT_NEAR(double(taps[1]["weight"]), tap1, 1e-12);
  const auto header = run_cli("shape -m zvd -f 1e5 -z 0.1 --export c-header --sample-time 0.001");
  EXPECT_EQ(header.exit_code, 0) << header.err;
  EXPECT_TRUE(contains(header.out, "#define CS_SHAPER_TAPS 2u")) << header.out;
  EXPECT_FALSE(contains(header.err, "taps")) << header.err;
}
