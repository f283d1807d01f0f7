// The mode map identified from runs (arm/mode_map.hpp; docs/arm.md §7).
#include "clearshape/arm/mode_map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "clearshape/arm/trajectory.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

void require(bool ok, const std::string& field, const std::string& allowed) {
  if (!ok) throw InvalidArgument("ModeMapOptions." + field + ": allowed " + allowed);
}

/// One run's estimate of one mode (Hz).
struct RunEstimate {
  double f_hz, f_std_hz, zeta, zeta_std;
};

std::vector<signal::AxisLimits> step_limits(const ModeMapOptions& o, int dof) {
  if (!o.limits.empty()) return o.limits;
  return std::vector<signal::AxisLimits>(static_cast<std::size_t>(dof), {2.0, 40.0, 4000.0});
}

/// Each link resting on the flank that carries its gravity torque, φ_i = −sign(g_i)(β_i + |g_i|/K_i)
/// (the equilibrium τ_contact = g(q) of docs/arm.md §1 with the flank's tangent stiffness K_i:
/// exact for a linear flank), so that a run does not start with the links dropping across their play.
/// A joint without gravity torque starts on the flank `unloaded_side` (−1: trailing a positive ramp, 0: centred).
Eigen::VectorXd resting_on_flanks(const ArmModel& arm, const Eigen::VectorXd& pose, const ArmModes& modes,
                                  double unloaded_side) {
  ChainWorkspace workspace(arm.chain);
  Eigen::VectorXd g(arm.dof());
  workspace.gravity_torque(pose, g);
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    const double beta = arm.joints[static_cast<std::size_t>(i)].half_play_rad;
    phi(i) = g(i) != 0.0 ? -std::copysign(beta + std::abs(g(i)) / modes.stiffness_n_m_per_rad(i), g(i))
                         : unloaded_side * beta;
  }
  return phi;
}

/// One excitation: the joints' move and when its free-response window starts.
struct Excitation {
  std::string name;
  JointTrajectory move;
  double window_start_s = 0.0;
};

/// Joint j stepped by `step_deg`; the window starts once the step has ended and the drives settled.
Excitation step_excitation(const ArmModel& arm, const Eigen::VectorXd& pose, int j, const ModeMapOptions& o) {
  Eigen::VectorXd end = pose;
  end(j) += o.step_deg * std::numbers::pi / 180.0;
  JointTrajectory move = plan_move(arm, pose, end, step_limits(o, arm.dof()), 1.0 / o.output_rate_hz);
  const double start_s = move.time_s.back() + o.settle_s;
  return {"step of " + arm.joints[static_cast<std::size_t>(j)].name, std::move(move), start_s};
}

/// Every joint ramping at ramp_velocity_rad_s: the bearings' friction keeps each link on its
/// trailing flank. The window starts once the joints cruise (ramp-up T = v/a + a/j, symmetric, so
/// it covers v·T/2) and the drives settled; the ramp starts before `pose` so that the joints pass
/// it in the middle of the window.
Excitation ramp_excitation(const ArmModel& arm, const Eigen::VectorXd& pose, const ModeMapOptions& o) {
  const double v = o.ramp_velocity_rad_s, a = o.ramp_acceleration_rad_s2, j = 100.0 * a;
  const double ramp_up_s = v / a + a / j;
  const double start_s = ramp_up_s + o.settle_s;
  const double middle_s = start_s + 0.5 * o.window_s;
  const Eigen::VectorXd from = pose.array() - v * (middle_s - 0.5 * ramp_up_s);
  const Eigen::VectorXd end = from.array() + v * (start_s + o.window_s + 1.0);  // still cruising at the window's end
  const std::vector<signal::AxisLimits> limits(static_cast<std::size_t>(arm.dof()), {v, a, j});
  return {"loaded ramp", plan_move(arm, from, end, limits, 1.0 / o.output_rate_hz), start_s};
}

/// The excitation simulated from the links resting on their flanks (resting_on_flanks).
SimulatedRun simulate_run(const ArmModel& arm, const Excitation& e, const ArmModes& modes, const ModeMapOptions& o,
                          int joint) {
  const bool ramp = o.excitation == ModeMapExcitation::loaded_ramp;
  ArmSimulationOptions sim;
  sim.duration_s = e.window_start_s + o.window_s;
  sim.output_rate_hz = o.output_rate_hz;
  sim.solver = o.solver;
  const Eigen::VectorXd from = e.move.position_rad.row(0).transpose();
  sim.initial.relative_angle_rad = resting_on_flanks(arm, from, modes, ramp ? -1.0 : 0.0);
  return {o.excitation, joint, e.name, e.window_start_s, simulate_arm(arm, drive_commands(arm, e.move), sim)};
}

