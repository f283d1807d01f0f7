// clearshape shape / sensitivity: table and JSON output, custom impulses, two modes, CSV
// shaping, the V(r) curve, and bad input → exit 2 with a clear message.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("clearshape_shape_cli_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::json parse(const std::string& text) { return nlohmann::json::parse(text); }

}  // namespace

TEST(ShapeCli, TableForThesisZvdd) {
  const auto r = run_cli("shape --method zvdd --frequency-hz 10 --zeta 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("method      zvdd"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.19338752"), std::string::npos) << r.out;  // reference table (c2): 0.193388
  EXPECT_NE(r.out.find("duration_s  0.15075567"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("insensitivity at V <= 5 %: 0.5744"), std::string::npos) << r.out;
}

TEST(ShapeCli, JsonFields) {
  const auto r = run_cli("shape --method zvd --frequency-hz 10 --zeta 0.1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_TRUE(j.contains("schema_version"));
  EXPECT_EQ(j["method"], "zvd");
  ASSERT_EQ(j["impulses"].size(), 3u);
  EXPECT_EQ(j["impulses"][0]["time_s"], 0.0);
  EXPECT_NEAR(double(j["impulses"][0]["amplitude"]), 0.334415, 1e-6);
  EXPECT_NEAR(double(j["impulses"][2]["time_s"]), 0.100504, 1e-6);
  EXPECT_NEAR(double(j["duration_s"]), 0.100504, 1e-6);
  EXPECT_NEAR(double(j["insensitivity"]["width"]), 0.3402, 1e-4);
  EXPECT_EQ(j["insensitivity"]["vtol"], 0.05);
  EXPECT_NEAR(double(j["mode"]["natural_frequency_rad_s"]), 2 * M_PI * 10, 1e-9);
  EXPECT_LT(double(j["residual_at_design"]), 1e-12);
  EXPECT_EQ(j["positive"], true);
}

// One impulse schema: shape --json names the impulses as simulate's sidecar does (time_s,
// amplitude; the same numbers bit for bit), and keeps the schema-1 names t/a beside them for one
// version (docs/cli.md).
TEST(ShapeCli, ImpulsesAreNamedAsInSimulateWithTheOldNamesBeside) {
  const auto r = run_cli("shape --method zvdd --frequency-hz 3.32 --zeta 0.288 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto shape = parse(r.out);
  const auto csv = temp_path("sim.csv");
  const auto sim = run_cli("simulate --mode speed --signal step --amplitude 1 --duration 0.05 --shaper zvdd "
                           "--shaper-frequency-hz 3.32 --shaper-zeta 0.288 -o " + csv.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  std::ifstream sidecar(fs::path(csv).replace_extension(".json"));
  const auto expected = nlohmann::json::parse(sidecar)["configuration"]["shaper"]["impulses"];
  ASSERT_EQ(shape["impulses"].size(), 4u);
  ASSERT_EQ(shape["impulses"].size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& p = shape["impulses"][i];
    EXPECT_EQ(p["time_s"], expected[i]["time_s"]) << i;
    EXPECT_EQ(p["amplitude"], expected[i]["amplitude"]) << i;
    EXPECT_FALSE(p.contains("t") || p.contains("a")) << i;  // schema 2: the old names are gone
  }
  EXPECT_EQ(shape["schema_version"], 2);
  EXPECT_EQ(shape["units"]["time_s"], "s");
  EXPECT_FALSE(shape["units"].contains("a"));
  fs::remove(csv);
  fs::remove(fs::path(csv).replace_extension(".json"));
}

TEST(ShapeCli, WnAndEiVtol) {
  const auto r = run_cli("shape --method ei --vtol 0.02 --wn 62.83185307179586 --zeta 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_EQ(j["vtol"], 0.02);
  EXPECT_NEAR(double(j["impulses"][0]["amplitude"]), 1.02 / 4, 1e-12);  // exact undamped EI
  EXPECT_NEAR(double(j["residual_at_design"]), 0.02, 1e-12);
}

TEST(ShapeCli, EveryMethodRuns) {
  for (const char* m : {"zv", "zvd", "zvdd", "zvddd", "mzv", "ei", "ei2", "ei3", "um-zv"}) {
    const auto r = run_cli(std::string("shape --json -m ") + m + " -f 5 -z 0.05");
    ASSERT_EQ(r.exit_code, 0) << m << ": " << r.err;
    EXPECT_EQ(parse(r.out)["method"], m);
  }
  const auto si = run_cli("shape --json -m si -f 10 -z 0.05 --band-low-hz 8 --band-high-hz 12");
  ASSERT_EQ(si.exit_code, 0) << si.err;
  const auto j = parse(si.out);
  EXPECT_EQ(j["method"], "si");
  EXPECT_LT(double(j["duration_s"]), 0.1005);  // no longer than EI's period for a ±20 % band
  EXPECT_GE(double(j["insensitivity"]["ratio_high"]), 1.2 - 1e-6);
  EXPECT_LE(double(j["insensitivity"]["ratio_low"]), 0.8 + 1e-6);
}

TEST(ShapeCli, UmZvWarnsAboutClearance) {
  const auto r = run_cli("shape --method um-zv --frequency-hz 4 --zeta 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("clearance"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("impact"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("-1.000000000000"), std::string::npos) << r.out;
}

TEST(ShapeCli, CustomImpulses) {
  auto r = run_cli("shape --method custom --impulses \"0:0.5,0.05:0.5\" --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = parse(r.out);
  EXPECT_EQ(j["impulses"][1]["time_s"], 0.05);
  EXPECT_TRUE(j["insensitivity"].is_null());
  r = run_cli("shape --method custom --impulses \"0:1,0.05:1\" --frequency-hz 10 --zeta 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = parse(r.out);
  EXPECT_EQ(j["impulses"][1]["amplitude"], 0.5);  // normalised
  EXPECT_NEAR(double(j["insensitivity"]["width"]), 0.0637, 1e-4);  // it is the undamped ZV
  r = run_cli("shape --method custom --impulses \"0:0.5,0.05:abc\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("entry 2"), std::string::npos) << r.err;
}

TEST(ShapeCli, TwoModesByConvolution) {
  const auto r = run_cli("shape --method zv -f 4 -z 0.05 --second-frequency-hz 11 --second-zeta 0.02 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_EQ(j["method"], "zv*zv");
  EXPECT_EQ(j["impulses"].size(), 4u);
  EXPECT_NEAR(double(j["second_mode"]["frequency_hz"]), 11.0, 1e-12);
}

TEST(ShapeCli, BadInputExitsTwo) {
  auto r = run_cli("shape --method zvd --frequency-hz 2 --zeta 1.0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("damping_ratio = 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not oscillatory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("clearshape modes"), std::string::npos) << r.err;
  r = run_cli("shape --method zvdx --frequency-hz 2 --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'zvdx' is not a shaper method"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("um-zv"), std::string::npos) << r.err;
  r = run_cli("shape --method zvd --frequency-hz -3 --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frequency-hz = -3"), std::string::npos) << r.err;
  r = run_cli("shape --method zvd --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--frequency-hz"), std::string::npos) << r.err;
  r = run_cli("shape --method ei --frequency-hz 2 --zeta 0.1 --vtol 1.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("vtol = 1.5"), std::string::npos) << r.err;
  r = run_cli("shape --method si --frequency-hz 10 --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--band-low-hz"), std::string::npos) << r.err;
  r = run_cli("shape --method zvd --frequency-hz 2 --wn 3 --zeta 0.1");
  EXPECT_EQ(r.exit_code, 2);
}

TEST(ShapeCli, ShapesACsvColumn) {
  const fs::path in = temp_path("in.csv");
  const fs::path out = temp_path("out.csv");
  {
    std::ofstream f(in);
    f << "time_s,command_deg,other\n";
    for (int i = 0; i <= 100; ++i) f << i * 0.001 << "," << (i >= 10 ? 20.0 : 0.0) << ",1\n";
  }
  // 25 Hz undamped ZV: impulses at 0 and 20 ms (on the 1 ms grid).
  const auto r = run_cli("shape -m zv -f 25 -z 0 --input " + in.string() + " --column command_deg --output " +
                         out.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parse(r.out)["shaped_csv"]["shaped_column"], "command_deg_shaped");
  const auto table = clearshape::io::read_table(out);
  ASSERT_EQ(table.names, (std::vector<std::string>{"time_s", "command_deg", "command_deg_shaped"}));
  ASSERT_EQ(table.rows(), 121u);  // extended by the shaper's 20 ms
  const auto& y = table.column("command_deg_shaped");
  EXPECT_EQ(y[9], 0.0);
  EXPECT_NEAR(y[10], 10.0, 1e-12);  // half the step at once
  EXPECT_NEAR(y[29], 10.0, 1e-12);
  EXPECT_NEAR(y[30], 20.0, 1e-12);  // the rest 20 ms later
  EXPECT_NEAR(y.back(), 20.0, 1e-12);
  EXPECT_NEAR(table.column("command_deg").back(), 20.0, 1e-12);
  const auto bad = run_cli("shape -m zv -f 25 -z 0 --input " + in.string() + " --column nope --output " + out.string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("nope"), std::string::npos) << bad.err;
  fs::remove(in);
  fs::remove(out);
}

TEST(SensitivityCli, CsvJsonAndFile) {
  auto r = run_cli("sensitivity --method zv --frequency-hz 10 --zeta 0 --from 0.5 --to 1.5 --points 11");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto table = clearshape::io::parse_table(r.out, "stdout");
  ASSERT_EQ(table.names, (std::vector<std::string>{"frequency_ratio", "frequency_hz", "residual"}));
  ASSERT_EQ(table.rows(), 11u);
  for (std::size_t i = 0; i < table.rows(); ++i) {
    const double ratio = table.columns[0][i];
    EXPECT_NEAR(table.columns[1][i], 10 * ratio, 1e-12);
    EXPECT_NEAR(table.columns[2][i], std::abs(std::cos(M_PI * ratio / 2)), 1e-12);  // (c1)
  }
  r = run_cli("sensitivity -m zvd -f 10 -z 0.1 --actual-zeta 0 --from 1 --to 2 --points 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = parse(r.out);
  EXPECT_EQ(j["actual_zeta"], 0.0);
  ASSERT_EQ(j["points"].size(), 2u);
  EXPECT_NEAR(double(j["points"][0]["residual"]), 0.02458, 1e-5);  // (c4) damping mismatch, ZVD 2.458 %
  const fs::path out = temp_path("curve.csv");
  r = run_cli("sensitivity -m ei -f 10 -z 0.1 -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_EQ(clearshape::io::read_table(out).rows(), 201u);
  fs::remove(out);
  r = run_cli("sensitivity -m zvd -f 10 -z 0.1 --from 2 --to 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--to = 1"), std::string::npos) << r.err;
  r = run_cli("sensitivity -m zvd -f 10 -z 0.1 --actual-zeta 1.2");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("sensitivity -m zvd -f 10 -z 1.2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("clearshape modes"), std::string::npos) << r.err;
}
