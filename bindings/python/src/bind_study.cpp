// Python: what the CLI's recommend, shape --model and simulate --config read and compute, from
// the library (rig/config.hpp, study/clearance_model_json.hpp, study/recommend_report.hpp): the
// same C++ as `clearshape recommend --json`, so the numbers are the CLI's bit for bit.
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/config.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/study/axis_calibration.hpp"
#include "clearshape/study/clearance_model_json.hpp"
#include "clearshape/study/fit_clearance.hpp"
#include "clearshape/study/recommend_report.hpp"
#include "clearshape/study/recordings.hpp"
#include "clearshape/study/runner.hpp"
#include "clearshape/study/study_setup.hpp"

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

// recommend()'s and analyse_calibration()'s ranking options (advise/recommend.hpp).
advise::RecommendOptions recommend_options(std::optional<double> max_delay_s,
                                           const std::optional<std::vector<std::string>>& candidates,
                                           double vibration_tolerance, std::optional<double> min_frequency_hz,
                                           double grid_hz) {
  advise::RecommendOptions o;
  if (candidates) o.candidates = *candidates;
  if (max_delay_s) o.max_delay_s = *max_delay_s;
  o.vibration_tolerance = vibration_tolerance;
  o.min_frequency_hz = min_frequency_hz;
  o.update_grid_hz = grid_hz;
  return o;
}