/// A run's window, from its first sample at or after window_start_s to the trace's end; the
/// sample time is the trace's mean step, as io::uniform_sample_time takes it from a recorded file.
RunRecord window_of(const SimulatedRun& run) {
  const std::vector<double>& t = run.trace.time_s;
  if (t.size() < 2) throw RuntimeError("run '" + run.name + "': the simulation gave fewer than 2 samples");
  const auto k0 = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), run.window_start_s - 1e-12) - t.begin());
  const auto n = static_cast<Eigen::Index>(t.size() - std::min(k0, t.size() - 1));
  const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  return {run.name, t[t.size() - static_cast<std::size_t>(n)], dt, run.trace.link_rate_rad_s.bottomRows(n),
          run.trace.gyro_rad_s.bottomRows(n)};
}

constexpr double kGyroAxisFloor = 0.01;  // an axis below 1 % of the strongest's RMS does not turn

/// The records options.sensor reads from a run: every link's rate, or the last link's gyro axes
/// that turn in the window: peak above 1e-9 rad/s (a planar arm's out-of-plane axes carry nothing)
/// and RMS at least 1 % of the strongest axis's (a recorded axis about which the link does not
/// turn carries the gyro's noise alone, whose lines would be taken for modes).
std::vector<std::pair<std::string, UniformSeries>> sensor_records(const ArmModel& arm, const RunRecord& run,
                                                                  ModeMapSensor sensor) {
  const bool gyro = sensor == ModeMapSensor::last_link_gyro;
  const Eigen::MatrixXd& rates = gyro ? run.gyro_rad_s : run.link_rate_rad_s;
  const Eigen::Index want = gyro ? 3 : arm.dof();
  if (rates.cols() != want || rates.rows() == 0) {
    throw InvalidArgument("mode_map_from_runs: run '" + run.name + "' has " + std::to_string(rates.cols()) +
                          (gyro ? " gyro axes" : " link rates") + "; allowed: " + std::to_string(want) +
                          " columns of samples for sensor " + (gyro ? "last_link_gyro" : "link_rates"));
  }
  std::vector<std::pair<std::string, UniformSeries>> out;
  const Eigen::RowVectorXd rms = (rates.colwise().squaredNorm() / static_cast<double>(rates.rows())).cwiseSqrt();
  for (Eigen::Index i = 0; i < rates.cols(); ++i) {
    const Eigen::VectorXd w = rates.col(i);
    if (gyro && (w.cwiseAbs().maxCoeff() <= 1e-9 || rms(i) < kGyroAxisFloor * rms.maxCoeff())) continue;
    out.emplace_back(gyro ? std::string("last link's gyro ") + "xyz"[i] : "rate of " + arm.joints[static_cast<std::size_t>(i)].name,
                     UniformSeries{run.start_s, run.sample_time_s, std::vector<double>(w.data(), w.data() + w.size())});
  }
  return out;
}

/// Groups the estimates within `tolerance` of the group's lowest frequency; each group keeps its
/// best-determined estimate (smallest 1σ in frequency): the runs share a pose, so their errors are
/// not independent and are not pooled.
std::vector<MapMode> merge_estimates(std::vector<RunEstimate> e, double tolerance) {
  std::sort(e.begin(), e.end(), [](const RunEstimate& a, const RunEstimate& b) { return a.f_hz < b.f_hz; });
  std::vector<MapMode> out;
  double group_f = -1.0;
  for (const RunEstimate& r : e) {
    if (out.empty() || r.f_hz > group_f * (1.0 + tolerance)) {
      group_f = r.f_hz;
      out.push_back({r.f_hz, r.f_std_hz, r.zeta, r.zeta_std, 1});
      continue;
    }
    MapMode& m = out.back();
    ++m.runs;
    if (r.f_std_hz < m.natural_frequency_std_hz) {
      std::tie(m.natural_frequency_hz, m.natural_frequency_std_hz, m.damping_ratio, m.damping_ratio_std) =
          std::tuple(r.f_hz, r.f_std_hz, r.zeta, r.zeta_std);
    }
  }
  return out;
}

void set_nearest_linear(MapMode& m, const ArmModes& lin) {
  Eigen::Index k = 0;
  (lin.natural_frequency_rad_s / two_pi - Eigen::VectorXd::Constant(lin.natural_frequency_rad_s.size(),
                                                                     m.natural_frequency_hz))
      .cwiseAbs()
      .minCoeff(&k);
  m.linear_mode = static_cast<int>(k);
  m.linear_frequency_hz = lin.natural_frequency_rad_s(k) / two_pi;
  m.linear_damping_ratio = lin.damping_ratio(k);
  m.relative_frequency_error = (m.natural_frequency_hz - m.linear_frequency_hz) / m.linear_frequency_hz;
}

