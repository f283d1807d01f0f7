// Python: the simulated rig — a truth (rig/truth.hpp), one whole run from a truth and a command
// (rig::simulate_run, rig/offline.hpp: the nominal rig, as `clearshape simulate`), and a run on
// a SimRig built from the truth (the run-to-run variation drawn per run, as the study records).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/offline.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/record.hpp"
#include "truth_state.hpp"

namespace clearshape::python {
namespace {

namespace rg = clearshape::rig;

rg::ContactSpec& contact_of(rg::RigTruth& t, const std::string& mode) {
  return rg::command_mode_from_string(mode) == rg::CommandMode::position ? t.position_contact : t.speed_contact;
}

py::dict simulate(const DoubleArray& command, double sample_time_s, const std::string& mode_name,
                  const rg::RigTruth& truth, double duration_s, double output_rate_hz,
                  double initial_play_fraction, std::uint64_t seed, bool sensor_noise) {
  const rg::CommandMode mode = rg::command_mode_from_string(mode_name);
  rg::RunOptions options;
  options.duration_s = duration_s;
  options.output_rate_hz = output_rate_hz;
  options.initial_play_fraction = initial_play_fraction;
  options.seed = seed;
  options.sensor_noise = sensor_noise;
  const UniformSeries series = to_series(command, sample_time_s, 0.0, "command");
  rg::RunRecord run;
  {
    py::gil_scoped_release release;  // a run takes milliseconds; other Python threads may go on
    run = rg::simulate_run(truth, mode, series, options);
  }
  const auto& s = run.simulation;
  py::dict d;
  d["time_s"] = to_array(s.time_s);
  d["command_drive"] = to_array(run.command_drive);
  d["motor_angle_rad"] = to_array(s.motor_angle_rad);
  d["motor_rate_rad_s"] = to_array(s.motor_rate_rad_s);
  d["link_angle_rad"] = to_array(s.link_angle_rad);
  d["link_rate_rad_s"] = to_array(s.link_rate_rad_s);
  d["relative_angle_rad"] = to_array(s.relative_angle_rad);
  d["contact_torque_n_m"] = to_array(s.contact_torque_n_m);
  d["penetration_rad"] = to_array(s.penetration);
  d["encoder_counts"] = to_array(run.encoder_counts);
  d["encoder_angle_rad"] = to_array(run.encoder_angle_rad);
  d["gyro_raw"] = to_array(run.gyro_raw);
  d["gyro_rate_rad_s"] = to_array(run.gyro_rate_rad_s);
  d["limited_commands"] = run.limited_commands;
  d["rigid"] = run.rigid;
  d["events"] = s.stats.events;
  return d;
}

py::dict simulate_rig(const DoubleArray& command, double sample_time_s, const std::string& mode_name,
                      const rg::RigTruth& truth, double duration_s, std::uint64_t seed) {
  rg::SimRigOptions options;
  options.mode = rg::command_mode_from_string(mode_name);
  require_positive("sample_time_s", sample_time_s);
  options.sample_rate_hz = 1.0 / sample_time_s;
  options.seed = seed;
  study::RunRequest request;
  request.id = "python";
  request.seed = seed;
  request.command = to_series(command, sample_time_s, 0.0, "command");
  require_positive("duration_s", duration_s);
  request.record_s = duration_s;
  study::Record r;
  {
    py::gil_scoped_release release;
    auto sim = rg::make_sim_rig_with_truth(options, truth);
    r = study::execute_run(*sim, request);
  }
  py::dict d;
  d["time_s"] = to_array(r.time_s);
  d["command"] = to_array(r.command);
  d["command_applied"] = to_array(r.command_applied);
  d["encoder_counts"] = to_array(r.encoder_counts);
  d["motor_angle_deg"] = to_array(r.motor_angle_deg);
  d["gyro_raw"] = to_array(r.gyro_raw);
  d["link_rate_deg_s"] = to_array(r.link_rate_deg_s);
  d["flags"] = to_array(r.flags);
  return d;
}

py::dict contact_dict(rg::RigTruth& t, const std::string& mode) {
  const auto& c = contact_of(t, mode);
  py::dict d;
  d["model"] = std::string(rg::to_string(c.model));
  d["stiffness"] = c.stiffness;
  d["exponent"] = c.exponent;
  d["damping"] = c.damping;
  d["restitution"] = c.restitution;
  return d;
}

void set_contact(rg::RigTruth& t, const std::string& mode, std::optional<double> stiffness,
                 std::optional<double> damping, std::optional<double> exponent) {
  auto& c = contact_of(t, mode);
  if (stiffness) c.stiffness = *stiffness;
  if (damping) c.damping = *damping;
  if (exponent) c.exponent = *exponent;
  c.validate();
}

py::dict variation_dict(const rg::RigTruth& t) { return variation_state(t.variation); }

// Sets the σs a dict names (the others keep their values); an unknown key or a value out of
// range changes nothing.
void set_variation(rg::RigTruth& t, const py::dict& d) {
  rg::RunVariation v = t.variation;
  for (const auto& [key, value] : d) {
    const auto k = key.cast<std::string>();
    const double x = value.cast<double>();
    if (k == "position_gain_rel_sigma") v.position_gain_rel_sigma = x;
    else if (k == "speed_gain_rel_sigma") v.speed_gain_rel_sigma = x;
    else if (k == "start_latency_max_s") v.start_latency_max_s = x;
    else if (k == "analog_noise_v") v.analog_noise_v = x;
    else if (k == "analog_offset_sigma_v") v.analog_offset_sigma_v = x;
    else if (k == "flank_damping_rel_sigma") v.flank_damping_rel_sigma = x;
    else throw InvalidArgument("variation." + k + " is not known; allowed: position_gain_rel_sigma, "
                               "speed_gain_rel_sigma, start_latency_max_s, analog_noise_v, "
                               "analog_offset_sigma_v, flank_damping_rel_sigma");
  }
  v.validate();
  t.variation = v;
}

// The class RigTruth.
void bind_rig_truth(py::module_& m) {
  py::class_<rg::RigTruth>(m, "RigTruth",
                           "The simulated rig's true parameters (SI units). thesis_truth() is the calibrated thesis rig.")
      .def(py::init<>())
      .def("copy", [](const rg::RigTruth& t) { return rg::RigTruth(t); })
      .def("validate", &rg::RigTruth::validate, "Raises ValueError naming a field out of range.")
      .def_readwrite("clearance_rad", &rg::RigTruth::clearance_rad, "Total play 2β (rad); 0 = rigid joint.")
      .def_property("link_inertia_kg_m2", [](const rg::RigTruth& t) { return t.link.inertia_kg_m2; },
                    [](rg::RigTruth& t, double v) { t.link.inertia_kg_m2 = v; }, "Link inertia J (kg·m²).")
      .def_property("ground_viscous_n_m_s_per_rad", [](const rg::RigTruth& t) { return t.link.ground_viscous_n_m_s_per_rad; },
                    [](rg::RigTruth& t, double v) { t.link.ground_viscous_n_m_s_per_rad = v; },
                    "Link drag to the ground (N·m·s/rad).")
      .def("contact", &contact_dict, py::arg("mode"),
           "The contact law of a mode: model, stiffness K (N·m/rad^n), exponent n, damping D (N·m·s/rad), restitution e.")
      .def("set_contact", &set_contact, py::arg("mode"), py::kw_only(), py::arg("stiffness") = py::none(),
           py::arg("damping") = py::none(), py::arg("exponent") = py::none(),
           "Changes the contact law's stiffness K (N·m/rad^n), damping D (N·m·s/rad) or exponent n for a mode.")
      .def_property("variation", &variation_dict, &set_variation,
                    "Run-to-run variation σs (dict; rig/variation.hpp). simulate() runs the nominal rig; simulate_rig() draws them.")
      // A value (docs/design.md §3): == compares every field, a pickle carries every field bit for
      // bit (multiprocessing, Dask); mutable, so not hashable.
      .def("__eq__", [](const rg::RigTruth& a, const rg::RigTruth& b) { return truth_state(a).equal(truth_state(b)); },
           py::is_operator())
      .def(py::pickle(&truth_state, &truth_from_state));
}

// The names truth(name) knows: the built-in truths (rig/builtin_truths.hpp) and the prior.
std::vector<std::string> truth_names() {
  std::vector<std::string> names;
  for (auto n : rg::kBuiltinTruthNames) names.emplace_back(n);
  names.emplace_back("uncalibrated");
  return names;
}

rg::RigTruth truth_of(const std::string& name) {
  if (name == "uncalibrated") return rg::uncalibrated_thesis_rig_prior();
  if (rg::is_builtin_truth(name)) return rg::builtin_truth(name, "truth");
  std::string allowed;
  for (const auto& n : truth_names()) allowed += (allowed.empty() ? "" : ", ") + n;
  throw InvalidArgument("truth = '" + name + "' is not a known truth; allowed: " + allowed);
}

// The built-in truths by name: truth_names(), truth(name), thesis_truth(), uncalibrated_truth().
void bind_truths(py::module_& m) {
  m.def("truth_names", &truth_names,
        "Names of the truths truth(name) knows: the built-in ones (thesis, large-play, …) and uncalibrated.");
  m.def("truth", &truth_of, py::arg("name"),
        "A truth by name: thesis (the calibrated thesis rig), large-play (1° steel-pin joint; docs/large-play.md), "
        "worn-coupling (1° of play, soft flank, bearing Coulomb; docs/worn-coupling.md), uncalibrated (the physical "
        "prior of the calibration). An unknown name raises ValueError listing truth_names().");
  m.def("thesis_truth", &rg::thesis_rig_truth, "The built-in truth: the calibrated thesis rig (2β = 0.032°).");
  m.def("uncalibrated_truth", &rg::uncalibrated_thesis_rig_prior,
        "The physical prior the calibration starts from (2β = 1.0°).");
}

// simulate() (the nominal rig, rig::simulate_run) and simulate_rig() (a run recorded from a SimRig).
void bind_runs(py::module_& m) {
  m.def("simulate", &simulate, py::arg("command"), py::arg("sample_time_s"), py::arg("mode") = "position",
        py::arg("truth") = rg::thesis_rig_truth(), py::arg("duration_s") = 5.0, py::arg("output_rate_hz") = 1000.0,
        py::arg("initial_play_fraction") = 0.0, py::arg("seed") = 1, py::arg("sensor_noise") = true,
        R"doc(One run of the simulated rig (as `clearshape simulate`): the command through the mode's
command path, the drive + link with clearance integrated by CVODE, the sensors.

command: samples every sample_time_s (s) in rig units — position mode rad (motor-angle
target), speed mode V (driver input); held after its end. mode: 'position' or 'speed'.
truth: a RigTruth (default the calibrated thesis rig; its variation is not applied).
initial_play_fraction: φ(0)/β in [−1, 1]; seed: gyroscope noise. Returns a dict of arrays on
the output grid (time_s; angles rad, rates rad/s, contact_torque_n_m in N·m,
gyro_rate_rad_s, encoder_angle_rad, …) and limited_commands, rigid, events.)doc");

  m.def("simulate_rig", &simulate_rig, py::arg("command"), py::arg("sample_time_s"), py::arg("mode") = "position",
        py::arg("truth") = rg::thesis_rig_truth(), py::arg("duration_s") = 5.0, py::arg("seed") = 1,
        R"doc(One run recorded from a SimRig built with `truth` (as the study records it): the
rig draws its run-to-run variation and the initial play from `seed`. command: samples every
sample_time_s (s) in command units — position mode deg, speed mode V. Returns a dict of
arrays: time_s, command, command_applied, encoder_counts, motor_angle_deg, gyro_raw,
link_rate_deg_s (the gyroscope), flags.)doc");
}

}  // namespace

void bind_simulation(py::module_& m) {
  bind_rig_truth(m);  // first: the defaults of simulate() and simulate_rig() are RigTruths
  bind_truths(m);
  bind_runs(m);
}

}  // namespace clearshape::python
