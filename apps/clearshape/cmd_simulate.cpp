// clearshape simulate: one run of the simulated rig (drive + link with clearance + sensors)
// under a command signal, optionally input-shaped — the thesis's simulation tests (§5.1.1,
// §5.2.1) with the rig's truth chosen explicitly (rig/truth.hpp; flags and a TOML file).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/config.hpp"
#include "clearshape/rig/offline.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/signal.hpp"
#include "command.hpp"
#include "run_json.hpp"
#include "signal_options.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;
namespace rig = clearshape::rig;

namespace {

struct SimulateState {
  std::string mode = "position";
  std::string type = "step";
  cs::cli::SignalOptions signal_options;  // command units: deg (position) or V (speed)

  std::string shaper;
  std::string shaper_impulses;
  CLI::Option* shaper_impulses_option = nullptr;
  double shaper_frequency_hz = 0.0;
  double shaper_zeta = 0.0;
  CLI::Option* shaper_frequency_option = nullptr;
  CLI::Option* shaper_zeta_option = nullptr;

  double clearance_deg = 0.0;
  CLI::Option* clearance_option = nullptr;
  std::string contact;
  double restitution = 0.0;
  CLI::Option* restitution_option = nullptr;
  std::string config;
  std::string rig_name;
  CLI::Option* rig_option = nullptr;
  double duration_s = 0.0;
  CLI::Option* duration_option = nullptr;
  double rate_hz = 0.0;
  CLI::Option* rate_option = nullptr;
  double initial_play = 0.0;
  CLI::Option* initial_play_option = nullptr;
  std::uint64_t noise_seed = 0;
  CLI::Option* noise_seed_option = nullptr;
  bool no_noise = false;
  std::string command_path = "offline";  // offline (known trajectory) or realtime (the rig's loop)
  std::string output;
  bool json = false;
};

nlohmann::ordered_json contact_json(const rig::ContactSpec& c) {
  nlohmann::ordered_json j = {{"model", std::string(rig::to_string(c.model))}};
  switch (c.model) {
    case rig::ContactModel::thesis:
      j["stiffness_n_m_per_rad_pow_n"] = c.stiffness;
      j["exponent"] = c.exponent;
      j["damping_n_m_s_per_rad"] = c.damping;
      j["damping_policy"] = "clamped";
      break;
    case rig::ContactModel::kelvin_voigt:
      j["stiffness_n_m_per_rad"] = c.stiffness;
      j["restitution"] = c.restitution;
      break;
    case rig::ContactModel::impulse:
      j["restitution"] = c.restitution;
      j["static_rate_rad_s"] = c.static_rate_rad_s;
      break;
    default:
      j["stiffness_n_m_per_rad_pow_n"] = c.stiffness;
      j["exponent"] = c.exponent;
      j["restitution"] = c.restitution;
  }
  return j;
}

nlohmann::ordered_json truth_json(const rig::RigTruth& t, rig::CommandMode mode) {
  const auto& drive = t.drive(mode);
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  nlohmann::ordered_json b = nlohmann::ordered_json::array();
  nlohmann::ordered_json c_angle = nlohmann::ordered_json::array();
  nlohmann::ordered_json c_rate = nlohmann::ordered_json::array();
  for (Eigen::Index i = 0; i < drive.a().rows(); ++i) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (Eigen::Index j = 0; j < drive.a().cols(); ++j) row.push_back(drive.a()(i, j));
    a.push_back(row);
    b.push_back(drive.b()(i));
    c_angle.push_back(drive.angle_output()(i));
    c_rate.push_back(drive.rate_output()(i));
  }
  return {
      {"drive", {{"mode", std::string(rig::to_string(mode))},
                 {"dc_gain", cs::rad_to_deg(drive.dc_gain())},
                 {"dc_gain_unit", mode == rig::CommandMode::position ? "deg/deg" : "(deg/s)/V"},
                 {"delay_s", drive.delay_s()},
                 {"order", drive.order()},
                 {"a_matrix_cascade_realization", a},
                 // x' = A x + B u (u in drive units), θ_m = c_angle·x (rad), ω_m = c_rate·x + d_rate·u
                 {"b_vector", b},
                 {"c_angle_rad", c_angle},
                 {"c_rate_rad_s", c_rate},
                 {"d_rate_rad_s", drive.rate_feedthrough()}}},
      {"clearance_deg", cs::rad_to_deg(t.clearance_rad)},
      {"contact", contact_json(t.contact(mode))},
      {"link", {{"inertia_kg_m2", t.link.inertia_kg_m2},
                {"mass_kg", t.link.mass_kg},
                {"com_distance_m", t.link.com_distance_m},
                {"axis_tilt_deg", cs::rad_to_deg(t.link.axis_tilt_rad)},
                {"ground_viscous_n_m_s_per_rad", t.link.ground_viscous_n_m_s_per_rad}}},
      {"joint_friction", {{"viscous_n_m_s_per_rad", t.joint_friction.viscous},
                          {"coulomb_n_m", t.joint_friction.coulomb}}},
      {"encoder", {{"lines_per_revolution", t.encoder.lines_per_revolution},
                   {"decoding", static_cast<int>(t.encoder.decoding)}}},
      {"gyroscope", {{"sensitivity_lsb_per_dps", t.gyro.sensitivity_lsb_per_dps},
                     {"full_scale_dps", t.gyro.full_scale_dps},
                     {"noise_density_dps_per_rthz", t.gyro.noise_density_dps_per_rthz},
                     {"bias_dps", t.gyro.bias_dps},
                     {"low_pass_hz", cs::plant::bandwidth_hz(t.gyro.low_pass)},
                     {"latency_samples", t.gyro.latency_samples}}},
      {"position_path", {{"update_rate_hz", t.pulse_train.update_rate_hz},
                         {"counts_per_rev", t.pulse_train.counts_per_rev},
                         {"gear_ratio", t.pulse_train.gear_ratio},
                         {"max_pulse_frequency_hz", t.pulse_train.max_pulse_frequency_hz}}},
      {"speed_path", {{"volts_per_unit", t.analog_output.volts_per_unit},
                      {"resolution_bits", t.analog_output.resolution_bits},
                      {"full_scale_v", t.analog_output.full_scale_v}}},
      {"solver", {{"integrator", t.solver.integrator == cs::plant::Integrator::bdf ? "bdf" : "adams"},
                  {"relative_tolerance", t.solver.relative_tolerance},
                  {"angle_tolerance_rad", t.solver.angle_tolerance_rad},
                  {"rate_tolerance_rad_s", t.solver.rate_tolerance_rad_s}}},
  };
}