/// Marks the modes at an integer multiple of a lower one (the lower ones are not harmonics).
void mark_harmonics(std::vector<MapMode>& modes, double tolerance) {
  for (std::size_t i = 0; i < modes.size(); ++i) {
    for (std::size_t l = 0; l < i && modes[i].harmonic == 0; ++l) {
      if (modes[l].harmonic != 0) continue;
      const double ratio = modes[i].natural_frequency_hz / modes[l].natural_frequency_hz;
      const double k = std::round(ratio);
      if (k >= 2.0 && k <= 9.0 && std::abs(ratio / k - 1.0) < tolerance) modes[i].harmonic = static_cast<int>(k);
    }
  }
}

/// The modes of one record (link rate) into `estimates`; a record without one into `failures`.
void identify_record(const UniformSeries& rate, const ident::ModeOptions& mo, const std::string& what,
                     std::vector<RunEstimate>& estimates, std::vector<std::string>& failures) {
  try {
    for (const auto& m : ident::identify_free_response_modes(rate, mo).modes) {
      // a growing pole (ζ below −3σ) or one without an uncertainty is not a residual mode
      if (!std::isfinite(m.natural_frequency_std_rad_s) || m.damping_ratio + 3.0 * m.damping_ratio_std <= 0.0) continue;
      estimates.push_back({m.natural_frequency_hz(), m.natural_frequency_std_hz(), m.damping_ratio, m.damping_ratio_std});
    }
  } catch (const std::runtime_error& e) {
    failures.push_back(what + ": " + e.what());
  }
}

ModeMapPoint identify_point(const ArmModel& arm, const PoseRuns& pr, const ModeMapOptions& o) {
  ModeMapPoint p{pr.pose_rad, {}, joint_modes(arm, pr.pose_rad, o.linearisation), pr.failures};
  ident::ModeOptions mo = o.identification;
  if (mo.modes == 0) mo.modes = static_cast<std::size_t>(arm.dof());
  std::vector<RunEstimate> estimates;
  for (const RunRecord& run : pr.runs) {
    for (const auto& [name, series] : sensor_records(arm, run, o.sensor)) {
      identify_record(series, mo, run.name + ", " + name, estimates, p.failures);
    }
  }
  p.modes = merge_estimates(std::move(estimates), o.merge_tolerance);
  for (MapMode& m : p.modes) set_nearest_linear(m, p.linearised);
  mark_harmonics(p.modes, o.harmonic_tolerance);
  return p;
}

/// The runs of options.excitation at one pose, simulated; a failed simulation in `failures`.
SimulatedPose simulate_pose(const ArmModel& arm, const Eigen::VectorXd& pose, const ModeMapOptions& o) {
  SimulatedPose sp{pose, {}, {}};
  const ArmModes modes = joint_modes(arm, pose, o.linearisation);
  const bool ramp = o.excitation == ModeMapExcitation::loaded_ramp;
  for (int j = ramp ? -1 : 0; j < (ramp ? 0 : arm.dof()); ++j) {
    const Excitation e = ramp ? ramp_excitation(arm, pose, o) : step_excitation(arm, pose, j, o);
    try {
      sp.runs.push_back(simulate_run(arm, e, modes, o, j));
    } catch (const std::runtime_error& e_run) {
      sp.failures.push_back(e.name + ": " + e_run.what());
    }
  }
  return sp;
}

void require_pose(const ArmModel& arm, const Eigen::VectorXd& pose, std::size_t index, const char* function) {
  if (pose.size() != arm.dof() || !pose.allFinite()) {
    throw InvalidArgument(std::string(function) + ": poses[" + std::to_string(index) + "]: allowed " +
                          std::to_string(arm.dof()) + " finite angles (rad)");
  }
}

}  // namespace

