// Python: the arm as a plant (docs/arm.md) — the built-in arms' texts and a simulation of a
// built-in arm or of one's own URDF + TOML under one command per joint.
#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arm_model.hpp"
#include "arrays.hpp"
#include "clearshape/arm/benchmark.hpp"
#include "clearshape/arm/clearance_aware.hpp"
#include "clearshape/arm/simulation.hpp"
#include "clearshape/arm/trajectory.hpp"

namespace clearshape::python {

arm::ArmModel arm_model_of(const std::string& name, const std::optional<std::string>& urdf,
                           const std::optional<std::string>& toml) {
  if (urdf.has_value() != toml.has_value()) {
    throw InvalidArgument("urdf and toml go together: give both texts (one's own arm) or neither (a built-in arm)");
  }
  if (urdf) return arm::arm_from_text(*urdf, "<urdf argument>", *toml, "<toml argument>");
  return arm::builtin_arm(name);
}

namespace {

// A samples × columns copy of an Eigen matrix.
py::array_t<double> to_array2(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) view(r, c) = m(r, c);
  }
  return out;
}

std::vector<plant::Command> commands_of(const DoubleArray& commands, double sample_time_s, int dof,
                                        const std::string& interpolation) {
  if (commands.ndim() != 2 || commands.shape(0) != dof) {
    throw InvalidArgument("commands must be a 2-D array with one row per joint (" + std::to_string(dof) + " rows)");
  }
  if (interpolation != "linear" && interpolation != "zero_order_hold") {
    throw InvalidArgument("interpolation = '" + interpolation + "'; allowed: linear, zero_order_hold");
  }
  std::vector<plant::Command> out;
  auto view = commands.unchecked<2>();
  for (int j = 0; j < dof; ++j) {
    UniformSeries s{0.0, sample_time_s, {}};
    for (py::ssize_t k = 0; k < commands.shape(1); ++k) s.values.push_back(view(j, k));
    out.emplace_back(std::move(s), interpolation == "linear" ? plant::Interpolation::linear
                                                               : plant::Interpolation::zero_order_hold);
  }
  return out;
}

py::dict simulate_arm(const DoubleArray& commands, double sample_time_s, const std::string& name,
                      const std::optional<std::string>& urdf, const std::optional<std::string>& toml,
                      double duration_s, double output_rate_hz, const std::string& interpolation,
                      double relative_tolerance) {
  require_positive("sample_time_s", sample_time_s);
  const arm::ArmModel model = arm_model_of(name, urdf, toml);
  const std::vector<plant::Command> cmd = commands_of(commands, sample_time_s, model.dof(), interpolation);
  arm::ArmSimulationOptions o;
  o.duration_s = duration_s;
  o.output_rate_hz = output_rate_hz;
  o.solver.relative_tolerance = relative_tolerance;
  arm::ArmTrace tr;
  {
    py::gil_scoped_release release;
    tr = arm::simulate_arm(model, cmd, o);
  }
  py::dict d;
  d["time_s"] = to_array(tr.time_s);
  d["motor_angle_rad"] = to_array2(tr.motor_angle_rad);
  d["encoder_angle_rad"] = to_array2(tr.encoder_angle_rad);
  d["output_angle_rad"] = to_array2(tr.output_angle_rad);
  d["link_angle_rad"] = to_array2(tr.link_angle_rad);
  d["link_rate_rad_s"] = to_array2(tr.link_rate_rad_s);
  d["contact_torque_n_m"] = to_array2(tr.contact_torque_n_m);
  d["tool_position_m"] = to_array2(tr.tool_position_m);
  d["gyro_rad_s"] = to_array2(tr.gyro_rad_s);
  d["accel_m_s2"] = to_array2(tr.accel_m_s2);
  d["kinetic_j"] = to_array(tr.kinetic_j);
  d["potential_j"] = to_array(tr.potential_j);
  d["contact_energy_j"] = to_array(tr.contact_energy_j);
  py::list events;
  for (const arm::ArmEvent& e : tr.events) {
    events.append(py::dict(py::arg("time_s") = e.time_s, py::arg("joint") = e.joint, py::arg("side") = e.side,
                           py::arg("onset") = e.onset, py::arg("rate_rad_s") = e.rate_rad_s));
  }
  d["events"] = events;
  std::vector<std::string> joints;
  for (const arm::ArmJoint& j : model.joints) joints.push_back(j.name);
  d["joints"] = joints;
  d["gear_ratio"] = [&] {
    std::vector<double> g;
    for (const arm::ArmJoint& j : model.joints) g.push_back(j.gear_ratio);
    return to_array(g);
  }();
  d["steps"] = tr.steps;
  return d;
}

