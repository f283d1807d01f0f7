// Python: the arm's pose-dependent mode map (docs/arm.md §7, "Modes that move with the pose") —
// identified from simulated runs on a grid of poses (arm/mode_map.hpp) or from recorded runs
// listed in a manifest (arm/mode_recordings.hpp), the linearised modes beside them. The result is
// the document `clearshape arm modes --identify --json` (or `--recordings MANIFEST --json`) prints,
// built from the same library calls and options, plus the map per pose.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/stl.h>

#include "arm_model.hpp"
#include "arrays.hpp"
#include "clearshape/arm/mode_map.hpp"
#include "clearshape/arm/mode_recordings.hpp"
#include "clearshape/io/json.hpp"

namespace clearshape::python {
namespace {

/// arm_mode_map's arguments; the simulated runs' knobs are empty when not given (CLI defaults).
struct ModeMapArgs {
  std::optional<double> play_deg;
  std::optional<int> grid;
  std::optional<double> step_deg;
  std::string sensor = "links";
  std::optional<std::string> excitation;
  std::optional<double> ramp_velocity_rad_s;
  double max_damping = 0.05;
  std::optional<std::string> recordings, write_recordings;
};

// The ranges of `clearshape arm modes` (apps/clearshape/cmd_arm_modes.cpp), named as the arguments.
void validate_mode_map_args(const ModeMapArgs& a) {
  if (a.play_deg) require_in_closed("play_deg", *a.play_deg, 0.0, 10.0);
  if (a.grid) require_in_closed("grid", *a.grid, 1, 10);
  if (a.step_deg) require_in_closed("step_deg", *a.step_deg, 0.01, 30.0);
  if (a.ramp_velocity_rad_s) require_in_closed("ramp_velocity_rad_s", *a.ramp_velocity_rad_s, 1e-3, 1.0);
  require_in_closed("max_damping", a.max_damping, 0.001, 1.0);
  if (a.sensor != "links" && a.sensor != "gyro") {
    throw InvalidArgument("sensor = '" + a.sensor + "'; allowed: links, gyro");
  }
  if (a.excitation && *a.excitation != "step" && *a.excitation != "loaded-ramp") {
    throw InvalidArgument("excitation = '" + *a.excitation + "'; allowed: step, loaded-ramp");
  }
  if (!a.recordings) return;
  for (const auto& [given, name] : {std::pair{a.grid.has_value(), "grid"}, {a.step_deg.has_value(), "step_deg"},
                                    {a.excitation.has_value(), "excitation"},
                                    {a.ramp_velocity_rad_s.has_value(), "ramp_velocity_rad_s"},
                                    {a.write_recordings.has_value(), "write_recordings"}}) {
    if (given) {
      throw InvalidArgument(std::string("recordings and ") + name + ": give one (" + name +
                            " is for the simulated runs; the recordings bring their own)");
    }
  }
}

// As the CLI's map_options (cmd_arm_modes.cpp).
arm::ModeMapOptions mode_map_options(const ModeMapArgs& a) {
  arm::ModeMapOptions o;
  o.step_deg = a.step_deg.value_or(1.0);
  o.identification.max_damping_ratio = a.max_damping;
  o.excitation = a.excitation.value_or("step") == "step" ? arm::ModeMapExcitation::step
                                                          : arm::ModeMapExcitation::loaded_ramp;
  o.sensor = a.sensor == "gyro" ? arm::ModeMapSensor::last_link_gyro : arm::ModeMapSensor::link_rates;
  o.ramp_velocity_rad_s = a.ramp_velocity_rad_s.value_or(0.02);
  return o;
}

// The map from the recordings, or simulated on the grid (written as recordings when asked).
arm::ModeMap compute_mode_map(const arm::ArmModel& model, const ModeMapArgs& a, std::string& source) {
  const arm::ModeMapOptions o = mode_map_options(a);
  if (a.recordings) {
    source = "identified from the recorded runs of " + *a.recordings + " (arm::mode_map_from_recordings)";
    return arm::mode_map_from_recordings(model, arm::read_mode_recordings(*a.recordings, model), o);
  }
  source = "identified from simulated " + a.excitation.value_or("step") + " runs (arm::identify_mode_map)";
  const auto simulated = arm::simulate_mode_runs(model, arm::pose_grid(model, a.grid.value_or(3)), o);
  if (a.write_recordings) arm::write_mode_recordings(*a.write_recordings, model, simulated);
  return arm::mode_map_from_runs(model, arm::simulated_windows(simulated), o);
}

std::vector<double> std_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

/// One identified mode as a row of `arm modes --json` (pose columns <joint>_rad first).
nlohmann::ordered_json mode_row(const arm::ModeMap& map, const Eigen::VectorXd& pose_rad, const arm::MapMode& m) {
  nlohmann::ordered_json row;
  for (std::size_t i = 0; i < map.joint_names.size(); ++i) {
    row[map.joint_names[i] + "_rad"] = pose_rad(static_cast<Eigen::Index>(i));
  }
  row["linear_mode"] = m.linear_mode;
  const std::pair<const char*, double> values[] = {
      {"frequency_hz", m.natural_frequency_hz}, {"frequency_std_hz", m.natural_frequency_std_hz},
      {"damping_ratio", m.damping_ratio},       {"damping_ratio_std", m.damping_ratio_std}};
  for (const auto& [name, value] : values) {
    if (std::isfinite(value)) row[name] = value;
  }
  row["runs"] = m.runs;
  for (const auto& [name, value] : {std::pair<const char*, double>{"linear_frequency_hz", m.linear_frequency_hz},
                                    {"linear_damping_ratio", m.linear_damping_ratio},
                                    {"relative_frequency_error", m.relative_frequency_error}}) {
    if (std::isfinite(value)) row[name] = value;
  }
  row["harmonic"] = m.harmonic;
  return row;
}

/// One pose of the map: its identified modes (rows as above), the linearised modes and the failures.
nlohmann::ordered_json map_point(const arm::ModeMap& map, const arm::ModeMapPoint& p) {
  nlohmann::ordered_json point;
  point["pose_rad"] = std_vector(p.pose_rad);
  point["modes"] = nlohmann::ordered_json::array();
  for (const arm::MapMode& m : p.modes) point["modes"].push_back(mode_row(map, p.pose_rad, m));
  const Eigen::VectorXd f_hz = p.linearised.natural_frequency_rad_s / (2 * M_PI);
  point["linearised"] = {{"natural_frequency_hz", std_vector(f_hz)},
                         {"damping_ratio", std_vector(p.linearised.damping_ratio)}};
  point["failures"] = p.failures;
  return point;
}

// The CLI's --json document (io::make_document, arm, source, modes, failures) and `points`.
nlohmann::ordered_json mode_map_document(const arm::ModeMap& map, const std::string& source) {
  nlohmann::ordered_json doc = io::make_document();
  doc["arm"] = map.arm_name;
  doc["source"] = source;
  doc["modes"] = nlohmann::ordered_json::array();
  doc["failures"] = nlohmann::ordered_json::array();
  doc["points"] = nlohmann::ordered_json::array();
  for (const arm::ModeMapPoint& p : map.points) {
    for (const arm::MapMode& m : p.modes) doc["modes"].push_back(mode_row(map, p.pose_rad, m));
    for (const std::string& f : p.failures) doc["failures"].push_back({{"pose_rad", std_vector(p.pose_rad)}, {"run", f}});
    doc["points"].push_back(map_point(map, p));
  }
  return doc;
}

py::dict arm_mode_map(const std::string& name, const std::optional<std::string>& urdf,
                        const std::optional<std::string>& toml, const ModeMapArgs& args) {
  validate_mode_map_args(args);
  arm::ArmModel model = arm_model_of(name, urdf, toml);
  if (args.play_deg) {
    for (arm::ArmJoint& j : model.joints) j.half_play_rad = 0.5 * *args.play_deg * M_PI / 180.0;
  }
  std::string source;
  nlohmann::ordered_json doc;
  {
    py::gil_scoped_release release;
    doc = mode_map_document(compute_mode_map(model, args, source), source);
  }
  // Shortest round-trip text, read back by Python's json: the same doubles as the CLI's --json.
  return py::module_::import("json").attr("loads")(doc.dump()).cast<py::dict>();
}

}  // namespace

void bind_arm_mode_map(py::module_& m) {
  m.def(
      "arm_mode_map",
      [](const std::string& name, const std::optional<std::string>& urdf, const std::optional<std::string>& toml,
         std::optional<double> play_deg, std::optional<int> grid, std::optional<double> step_deg,
         const std::string& sensor, std::optional<std::string> excitation, std::optional<double> ramp_velocity_rad_s,
         double max_damping, std::optional<std::string> recordings, std::optional<std::string> write_recordings) {
        return arm_mode_map(name, urdf, toml,
                            {play_deg, grid, step_deg, sensor, std::move(excitation), ramp_velocity_rad_s,
                             max_damping, std::move(recordings), std::move(write_recordings)});
      },
      py::arg("arm") = "scara-2", py::arg("urdf") = py::none(), py::arg("toml") = py::none(),
      py::arg("play_deg") = py::none(), py::arg("grid") = py::none(), py::arg("step_deg") = py::none(),
      py::arg("sensor") = "links", py::arg("excitation") = py::none(), py::arg("ramp_velocity_rad_s") = py::none(),
      py::arg("max_damping") = 0.05, py::arg("recordings") = py::none(), py::arg("write_recordings") = py::none(),
      R"doc(The arm's mode map (docs/arm.md §7): the residual modes identified at every pose of a grid
from simulated runs (arm::identify_mode_map), or from recorded runs listed in the manifest
`recordings` (arm::mode_map_from_recordings), each beside the nearest linearised mode. As
`clearshape arm modes --identify` / `--recordings MANIFEST`, with the same ranges: play_deg
(0-10, every joint's total play; None: the arm's own), grid (1-10 poses per joint; default 3),
step_deg (0.01-30; default 1), sensor 'links' (every link's rate) or 'gyro' (the last link's
gyroscope), excitation 'step' (default) or 'loaded-ramp', ramp_velocity_rad_s (1e-3-1; default
0.02), max_damping (0.001-1). grid, step_deg, excitation, ramp_velocity_rad_s and
write_recordings are for the simulated runs and refused with recordings. write_recordings=DIR
also writes the simulated runs as recordings (a CSV per run and manifest.toml): the template of
a recording. Returns the `arm modes --json` document as a dict — schema_version,
clearshape_version, arm, source, modes (rows: <joint>_rad, linear_mode, frequency_hz,
frequency_std_hz, damping_ratio, damping_ratio_std (1σ), runs, linear_frequency_hz,
linear_damping_ratio, relative_frequency_error, harmonic), failures (pose_rad, run) — and points:
per pose its pose_rad, modes (the same rows), linearised (natural_frequency_hz, damping_ratio)
and failures. Releases the GIL while it runs.)doc");
}

}  // namespace clearshape::python