void ModeMapOptions::validate(int dof) const {
  require(std::isfinite(step_deg) && step_deg > 0.0, "step_deg = " + std::to_string(step_deg), "> 0 (deg)");
  require(limits.empty() || limits.size() == static_cast<std::size_t>(dof),
          "limits (" + std::to_string(limits.size()) + " entries)", "empty or one per joint (" + std::to_string(dof) + ")");
  for (std::size_t i = 0; i < limits.size(); ++i) limits[i].validate("ModeMapOptions.limits[" + std::to_string(i) + "]");
  require(std::isfinite(settle_s) && settle_s >= 0.0, "settle_s = " + std::to_string(settle_s), ">= 0 (s)");
  require(std::isfinite(window_s) && window_s > 0.0, "window_s = " + std::to_string(window_s), "> 0 (s)");
  require(std::isfinite(output_rate_hz) && output_rate_hz > 0.0, "output_rate_hz = " + std::to_string(output_rate_hz),
          "> 0 (Hz)");
  require(window_s * output_rate_hz >= 50.0, "window_s × output_rate_hz = " + std::to_string(window_s * output_rate_hz),
          ">= 50 samples (the identification needs them)");
  require(merge_tolerance > 0.0 && merge_tolerance < 1.0, "merge_tolerance = " + std::to_string(merge_tolerance),
          "in (0, 1)");
  require(harmonic_tolerance >= 0.0 && harmonic_tolerance < merge_tolerance,
          "harmonic_tolerance = " + std::to_string(harmonic_tolerance), "in [0, merge_tolerance)");
  require(std::isfinite(ramp_velocity_rad_s) && ramp_velocity_rad_s > 0.0,
          "ramp_velocity_rad_s = " + std::to_string(ramp_velocity_rad_s), "> 0 (rad/s)");
  require(std::isfinite(ramp_acceleration_rad_s2) && ramp_acceleration_rad_s2 > 0.0,
          "ramp_acceleration_rad_s2 = " + std::to_string(ramp_acceleration_rad_s2), "> 0 (rad/s²)");
  solver.validate();
  linearisation.validate();
}

std::vector<Eigen::VectorXd> pose_grid(const ArmModel& arm, int points_per_joint) {
  const int n = arm.dof();
  if (points_per_joint < 1 || std::pow(points_per_joint, n) > 10000.0) {
    throw InvalidArgument("pose_grid: points_per_joint = " + std::to_string(points_per_joint) +
                          "; allowed: >= 1 and at most 10000 poses in all (" + std::to_string(n) + " joints)");
  }
  std::vector<Eigen::VectorXd> poses;
  const auto& joints = arm.chain.joints();
  const auto total = static_cast<long>(std::lround(std::pow(points_per_joint, n)));
  for (long index = 0; index < total; ++index) {
    Eigen::VectorXd q(n);
    long rest = index;
    for (int i = n - 1; i >= 0; --i, rest /= points_per_joint) {  // the last joint varies fastest
      const ChainJoint& jt = joints[static_cast<std::size_t>(i)];
      const double lo = jt.limited ? jt.lower_rad : -std::numbers::pi;
      const double hi = jt.limited ? jt.upper_rad : std::numbers::pi;
      q(i) = lo + (static_cast<double>(rest % points_per_joint) + 0.5) * (hi - lo) / points_per_joint;
    }
    poses.push_back(q);
  }
  return poses;
}

std::vector<SimulatedPose> simulate_mode_runs(const ArmModel& arm, const std::vector<Eigen::VectorXd>& poses,
                                              const ModeMapOptions& options) {
  options.validate(arm.dof());
  std::vector<SimulatedPose> out;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    require_pose(arm, poses[p], p, "identify_mode_map");
    out.push_back(simulate_pose(arm, poses[p], options));
  }
  return out;
}

std::vector<PoseRuns> simulated_windows(const std::vector<SimulatedPose>& simulated) {
  std::vector<PoseRuns> out;
  for (const SimulatedPose& sp : simulated) {
    PoseRuns pr{sp.pose_rad, {}, sp.failures};
    for (const SimulatedRun& run : sp.runs) pr.runs.push_back(window_of(run));
    out.push_back(std::move(pr));
  }
  return out;
}

ModeMap mode_map_from_runs(const ArmModel& arm, const std::vector<PoseRuns>& poses, const ModeMapOptions& options) {
  options.validate(arm.dof());
  ModeMap map{arm.name, {}, {}};
  for (const ArmJoint& j : arm.joints) map.joint_names.push_back(j.name);
  for (std::size_t p = 0; p < poses.size(); ++p) {
    require_pose(arm, poses[p].pose_rad, p, "mode_map_from_runs");
    map.points.push_back(identify_point(arm, poses[p], options));
  }
  return map;
}

ModeMap identify_mode_map(const ArmModel& arm, const std::vector<Eigen::VectorXd>& poses,
                          const ModeMapOptions& options) {
  return mode_map_from_runs(arm, simulated_windows(simulate_mode_runs(arm, poses, options)), options);
}

}  // namespace clearshape::arm
