// --grid-hz (a drive that takes a new command only at its updates, thesis §3.2) through
// `shape` (table, --json, --input, every --export) and `recommend` (table, --json, --model),
// against independent references: V = |cos(π f T)| of a ZV whose second impulse moves from
// 1/(2f) to T; shaping a CSV with the grid shaper equals shaping it with the same impulses
// given as a custom list; the predicted MDs on a rigid-link model rank as the linear V (Eq. 2.19,
// computed here) of the applied impulses the JSON lists; and the bad values are exit 2.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"
#include "support/recommend_model.hpp"

using namespace clearshape::testing;

namespace {

std::filesystem::path temp(const std::string& name) { return pid_temp_file("grid_cli", name); }

nlohmann::json run_json(const std::string& args) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

bool on_grid(const nlohmann::json& impulses, double grid_hz, const char* time_key) {
  for (const auto& i : impulses) {
    const double k = i[time_key].get<double>() * grid_hz;
    if (std::abs(k - std::round(k)) > 1e-12) return false;
  }
  return true;
}

const std::string kRecommend = "recommend --data " + golden_path("recommend_one_mode.csv").string() + " --column gyro_deg_s";

}  // namespace

// ZV for 14 Hz, ζ = 0 (½ at 0, ½ at 1/28 s): a 30 Hz drive applies the second at 1/30 s, which
// leaves |cos(π·14/30)| = 0.1045 at 14 Hz; for 15 Hz the half period is one update: nothing moves.
TEST(GridCli, ShapeJsonShowsTheAppliedShaperAndTheDesign) {
  const auto j = run_json("shape --method zv -f 14 -z 0 --grid-hz 30 --json");
  ASSERT_EQ(j["impulses"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["impulses"][1]["time_s"].get<double>(), 1.0 / 30.0);
  EXPECT_NEAR(j["residual_at_design"].get<double>(), std::abs(std::cos(M_PI * 14.0 / 30.0)), 1e-12);
  EXPECT_DOUBLE_EQ(j["duration_s"].get<double>(), 1.0 / 30.0);
  EXPECT_DOUBLE_EQ(j["update_grid"]["grid_hz"].get<double>(), 30.0);
  EXPECT_NEAR(j["update_grid"]["designed_impulses"][1]["time_s"].get<double>(), 1.0 / 28.0, 1e-15);
  EXPECT_LT(j["update_grid"]["designed_residual_at_design"].get<double>(), 1e-12);

  const auto on = run_json("shape --method zv -f 15 -z 0 --grid-hz 30 --json");
  const auto off = run_json("shape --method zv -f 15 -z 0 --json");
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(on["impulses"][i]["time_s"].get<double>(), off["impulses"][i]["time_s"].get<double>(), 1e-12);
    EXPECT_NEAR(on["impulses"][i]["amplitude"].get<double>(), off["impulses"][i]["amplitude"].get<double>(), 1e-12);
  }
  EXPECT_LT(on["residual_at_design"].get<double>(), 1e-12);
  EXPECT_FALSE(off.contains("update_grid"));

  const auto table = run_cli("shape --method zvd -f 14.955 -z 0.129 --grid-hz 30");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("30 Hz drive updates"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("0.066666667"), std::string::npos) << table.out;
}

TEST(GridCli, ShapingACsvUsesTheGridShaper) {
  const auto in = temp("in.csv");
  std::string csv = "time_s,command_deg\n";
  for (int k = 0; k < 400; ++k) csv += std::to_string(k * 0.001) + "," + (k >= 50 ? "20" : "0") + (k % 7 == 0 ? ".5" : "") + "\n";
  write_text(in, csv);
  const auto grid = temp("grid.csv"), custom = temp("custom.csv");
  const auto a = run_cli("shape --method zv -f 14 -z 0 --grid-hz 30 -i " + in.string() + " --column command_deg -o " + grid.string());
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run_cli("shape --method custom --impulses \"0:0.5,0.03333333333333333:0.5\" -i " + in.string() +
                         " --column command_deg -o " + custom.string());
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(read_bytes(grid), read_bytes(custom));
  EXPECT_EQ(read_bytes(in), csv);  // the input is never modified
  for (const auto& p : {in, grid, custom}) std::filesystem::remove(p);
}

TEST(GridCli, EveryExportCarriesTheGridShaper) {
  const std::string zvd = "shape --method zvd -f 14.955 -z 0.129 --grid-hz 30 ";
  const auto j = run_json(zvd + "--export json --sample-time 0.001");
  EXPECT_DOUBLE_EQ(j["design"]["update_grid_hz"].get<double>(), 30.0);
  EXPECT_TRUE(on_grid(j["impulses"], 30.0, "time_s"));
  EXPECT_DOUBLE_EQ(j["design"]["duration_s"].get<double>(), 2.0 / 30.0);
  EXPECT_NE(j["design"]["command"].get<std::string>().find("--grid-hz 30"), std::string::npos);
  // The grid ZVD leaves 2.1e-4 at the mode (the NumPy golden's v_snapped for this case).
  EXPECT_NEAR(j["residual_vibration"]["at_design"]["continuous"].get<double>(), 2.0629e-4, 1e-7);

  const auto header = run_cli(zvd + "--export c-header --sample-time 0.001");
  ASSERT_EQ(header.exit_code, 0) << header.err;
  EXPECT_NE(header.out.find("on the drive's 30 Hz update grid"), std::string::npos);
  EXPECT_NE(header.out.find("#define CS_SHAPER_DELAYS { 0u, 33u, 34u, 66u, 67u }"), std::string::npos) << header.out;

  // RRF's own ZVD is off the grid: the custom form carries the grid impulses (T = 1/30 s each).
  const auto rrf = run_cli(zvd + "--export rrf");
  ASSERT_EQ(rrf.exit_code, 0) << rrf.err;
  EXPECT_NE(rrf.out.find("M593 P\"custom\" H0.360926:0.840616 T0.0333333:0.0333333"), std::string::npos) << rrf.out;
  EXPECT_NE(rrf.err.find("update grid"), std::string::npos) << rrf.err;

  // Klipper builds its own (off-grid) ZVD: refused, naming the grid; a ZV already on the grid passes.
  const auto klipper = run_cli(zvd + "--export klipper");
  EXPECT_EQ(klipper.exit_code, 2);
  EXPECT_NE(klipper.err.find("not the design on the 30 Hz update grid"), std::string::npos) << klipper.err;
  const auto zv15 = run_cli("shape --method zv -f 15 -z 0 --grid-hz 30 --export klipper");
  ASSERT_EQ(zv15.exit_code, 0) << zv15.err;
  EXPECT_NE(zv15.out.find("shaper_freq_x: 15\n"), std::string::npos) << zv15.out;
}

