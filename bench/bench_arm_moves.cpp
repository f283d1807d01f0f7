// Shaped point-to-point moves on the built-in scara-2 (docs/arm.md §7): six synchronised
// jerk-limited moves across the workspace, each played unshaped, with one fixed ZVD shaper per
// joint designed at the workspace centre, and with ZVD shapers designed at the move's end pose
// (arm/trajectory.hpp). The benchmark times planning + shaping + simulating one move;
// `bench_arm_moves --report` prints the tool-tip residual of every move (Eq. 5.1 on each tool
// coordinate from the end of the command, combined as √(MD_x² + MD_y²), in mm) with 0.5° play
// per joint (the built-in) and with no play (a stiff linear joint) and exits.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "clearshape/arm/simulation.hpp"
#include "clearshape/arm/trajectory.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "benchmark_main.hpp"

namespace arm = clearshape::arm;

namespace {

// Link limits per joint: rad/s, rad/s², rad/s³ (a desktop arm's brisk pick-and-place).
const std::vector<clearshape::signal::AxisLimits> kLimits{{2.0, 20.0, 400.0}, {3.0, 30.0, 600.0}};
constexpr double kSettle_s = 1.5;  // recorded after the command ends

struct Move {
  double from[2], to[2];
};
constexpr Move kMoves[] = {{{0.0, 1.5}, {1.2, 0.6}},   {{1.2, 0.6}, {-0.8, 1.9}}, {{-0.8, 1.9}, {0.4, -1.4}},
                           {{0.4, -1.4}, {-1.0, -0.5}}, {{-1.0, -0.5}, {0.9, 2.2}}, {{0.9, 2.2}, {0.0, 1.5}}};

struct Outcome {
  double md_mm = 0.0;
  double shaper_s = 0.0;
  long onsets = 0;
};

// Eq. 5.1 on the tool's x and y from `from_s` on (metrics/mean_deviation.hpp), combined.
double tool_md_mm(const arm::ArmTrace& tr, double from_s) {
  double sum = 0.0;
  for (int axis = 0; axis < 2; ++axis) {
    clearshape::UniformSeries s{tr.time_s.front(), tr.time_s[1] - tr.time_s[0], {}};
    for (Eigen::Index k = 0; k < tr.tool_position_m.rows(); ++k) s.values.push_back(tr.tool_position_m(k, axis));
    clearshape::metrics::MeanDeviationOptions o;
    o.search_from_s = from_s;
    const double md = clearshape::metrics::mean_deviation(s, o).mean_deviation;
    sum += md * md;
  }
  return 1e3 * std::sqrt(sum);
}

Outcome play(const arm::ArmModel& model, const Move& m, arm::ShaperSchedule schedule, bool every_mode) {
  const Eigen::Vector2d q0(m.from[0], m.from[1]), q1(m.to[0], m.to[1]);
  const arm::JointTrajectory move = arm::plan_move(model, q0, q1, kLimits, 1e-3);
  const auto shapers = arm::joint_shapers(model, q1, {.schedule = schedule, .method = clearshape::shaping::Method::zvd, .every_mode = every_mode});
  const arm::JointTrajectory shaped = arm::shape_trajectory(move, shapers);
  arm::ArmSimulationOptions o;
  o.duration_s = shaped.time_s.back() + kSettle_s;
  const arm::ArmTrace tr = arm::simulate_arm(model, arm::drive_commands(model, shaped), o);
  Outcome out{tool_md_mm(tr, shaped.time_s.back()), std::max(shapers[0].duration_s(), shapers[1].duration_s()), 0};
  for (const arm::ArmEvent& e : tr.events) out.onsets += e.onset ? 1 : 0;
  return out;
}

// A run CVODE cannot finish is printed as such, not left out.
void print_outcome(const arm::ArmModel& model, const Move& m, arm::ShaperSchedule schedule, bool every_mode) {
  try {
    const Outcome o = play(model, m, schedule, every_mode);
    std::printf("  %.5f (%ld)", o.md_mm, o.onsets);
  } catch (const clearshape::RuntimeError& e) {
    std::printf("  CVODE-failed");
    std::fprintf(stderr, "%s\n", e.what());
  }
  std::fflush(stdout);
}

arm::ArmModel stiff_without_play() {
  arm::ArmModel model = arm::builtin_arm("scara-2");
  for (arm::ArmJoint& j : model.joints) j.half_play_rad = 0.0;  // the same flanks, linear, no play
  return model;
}

void report() {
  const arm::ArmModel with_play = arm::builtin_arm("scara-2"), without_play = stiff_without_play();
  const arm::ArmModes centre = arm::joint_modes(with_play, arm::workspace_centre(with_play));
  std::printf("fixed shapers at the centre: shoulder %.1f Hz, elbow %.1f Hz\n",
              centre.joint_mode(0).natural_frequency_hz(), centre.joint_mode(1).natural_frequency_hz());
  std::printf("end pose (rad)  end modes (Hz)  play  MD (mm; contact onsets): unshaped, fixed, scheduled "
              "(dominant mode per joint), fixed, scheduled (both modes)\n");
  for (const Move& m : kMoves) {
    const arm::ArmModes end = arm::joint_modes(with_play, Eigen::Vector2d(m.to[0], m.to[1]));
    for (const arm::ArmModel* model : {&with_play, &without_play}) {
      std::printf("%5.1f,%4.1f  %5.1f %5.1f  %s", m.to[0], m.to[1], end.joint_mode(0).natural_frequency_hz(),
                  end.joint_mode(1).natural_frequency_hz(), model == &with_play ? "0.5°" : "0   ");
      print_outcome(*model, m, arm::ShaperSchedule::none, false);
      for (const bool every : {false, true}) {
        for (const auto s : {arm::ShaperSchedule::fixed, arm::ShaperSchedule::end_pose}) print_outcome(*model, m, s, every);
      }
      std::printf("\n");
    }
  }
}

void BM_ArmShapedMove(benchmark::State& state) {
  const arm::ArmModel model = arm::builtin_arm("scara-2");
  for (auto _ : state) benchmark::DoNotOptimize(play(model, kMoves[0], arm::ShaperSchedule::end_pose, false).md_mm);
}
BENCHMARK(BM_ArmShapedMove)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--report") == 0) {
      report();
      return 0;
    }
  }
  return run_google_benchmarks(argc, argv);
}
