// RigTruth <-> dict of its fields (truth_state.hpp). Every field of RigTruth and of the structs
// it holds is here; the static_assert below fails the build when RigTruth changes size, so a new
// field cannot be left out of the pickle silently.
#include "truth_state.hpp"

#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "clearshape/core/error.hpp"

namespace clearshape::python {
namespace {

namespace py = pybind11;
namespace rg = clearshape::rig;
namespace pl = clearshape::plant;

constexpr int kStateVersion = 1;
#if defined(__x86_64__) && EIGEN_MAX_STATIC_ALIGN_BYTES == 16  // the size below is this ABI's
static_assert(sizeof(rg::RigTruth) == 2112,
              "RigTruth changed: add the new field to truth_state/truth_from_state, then update this size");
#endif

// The value of `key` in `d`; InvalidArgument naming `where.key` when it is missing.
template <class T>
T field(const py::dict& d, const char* key, const std::string& where) {
  if (!d.contains(key)) throw InvalidArgument("RigTruth state: " + where + "." + key + " is missing");
  return d[key].cast<T>();
}

// Eigen matrices as lists (rows) of floats, so that states compare with == as plain values.
py::list matrix_list(const pl::DriveModel::Matrix& a) {
  py::list rows;
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    py::list row;
    for (Eigen::Index j = 0; j < a.cols(); ++j) row.append(a(i, j));
    rows.append(row);
  }
  return rows;
}

py::list vector_list(const pl::DriveModel::Vector& v) {
  py::list out;
  for (Eigen::Index i = 0; i < v.size(); ++i) out.append(v(i));
  return out;
}

pl::DriveModel::Vector vector_from(const std::vector<double>& v, const std::string& where) {
  if (v.empty() || v.size() > static_cast<std::size_t>(pl::kMaxDriveOrder)) {
    throw_invalid(where + " length", static_cast<double>(v.size()), "1…" + std::to_string(pl::kMaxDriveOrder));
  }
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

pl::DriveModel::Matrix matrix_from(const std::vector<std::vector<double>>& rows, const std::string& where) {
  const auto n = static_cast<Eigen::Index>(rows.size());
  if (n < 1 || n > pl::kMaxDriveOrder) throw_invalid(where + " rows", static_cast<double>(n), "1…" + std::to_string(pl::kMaxDriveOrder));
  pl::DriveModel::Matrix a(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& row = rows[static_cast<std::size_t>(i)];
    if (static_cast<Eigen::Index>(row.size()) != n) throw InvalidArgument(where + ": expected a square matrix");
    for (Eigen::Index j = 0; j < n; ++j) a(i, j) = row[static_cast<std::size_t>(j)];
  }
  return a;
}

py::dict drive_state(const pl::DriveModel& m) {
  const auto r = m.realization();
  py::dict d;
  d["mode"] = static_cast<int>(r.mode);
  d["a"] = matrix_list(r.a);
  d["b"] = vector_list(r.b);
  d["c_angle"] = vector_list(r.c_angle);
  d["c_rate"] = vector_list(r.c_rate);
  d["d_rate"] = r.d_rate;
  d["delay_s"] = r.delay_s;
  return d;
}

pl::DriveModel drive_from(const py::dict& d, const std::string& w) {
  pl::DriveModel::Realization r;
  const int mode = field<int>(d, "mode", w);
  if (mode != 0 && mode != 1) throw_invalid(w + ".mode", mode, "0 (position), 1 (speed)");
  r.mode = static_cast<pl::DriveMode>(mode);
  r.a = matrix_from(field<std::vector<std::vector<double>>>(d, "a", w), w + ".a");
  r.b = vector_from(field<std::vector<double>>(d, "b", w), w + ".b");
  r.c_angle = vector_from(field<std::vector<double>>(d, "c_angle", w), w + ".c_angle");
  r.c_rate = vector_from(field<std::vector<double>>(d, "c_rate", w), w + ".c_rate");
  r.d_rate = field<double>(d, "d_rate", w);
  r.delay_s = field<double>(d, "delay_s", w);
  return pl::DriveModel::from_realization(r);
}

// A struct's double fields, each named once: the pickle writes and reads them from this table.
template <class T>
using DoubleFields = std::initializer_list<std::pair<const char*, double T::*>>;

template <class T>
void put_doubles(py::dict& d, const T& value, DoubleFields<T> fields) {
  for (const auto& [name, member] : fields) d[name] = value.*member;
}

template <class T>
void get_doubles(const py::dict& d, T& value, DoubleFields<T> fields, const std::string& w) {
  for (const auto& [name, member] : fields) value.*member = field<double>(d, name, w);
}

const DoubleFields<pl::Link> kLinkFields{{"inertia_kg_m2", &pl::Link::inertia_kg_m2},
                                         {"mass_kg", &pl::Link::mass_kg},
                                         {"com_distance_m", &pl::Link::com_distance_m},
                                         {"axis_tilt_rad", &pl::Link::axis_tilt_rad},
                                         {"gravity_m_s2", &pl::Link::gravity_m_s2},
                                         {"ground_viscous_n_m_s_per_rad", &pl::Link::ground_viscous_n_m_s_per_rad},
                                         {"external_torque_n_m", &pl::Link::external_torque_n_m}};
const DoubleFields<rg::ContactSpec> kContactFields{{"stiffness", &rg::ContactSpec::stiffness},
                                                   {"exponent", &rg::ContactSpec::exponent},
                                                   {"damping", &rg::ContactSpec::damping},
                                                   {"restitution", &rg::ContactSpec::restitution},
                                                   {"static_rate_rad_s", &rg::ContactSpec::static_rate_rad_s}};
const DoubleFields<pl::Friction> kFrictionFields{{"viscous", &pl::Friction::viscous},
                                                 {"coulomb", &pl::Friction::coulomb},
                                                 {"static_level", &pl::Friction::static_level},
                                                 {"stribeck_rate", &pl::Friction::stribeck_rate},
                                                 {"regularization_rate", &pl::Friction::regularization_rate}};

py::dict link_state(const pl::Link& l) {
  py::dict d;
  put_doubles(d, l, kLinkFields);
  return d;
}

pl::Link link_from(const py::dict& d, const std::string& w) {
  pl::Link l;
  get_doubles(d, l, kLinkFields, w);
  return l;
}

py::dict contact_state(const rg::ContactSpec& c) {
  py::dict d;
  d["model"] = std::string(rg::to_string(c.model));
  put_doubles(d, c, kContactFields);
  return d;
}

rg::ContactSpec contact_from(const py::dict& d, const std::string& w) {
  rg::ContactSpec c;
  c.model = rg::contact_model_from_string(field<std::string>(d, "model", w));
  get_doubles(d, c, kContactFields, w);
  return c;
}

py::dict friction_state(const pl::Friction& f) {
  py::dict d;
  put_doubles(d, f, kFrictionFields);
  return d;
}

pl::Friction friction_from(const py::dict& d, const std::string& w) {
  pl::Friction f;
  get_doubles(d, f, kFrictionFields, w);
  return f;
}

py::dict sensors_state(const rg::RigTruth& t) {
  py::dict e, g;
  e["lines_per_revolution"] = t.encoder.lines_per_revolution;
  e["decoding"] = static_cast<int>(t.encoder.decoding);
  e["zero_angle_rad"] = t.encoder.zero_angle_rad;
  g["sensitivity_lsb_per_dps"] = t.gyro.sensitivity_lsb_per_dps;
  g["full_scale_dps"] = t.gyro.full_scale_dps;
  g["noise_density_dps_per_rthz"] = t.gyro.noise_density_dps_per_rthz;
  g["bias_dps"] = t.gyro.bias_dps;
  g["low_pass"] = static_cast<int>(t.gyro.low_pass);
  g["sample_rate_hz"] = t.gyro.sample_rate_hz;
  g["latency_samples"] = t.gyro.latency_samples;
  g["seed"] = t.gyro.seed;
  py::dict d;
  d["encoder"] = e;
  d["gyro"] = g;
  return d;
}

// An enum stored as its integer, checked against its values.
template <class E>
E enum_from(const py::dict& d, const char* key, const std::string& w, const std::vector<int>& allowed,
            const std::string& names) {
  const int v = field<int>(d, key, w);
  for (int a : allowed) {
    if (v == a) return static_cast<E>(v);
  }
  throw_invalid(w + "." + key, v, names);
}

void sensors_from(const py::dict& d, rg::RigTruth& t) {
  const auto e = field<py::dict>(d, "encoder", "sensors");
  t.encoder.lines_per_revolution = field<int>(e, "lines_per_revolution", "encoder");
  t.encoder.decoding = enum_from<pl::Decoding>(e, "decoding", "encoder", {1, 2, 4}, "1, 2, 4");
  t.encoder.zero_angle_rad = field<double>(e, "zero_angle_rad", "encoder");
  const auto g = field<py::dict>(d, "gyro", "sensors");
  t.gyro.sensitivity_lsb_per_dps = field<double>(g, "sensitivity_lsb_per_dps", "gyro");
  t.gyro.full_scale_dps = field<double>(g, "full_scale_dps", "gyro");
  t.gyro.noise_density_dps_per_rthz = field<double>(g, "noise_density_dps_per_rthz", "gyro");
  t.gyro.bias_dps = field<double>(g, "bias_dps", "gyro");
  t.gyro.low_pass = enum_from<pl::GyroLowPass>(g, "low_pass", "gyro", {0, 1, 2, 3, 4, 5, 6, 7}, "0 … 7");
  t.gyro.sample_rate_hz = field<double>(g, "sample_rate_hz", "gyro");
  t.gyro.latency_samples = field<int>(g, "latency_samples", "gyro");
  t.gyro.seed = field<std::uint64_t>(g, "seed", "gyro");
}

py::dict paths_state(const rg::RigTruth& t) {
  py::dict p, a;
  p["update_rate_hz"] = t.pulse_train.update_rate_hz;
  p["counts_per_rev"] = t.pulse_train.counts_per_rev;
  p["gear_ratio"] = t.pulse_train.gear_ratio;
  p["max_pulse_frequency_hz"] = t.pulse_train.max_pulse_frequency_hz;
  p["velocity_hold"] = static_cast<int>(t.pulse_train.velocity_hold);
  a["volts_per_unit"] = t.analog_output.volts_per_unit;
  a["resolution_bits"] = t.analog_output.resolution_bits;
  a["full_scale_v"] = t.analog_output.full_scale_v;
  py::dict d;
  d["pulse_train"] = p;
  d["analog_output"] = a;
  return d;
}

void paths_from(const py::dict& d, rg::RigTruth& t) {
  const auto p = field<py::dict>(d, "pulse_train", "paths");
  t.pulse_train.update_rate_hz = field<double>(p, "update_rate_hz", "pulse_train");
  t.pulse_train.counts_per_rev = field<double>(p, "counts_per_rev", "pulse_train");
  t.pulse_train.gear_ratio = field<double>(p, "gear_ratio", "pulse_train");
  t.pulse_train.max_pulse_frequency_hz = field<double>(p, "max_pulse_frequency_hz", "pulse_train");
  t.pulse_train.velocity_hold =
      enum_from<signal::VelocityHold>(p, "velocity_hold", "pulse_train", {0, 1}, "0 (lookahead), 1 (sampled)");
  const auto a = field<py::dict>(d, "analog_output", "paths");
  t.analog_output.volts_per_unit = field<double>(a, "volts_per_unit", "analog_output");
  t.analog_output.resolution_bits = field<int>(a, "resolution_bits", "analog_output");
  t.analog_output.full_scale_v = field<double>(a, "full_scale_v", "analog_output");
}

py::dict solver_state(const pl::SolverOptions& s) {
  py::dict d;
  d["integrator"] = static_cast<int>(s.integrator);
  d["relative_tolerance"] = s.relative_tolerance;
  d["angle_tolerance_rad"] = s.angle_tolerance_rad;
  d["rate_tolerance_rad_s"] = s.rate_tolerance_rad_s;
  d["length_tolerance_m"] = s.length_tolerance_m;
  d["speed_tolerance_m_s"] = s.speed_tolerance_m_s;
  d["max_step_s"] = s.max_step_s;
  d["max_steps_per_output"] = s.max_steps_per_output;
  d["max_total_steps"] = s.max_total_steps;
  d["analytic_jacobian"] = s.analytic_jacobian;
  d["control_energy_error"] = s.control_energy_error;
  d["zeno_events"] = s.zeno_events;
  d["zeno_window_s"] = s.zeno_window_s;
  d["release_gap_fraction"] = s.release_gap_fraction;
  return d;
}

pl::SolverOptions solver_from(const py::dict& d, const std::string& w) {
  pl::SolverOptions s;
  s.integrator = enum_from<pl::Integrator>(d, "integrator", w, {0, 1}, "0 (bdf), 1 (adams)");
  s.relative_tolerance = field<double>(d, "relative_tolerance", w);
  s.angle_tolerance_rad = field<double>(d, "angle_tolerance_rad", w);
  s.rate_tolerance_rad_s = field<double>(d, "rate_tolerance_rad_s", w);
  s.length_tolerance_m = field<double>(d, "length_tolerance_m", w);
  s.speed_tolerance_m_s = field<double>(d, "speed_tolerance_m_s", w);
  s.max_step_s = field<double>(d, "max_step_s", w);
  s.max_steps_per_output = field<long>(d, "max_steps_per_output", w);
  s.max_total_steps = field<long>(d, "max_total_steps", w);
  s.analytic_jacobian = field<bool>(d, "analytic_jacobian", w);
  s.control_energy_error = field<bool>(d, "control_energy_error", w);
  s.zeno_events = field<int>(d, "zeno_events", w);
  s.zeno_window_s = field<double>(d, "zeno_window_s", w);
  s.release_gap_fraction = field<double>(d, "release_gap_fraction", w);
  return s;
}

rg::RunVariation variation_from(const py::dict& d, const std::string& w) {
  rg::RunVariation v;
  v.position_gain_rel_sigma = field<double>(d, "position_gain_rel_sigma", w);
  v.speed_gain_rel_sigma = field<double>(d, "speed_gain_rel_sigma", w);
  v.start_latency_max_s = field<double>(d, "start_latency_max_s", w);
  v.analog_noise_v = field<double>(d, "analog_noise_v", w);
  v.analog_offset_sigma_v = field<double>(d, "analog_offset_sigma_v", w);
  v.flank_damping_rel_sigma = field<double>(d, "flank_damping_rel_sigma", w);
  return v;
}

}  // namespace

py::dict variation_state(const rg::RunVariation& v) {
  py::dict d;
  d["position_gain_rel_sigma"] = v.position_gain_rel_sigma;
  d["speed_gain_rel_sigma"] = v.speed_gain_rel_sigma;
  d["start_latency_max_s"] = v.start_latency_max_s;
  d["analog_noise_v"] = v.analog_noise_v;
  d["analog_offset_sigma_v"] = v.analog_offset_sigma_v;
  d["flank_damping_rel_sigma"] = v.flank_damping_rel_sigma;
  return d;
}

py::dict truth_state(const rg::RigTruth& t) {
  py::dict d;
  d["version"] = kStateVersion;
  d["position_drive"] = drive_state(t.position_drive);
  d["speed_drive"] = drive_state(t.speed_drive);
  d["link"] = link_state(t.link);
  d["clearance_rad"] = t.clearance_rad;
  d["position_contact"] = contact_state(t.position_contact);
  d["speed_contact"] = contact_state(t.speed_contact);
  d["joint_friction"] = friction_state(t.joint_friction);
  d["sensors"] = sensors_state(t);
  d["paths"] = paths_state(t);
  d["solver"] = solver_state(t.solver);
  d["random_initial_play"] = t.random_initial_play;
  d["initial_play_fraction"] = t.initial_play_fraction;
  d["variation"] = variation_state(t.variation);
  return d;
}

rg::RigTruth truth_from_state(const py::dict& d) {
  const int version = field<int>(d, "version", "truth");
  if (version != kStateVersion) throw_invalid("RigTruth state version", version, std::to_string(kStateVersion));
  rg::RigTruth t;
  t.position_drive = drive_from(field<py::dict>(d, "position_drive", "truth"), "position_drive");
  t.speed_drive = drive_from(field<py::dict>(d, "speed_drive", "truth"), "speed_drive");
  t.link = link_from(field<py::dict>(d, "link", "truth"), "link");
  t.clearance_rad = field<double>(d, "clearance_rad", "truth");
  t.position_contact = contact_from(field<py::dict>(d, "position_contact", "truth"), "position_contact");
  t.speed_contact = contact_from(field<py::dict>(d, "speed_contact", "truth"), "speed_contact");
  t.joint_friction = friction_from(field<py::dict>(d, "joint_friction", "truth"), "joint_friction");
  sensors_from(field<py::dict>(d, "sensors", "truth"), t);
  paths_from(field<py::dict>(d, "paths", "truth"), t);
  t.solver = solver_from(field<py::dict>(d, "solver", "truth"), "solver");
  t.random_initial_play = field<bool>(d, "random_initial_play", "truth");
  t.initial_play_fraction = field<double>(d, "initial_play_fraction", "truth");
  t.variation = variation_from(field<py::dict>(d, "variation", "truth"), "variation");
  t.validate();
  return t;
}

}  // namespace clearshape::python