py::object recommend(const std::vector<std::string>& data, const std::string& column, const std::string& time_column,
                     std::optional<double> from_s, std::optional<double> to_s, double segment_s, std::size_t modes,
                     bool free_decay_fit, std::optional<double> max_delay_s, std::optional<std::vector<std::string>> candidates,
                     double vibration_tolerance, std::optional<double> min_frequency_hz, double grid_hz,
                     std::optional<std::string> model, const std::string& move, const py::dict& move_parameters_dict,
                     double move_duration_s, double move_rate_hz, double initial_play, bool clearance_aware) {
  const advise::RecommendOptions o =
      recommend_options(max_delay_s, candidates, vibration_tolerance, min_frequency_hz, grid_hz);
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

// The drive: identify --json at `drive`, or a structure code with its parameters.
lti::ProcessModel drive_of(const std::optional<std::string>& drive, const std::optional<std::string>& drive_model,
                           const py::dict& drive_parameters) {
  if (drive) return study::read_identified_drive(*drive);
  if (!drive_model) throw InvalidArgument("fit_clearance: give drive= (identify --json) or drive_model= with drive_parameters=");
  lti::ProcessParameters p;
  for (const auto& [name, value] : drive_parameters) p.set(py::cast<std::string>(name), py::cast<double>(value));
  return lti::ProcessModel(*drive_model, p);
}

struct FitStart {
  double link_inertia_kg_m2, play_deg, stiffness, exponent, damping, restitution;
  std::string contact_law;
};

study::ClearanceModel start_model(const std::string& mode, lti::ProcessModel drive, const FitStart& s) {
  study::ClearanceModel m;
  m.mode = rig::command_mode_from_string(mode);
  m.drive = std::move(drive);
  require_positive("link_inertia_kg_m2", s.link_inertia_kg_m2);
  m.link_inertia_kg_m2 = s.link_inertia_kg_m2;
  m.play_rad = deg_to_rad(s.play_deg);
  m.stiffness = s.stiffness;
  m.exponent = s.exponent;
  m.damping = s.damping;
  m.contact_law = study::contact_law_from_string(s.contact_law);
  require_in_closed("restitution", s.restitution, 0.05, 1.0);
  m.restitution = s.restitution;
  return m;
}

py::object fit_clearance(const std::vector<std::string>& data, const std::optional<std::string>& drive,
                         const std::optional<std::string>& drive_model, const py::dict& drive_parameters, const std::string& mode,
                         const std::string& time_column, const std::string& command_column, const std::string& gyro_column,
                         double gyro_scale_deg_s, double window_s, const FitStart& start, const std::vector<std::string>& fit,
                         double envelope_window_s, double link_wn_rad_s, double link_zeta,
                         std::optional<double> sensor_low_pass_hz, int max_evaluations) {
  study::ClearanceFitProblem fp;
  fp.start = start_model(mode, drive_of(drive, drive_model, drive_parameters), start);
  fp.free = fit;
  fp.link_natural_frequency_rad_s = link_wn_rad_s;
  fp.link_damping_ratio = link_zeta;
  require_in_closed("max_evaluations", max_evaluations, 5, 100000);
  fp.max_evaluations = max_evaluations;
  if (sensor_low_pass_hz) require_non_negative("sensor_low_pass_hz", *sensor_low_pass_hz, "0: none; None: try the ITG-3205 settings");
  fp.sensor_low_pass_grid_hz = sensor_low_pass_hz ? std::vector<double>{*sensor_low_pass_hz} : study::gyro_low_pass_settings_hz();
  require_positive("window_s", window_s);
  require_in_closed("envelope_window_s", envelope_window_s, 0.0, 10.0);
  study::LinkRecordsRequest records{{data.begin(), data.end()}, time_column, command_column, gyro_column,
                                    gyro_scale_deg_s, window_s, envelope_window_s};
  study::read_link_records(records, fp.start.mode, fp);
  nlohmann::ordered_json doc;
  {
    py::gil_scoped_release release;  // seconds: other Python threads may go on
    doc = study::fit_clearance_document(fp, study::fit_clearance(fp));
  }
  return json_to_python(doc);
}

// One recorded calibration run from a dict of arrays (command, gyro_deg_s, motor_deg for a chirp;
// time_s optional: k·sample_time_s), as record_calibration_runs would have returned it, complete.
study::AxisCalibrationRun calibration_run(const py::dict& d, double sample_time_s, std::size_t index) {
  study::AxisCalibrationRun run;
  const std::string where = "runs[" + std::to_string(index) + "]";
  run.label = d.contains("label") ? d["label"].cast<std::string>() : where;
  const auto column = [&](const char* key, bool required) {
    if (!d.contains(key)) {
      if (required) throw InvalidArgument(where + "." + key + " is missing (an array, one value per sample)");
      return std::vector<double>{};
    }
    return to_vector(DoubleArray::ensure(d[key]), where + "." + key);
  };
  run.record.command = column("command", true);
  run.record.gyro_deg_s = column("gyro_deg_s", true);
  run.record.motor_deg = column("motor_deg", false);
  if (run.record.motor_deg.empty()) run.record.motor_deg = run.record.command;
  run.record.time_s = column("time_s", false);
  const std::size_t n = run.record.command.size();
  if (run.record.time_s.empty()) {
    for (std::size_t k = 0; k < n; ++k) run.record.time_s.push_back(static_cast<double>(k) * sample_time_s);
  }
  for (const auto* c : {&run.record.gyro_deg_s, &run.record.motor_deg, &run.record.time_s}) {
    if (c->size() != n) throw InvalidArgument(where + ": every column must have command's " + std::to_string(n) + " samples");
  }
  return run;
}

py::object analyse_calibration(const py::list& runs, double sample_time_s, const py::list& excitations,
                               std::optional<double> from_s, double segment_s, std::size_t modes, bool free_decay_fit,
                               std::optional<double> max_delay_s, std::optional<std::vector<std::string>> candidates,
                               double vibration_tolerance, std::optional<double> min_frequency_hz, double grid_hz) {
  require_positive("sample_time_s", sample_time_s);
  study::AxisCalibrationRequest q;
  for (const auto& e : excitations) {
    const auto d = e.cast<py::dict>();
    if (!d.contains("type")) throw InvalidArgument("excitations: each needs 'type' (e.g. {'type': 'step', 'amplitude': 10})");
    py::dict parameters;
    for (const auto& [key, value] : d) {
      if (key.cast<std::string>() != "type") parameters[key] = value;
    }
    q.excitations.push_back(signal::make_signal(d["type"].cast<std::string>(), move_parameters(parameters)));
  }
  q.from_s = from_s;
  require_non_negative("segment_s", segment_s, "0: automatic");
  q.segment_s = segment_s;
  const advise::RecommendOptions o =
      recommend_options(max_delay_s, candidates, vibration_tolerance, min_frequency_hz, grid_hz);
  study::RecommendRequest rq = request_of({}, modes, free_decay_fit, o);
  q.modes = rq.modes;
  q.options = rq.options;
  std::vector<study::AxisCalibrationRun> records;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    records.push_back(calibration_run(runs[i].cast<py::dict>(), sample_time_s, i));
    // the runs' length, as the request that recorded them had it (from_s and segment_s are checked against it)
    q.duration_s = std::max(i == 0 ? 0.0 : q.duration_s, static_cast<double>(records.back().record.size()) * sample_time_s);
  }
  study::AxisCalibration c;
  {
    py::gil_scoped_release release;
    c = study::analyse_calibration(records, q, sample_time_s);
  }
  study::RecommendReport report{c.spectra, c.estimation, c.recommendation, std::nullopt, std::nullopt};
  auto doc = study::recommend_document(rq, report);
  doc["command"] = "rig calibrate";
  doc["window_start_s"] = c.window_start_s;
  return json_to_python(doc);
}