nlohmann::ordered_json md_json(const cs::metrics::MeanDeviationResult& r) {
  return {{"mean_deviation", r.mean_deviation},
          {"steady_mean", r.steady_mean},
          {"start_s", r.start_time_s},
          {"samples", r.samples},
          {"converged", r.converged}};
}

// --- plan: the rig, the run options and the command the flags ask for ---------------------------

struct Plan {
  rig::CommandMode mode = rig::CommandMode::position;
  rig::RigTruth truth;
  rig::RunOptions options;
  rig::ContactSpec contact;  ///< the commanded mode's contact law (also in truth)
};

// The truth starts from the built-in rig (--rig, default the calibrated thesis rig) or a config file.
rig::RigConfig rig_config(const SimulateState& st, rig::CommandMode mode) {
  if (st.rig_option->count() > 0 && !st.config.empty()) {
    throw cs::InvalidArgument("--rig and --config: give one (a config file starts from the thesis rig)");
  }
  rig::RigConfig config = st.config.empty() ? rig::RigConfig{} : rig::load_rig_config(st.config);
  if (st.rig_option->count() > 0) {
    config.truth = rig::builtin_truth(st.rig_name, "--rig");
    config.contact_model = config.truth.contact(mode).model;
  }
  return config;
}

// The config's run options with the flags given over them.
rig::RunOptions run_options(const SimulateState& st, rig::RunOptions options) {
  if (st.duration_option->count() > 0) options.duration_s = st.duration_s;
  if (st.rate_option->count() > 0) options.output_rate_hz = st.rate_hz;
  if (st.initial_play_option->count() > 0) options.initial_play_fraction = st.initial_play;
  if (st.noise_seed_option->count() > 0) options.seed = st.noise_seed;
  if (st.no_noise) options.sensor_noise = false;
  options.realtime_command_path = st.command_path == "realtime";
  return options;
}

