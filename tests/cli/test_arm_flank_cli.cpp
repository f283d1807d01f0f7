// clearshape arm move --flank-margin/--flank-floor (docs/arm.md §7, "The flank-keeping stop"): on
// vertical-2's study move 17 the shoulder's acceleration limit is lowered to margin · |g_1| / M_11
// at the end pose (g and M from the chain's own dynamics, arm/chain.hpp — independent of the
// lowering), and the written move reaches exactly that; every shaper plans within it. A margin or
// floor out of range: test_arm_cli.cpp's BadInputExits2NamingTheOption.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/arm/arm.hpp"
#include "clearshape/arm/benchmark.hpp"
#include "clearshape/arm/chain.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

// --arm vertical-2 --from … --to … of the study's move 17 (pick_and_place_moves(arm, 20, 1)[17])
std::string move17(const clearshape::arm::ArmModel& arm) {
  const auto m = clearshape::arm::pick_and_place_moves(arm, 20, 1, 0.1)[17];
  return fmt::format("arm move --arm vertical-2 --from={:.17g},{:.17g} --to={:.17g},{:.17g} ", m.from_rad(0),
                     m.from_rad(1), m.to_rad(0), m.to_rad(1));
}

double peak_acceleration(const fs::path& json, int joint) {
  std::ifstream in(json);
  const auto doc = nlohmann::json::parse(in);
  double a = 0.0;
  for (const auto& p : doc["points"]) a = std::max(a, std::abs(p["accelerations"][joint].get<double>()));
  return a;
}

TEST(ArmFlankCli, ShouldersPeakAccelerationIsTheFlankBound) {
  const auto arm = clearshape::arm::builtin_arm("vertical-2");
  const Eigen::VectorXd end = clearshape::arm::pick_and_place_moves(arm, 20, 1, 0.1)[17].to_rad;
  clearshape::arm::ChainWorkspace ws(arm.chain);
  Eigen::VectorXd g;
  Eigen::MatrixXd m;
  ws.gravity_torque(end, g);
  ws.mass_matrix(end, m);
  const double bound_rad_s2 = 0.5 * std::abs(g(0)) / m(0, 0);  // M q̈ + g = τ keeps g's sign for |q̈| < |g|/M_ii
  ASSERT_LT(bound_rad_s2, 20.0) << "the shoulder's default limit already keeps the flank: the test shows nothing";
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_flank_cli");
  auto r = run_cli(move17(arm) + "-o " + (dir / "default.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("flank stop"), std::string::npos) << r.out;  // off by default
  r = run_cli(move17(arm) + "--flank-margin 0.5 -o " + (dir / "flank.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(fmt::format("acceleration 20,20 -> {:.6g},", bound_rad_s2)), std::string::npos) << r.out;
  const double flank = peak_acceleration(dir / "flank.json", 0), plain = peak_acceleration(dir / "default.json", 0);
  EXPECT_NEAR(flank, bound_rad_s2, 1e-9);
  EXPECT_LT(flank, plain);
  RecordProperty("move", move17(arm));
  RecordProperty("bound_rad_s2", fmt::format("{:.6f}", bound_rad_s2));
  RecordProperty("default_peak_rad_s2", fmt::format("{:.6f}", plain));
}

// The printed "move … rad, D s unshaped" of `arm move ARGS` (-1 when it fails).
double unshaped_s(const std::string& args) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  const auto at = r.out.find(" s unshaped");
  return at == std::string::npos ? -1.0 : std::stod(r.out.substr(r.out.rfind(' ', at - 1) + 1));
}

// Every shaper plans within the lowered limits: the printed unshaped move is the same longer one.
TEST(ArmFlankCli, EveryShaperPlansWithinTheLoweredLimits) {
  const auto arm = clearshape::arm::builtin_arm("vertical-2");
  const double plain_s = unshaped_s(move17(arm));
  const double none_s = unshaped_s(move17(arm) + "--flank-margin 0.5");
  EXPECT_GT(none_s, plain_s);
  for (const char* s : {"fixed", "scheduled", "clearance-aware --evaluations 10 --design-settle-s 0.3"}) {
    EXPECT_EQ(unshaped_s(move17(arm) + "--flank-margin 0.5 --shaper " + s), none_s) << s;
  }
}

}  // namespace