struct StudyArgs {
  std::string protocol, out_dir;
  bool quick = false, fresh = false;
  int threads = 0;
  std::optional<std::string> rig, rig_config, recordings;
  double max_memory_gb = 4.0;
};

// As `clearshape study` sets it up (apps/clearshape/cmd_study.cpp), the serial rig aside.
py::object run_study(const StudyArgs& a) {
  if (static_cast<int>(a.rig.has_value()) + static_cast<int>(a.rig_config.has_value()) + static_cast<int>(a.recordings.has_value()) > 1) {
    throw InvalidArgument("study: give one of recordings, rig_config and rig, not several");
  }
  study::Protocol protocol = study::load_protocol(a.protocol);
  if (a.quick) protocol = study::quick_variant(protocol);
  require_positive("max_memory_gb", a.max_memory_gb);
  study::check_study_size(protocol, a.threads, a.max_memory_gb);
  study::StudyOptions options;
  options.out_dir = a.out_dir;
  options.fresh = a.fresh;
  options.threads = a.threads;
  options.rig = a.rig_config ? study::configured_sim_rig_factory(*a.rig_config) : study::sim_rig_factory(a.rig.value_or(protocol.rig));
  if (a.recordings) {
    options.source = study::recordings_run_source(study::load_recordings_manifest(*a.recordings, protocol), protocol);
  }
  nlohmann::ordered_json summary;
  {
    py::gil_scoped_release release;  // seconds to minutes
    summary = study::run_study(protocol, options).summary();
  }
  summary["out_dir"] = options.out_dir.string();
  return json_to_python(summary);
}

}  // namespace

void bind_calibration(py::module_& m) {
  m.def("analyse_calibration", &analyse_calibration, py::arg("runs"), py::arg("sample_time_s"), py::kw_only(),
        py::arg("excitations"), py::arg("from_s") = py::none(), py::arg("segment_s") = 0.0, py::arg("modes") = 2,
        py::arg("free_decay_fit") = true, py::arg("max_delay_s") = py::none(), py::arg("candidates") = py::none(),
        py::arg("vibration_tolerance") = 0.01, py::arg("min_frequency_hz") = py::none(), py::arg("grid_hz") = 0.0,
        R"doc(The analysis step of `clearshape rig calibrate` (study/axis_calibration.hpp) on runs
already recorded: each run's link gyro rate in its analysis window becomes a Welch spectrum
(for a chirp: the transmissibility motor_deg → gyro_deg_s), the modes are estimated over all of
them and the shaper candidates ranked. Returns the `rig calibrate --json` document as a dict
(modes, candidates, recommendation, reason, window_start_s per run).

runs: one dict per run with arrays command (deg or V), gyro_deg_s (deg/s), optionally
motor_deg (deg; a chirp needs it, default the command), time_s and label, every sample_time_s
(s). excitations: the signal of each run as a dict {'type': 'step', 'amplitude': 10,
'start_s': 0.5, 'rise_s': 1/30} (signal_parameters(type) lists the keys). from_s: the window
start (s; None: each step's end, a chirp's start); the other options as recommend(). Raises
ValueError for bad input or when no mode stands out of the noise.)doc");
}