// --contact (else the config's law, else the thesis law) with --restitution over it.
rig::ContactSpec contact_of(const SimulateState& st, const rig::RigConfig& config, rig::CommandMode mode) {
  const rig::ContactModel model = !st.contact.empty()
                                      ? rig::contact_model_from_string(st.contact)
                                      : config.contact_model.value_or(rig::ContactModel::thesis);
  rig::ContactSpec contact = rig::resolve_contact(config, model, mode);
  if (st.restitution_option->count() > 0) {
    if (model == rig::ContactModel::thesis) {
      throw cs::InvalidArgument("--restitution does not apply to --contact thesis (it has K and D); "
                                "choose kelvin-voigt, hunt-crossley, lankarani-nikravesh, flores or impulse");
    }
    contact.restitution = st.restitution;
  }
  return contact;
}

// Truth: built-in rig < config file < flags.
Plan plan(const SimulateState& st) {
  Plan p;
  p.mode = rig::command_mode_from_string(st.mode);
  const rig::RigConfig config = rig_config(st, p.mode);
  p.truth = config.truth;
  p.options = run_options(st, config.run);
  if (st.clearance_option->count() > 0) {
    cs::require_non_negative("--clearance-deg", st.clearance_deg, "0 means a rigid joint");
    p.truth.clearance_rad = cs::deg_to_rad(st.clearance_deg);
  }
  p.contact = contact_of(st, config, p.mode);
  (p.mode == rig::CommandMode::position ? p.truth.position_contact : p.truth.speed_contact) = p.contact;
  p.options.validate();
  if (p.options.output_rate_hz * p.options.duration_s > 1e7) {
    cs::throw_invalid("--rate x --duration", p.options.output_rate_hz * p.options.duration_s,
                      "<= 1e7 samples", "Lower the rate or shorten the duration");
  }
  return p;
}

// The shaper of --shaper (a method and the mode to cancel, or `custom` impulses), if any.
std::optional<cs::shaping::Shaper> shaper_of(const SimulateState& st) {
  cs::shaping::DesignRequest request;
  if (st.shaper == "custom") {  // e.g. the impulses of `shape --method clearance-aware`
    if (st.shaper_impulses_option->count() == 0) {
      throw cs::InvalidArgument("--shaper custom needs --shaper-impulses \"t1:a1,t2:a2,...\"");
    }
    request.method = cs::shaping::Method::custom;
    request.impulses = cs::shaping::parse_impulses(st.shaper_impulses);
    return cs::shaping::design(request);
  }
  if (st.shaper_impulses_option->count() > 0) {
    throw cs::InvalidArgument("--shaper-impulses applies to --shaper custom");
  }
  if (st.shaper.empty()) {
    if (st.shaper_frequency_option->count() > 0 || st.shaper_zeta_option->count() > 0) {
      throw cs::InvalidArgument("--shaper-frequency-hz and --shaper-zeta need --shaper METHOD");
    }
    return std::nullopt;
  }
  if (st.shaper_frequency_option->count() == 0 || st.shaper_zeta_option->count() == 0) {
    throw cs::InvalidArgument("--shaper needs --shaper-frequency-hz and --shaper-zeta (the mode to cancel)");
  }
  cs::require_positive("--shaper-frequency-hz", st.shaper_frequency_hz);
  request.method = cs::shaping::method_from_string(st.shaper);
  request.mode = cs::shaping::Mode::from_hz(st.shaper_frequency_hz, st.shaper_zeta);
  return cs::shaping::design(request);
}

