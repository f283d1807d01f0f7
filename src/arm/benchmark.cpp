#include "clearshape/arm/benchmark.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "clearshape/arm/chain.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"

namespace clearshape::arm {

std::vector<PointToPoint> pick_and_place_moves(const ArmModel& arm, std::size_t count, std::uint64_t seed,
                                               double margin) {
  if (count == 0) throw InvalidArgument("pick_and_place_moves: count is 0; allowed: at least one move");
  require_in_closed("margin", margin, 0.0, 0.45);
  const auto& joints = arm.chain.joints();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<PointToPoint> moves;
  Eigen::VectorXd at = workspace_centre(arm);
  for (std::size_t m = 0; m < count; ++m) {
    Eigen::VectorXd to(at.size());
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const double lo = joints[i].limited ? joints[i].lower_rad : -std::numbers::pi;
      const double hi = joints[i].limited ? joints[i].upper_rad : std::numbers::pi;
      const double span = hi - lo;
      to(static_cast<Eigen::Index>(i)) = lo + span * (margin + (1.0 - 2.0 * margin) * unit(rng));
    }
    moves.push_back({at, to});
    at = to;
  }
  return moves;
}

double tool_residual_m(const ArmTrace& trace, double from_s) {
  if (trace.time_s.size() < 2) throw InvalidArgument("tool_residual_m: the trace has fewer than 2 samples");
  double sum = 0.0;
  for (Eigen::Index axis = 0; axis < 3; ++axis) {  // every coordinate: a vertical arm moves in x–z
    UniformSeries s{trace.time_s.front(), trace.time_s[1] - trace.time_s[0], {}};
    s.values.reserve(static_cast<std::size_t>(trace.tool_position_m.rows()));
    for (Eigen::Index k = 0; k < trace.tool_position_m.rows(); ++k) s.values.push_back(trace.tool_position_m(k, axis));
    metrics::MeanDeviationOptions o;
    o.search_from_s = from_s;
    const double md = metrics::mean_deviation(s, o).mean_deviation;  // Eq. 5.1
    sum += md * md;
  }
  return std::sqrt(sum);
}

MovePlay play_move(const ArmModel& arm, const PointToPoint& move, const MoveShaping& shaping,
                   const MovePlayOptions& options) {
  return play_move_with(arm, move, joint_shapers(arm, move.to_rad, shaping), options);
}

std::vector<signal::AxisLimits> flank_keeping_limits(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                                     std::span<const signal::AxisLimits> limits, double margin,
                                                     double floor) {
  require_in_closed("flank_margin", margin, 0.0, 1.0, "0: off");
  if (!(floor > 0.0 && floor <= 1.0)) throw_invalid("flank_floor", floor, "(0, 1]");
  if (end_pose_rad.size() != arm.dof() || limits.size() != static_cast<std::size_t>(arm.dof())) {
    throw_invalid("flank_keeping_limits: pose and limits size", static_cast<double>(end_pose_rad.size()),
                  fmt::format("{} (one per joint), {} limits given", arm.dof(), limits.size()));
  }
  std::vector<signal::AxisLimits> out(limits.begin(), limits.end());
  if (margin == 0.0) return out;
  ChainWorkspace ws(arm.chain);
  Eigen::VectorXd g;
  Eigen::MatrixXd m;
  ws.gravity_torque(end_pose_rad, g);
  ws.mass_matrix(end_pose_rad, m);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const double bound_rad_s2 = std::abs(g(k)) / m(k, k);  // |q̈_i| < |g_i| / M_ii keeps the flank loaded
    if (bound_rad_s2 <= 1e-9 * out[i].acceleration) continue;  // no gravity on this joint (g_i = 0 to rounding)
    out[i].acceleration = std::max(floor * out[i].acceleration, std::min(out[i].acceleration, margin * bound_rad_s2));
  }
  return out;
}

MovePlay play_move_with(const ArmModel& arm, const PointToPoint& move, std::span<const shaping::Shaper> shapers,
                        const MovePlayOptions& options) {
  require_in_closed("flank_margin", options.flank_margin, 0.0, 1.0, "0: off");
  const std::vector<signal::AxisLimits> limits =
      options.flank_margin > 0.0 ? flank_keeping_limits(arm, move.to_rad, options.limits, options.flank_margin, options.flank_floor)
                                 : options.limits;
  const JointTrajectory planned = plan_move(arm, move.from_rad, move.to_rad, limits, options.sample_time_s);
  const JointTrajectory shaped = shape_trajectory(planned, shapers);
  ArmSimulationOptions o;
  o.duration_s = shaped.time_s.back() + options.settle_s;
  o.output_rate_hz = 1.0 / options.sample_time_s;
  if (options.start_play_fraction.size() > 0) {
    if (options.start_play_fraction.size() != arm.dof()) {
      throw_invalid("start_play_fraction size", static_cast<double>(options.start_play_fraction.size()),
                    fmt::format("{} (one per joint)", arm.dof()));
    }
    o.initial.relative_angle_rad = Eigen::VectorXd(arm.dof());
    for (int i = 0; i < arm.dof(); ++i) {
      require_in_closed("start_play_fraction", options.start_play_fraction(i), -1.0, 1.0);
      o.initial.relative_angle_rad(i) = options.start_play_fraction(i) * arm.joints[static_cast<std::size_t>(i)].half_play_rad;
    }
  }
  const ArmTrace trace = simulate_arm(arm, drive_commands(arm, shaped), o);
  MovePlay out;
  out.command_end_s = shaped.time_s.back();
  out.residual_m = tool_residual_m(trace, out.command_end_s);
  for (const shaping::Shaper& s : shapers) out.shaper_duration_s = std::max(out.shaper_duration_s, s.duration_s());
  for (const ArmEvent& e : trace.events) out.contact_onsets += e.onset ? 1 : 0;
  return out;
}

std::vector<BenchmarkDesign> run_benchmark(const ArmModel& arm, std::span<const PointToPoint> moves,
                                           std::span<const MoveShaping> designs, const MovePlayOptions& options) {
  if (designs.empty()) throw InvalidArgument("run_benchmark: no designs; allowed: at least one (the first is the reference)");
  std::vector<BenchmarkDesign> out;
  for (const MoveShaping& d : designs) {
    const std::string name = d.schedule == ShaperSchedule::none
                                 ? "unshaped"
                                 : fmt::format("{} {}{}", shaping::to_string(d.method), to_string(d.schedule),
                                               d.every_mode ? " every-mode" : "");
    BenchmarkDesign b{name, d, {}, 0.0, 0.0};
    for (const PointToPoint& m : moves) {
      b.moves.push_back(play_move(arm, m, d, options));
      b.total_residual_m += b.moves.back().residual_m;
    }
    out.push_back(std::move(b));
  }
  for (BenchmarkDesign& b : out) {
    b.improvement = out.front().total_residual_m > 0.0 ? 1.0 - b.total_residual_m / out.front().total_residual_m : 0.0;
  }
  return out;
}

}  // namespace clearshape::arm
