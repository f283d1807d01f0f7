#include "clearshape/arm/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/apply.hpp"

namespace clearshape::arm {

namespace {

void require_matrix(const Eigen::MatrixXd& m, const char* field, std::size_t rows, std::size_t cols) {
  if (static_cast<std::size_t>(m.rows()) != rows || static_cast<std::size_t>(m.cols()) != cols) {
    throw InvalidArgument(std::string("JointTrajectory.") + field + " is " + std::to_string(m.rows()) + " × " +
                          std::to_string(m.cols()) + "; allowed: samples × joints = " + std::to_string(rows) +
                          " × " + std::to_string(cols));
  }
  if (!m.allFinite()) throw InvalidArgument(std::string("JointTrajectory.") + field + " has a non-finite value");
}

// The common sample time of a uniformly sampled trajectory (relative tolerance 1e-6: times read
// back from time_from_start are rounded to 1 ns).
double uniform_step_s(const JointTrajectory& t) {
  if (t.time_s.size() < 2) throw InvalidArgument("JointTrajectory needs at least two samples here");
  const double dt = (t.time_s.back() - t.time_s.front()) / static_cast<double>(t.time_s.size() - 1);
  for (std::size_t k = 1; k < t.time_s.size(); ++k) {
    if (std::abs(t.time_s[k] - t.time_s[k - 1] - dt) > 1e-6 * dt) {
      throw InvalidArgument("JointTrajectory.time_s[" + std::to_string(k) + "] = " + std::to_string(t.time_s[k]) +
                            ": the samples must be uniform (step " + std::to_string(dt) + " s)");
    }
  }
  return dt;
}

JointTrajectory empty_like(const std::vector<std::string>& names, std::size_t samples, double dt) {
  JointTrajectory t;
  t.joint_names = names;
  t.time_s.resize(samples);
  for (std::size_t k = 0; k < samples; ++k) t.time_s[k] = static_cast<double>(k) * dt;
  const auto rows = static_cast<Eigen::Index>(samples), cols = static_cast<Eigen::Index>(names.size());
  t.position_rad.setZero(rows, cols);
  t.velocity_rad_s.setZero(rows, cols);
  t.acceleration_rad_s2.setZero(rows, cols);
  return t;
}

std::vector<std::string> joint_names(const ArmModel& arm) {
  std::vector<std::string> names;
  for (const ArmJoint& j : arm.joints) names.push_back(j.name);
  return names;
}

}  // namespace

void JointTrajectory::validate() const {
  if (joint_names.empty()) throw InvalidArgument("JointTrajectory.joint_names is empty; allowed: one name per joint");
  if (time_s.empty()) throw InvalidArgument("JointTrajectory.time_s is empty; allowed: at least one sample");
  if (!(time_s.front() >= 0.0)) throw InvalidArgument("JointTrajectory.time_s[0] must be >= 0");
  for (std::size_t k = 1; k < time_s.size(); ++k) {
    if (!(time_s[k] > time_s[k - 1]) || !std::isfinite(time_s[k])) {
      throw InvalidArgument("JointTrajectory.time_s[" + std::to_string(k) + "] is not after time_s[" +
                            std::to_string(k - 1) + "]; allowed: strictly increasing finite times");
    }
  }
  require_matrix(position_rad, "position_rad", time_s.size(), joint_names.size());
  require_matrix(velocity_rad_s, "velocity_rad_s", time_s.size(), joint_names.size());
  require_matrix(acceleration_rad_s2, "acceleration_rad_s2", time_s.size(), joint_names.size());
}

JointTrajectory plan_move(const ArmModel& arm, const Eigen::VectorXd& start_rad, const Eigen::VectorXd& end_rad,
                          std::span<const signal::AxisLimits> limits, double sample_time_s) {
  const std::vector<double> q0(start_rad.data(), start_rad.data() + start_rad.size());
  const std::vector<double> q1(end_rad.data(), end_rad.data() + end_rad.size());
  if (q0.size() != static_cast<std::size_t>(arm.dof())) {
    throw InvalidArgument("plan_move: start_rad has " + std::to_string(q0.size()) + " angles; allowed: one per joint (" +
                          std::to_string(arm.dof()) + ")");
  }
  const signal::SynchronizedMove move = signal::synchronized_move(q0, q1, limits);
  const std::vector<signal::SampledAxis> s = signal::sample_move(move, sample_time_s);
  JointTrajectory t = empty_like(joint_names(arm), s.front().position.size(), sample_time_s);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    t.position_rad.col(c) = Eigen::Map<const Eigen::VectorXd>(s[i].position.values.data(), t.position_rad.rows());
    t.velocity_rad_s.col(c) = Eigen::Map<const Eigen::VectorXd>(s[i].velocity.values.data(), t.position_rad.rows());
    t.acceleration_rad_s2.col(c) =
        Eigen::Map<const Eigen::VectorXd>(s[i].acceleration.values.data(), t.position_rad.rows());
  }
  return t;
}