// The requested command in deg (position) or V (speed): the signal, shaped offline.
struct Command {
  sig::Signal signal;
  std::optional<cs::shaping::Shaper> shaper;
  cs::UniformSeries values;
};

Command command_of(const SimulateState& st, const rig::RunOptions& options) {
  sig::Signal signal = st.signal_options.build(st.type);
  cs::UniformSeries values = sig::sample(signal, options.output_rate_hz, options.duration_s);
  std::optional<cs::shaping::Shaper> shaper = shaper_of(st);
  if (shaper) values = cs::shaping::shape_offline(*shaper, values, false);
  return {std::move(signal), std::move(shaper), std::move(values)};
}

// The command in rig units: rad (position) or V (speed).
cs::UniformSeries rig_units(const cs::UniformSeries& command, rig::CommandMode mode) {
  cs::UniformSeries out = command;
  if (mode == rig::CommandMode::position) {
    for (double& v : out.values) v = cs::deg_to_rad(v);
  }
  return out;
}

// --- tabulate: the run's columns in deg and its Eq. 5.1 summary ----------------------------------

struct DegreeColumns {
  std::vector<double> requested, motor_deg, motor_deg_s, link_deg, link_deg_s, penetration_deg, encoder_deg,
      gyro_deg_s;
};

DegreeColumns degree_columns(const rig::RunRecord& run, const cs::UniformSeries& command) {
  const auto& s = run.simulation;
  const auto deg = [](const std::vector<double>& v) {
    std::vector<double> out(v.size());
    std::transform(v.begin(), v.end(), out.begin(), [](double x) { return cs::rad_to_deg(x); });
    return out;
  };
  DegreeColumns d;
  d.requested.assign(command.values.begin(), command.values.end());
  d.requested.resize(s.size(), d.requested.empty() ? 0.0 : d.requested.back());
  d.motor_deg = deg(s.motor_angle_rad);
  d.motor_deg_s = deg(s.motor_rate_rad_s);
  d.link_deg = deg(s.link_angle_rad);
  d.link_deg_s = deg(s.link_rate_rad_s);
  d.penetration_deg = deg(s.penetration);
  d.encoder_deg = deg(run.encoder_angle_rad);
  d.gyro_deg_s = deg(run.gyro_rate_rad_s);
  return d;
}

std::vector<std::string> column_names(rig::CommandMode mode) {
  const std::string unit = mode == rig::CommandMode::position ? "deg" : "v";
  return {"time_s",    "command_" + unit,     "drive_command_" + unit, "motor_deg",   "motor_deg_s", "link_deg",
          "link_deg_s", "contact_torque_n_m", "penetration_deg",       "encoder_deg", "gyro_deg_s"};
}

std::vector<const std::vector<double>*> column_data(const rig::RunRecord& run, const DegreeColumns& d) {
  const auto& s = run.simulation;
  return {&s.time_s,     &d.requested,          &run.command_drive,   &d.motor_deg,   &d.motor_deg_s, &d.link_deg,
          &d.link_deg_s, &s.contact_torque_n_m, &d.penetration_deg,   &d.encoder_deg, &d.gyro_deg_s};
}

struct Summary {
  cs::metrics::MeanDeviationResult md_link_rate, md_gyro, md_link_angle;  // Eq. 5.1
  double peak_torque_n_m = 0.0;
  double wall_s = 0.0;
  nlohmann::ordered_json json;
};

