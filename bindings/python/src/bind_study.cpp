// Python: what the CLI's recommend, shape --model and simulate --config read and compute, from
// the library (rig/config.hpp, study/clearance_model_json.hpp, study/recommend_report.hpp): the
// same C++ as `clearshape recommend --json`, so the numbers are the CLI's bit for bit.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/rig/config.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/study/clearance_model_json.hpp"
#include "clearshape/study/recommend_report.hpp"

namespace clearshape::python {
namespace {

py::object json_to_python(const nlohmann::ordered_json& doc) {
  // Shortest round-trip text, read back by Python's json: the same doubles as the CLI's --json.
  return py::module_::import("json").attr("loads")(doc.dump());
}

py::dict rig_config_dict(const std::string& path) {
  const rig::RigConfig config = rig::load_rig_config(path);
  py::dict d;
  d["truth"] = rig::configured_truth(config);
  d["duration_s"] = config.run.duration_s;
  d["output_rate_hz"] = config.run.output_rate_hz;
  d["initial_play_fraction"] = config.run.initial_play_fraction;
  d["seed"] = config.run.seed;
  d["sensor_noise"] = config.run.sensor_noise;
  return d;
}

py::dict clearance_model_dict(const std::string& path) {
  const study::IdentifiedClearanceModel m = study::read_clearance_model_json(path);
  const study::ClearanceModel& c = m.model;
  py::dict d;
  d["mode"] = std::string(rig::to_string(c.mode));
  d["drive_model"] = c.drive.code();
  py::dict drive;
  const auto names = c.drive.structure().parameter_names();
  const auto values = c.drive.to_vector();
  for (std::size_t i = 0; i < names.size(); ++i) drive[py::str(std::string(names[i]))] = values[i];
  d["drive_parameters"] = drive;
  d["play_rad"] = c.play_rad;
  d["stiffness"] = c.stiffness;
  d["damping"] = c.damping;
  d["exponent"] = c.exponent;
  d["contact_law"] = std::string(study::to_string(c.contact_law));
  d["restitution"] = c.restitution;
  d["coulomb_n_m"] = c.coulomb_n_m;
  d["viscous_n_m_s_per_rad"] = c.viscous_n_m_s_per_rad;
  d["link_inertia_kg_m2"] = c.link_inertia_kg_m2;
  d["link_frequency_hz"] = m.link_frequency_hz ? py::cast(*m.link_frequency_hz) : py::none();
  d["link_damping_ratio"] = m.link_damping_ratio ? py::cast(*m.link_damping_ratio) : py::none();
  return d;
}

signal::SignalParameters move_parameters(const py::dict& parameters) {
  signal::SignalParameters out;
  for (const auto& [key, value] : parameters) {
    const auto name = py::cast<std::string>(key);
    if (py::isinstance<py::bool_>(value)) {
      out[name] = py::cast<bool>(value);
    } else if (py::isinstance<py::str>(value)) {
      out[name] = py::cast<std::string>(value);
    } else if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
      out[name] = py::cast<double>(value);
    } else {
      out[name] = py::cast<std::vector<double>>(value);
    }
  }
  return out;
}

struct SpectrumArgs {
  std::vector<std::string> data;
  std::string column, time_column;
  std::optional<double> from_s, to_s;
  double segment_s = 0.0;
};

study::RecommendRequest request_of(const SpectrumArgs& s, std::size_t modes, bool free_decay_fit,
                                   advise::RecommendOptions options) {
  study::RecommendRequest q;
  for (const auto& path : s.data) {
    advise::SpectrumRequest r;
    r.path = path;
    r.column = s.column;
    r.time_column = s.time_column;
    r.from_s = s.from_s;
    r.to_s = s.to_s;
    r.segment_s = s.segment_s;
    q.data.push_back(r);
  }
  if (modes < 1 || modes > 2) throw_invalid("modes", static_cast<double>(modes), "1 or 2");
  q.modes.max_modes = modes;
  q.modes.free_decay_fit = free_decay_fit;
  q.modes.min_frequency_hz = options.min_frequency_hz;
  q.options = std::move(options);
  return q;
}

py::object recommend(const std::vector<std::string>& data, const std::string& column, const std::string& time_column,
                     std::optional<double> from_s, std::optional<double> to_s, double segment_s, std::size_t modes,
                     bool free_decay_fit, std::optional<double> max_delay_s, std::optional<std::vector<std::string>> candidates,
                     double vibration_tolerance, std::optional<double> min_frequency_hz, double grid_hz,
                     std::optional<std::string> model, const std::string& move, const py::dict& move_parameters_dict,
                     double move_duration_s, double move_rate_hz, double initial_play, bool clearance_aware) {
  advise::RecommendOptions o;
  if (candidates) o.candidates = *candidates;
  if (max_delay_s) o.max_delay_s = *max_delay_s;
  o.vibration_tolerance = vibration_tolerance;
  o.min_frequency_hz = min_frequency_hz;
  o.update_grid_hz = grid_hz;
  require_non_negative("segment_s", segment_s, "0: automatic");
  study::RecommendRequest q = request_of({data, column, time_column, from_s, to_s, segment_s}, modes, free_decay_fit, o);
  if (!model && clearance_aware) throw InvalidArgument("clearance_aware needs model= (the design runs on the model)");
  study::RecommendReport report;
  {
    py::gil_scoped_release release;  // seconds with a model: other Python threads may go on
    report = study::recommend_from_spectra(q);
  }
  if (model) {
    study::MoveRequest m;
    m.model = *model;
    m.move_type = move;
    m.move = signal::make_signal(move, move_parameters(move_parameters_dict));
    m.duration_s = move_duration_s;
    require_positive("move_rate_hz", move_rate_hz);
    m.sample_time_s = 1.0 / move_rate_hz;
    m.initial_play_fraction = initial_play;
    m.clearance_aware = clearance_aware;
    q.model = m;
    py::gil_scoped_release release;
    study::add_model_predictions(q, report);
  }
  return json_to_python(study::recommend_document(q, report));
}

}  // namespace