std::string_view to_string(ShaperSchedule schedule) noexcept {
  switch (schedule) {
    case ShaperSchedule::none: return "unshaped";
    case ShaperSchedule::fixed: return "fixed";
    case ShaperSchedule::end_pose: return "scheduled";
  }
  return "unshaped";
}

namespace {

shaping::Shaper design_at(const MoveShaping& shaping, const shaping::Mode& mode) {
  shaping::DesignRequest request;
  request.method = shaping.method;
  request.mode = mode;
  request.vtol = shaping.vtol;
  return shaping::design(request);
}

}  // namespace

std::vector<shaping::Shaper> joint_shapers(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                           const MoveShaping& shaping) {
  std::vector<shaping::Shaper> out;
  if (shaping.schedule == ShaperSchedule::none) {
    out.assign(static_cast<std::size_t>(arm.dof()), shaping::Shaper("none", {{0.0, 1.0}}));
    return out;
  }
  const Eigen::VectorXd pose = shaping.schedule == ShaperSchedule::fixed ? workspace_centre(arm) : end_pose_rad;
  const ArmModes modes = joint_modes(arm, pose, shaping.modes);
  if (shaping.every_mode) {
    shaping::Shaper all = design_at(shaping, {modes.natural_frequency_rad_s(0), modes.damping_ratio(0)});
    for (int k = 1; k < arm.dof(); ++k) {
      all = shaping::convolve(all, design_at(shaping, {modes.natural_frequency_rad_s(k), modes.damping_ratio(k)}));
    }
    out.assign(static_cast<std::size_t>(arm.dof()), all);
    return out;
  }
  for (int i = 0; i < arm.dof(); ++i) out.push_back(design_at(shaping, modes.joint_mode(i)));
  return out;
}

JointTrajectory shape_trajectory(const JointTrajectory& trajectory, std::span<const shaping::Shaper> shapers) {
  trajectory.validate();
  const double dt = uniform_step_s(trajectory);
  if (shapers.size() != trajectory.joint_names.size()) {
    throw InvalidArgument("shape_trajectory: " + std::to_string(shapers.size()) + " shapers for " +
                          std::to_string(trajectory.joint_names.size()) + " joints; allowed: one per joint");
  }
  std::vector<std::array<UniformSeries, 3>> shaped;
  std::size_t samples = 0;
  for (std::size_t i = 0; i < shapers.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    std::array<UniformSeries, 3> joint;
    const Eigen::MatrixXd* in[3] = {&trajectory.position_rad, &trajectory.velocity_rad_s,
                                    &trajectory.acceleration_rad_s2};
    for (int s = 0; s < 3; ++s) {
      const UniformSeries u{0.0, dt, std::vector<double>(in[s]->col(c).data(), in[s]->col(c).data() + in[s]->rows())};
      joint[static_cast<std::size_t>(s)] = shaping::shape_offline(shapers[i], u, true);
    }
    samples = std::max(samples, joint[0].size());
    shaped.push_back(std::move(joint));
  }
  JointTrajectory t = empty_like(trajectory.joint_names, samples, dt);
  Eigen::MatrixXd* out[3] = {&t.position_rad, &t.velocity_rad_s, &t.acceleration_rad_s2};
  for (std::size_t i = 0; i < shaped.size(); ++i) {
    for (std::size_t s = 0; s < 3; ++s) {
      const std::vector<double>& v = shaped[i][s].values;
      for (std::size_t k = 0; k < samples; ++k) {
        (*out[s])(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = v[std::min(k, v.size() - 1)];
      }
    }
  }
  return t;
}

std::vector<plant::Command> drive_commands(const ArmModel& arm, const JointTrajectory& trajectory) {
  trajectory.validate();
  const double dt = uniform_step_s(trajectory);
  if (trajectory.joint_names != joint_names(arm)) {
    throw InvalidArgument("drive_commands: the trajectory's joints differ from the arm's (" + arm.name + ")");
  }
  std::vector<plant::Command> out;
  for (std::size_t i = 0; i < arm.joints.size(); ++i) {
    const ArmJoint& j = arm.joints[i];
    if (j.drive.mode() != plant::DriveMode::position) {
      throw InvalidArgument("joint[" + std::to_string(i) + "] '" + j.name +
                            "'.drive.mode = speed; allowed: position (a trajectory of angles)");
    }
    const double per_rad = j.gear_ratio / j.drive.dc_gain();  // command units per link radian
    const Eigen::VectorXd u = trajectory.position_rad.col(static_cast<Eigen::Index>(i)) * per_rad;
    out.emplace_back(UniformSeries{trajectory.time_s.front(), dt, std::vector<double>(u.data(), u.data() + u.size())},
                     plant::Interpolation::linear);
  }
  return out;
}

}  // namespace clearshape::arm