Summary summarize(const rig::RunRecord& run, const DegreeColumns& d, double rate_hz, double wall_s) {
  const auto& s = run.simulation;
  const double ts = 1.0 / rate_hz;
  const auto series = [&](const std::vector<double>& v) { return cs::UniformSeries{0.0, ts, v}; };
  Summary out;
  out.md_link_rate = cs::metrics::mean_deviation(series(d.link_deg_s));
  out.md_gyro = cs::metrics::mean_deviation(series(d.gyro_deg_s));
  out.md_link_angle = cs::metrics::mean_deviation(series(d.link_deg));
  out.wall_s = wall_s;
  double max_penetration_deg = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    out.peak_torque_n_m = std::max(out.peak_torque_n_m, std::abs(s.contact_torque_n_m[k]));
    max_penetration_deg = std::max(max_penetration_deg, d.penetration_deg[k]);
  }
  const double duration_s = s.time_s.empty() ? 0.0 : s.time_s.back();
  out.json = {{"samples", s.size()},
              {"duration_s", duration_s},
              {"events", s.stats.events},
              {"mean_deviation_eq_5_1", {{"link_rate_deg_s", md_json(out.md_link_rate)},
                                         {"gyro_deg_s", md_json(out.md_gyro)},
                                         {"link_angle_deg", md_json(out.md_link_angle)}}},
              {"peak_contact_torque_n_m", out.peak_torque_n_m},
              {"max_penetration_deg", max_penetration_deg},
              {"limited_commands", run.limited_commands},
              {"rigid", run.rigid},
              {"wall_time_s", wall_s},
              {"real_time_factor", wall_s > 0.0 ? duration_s / wall_s : 0.0},
              {"solver", {{"steps", s.stats.steps},
                          {"rhs_evaluations", s.stats.rhs_evaluations},
                          {"jacobian_evaluations", s.stats.jacobian_evaluations},
                          {"restarts", s.stats.restarts},
                          {"command_stops", s.stats.command_stops}}}};
  return out;
}

// --- write: the CSV with its sidecar, and stdout ---------------------------------------------------

std::string rig_name(const SimulateState& st) { return st.rig_option->count() > 0 ? st.rig_name : std::string("thesis"); }

nlohmann::ordered_json configuration_json(const SimulateState& st, const Plan& p, const Command& c) {
  return {{"mode", st.mode},
          {"signal", {{"type", st.type}, {"parameters", cs::cli::signal_parameters_json(c.signal)}}},
          {"shaper", c.shaper ? cs::cli::shaper_json(*c.shaper, st.shaper_frequency_hz, st.shaper_zeta)
                              : nlohmann::ordered_json(nullptr)},
          {"builtin_rig", rig_name(st)},
          {"config_file", st.config.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(st.config)},
          {"duration_s", p.options.duration_s},
          {"output_rate_hz", p.options.output_rate_hz},
          {"initial_play_fraction", p.options.initial_play_fraction},
          {"noise_seed", p.options.seed},
          {"sensor_noise", p.options.sensor_noise},
          {"command_path", p.options.realtime_command_path ? "realtime" : "offline"},
          {"rig", truth_json(p.truth, p.mode)}};
}

nlohmann::ordered_json events_json(const std::vector<cs::plant::ContactEvent>& events) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& e : events) {
    out.push_back({{"time_s", e.time_s}, {"kind", std::string(cs::plant::to_string(e.kind))},
                   {"side", e.side}, {"rate_rad_s", e.rate}});
    if (out.size() >= 1000) break;
  }
  return out;
}

// CSV and sidecar appear together or not at all; `-o run.json` (the sidecar's own name) is
// refused by the batch instead of overwriting the CSV with the sidecar.
void write_files(const SimulateState& st, const Plan& p, const Command& c, const rig::RunRecord& run,
                 const DegreeColumns& d, const Summary& summary) {
  const bool position = p.mode == rig::CommandMode::position;
  const std::vector<std::string> names = column_names(p.mode);
  cs::io::AtomicBatch batch;
  batch.add(st.output, cs::io::format_csv(names, column_data(run, d)));
  auto doc = cs::io::make_document();
  doc["command"] = "simulate";
  doc["csv"] = st.output;
  doc["columns"] = names;
  doc["units"] = {{"command", position ? "deg (motor-angle target)" : "V (driver speed input)"},
                  {"drive_command", position ? "deg (after the 30 Hz pulse train)" : "V (after the 12-bit D/A)"},
                  {"angles", "deg"},
                  {"rates", "deg/s"},
                  {"contact_torque", "N·m (on the link)"},
                  {"penetration", "deg (< 0 inside the play)"}};
  doc["configuration"] = configuration_json(st, p, c);
  doc["summary"] = summary.json;
  doc["events_first_1000"] = events_json(run.simulation.events);
  const auto sidecar = cs::cli::sidecar_path(st.output);
  batch.add(sidecar, doc.dump(2) + "\n");
  batch.commit();
  fmt::print(stderr, "clearshape simulate: wrote {} ({} rows) and {}\n", st.output, run.simulation.size(),
             sidecar.string());
}

