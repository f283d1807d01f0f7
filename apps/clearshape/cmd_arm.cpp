// clearshape arm: the multi-joint arm of docs/arm.md from the command line — `arm simulate`
// (a joint trajectory or a move played by simulate_arm), `arm move` (a synchronised jerk-limited
// move, shaped per joint, written as ROS JointTrajectory JSON or CSV) and `arm modes`
// (cmd_arm_modes.cpp). The library does the work (arm/trajectory.hpp, arm/simulation.hpp).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "arm_options.hpp"
#include "clearshape/arm/benchmark.hpp"
#include "clearshape/arm/shaper_export.hpp"
#include "clearshape/arm/simulation.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "command.hpp"

namespace clearshape::cli {

void add_move_options(CLI::App& app, MoveRequest& m, bool required) {
  app.add_option("--from", m.from, "Start pose: one angle per joint, comma-separated (rad)")->required(required);
  app.add_option("--to", m.to, "End pose: one angle per joint, comma-separated (rad)")->required(required);
  app.add_option("--shaper", m.shaper,
                 "none; fixed: each joint's shaper designed at the workspace centre; scheduled: at the end pose; "
                 "clearance-aware: one positive shaper for every joint optimised on the arm with its play")
      ->check(CLI::IsMember({"none", "fixed", "scheduled", "clearance-aware"}))
      ->capture_default_str();
  app.add_option("--method", m.method, "Shaper design (zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3)")
      ->check(CLI::IsMember({"zv", "zvd", "zvdd", "zvddd", "mzv", "ei", "ei2", "ei3"}))
      ->capture_default_str();
  app.add_flag("--every-mode", m.every_mode, "Shape every mode of the design pose, not each joint's dominant one");
  app.add_option("--velocity", m.velocity, "Velocity limit at the link: one for every joint or one per joint, comma-separated (rad/s, 1e-6-1e3)")
      ->capture_default_str();
  app.add_option("--acceleration", m.acceleration,
                 "Acceleration limit at the link: one for every joint or one per joint (rad/s², 1e-6-1e5)")
      ->capture_default_str();
  app.add_option("--jerk", m.jerk, "Jerk limit at the link: one for every joint or one per joint (rad/s³, 1e-6-1e7)")
      ->capture_default_str();
  app.add_option("--sample-time", m.sample_time_s, "Sample time of the trajectory (s, 1e-5-0.1)")
      ->check(CLI::Range(1e-5, 0.1))->capture_default_str();
  app.add_option("--evaluations", m.evaluations, "clearance-aware: evaluations of the objective (10-100000)")
      ->check(CLI::Range(10, 100000))->capture_default_str();
  app.add_option("--slots", m.slots, "clearance-aware: impulse slots (2-32)")
      ->check(CLI::Range(2, 32))->capture_default_str();
  app.add_option("--grid-s", m.grid_s,
                 "clearance-aware: slot spacing (s, 0-1; 0: a quarter period of the end pose's lowest mode)")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--start-places", m.start_places,
                 "clearance-aware: where the links start in their plays, 'f1,f2;f1,f2;…' (each in [-1, 1]; "
                 "default: all at -1, 0, +1 and the two mixed corners)");
  app.add_option("--design-settle-s", m.design_settle_s,
                 "clearance-aware: simulated time after the shaped command in each trial (s, 0.1-10)")
      ->check(CLI::Range(0.1, 10.0))->capture_default_str();
  app.add_option("--threads", m.threads, "clearance-aware: parallel simulations (1-64); the design does not depend on it")
      ->check(CLI::Range(1, 64))->capture_default_str();
  app.add_option("--flank-margin", m.flank_margin,
                 "The flank-keeping stop: plan within acceleration limits lowered to this share of |g_i|/M_ii at "
                 "the end pose (0-1; 0: off; docs/arm.md §7)")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--flank-floor", m.flank_floor,
                 "The flank-keeping stop: no acceleration limit lowered below this share of its own (0-1, not 0)")
      ->capture_default_str();
}

namespace {

// The linear design --shaper fixed|scheduled names (arm/trajectory.hpp).
arm::MoveShaping arm_move_shaping(const MoveRequest& m) {
  arm::MoveShaping shaping;
  shaping.schedule = m.shaper == "fixed" ? arm::ShaperSchedule::fixed : arm::ShaperSchedule::end_pose;
  shaping.method = shaping::method_from_string(m.method);
  shaping.every_mode = m.every_mode;
  return shaping;
}

}  // namespace

