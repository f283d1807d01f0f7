// clearshape arm move --shaper clearance-aware: the trajectory it writes is the library's design
// (arm/clearance_aware.hpp) on the same move and options, shaped the same way, to the bit, and its
// --export headers are arm::joint_shaper_headers of that design, byte for byte; played
// on scara-2 with 0.5° of play from the design's start places it leaves less tool residual (Eq.
// 5.1, arm/benchmark.hpp) than the unshaped move on a benchmark move whose links rattle; bad
// options exit 2 naming the option and its range.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "clearshape/arm/clearance_aware.hpp"
#include "clearshape/arm/shaper_export.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace clearshape::arm {
namespace {

std::string angles(const Eigen::VectorXd& q) { return fmt::format("{:.17g},{:.17g}", q(0), q(1)); }

ArmModel scara_with_half_degree_play() {
  ArmModel arm = builtin_arm("scara-2");
  for (ArmJoint& j : arm.joints) j.half_play_rad = 0.25 * M_PI / 180.0;  // --play-deg 0.5: total play
  return arm;
}

// The tool residual of `trajectory` played from start place `fraction` (φ_i/β_i) for 1.5 s after it.
double played_residual_m(const ArmModel& arm, const JointTrajectory& trajectory, const Eigen::VectorXd& fraction) {
  ArmSimulationOptions o;
  o.duration_s = trajectory.time_s.back() + 1.5;
  o.output_rate_hz = 1000.0;
  o.initial.relative_angle_rad = Eigen::VectorXd(arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    o.initial.relative_angle_rad(i) = fraction(i) * arm.joints[static_cast<std::size_t>(i)].half_play_rad;
  }
  return tool_residual_m(simulate_arm(arm, drive_commands(arm, trajectory), o), trajectory.time_s.back());
}

TEST(ArmClearanceAwareCli, WritesTheLibrarysDesignAndLeavesLessResidualThanUnshaped) {
  const ArmModel arm = scara_with_half_degree_play();
  const PointToPoint move = pick_and_place_moves(arm, 12, 1)[9];  // rattles: docs/arm.md §7
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_clearance_aware_cli");
  fs::create_directories(dir / "headers");
  const auto r = run_cli(fmt::format("arm move --play-deg 0.5 --from {} --to {} --shaper clearance-aware "
                                     "--evaluations 12 -o {} --export {}",
                                     angles(move.from_rad), angles(move.to_rad), (dir / "move.json").string(),
                                     (dir / "headers").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("worst ratio to unshaped"), std::string::npos) << r.out;

  ArmClearanceAwareOptions o;  // the CLI's defaults, written out
  o.play.limits.assign(2, {2.0, 20.0, 400.0});
  o.play.sample_time_s = 1e-3;
  o.play.settle_s = 1.5;
  o.max_evaluations = 12;
  o.threads = 2;
  const ArmClearanceAwareResult d = design_clearance_aware_move(arm, move, o);
  const JointTrajectory planned = plan_move(arm, move.from_rad, move.to_rad, o.play.limits, o.play.sample_time_s);
  const JointTrajectory expected = shape_trajectory(planned, std::vector<shaping::Shaper>(2, d.shaper));
  const JointTrajectory written = read_trajectory_json(dir / "move.json");
  ASSERT_EQ(written.time_s.size(), expected.time_s.size());
  EXPECT_EQ(written.position_rad, expected.position_rad);  // bit for bit
  EXPECT_EQ(written.velocity_rad_s, expected.velocity_rad_s);
  EXPECT_EQ(d.worse_than_unshaped, r.out.find("WORSE") != std::string::npos) << r.out;
  const std::string command = fmt::format("clearshape arm move --arm scara-2 --from {} --to {} --shaper "
                                          "clearance-aware (arm/clearance_aware.hpp)",
                                          angles(move.from_rad), angles(move.to_rad));
  const std::vector<shaping::Shaper> shapers(2, d.shaper);
  for (const JointShaperFile& f : joint_shaper_headers(arm, shapers, 1e-3, "cs", command)) {
    std::ifstream in(dir / "headers" / f.file_name);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, f.text) << f.file_name;
  }

  double unshaped = 0.0, shaped = 0.0;
  for (const Eigen::VectorXd& place : d.start_places) {
    unshaped += played_residual_m(arm, planned, place);
    shaped += played_residual_m(arm, written, place);
  }
  RecordProperty("move", angles(move.from_rad) + " -> " + angles(move.to_rad));
  RecordProperty("unshaped_mm", fmt::format("{:.4f}", 1e3 * unshaped));
  RecordProperty("clearance_aware_mm", fmt::format("{:.4f}", 1e3 * shaped));
  EXPECT_GT(unshaped, 1e-4) << "the move does not rattle: " << unshaped;
  EXPECT_LT(shaped, 0.5 * unshaped) << shaped << " m against " << unshaped << " m unshaped";
}

TEST(ArmClearanceAwareCli, BadOptionsExit2NamingTheOption) {
  const std::string move = "arm move --from 0,1.5 --to 1.2,0.6 --shaper clearance-aware ";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--evaluations 5", "--evaluations"},      {"--slots 1", "--slots"},
      {"--grid-s 2", "--grid-s"},                {"--threads 0", "--threads"},
      {"--design-settle-s 0", "--design-settle-s"}, {"--start-places 0,2", "[-1, 1]"},
      {"--start-places 0", "--start-places"},    {"--start-places '0,0;x,1'", "--start-places"}};
  for (const auto& [option, named] : cases) {
    const auto r = run_cli(move + option);
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << option << ": " << r.err;
  }
  const auto none = run_cli("arm move --from 0,1.5 --to 1.2,0.6 --export .");  // no shaper to export
  EXPECT_EQ(none.exit_code, 2) << none.err;
  EXPECT_NE(none.err.find("--export"), std::string::npos) << none.err;
}

}  // namespace
}  // namespace clearshape::arm