void bind_study(py::module_& m) {
  bind_calibration(m);
  m.def("study",
        [](const std::string& protocol, const std::string& out_dir, bool quick, bool fresh, int threads, std::optional<std::string> rig,
           std::optional<std::string> rig_config, std::optional<std::string> recordings, double max_memory_gb) {
          return run_study({protocol, out_dir, quick, fresh, threads, std::move(rig), std::move(rig_config), std::move(recordings),
                            max_memory_gb});
        },
        py::arg("protocol"), py::arg("out_dir"), py::kw_only(), py::arg("quick") = false, py::arg("fresh") = false,
        py::arg("threads") = 0, py::arg("rig") = py::none(), py::arg("rig_config") = py::none(), py::arg("recordings") = py::none(),
        py::arg("max_memory_gb") = 4.0,
        R"doc(Runs a study protocol (studies/*.toml: the thesis's programme) as `clearshape study --json`
and returns its summary (tables, stages, rig, out_dir); results.json, tables.md, figures.json,
data/ and runs/ are written under out_dir (docs/study-outputs.md), byte for byte as the CLI's.

quick: the protocol's quick variant; fresh: discard finished runs first; threads: parallel runs
(0: all cores); the rig: a built-in simulated truth by name (rig='large-play'; default the
protocol's), a rig configuration file (rig_config=), or recorded runs (recordings= a folder with
its manifest). Raises ValueError for a bad protocol or option, RuntimeError when a run fails.)doc");
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
  m.def("fit_clearance",
        [](const std::vector<std::string>& data, const std::optional<std::string>& drive, const std::optional<std::string>& drive_model,
           const py::dict& drive_parameters, const std::string& mode, const std::string& time_column, const std::string& command_column,
           const std::string& gyro_column, double gyro_scale_deg_s, double window_s, double link_inertia_kg_m2, double play_deg,
           double stiffness, double exponent, double damping, const std::string& contact_law, double restitution,
           const std::vector<std::string>& fit, double envelope_window_s, double link_wn_rad_s, double link_zeta,
           std::optional<double> sensor_low_pass_hz, int max_evaluations) {
          const FitStart start{link_inertia_kg_m2, play_deg, stiffness, exponent, damping, restitution, contact_law};
          return fit_clearance(data, drive, drive_model, drive_parameters, mode, time_column, command_column, gyro_column,
                               gyro_scale_deg_s, window_s, start, fit, envelope_window_s, link_wn_rad_s, link_zeta,
                               sensor_low_pass_hz, max_evaluations);
        },
        py::arg("data"), py::kw_only(), py::arg("drive") = py::none(), py::arg("drive_model") = py::none(),
        py::arg("drive_parameters") = py::dict(), py::arg("mode") = "position", py::arg("time_column") = "",
        py::arg("command_column") = "", py::arg("gyro_column") = "link_rate_deg_s", py::arg("gyro_scale_deg_s") = 1.0,
        py::arg("window_s") = 2.0, py::arg("link_inertia_kg_m2") = 5e-3, py::arg("play_deg") = 0.1, py::arg("stiffness") = 300.0,
        py::arg("exponent") = 1.5, py::arg("damping") = 0.1, py::arg("contact_law") = "dashpot", py::arg("restitution") = 0.6,
        py::arg("fit") = std::vector<std::string>{"stiffness", "damping", "play", "exponent"}, py::arg("envelope_window_s") = 0.0,
        py::arg("link_wn_rad_s") = 0.0, py::arg("link_zeta") = 0.0, py::arg("sensor_low_pass_hz") = py::none(),
        py::arg("max_evaluations") = 150,
        R"doc(Fits the Eq. 4.3 contact parameters (thesis §4.2) to link records, given a drive model, as
`clearshape fit-clearance --json`, and returns that document as a dict (parameters with their
1σ, identifiable, at_bound; the Eq. 4.1 agreement; trusted and warnings; drive, mode,
link_inertia_kg_m2) — which read_clearance_model() and recommend(model=) read back from a file.

data: link records (CSV: time, the command the drive received, the link gyro), averaged;
drive: `identify --json` output, or drive_model (e.g. 'P3UZ') with drive_parameters
({'Kp': 0.99, …}); mode: position (deg) or speed (V); gyro_scale_deg_s: deg/s per unit of
gyro_column; window_s: compared from t = 0; the start values link_inertia_kg_m2 (held fixed),
play_deg (total play 2β), stiffness K, exponent n, damping D, contact_law ('dashpot' or
'flores' with restitution); fit: the free parameters of stiffness, damping, play, exponent,
coulomb, viscous; sensor_low_pass_hz: the gyro's low pass (None: try the ITG-3205 settings, 0:
none). Raises ValueError for bad input.)doc");
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