std::vector<signal::AxisLimits> joint_limits(const arm::ArmModel& arm, const MoveRequest& m) {
  const auto v = parse_joint_values(m.velocity, "--velocity", arm, "rad/s", 1e-6, 1e3);
  const auto a = parse_joint_values(m.acceleration, "--acceleration", arm, "rad/s²", 1e-6, 1e5);
  const auto j = parse_joint_values(m.jerk, "--jerk", arm, "rad/s³", 1e-6, 1e7);
  std::vector<signal::AxisLimits> limits;
  for (std::size_t i = 0; i < v.size(); ++i) limits.push_back({v[i], a[i], j[i]});
  return limits;
}

std::vector<signal::AxisLimits> move_limits(const arm::ArmModel& arm, const MoveRequest& m,
                                            const Eigen::VectorXd& end_pose_rad, std::string& summary) {
  if (!(m.flank_floor > 0.0 && m.flank_floor <= 1.0)) {
    throw InvalidArgument(fmt::format("--flank-floor = {}; allowed: (0, 1], the share of each acceleration limit "
                                      "kept at least", m.flank_floor));
  }
  const std::vector<signal::AxisLimits> given = joint_limits(arm, m);
  if (m.flank_margin == 0.0) return given;
  const auto lowered = arm::flank_keeping_limits(arm, end_pose_rad, given, m.flank_margin, m.flank_floor);
  std::string from, to;
  for (std::size_t i = 0; i < given.size(); ++i) {
    from += fmt::format("{}{:.6g}", i == 0 ? "" : ",", given[i].acceleration);
    to += fmt::format("{}{:.6g}", i == 0 ? "" : ",", lowered[i].acceleration);
  }
  summary += fmt::format("flank stop  margin {:g}, floor {:g}: acceleration {} -> {} rad/s² "
                         "(max(floor·a, min(a, margin·|g|/M_ii)) at the end pose)\n",
                         m.flank_margin, m.flank_floor, from, to);
  return lowered;
}

arm::JointTrajectory build_move(const arm::ArmModel& arm, const MoveRequest& m, std::string& summary,
                                std::vector<shaping::Shaper>* applied) {
  const Eigen::VectorXd q0 = parse_angles(m.from, "--from", arm);
  const Eigen::VectorXd q1 = parse_angles(m.to, "--to", arm);
  std::string flank;
  arm::JointTrajectory t = arm::plan_move(arm, q0, q1, move_limits(arm, m, q1, flank), m.sample_time_s);
  summary = fmt::format("move        {} -> {} rad, {:.4f} s unshaped\n", format_angles(q0), format_angles(q1),
                        t.time_s.back()) + flank;
  if (m.shaper == "none") return t;
  std::vector<shaping::Shaper> own;
  std::vector<shaping::Shaper>& shapers = applied != nullptr ? *applied : own;
  if (m.shaper == "clearance-aware") return clearance_aware_move(arm, m, t, summary, shapers);
  const arm::MoveShaping shaping = arm_move_shaping(m);
  shapers = arm::joint_shapers(arm, q1, shaping);
  const Eigen::VectorXd pose = m.shaper == "fixed" ? arm::workspace_centre(arm) : q1;
  const arm::ArmModes modes = arm::joint_modes(arm, pose, shaping.modes);
  for (int i = 0; i < arm.dof(); ++i) {
    const auto mode = modes.joint_mode(i);
    summary += fmt::format("shaper      {}: {} {} at {} rad, {} ({:.2f} Hz, zeta {:.2g}), {:.4f} s\n",
                           arm.joints[static_cast<std::size_t>(i)].name, m.method, m.shaper, format_angles(pose),
                           m.every_mode ? "every mode" : "dominant mode", mode.natural_frequency_rad_s / (2 * M_PI),
                           mode.damping_ratio, shapers[static_cast<std::size_t>(i)].duration_s());
  }
  return arm::shape_trajectory(t, shapers);
}