Eigen::VectorXd to_pose(const DoubleArray& a, const char* name) {
  const std::vector<double> v = to_vector(a, name);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

py::dict arm_modes(const DoubleArray& pose_rad, const std::string& name, const std::optional<std::string>& urdf,
                   const std::optional<std::string>& toml, double flank_penetration_rad) {
  const arm::ArmModel model = arm_model_of(name, urdf, toml);
  const arm::ArmModes m = arm::joint_modes(model, to_pose(pose_rad, "pose_rad"), {flank_penetration_rad});
  const Eigen::VectorXd f = m.natural_frequency_rad_s / (2.0 * 3.14159265358979323846);
  py::dict d;
  d["natural_frequency_hz"] = to_array(std::vector<double>(f.data(), f.data() + f.size()));
  d["damping_ratio"] = to_array(std::vector<double>(m.damping_ratio.data(), m.damping_ratio.data() + m.damping_ratio.size()));
  d["shapes"] = to_array2(m.shapes);
  d["share"] = to_array2(m.share);
  d["dominant_mode"] = m.dominant_mode;
  return d;
}

arm::ShaperSchedule schedule_of(const std::string& text) {
  for (const auto s : {arm::ShaperSchedule::none, arm::ShaperSchedule::fixed, arm::ShaperSchedule::end_pose}) {
    if (text == arm::to_string(s)) return s;
  }
  throw InvalidArgument("schedule = '" + text + "'; allowed: unshaped, fixed, scheduled, clearance-aware");
}

std::vector<signal::AxisLimits> limits_of(const DoubleArray& limits, int dof) {
  if (limits.ndim() != 2 || limits.shape(0) != dof || limits.shape(1) != 3) {
    throw InvalidArgument("limits must be a " + std::to_string(dof) +
                          " × 3 array: per joint (velocity rad/s, acceleration rad/s², jerk rad/s³)");
  }
  auto v = limits.unchecked<2>();
  std::vector<signal::AxisLimits> out;
  for (int j = 0; j < dof; ++j) out.push_back({v(j, 0), v(j, 1), v(j, 2)});
  return out;
}

/// The clearance-aware design's knobs (arm_move's keyword arguments; arm/clearance_aware.hpp).
struct ClearanceAwareArgs {
  int evaluations = 40;
  int slots = 8;
  double grid_s = 0.0;
  std::optional<DoubleArray> start_places;
  double settle_s = 1.5;
  int threads = 2;
  double flank_margin = 0.0;  ///< the design plays the move within the same flank-keeping limits
  double flank_floor = 0.05;
};

// One shaper for every joint by design_clearance_aware_move; its summary into `design`.
std::vector<shaping::Shaper> clearance_aware_shapers(const arm::ArmModel& model, const arm::PointToPoint& move,
                                                     std::span<const signal::AxisLimits> limits,
                                                     double sample_time_s, const ClearanceAwareArgs& a,
                                                     py::dict& design) {
  if (a.evaluations < 10 || a.evaluations > 100000) {
    throw InvalidArgument("evaluations = " + std::to_string(a.evaluations) + "; allowed: 10 … 100000");
  }
  arm::ArmClearanceAwareOptions o;
  o.play.limits.assign(limits.begin(), limits.end());
  o.play.sample_time_s = sample_time_s;
  o.play.settle_s = a.settle_s;
  o.play.flank_margin = a.flank_margin;
  o.play.flank_floor = a.flank_floor;
  o.slots = a.slots;
  o.grid_s = a.grid_s;
  o.max_evaluations = a.evaluations;
  o.threads = a.threads;
  if (a.start_places) {
    const DoubleArray& p = *a.start_places;
    if (p.ndim() != 2 || p.shape(1) != model.dof() || p.shape(0) < 1) {
      throw InvalidArgument("start_places must be a places × " + std::to_string(model.dof()) +
                            " array of φ/β in [-1, 1] (one row per start place)");
    }
    auto v = p.unchecked<2>();
    for (py::ssize_t r = 0; r < p.shape(0); ++r) {
      Eigen::VectorXd f(model.dof());
      for (int j = 0; j < model.dof(); ++j) f(j) = v(r, j);
      o.start_places.push_back(f);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const arm::ArmClearanceAwareResult d = arm::design_clearance_aware_move(model, move, o);
  Eigen::MatrixXd places(static_cast<Eigen::Index>(d.start_places.size()), model.dof());
  for (std::size_t r = 0; r < d.start_places.size(); ++r) places.row(static_cast<Eigen::Index>(r)) = d.start_places[r];
  design["start_places"] = to_array2(places);
  design["unshaped_residual_m"] = to_array(d.unshaped_residual_m);
  design["shaped_residual_m"] = to_array(d.shaped_residual_m);
  design["worst_ratio"] = d.worst_ratio;
  design["worse_than_unshaped"] = d.worse_than_unshaped;
  design["evaluations"] = d.evaluations;
  design["design_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::vector<shaping::Shaper>(static_cast<std::size_t>(model.dof()), d.shaper);
}

py::dict arm_move(const DoubleArray& start_rad, const DoubleArray& end_rad, const DoubleArray& limits,
                  double sample_time_s, const std::string& name, const std::optional<std::string>& urdf,
                  const std::optional<std::string>& toml, const std::string& schedule, const std::string& method,
                  double vtol, bool every_mode, const std::optional<std::string>& json_path,
                  const std::optional<std::string>& csv_path, int evaluations, int slots, double grid_s,
                  const std::optional<DoubleArray>& start_places, double design_settle_s, int threads,
                  double flank_margin, double flank_floor) {
  const arm::ArmModel model = arm_model_of(name, urdf, toml);
  const arm::PointToPoint p2p{to_pose(start_rad, "start_rad"), to_pose(end_rad, "end_rad")};
  const Eigen::VectorXd& q1 = p2p.to_rad;
  const std::vector<signal::AxisLimits> axis_limits = limits_of(limits, model.dof());
  // flank_keeping_limits refuses flank_margin outside [0, 1] and flank_floor outside (0, 1] by name; 0: as given
  const std::vector<signal::AxisLimits> planned_limits =
      arm::flank_keeping_limits(model, q1, axis_limits, flank_margin, flank_floor);
  const arm::JointTrajectory move = arm::plan_move(model, p2p.from_rad, q1, planned_limits, sample_time_s);
  py::dict design;
  const std::vector<shaping::Shaper> shapers =
      schedule == "clearance-aware"
          ? clearance_aware_shapers(model, p2p, axis_limits, sample_time_s,
                                    {evaluations, slots, grid_s, start_places, design_settle_s, threads, flank_margin, flank_floor},
                                    design)
          : arm::joint_shapers(model, q1,
                               {.schedule = schedule_of(schedule), .method = shaping::method_from_string(method),
                                .vtol = vtol, .every_mode = every_mode});
  const arm::JointTrajectory t = arm::shape_trajectory(move, shapers);
  if (json_path) arm::write_trajectory_json(*json_path, t);
  if (csv_path) arm::write_trajectory_csv(*csv_path, t);
  Eigen::MatrixXd commands(static_cast<Eigen::Index>(t.time_s.size()), model.dof());
  const std::vector<plant::Command> u = arm::drive_commands(model, t);
  for (int j = 0; j < model.dof(); ++j) {
    const std::vector<double>& v = u[static_cast<std::size_t>(j)].samples().values;
    commands.col(j) = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  py::dict d;
  d["joint_names"] = t.joint_names;
  d["time_s"] = to_array(t.time_s);
  d["position_rad"] = to_array2(t.position_rad);
  d["velocity_rad_s"] = to_array2(t.velocity_rad_s);
  d["acceleration_rad_s2"] = to_array2(t.acceleration_rad_s2);
  d["commands"] = to_array2(commands.transpose());
  d["move_duration_s"] = move.time_s.back();
  std::vector<double> acceleration_limits;
  for (const signal::AxisLimits& l : planned_limits) acceleration_limits.push_back(l.acceleration);
  d["acceleration_limits_rad_s2"] = to_array(acceleration_limits);
  d["shapers"] = shapers;
  if (schedule == "clearance-aware") d["design"] = design;
  return d;
}

}  // namespace

void bind_arm(py::module_& m) {
  m.def("arm_names", &arm::builtin_arm_names, "The built-in arms (docs/arm.md): scara-2, vertical-2.");
  m.def(
      "arm_text",
      [](const std::string& name) {
        const arm::ArmText t = arm::builtin_arm_text(name);
        return py::make_tuple(t.urdf, t.toml);
      },
      py::arg("name"), "(urdf, toml): the texts of a built-in arm, e.g. to start one's own.");
  m.def("simulate_arm", &simulate_arm, py::arg("commands"), py::arg("sample_time_s"), py::arg("arm") = "scara-2",
        py::arg("urdf") = py::none(), py::arg("toml") = py::none(), py::arg("duration_s") = 1.0,
        py::arg("output_rate_hz") = 1000.0, py::arg("interpolation") = "linear",
        py::arg("relative_tolerance") = 1e-7,
        R"doc(Simulates an arm (docs/arm.md): a built-in one by name, or one's own from urdf and toml
texts. commands: one row per joint, samples every sample_time_s in the drive's units (motor
degrees for a Kp = 1 position drive: a link move of A degrees is N·A), interpolated 'linear' or
held ('zero_order_hold'), the last value held after the end. Returns a dict: time_s, per joint
(samples × joints) motor_angle_rad, encoder_angle_rad, output_angle_rad (θ_m/N),
link_angle_rad, link_rate_rad_s, contact_torque_n_m; tool_position_m (samples × 3); the last
link's IMU in its frame, gyro_rad_s and accel_m_s2 (specific force a − g; samples × 3); the
energies kinetic_j, potential_j, contact_energy_j; events (onsets and separations); joints,
gear_ratio, steps.)doc");
  m.def("arm_modes", &arm_modes, py::arg("pose_rad"), py::arg("arm") = "scara-2", py::arg("urdf") = py::none(),
        py::arg("toml") = py::none(), py::arg("flank_penetration_rad") = 1e-4,
        R"doc(The arm's linearised modes at a pose (docs/arm.md §7): plays closed on the flanks, ω² =
eig(M(q)⁻¹K), modal ζ = φᵀCφ/(2ω). Returns natural_frequency_hz and damping_ratio (ascending),
shapes (joints × modes, φᵀMφ = 1), share (modes × joints: mode k's share in joint i's static
response to its own gearbox output) and dominant_mode (per joint).)doc");
  m.def("arm_move", &arm_move, py::arg("start_rad"), py::arg("end_rad"), py::arg("limits"),
        py::arg("sample_time_s") = 1e-3, py::arg("arm") = "scara-2", py::arg("urdf") = py::none(),
        py::arg("toml") = py::none(), py::arg("schedule") = "unshaped", py::arg("method") = "zvd",
        py::arg("vtol") = 0.05, py::arg("every_mode") = false, py::arg("json_path") = py::none(),
        py::arg("csv_path") = py::none(), py::arg("evaluations") = 40, py::arg("slots") = 8,
        py::arg("grid_s") = 0.0, py::arg("start_places") = py::none(), py::arg("design_settle_s") = 1.5,
        py::arg("threads") = 2, py::arg("flank_margin") = 0.0, py::arg("flank_floor") = 0.05,
        R"doc(A synchronised jerk-limited move of every joint (docs/arm.md §7), limits a joints × 3 array
(velocity, acceleration, jerk at the link, rad units), each joint shaped by `method` at its
dominant mode: schedule 'unshaped', 'fixed' (at the workspace centre) or 'scheduled' (at the end
pose) — or 'clearance-aware': one positive shaper for every joint optimised by simulating the arm
with its play from start places in the plays (arm/clearance_aware.hpp; evaluations 10-100000,
slots 2-32, grid_s 0-1 s with 0 a quarter period of the end pose's lowest mode, start_places a
places × joints array of φ/β in [-1, 1] or None for the five defaults, design_settle_s, threads
1-64); every_mode shapes every joint at all the pose's modes. flank_margin (0: off, up to 1) plans
the move within flank_keeping_limits at the end pose (each acceleration limit lowered to
max(flank_floor · a_i, min(a_i, flank_margin · |g_i| / M_ii)), flank_floor in (0, 1]; docs/arm.md
§7, "The flank-keeping stop"), for every schedule. Optionally written as a ROS
JointTrajectory JSON (json_path) and a CSV (csv_path). Returns joint_names, time_s,
position_rad, velocity_rad_s, acceleration_rad_s2 (samples × joints), commands (joints ×
samples: the drives' commands, ready for simulate_arm), move_duration_s (before shaping),
acceleration_limits_rad_s2 (the ones planned with),
shapers and, for 'clearance-aware', design (start_places, unshaped_residual_m,
shaped_residual_m, worst_ratio, worse_than_unshaped, evaluations, design_time_s).)doc");
  bind_arm_mode_map(m);
}

}  // namespace clearshape::python