void print_json(const SimulateState& st, const Plan& p, const Command& c, const Summary& summary) {
  auto doc = cs::io::make_document();
  doc["command"] = "simulate";
  doc["mode"] = st.mode;
  doc["signal"] = st.type;
  doc["shaper"] = c.shaper ? nlohmann::ordered_json(c.shaper->method()) : nlohmann::ordered_json(nullptr);
  doc["rig"] = rig_name(st);
  doc["clearance_deg"] = cs::rad_to_deg(p.truth.clearance_rad);
  doc["contact"] = contact_json(p.contact);
  for (const auto& [k, v] : summary.json.items()) doc[k] = v;
  doc["output"] = st.output.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(st.output);
  cs::cli::print_json(doc);
}

void print_table(const SimulateState& st, const Plan& p, const Command& c, const rig::RunRecord& run, const Summary& sm) {
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"mode", st.mode},
      {"signal", st.type},
      {"shaper", c.shaper ? c.shaper->method() : "none"},
      {"clearance", fmt::format("{} deg ({})", cs::rad_to_deg(p.truth.clearance_rad),
                                run.rigid ? "rigid" : std::string(rig::to_string(p.contact.model)))},
      {"samples", fmt::format("{} ({} Hz)", run.simulation.size(), p.options.output_rate_hz)},
      {"events", fmt::format("{}", run.simulation.stats.events)},
      {"MD link rate", fmt::format("{:.6g} deg/s (Eq. 5.1, from {:.4g} s)", sm.md_link_rate.mean_deviation,
                                   sm.md_link_rate.start_time_s)},
      {"MD gyro", fmt::format("{:.6g} deg/s", sm.md_gyro.mean_deviation)},
      {"MD link angle", fmt::format("{:.6g} deg", sm.md_link_angle.mean_deviation)},
      {"peak contact torque", fmt::format("{:.6g} N·m", sm.peak_torque_n_m)},
      {"wall time", fmt::format("{:.4g} s ({:.0f}x real time)", sm.wall_s,
                                sm.json["real_time_factor"].get<double>())}};
  for (const auto& [k, v] : rows) fmt::print("{:<22}{}\n", k, v);
  if (!st.output.empty()) fmt::print("{:<22}{}\n", "output", st.output);
}

void run(const SimulateState& st) {
  const Plan p = plan(st);
  const Command command = command_of(st, p.options);
  const cs::UniformSeries rig_command = rig_units(command.values, p.mode);

  const auto begin = std::chrono::steady_clock::now();
  const rig::RunRecord run = rig::simulate_run(p.truth, p.mode, rig_command, p.options);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();

  const DegreeColumns d = degree_columns(run, command.values);
  const Summary summary = summarize(run, d, p.options.output_rate_hz, wall_s);
  if (!st.output.empty()) write_files(st, p, command, run, d, summary);
  if (run.limited_commands > 0) {
    fmt::print(stderr, "clearshape simulate: warning: {} command sample(s)/update(s) were limited by the "
                       "command path (D/A range or pulse-rate cap)\n", run.limited_commands);
  }
  if (st.json) {
    print_json(st, p, command, summary);
  } else {
    print_table(st, p, command, run, summary);
  }
}