namespace {

struct MoveState {
  ArmSource source;
  MoveRequest move;
  std::string out, export_dir;
};

// --export: one C header per joint (arm/shaper_export.hpp), the linear designs with their modes.
void export_headers(const arm::ArmModel& model, const MoveState& st, std::span<const shaping::Shaper> shapers) {
  const double dt = st.move.sample_time_s;
  const auto files =
      st.move.shaper == "clearance-aware"
          ? arm::joint_shaper_headers(model, shapers, dt, "cs",
                                      fmt::format("clearshape arm move --arm {} --from {} --to {} --shaper "
                                                  "clearance-aware (arm/clearance_aware.hpp)",
                                                  model.name, st.move.from, st.move.to))
          : arm::joint_shaper_headers(model, parse_angles(st.move.to, "--to", model), arm_move_shaping(st.move), dt);
  arm::write_joint_shaper_headers(st.export_dir, files);
  for (const auto& f : files) fmt::print("written     {}\n", (std::filesystem::path(st.export_dir) / f.file_name).string());
}

void run_move(const MoveState& st) {
  if (!st.export_dir.empty() && st.move.shaper == "none") {
    throw InvalidArgument("--export: --shaper none has no shaper to export; allowed with --shaper fixed, scheduled "
                          "or clearance-aware");
  }
  const arm::ArmModel model = load_arm(st.source);
  std::string summary;
  std::vector<shaping::Shaper> shapers;
  const arm::JointTrajectory t = build_move(model, st.move, summary, &shapers);
  fmt::print("arm         {} ({} joints)\n{}duration    {:.4f} s, {} samples\n", model.name, model.dof(), summary,
             t.time_s.back(), t.time_s.size());
  if (!st.export_dir.empty()) export_headers(model, st, shapers);
  if (st.out.empty()) return;
  if (output_kind(st.out) == ".json") {
    arm::write_trajectory_json(st.out, t);
  } else {
    arm::write_trajectory_csv(st.out, t);
  }
  fmt::print("written     {}\n", st.out);
}

void setup_move(CLI::App& parent) {
  auto st = std::make_shared<MoveState>();
  CLI::App* sub = add_arm_subcommand(
      parent, "move", "A synchronised jerk-limited point-to-point move of every joint, shaped per joint, as a "
              "ROS JointTrajectory JSON or CSV (docs/arm.md §7)",
      st->source);
  add_move_options(*sub, st->move, true);
  sub->add_option("-o,--out", st->out, "Write the trajectory: a .json (ROS JointTrajectory) or .csv file");
  sub->add_option("--export", st->export_dir,
                  "Write each joint's shaper as a C header cs_<joint>.h into this existing folder (not with --shaper none)")
      ->check(CLI::ExistingDirectory);
  sub->callback([st] { run_move(*st); });
}

struct SimulateState {
  ArmSource source;
  MoveRequest move;
  std::string trajectory, out;
  double settle_s = 1.0;
  double rate_hz = 1000.0;
};

arm::JointTrajectory simulate_input(const arm::ArmModel& model, const SimulateState& st, std::string& summary) {
  const bool has_move = !st.move.from.empty() || !st.move.to.empty();
  if (st.trajectory.empty() == !has_move) {
    throw InvalidArgument("arm simulate: give either --trajectory FILE or --from and --to (a move)");
  }
  if (has_move) return build_move(model, st.move, summary);
  const std::string kind = output_kind(st.trajectory);  // the same two formats arm move writes
  summary = fmt::format("trajectory  {}\n", st.trajectory);
  return kind == ".json" ? arm::read_trajectory_json(st.trajectory) : arm::read_trajectory_csv(st.trajectory);
}

/// Eq. 5.1 (metrics/mean_deviation.hpp) on each tool coordinate from the command's end,
/// √(Σ MD²) in mm: the tool-tip residual vibration of docs/arm.md §7.
double residual_mm(const arm::ArmTrace& trace, double end_s) {
  double sum = 0.0;
  for (Eigen::Index axis = 0; axis < 3; ++axis) {
    const Eigen::VectorXd x = trace.tool_position_m.col(axis);
    const UniformSeries s{trace.time_s.front(), trace.time_s[1] - trace.time_s[0],
                          std::vector<double>(x.data(), x.data() + x.size())};
    metrics::MeanDeviationOptions o;
    o.search_from_s = end_s;
    const double md = metrics::mean_deviation(s, o).mean_deviation;
    sum += md * md;
  }
  return 1e3 * std::sqrt(sum);
}

void write_trace(const std::string& path, const arm::ArmModel& model, const arm::ArmTrace& trace) {
  std::vector<std::string> names{"time_s"};
  std::vector<std::vector<double>> columns{trace.time_s};
  const auto add = [&](const std::string& name, const Eigen::VectorXd& v, double scale) {
    names.push_back(name);
    columns.emplace_back(v.data(), v.data() + v.size());
    for (double& x : columns.back()) x *= scale;
  };
  for (int i = 0; i < model.dof(); ++i) {
    const std::string& j = model.joints[static_cast<std::size_t>(i)].name;
    add(j + "_link_deg", trace.link_angle_rad.col(i), 180.0 / M_PI);
    add(j + "_output_deg", trace.output_angle_rad.col(i), 180.0 / M_PI);
    add(j + "_encoder_deg", trace.encoder_angle_rad.col(i), 180.0 / M_PI);  // the motor's encoder
    add(j + "_link_rate_rad_s", trace.link_rate_rad_s.col(i), 1.0);  // the column arm modes --recordings reads
  }
  for (int c = 0; c < 3; ++c) add(std::string("tool_") + "xyz"[c] + "_m", trace.tool_position_m.col(c), 1.0);
  for (int c = 0; c < 3; ++c) add(std::string("gyro_") + "xyz"[c] + "_rad_s", trace.gyro_rad_s.col(c), 1.0);
  for (int c = 0; c < 3; ++c) add(std::string("accel_") + "xyz"[c] + "_m_s2", trace.accel_m_s2.col(c), 1.0);
  std::vector<const std::vector<double>*> pointers;
  for (const auto& c : columns) pointers.push_back(&c);
  io::write_csv(path, names, pointers);
}

void run_simulate(const SimulateState& st) {
  const arm::ArmModel model = load_arm(st.source);
  std::string summary;
  const arm::JointTrajectory t = simulate_input(model, st, summary);
  arm::ArmSimulationOptions options;
  options.duration_s = t.time_s.back() + st.settle_s;
  options.output_rate_hz = st.rate_hz;
  const arm::ArmTrace trace = arm::simulate_arm(model, arm::drive_commands(model, t), options);
  const auto onsets = std::count_if(trace.events.begin(), trace.events.end(), [](const auto& e) { return e.onset; });
  const Eigen::Vector3d tool = trace.tool_position_m.bottomRows<1>().transpose();
  fmt::print("arm         {} ({} joints)\n{}simulated   {:.4f} s ({} samples, {} CVODE steps)\n", model.name,
             model.dof(), summary, options.duration_s, trace.time_s.size(), trace.steps);
  fmt::print("contacts    {} onsets\ntool end    ({:.6f}, {:.6f}, {:.6f}) m\n", onsets, tool.x(), tool.y(), tool.z());
  fmt::print("residual    {:.4f} mm (Eq. 5.1 on the tool position from the command's end)\n",
             residual_mm(trace, t.time_s.back()));
  if (st.out.empty()) return;
  if (output_kind(st.out) != ".csv") throw InvalidArgument("-o = '" + st.out + "': allowed a .csv file name");
  write_trace(st.out, model, trace);
  fmt::print("written     {}\n", st.out);
}

void setup_simulate(CLI::App& parent) {
  auto st = std::make_shared<SimulateState>();
  CLI::App* sub = add_arm_subcommand(
      parent, "simulate", "Play a joint trajectory (from arm move) or a move on the arm with play in every joint "
                  "(CVODE with contact events; docs/arm.md §1)",
      st->source);
  sub->add_option("--trajectory", st->trajectory, "A joint trajectory written by arm move (.json or .csv)")
      ->check(CLI::ExistingFile);
  add_move_options(*sub, st->move, false);
  sub->add_option("--settle-s", st->settle_s, "Simulated time after the trajectory's end (s, 0-60)")
      ->check(CLI::Range(0.0, 60.0))->capture_default_str();
  sub->add_option("--rate", st->rate_hz, "Output samples per second (Hz, 10-100000)")
      ->check(CLI::Range(10.0, 1e5))->capture_default_str();
  sub->add_option("-o,--out", st->out, "Write the run as CSV: time_s, per joint link, gearbox-output and motor "
                                       "encoder angles (deg) and the link's rate (rad/s), the tool position (m), "
                                       "the last link's gyroscope (rad/s) and accelerometer (m/s², specific force) "
                                       "in its frame");
  sub->callback([st] { run_simulate(*st); });
}

const bool arm_registered = register_command(
    {"arm", "A multi-joint arm with play in every joint: simulate, modes at a pose, shaped moves, the study", 95,
     [](CLI::App& sub) {
       sub.require_subcommand(1);
       setup_simulate(sub);
       setup_arm_modes(sub);
       setup_move(sub);
       setup_arm_study(sub);
     }});

}  // namespace
}  // namespace clearshape::cli