TEST(GridCli, RecommendScoresTheAppliedShapers) {
  const auto off = run_json(kRecommend + " --json");
  const auto on = run_json(kRecommend + " --grid-hz 30 --json");
  EXPECT_FALSE(off["scoring"].contains("update_grid_hz"));
  EXPECT_FALSE(off["candidates"][0].contains("designed_impulses"));
  EXPECT_DOUBLE_EQ(on["scoring"]["update_grid_hz"].get<double>(), 30.0);
  for (const auto& c : on["candidates"]) {
    ASSERT_TRUE(c["available"].get<bool>()) << c["name"];
    EXPECT_TRUE(on_grid(c["impulses"], 30.0, "time_s")) << c["name"];
    EXPECT_TRUE(c["duplicate_of"].is_null()) << c["name"];
    EXPECT_TRUE(c.contains("designed_impulses") && c.contains("remaining_worst_designed")) << c["name"];
  }
  // Off the grid MZV is recommended; the drive would apply it on its updates. On the grid ZVD is.
  EXPECT_EQ(off["recommendation"]["name"], "mzv");
  EXPECT_EQ(on["recommendation"]["name"], "zvd");
  EXPECT_NE(on["recommendation"]["shape_command"].get<std::string>().find("--grid-hz 30"), std::string::npos);

  const auto table = run_cli(kRecommend + " --grid-hz 30");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("on the drive's 30 Hz update grid"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("applied: 0.00 ms"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("designed_%"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("--grid-hz 30\n"), std::string::npos) << table.out;
}

// A 42 Hz mode on a 15 Hz grid: ZV, MZV and SI all become the identity (one impulse).
TEST(GridCli, RecommendMarksCandidatesOnTheSameImpulses) {
  const std::string args = "recommend --data " + golden_path("recommend_klipper_raw.csv").string() + " --column accel_x --modes 1 --grid-hz 15";
  const auto j = run_json(args + " --json");
  int duplicates = 0;
  for (const auto& c : j["candidates"]) {
    if (c["duplicate_of"].is_null()) continue;
    ++duplicates;
    EXPECT_EQ(c["duplicate_of"], "zv") << c["name"];
    EXPECT_EQ(c["impulses"].size(), 1u);
    EXPECT_NE(j["recommendation"]["name"], c["name"]);
  }
  EXPECT_EQ(duplicates, 2);
  const auto table = run_cli(args);
  EXPECT_NE(table.out.find("(the same as zv: not chosen)"), std::string::npos) << table.out;
}

// A rigid link (zero play) on a speed-mode drive at 17 Hz, ζ 0.05: the predicted MDs must rank
// the candidates as the linear V of the impulses the JSON lists as applied (on the grid).
TEST(GridCli, RecommendPredictsTheMdOfTheAppliedShaper) {
  const double f_hz = 17.0, zeta = 0.05;
  const auto fit = temp("rigid.json");
  write_text(fit, R"({"command": "fit-clearance", "mode": "speed", "link_inertia_kg_m2": 0.005,
 "parameters": {"stiffness": {"value": 45.158834415041305}, "damping": {"value": 0.12355192243621643},
                "play": {"value": 0.0}, "exponent": {"value": 1.0}},
 "drive": {"model": "P2U", "parameters": {"Kp": {"value": 25.0}, "Zeta": {"value": 0.05}, "Tw": {"value": )" +
                      nlohmann::json(1.0 / (2.0 * M_PI * f_hz)).dump() + "}}}}");
  const auto j = run_json(kRecommend + " --grid-hz 30 --model " + fit.string() + " --move step --amplitude 1 --start-s 0.2 --move-duration-s 3 --json");
  const int compared = expect_md_ranks_as_linear_v(j, f_hz, zeta);
  EXPECT_GE(compared, 15);
  std::filesystem::remove(fit);
}

TEST(GridCli, BadGridRatesAreExit2NamingTheOptionAndItsRange) {
  for (const char* bad : {"0", "-30", "nan", "inf"}) {
    for (const std::string& cmd : {std::string("shape --method zv -f 14 -z 0"), kRecommend}) {
      const auto r = run_cli(cmd + " --grid-hz " + bad);
      EXPECT_EQ(r.exit_code, 2) << cmd << " " << bad;
      EXPECT_NE(r.err.find("--grid-hz"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("(0, 1e+06] Hz"), std::string::npos) << r.err;
    }
  }
  const auto ca = run_cli("shape --method clearance-aware --moves 5 --grid-hz 30");
  EXPECT_EQ(ca.exit_code, 2);
  EXPECT_NE(ca.err.find("--grid-hz"), std::string::npos) << ca.err;
}