void setup_simulate(CLI::App& sub) {
  auto st = std::make_shared<SimulateState>();
  sub.add_option("--mode", st->mode, "Drive mode: position (pulse train, deg) or speed (analog, V)")
      ->check(CLI::IsMember({"position", "speed"}))
      ->capture_default_str();
  sub.add_option("--signal", st->type, "Command signal: " + cs::cli::SignalOptions::type_list())
      ->check(cs::cli::SignalOptions::type_check())
      ->capture_default_str();
  st->signal_options.add_to(sub, "--signal");

  sub.add_option("--shaper", st->shaper, "Input shaper method (zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, um-zv, custom)");
  st->shaper_impulses_option = sub.add_option("--shaper-impulses", st->shaper_impulses,
                                              "--shaper custom: impulses \"t1:a1,t2:a2,...\" (t in s; normalised to sum 1)");
  st->shaper_frequency_option =
      sub.add_option("--shaper-frequency-hz", st->shaper_frequency_hz, "Natural frequency of the mode to cancel (Hz)");
  st->shaper_zeta_option = sub.add_option("--shaper-zeta", st->shaper_zeta, "Damping ratio of that mode, [0, 1)");

  st->clearance_option = sub.add_option("--clearance-deg", st->clearance_deg,
                                        "Total play of the joint (deg); 0 = rigid (default: the calibrated rig, 0.032)");
  sub.add_option("--contact", st->contact,
                 "Contact law: thesis|kelvin-voigt|hunt-crossley|lankarani-nikravesh|flores|impulse")
      ->check(CLI::IsMember({"thesis", "kelvin-voigt", "hunt-crossley", "lankarani-nikravesh", "flores", "impulse"}));
  st->restitution_option = sub.add_option("--restitution", st->restitution,
                                          "Coefficient of restitution e (not for the thesis law)");
  st->rig_option = sub.add_option("--rig", st->rig_name,
                                  "Built-in rig truth: thesis (calibrated, default), large-play (1 deg steel pin, "
                                  "docs/large-play.md) or worn-coupling (1 deg play on the soft flank, bearing "
                                  "friction, docs/worn-coupling.md); flags override it")
                       ->check(CLI::IsMember(std::vector<std::string>(rig::kBuiltinTruthNames.begin(),
                                                                      rig::kBuiltinTruthNames.end())));
  sub.add_option("--config", st->config, "Rig configuration (TOML); flags override it");
  st->duration_option = sub.add_option("--duration", st->duration_s, "Duration (s), default 5");
  st->rate_option = sub.add_option("--rate", st->rate_hz, "Output sample rate (Hz), default 1000");
  st->initial_play_option = sub.add_option("--initial-play", st->initial_play,
                                           "Initial link position in the play, phi(0)/beta in [-1, 1]; default 0");
  st->noise_seed_option = sub.add_option("--noise-seed", st->noise_seed, "Seed of the gyroscope noise (default 1)");
  sub.add_flag("--no-noise", st->no_noise, "Noise-free gyroscope (quantization kept)");
  sub.add_option("--command-path", st->command_path,
                 "Position mode: offline (the trajectory known beforehand, each 30 Hz update aims one period ahead; "
                 "default) or realtime (the rig's loop: the command at the tick of each update, reached by the next; "
                 "as the study's rig and the firmware)")
      ->check(CLI::IsMember({"offline", "realtime"}))
      ->capture_default_str();
  sub.add_option("--output,-o", st->output, "CSV of the run; a JSON sidecar (same name, .json) holds the configuration");
  sub.add_flag("--json", st->json, "Print a JSON summary on stdout");
  sub.footer(
      "Examples:\n"
      "  clearshape simulate --mode position --signal step --amplitude 20 -o step.csv\n"
      "  clearshape simulate --mode speed --signal step --amplitude 1 --shaper zvdd \\\n"
      "      --shaper-frequency-hz 3.32 --shaper-zeta 0.288 -o zvdd.csv --json");
  sub.callback([st] { run(*st); });
}

const bool simulate_registered = cs::cli::register_command(
    {"simulate", "Simulate the rig (drive + joint with clearance + sensors) under a command", 40, setup_simulate});

}  // namespace