void bind_study(py::module_& m) {
  m.def("load_rig_config", &rig_config_dict, py::arg("path"),
        R"doc(Reads a rig configuration file (TOML; the schema of `clearshape simulate --config`,
docs/cli.md) over the calibrated thesis rig. Returns a dict: truth (a RigTruth with both modes'
contact laws resolved, as `clearshape study --rig-config` simulates it), duration_s,
output_rate_hz, initial_play_fraction, seed, sensor_noise (the [run] table). Raises ValueError
naming the file, line and key.)doc");
  m.def("rig_truth_from_toml", [](const std::string& text, const std::string& file) {
    return rig::configured_truth(rig::parse_rig_config(text, file));
  }, py::arg("text"), py::arg("file") = "<string>",
        "The RigTruth of a rig configuration given as TOML text (as load_rig_config(path)['truth']); "
        "`file` names it in error messages.");
  m.def("read_clearance_model", &clearance_model_dict, py::arg("path"),
        R"doc(Reads an identified nonlinear model: the JSON of `clearshape fit-clearance --json` or a
study's results.json (sections.clearance). Returns a dict: mode, drive_model (its structure
code, canonical: P3UZ reads as P3ZU), drive_parameters (Eq. 4.2: Kp, Tz, …), play_rad (the total play 2β), stiffness, damping, exponent (Eq. 4.3), contact_law,
restitution, coulomb_n_m, viscous_n_m_s_per_rad, link_inertia_kg_m2, and the study's link mode
(link_frequency_hz, link_damping_ratio; None when absent). Raises ValueError naming the key.)doc");
  m.def("recommend", &recommend, py::arg("data"), py::kw_only(), py::arg("column") = "", py::arg("time_column") = "",
        py::arg("from_s") = py::none(), py::arg("to_s") = py::none(), py::arg("segment_s") = 0.0, py::arg("modes") = 2,
        py::arg("free_decay_fit") = true, py::arg("max_delay_s") = py::none(), py::arg("candidates") = py::none(),
        py::arg("vibration_tolerance") = 0.01, py::arg("min_frequency_hz") = py::none(), py::arg("grid_hz") = 0.0,
        py::arg("model") = py::none(), py::arg("move") = "step", py::arg("move_parameters") = py::dict(),
        py::arg("move_duration_s") = 4.0, py::arg("move_rate_hz") = 1000.0, py::arg("initial_play") = 0.0,
        py::arg("clearance_aware") = false,
        R"doc(Recommends an input shaper from recorded vibration, as `clearshape recommend --json`
(docs/recommend.md), and returns that document as a dict (modes, candidates with their
remaining vibration and impulses, recommendation, reason).

data: recording paths (a clearshape CSV, Klipper's raw accelerometer or PSD CSV); column: the
table's column (e.g. 'gyro_deg_s'); from_s/to_s: the window (s); segment_s: Welch segment (0:
automatic); modes: 1 or 2; max_delay_s: the delay budget (s); candidates: e.g. ['zv', 'zvd'];
grid_hz: the drive's update rate (0: none).
model: an identified nonlinear model (`fit-clearance --json` or a study's results.json): adds
each candidate's predicted Eq. 5.1 MD for the move — move: a signal type with
move_parameters (e.g. {'amplitude': 20, 'start_s': 0.2}), simulated for move_duration_s at
move_rate_hz from initial_play (φ(0)/β) — and, with clearance_aware=True (a step move), the
clearance-aware candidate designed on the model. Raises ValueError for bad input.)doc");
}

}  // namespace clearshape::python
