// clearshape arm modes: the arm's linearised modes at a pose (arm/modes.hpp), or with --identify
// the mode map identified from simulated step runs on a grid of poses beside them
// (arm/mode_map.hpp; --write-recordings DIR writes those runs as recordings), or with
// --recordings MANIFEST the map from recorded runs (arm/mode_recordings.hpp). A table on stdout;
// -o writes CSV or JSON.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "arm_options.hpp"
#include "clearshape/arm/mode_map.hpp"
#include "clearshape/arm/mode_recordings.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "command.hpp"

namespace clearshape::cli {
namespace {

struct ModesState {
  ArmSource source;
  std::string pose, out, recordings, write_recordings;
  bool identify = false;
  int grid = 3;
  double step_deg = 1.0;
  double max_damping = 0.05;
  std::string excitation = "step";
  std::string sensor = "links";
  double ramp_velocity = 0.02;
  bool json = false;
};

/// One row of the output: a mode at a pose (identified columns NaN for the linearised modes).
struct ModeRow {
  Eigen::VectorXd pose;
  int mode = 0;
  double f_hz = NAN, f_std_hz = NAN, zeta = NAN, zeta_std = NAN;
  int runs = 0;
  double linear_f_hz = NAN, linear_zeta = NAN, relative_error = NAN;
  int harmonic = 0;
};

std::vector<ModeRow> linear_rows(const arm::ArmModes& m) {
  std::vector<ModeRow> rows;
  for (Eigen::Index k = 0; k < m.natural_frequency_rad_s.size(); ++k) {
    ModeRow r{m.pose_rad, static_cast<int>(k)};
    r.linear_f_hz = m.natural_frequency_rad_s(k) / (2 * M_PI);
    r.linear_zeta = m.damping_ratio(k);
    rows.push_back(r);
  }
  return rows;
}

std::vector<ModeRow> map_rows(const arm::ModeMap& map) {
  std::vector<ModeRow> rows;
  for (const auto& p : map.points) {
    for (const auto& m : p.modes) {
      rows.push_back({p.pose_rad, m.linear_mode, m.natural_frequency_hz, m.natural_frequency_std_hz, m.damping_ratio,
                      m.damping_ratio_std, m.runs, m.linear_frequency_hz, m.linear_damping_ratio,
                      m.relative_frequency_error, m.harmonic});
    }
    for (const auto& f : p.failures) fmt::print(stderr, "clearshape arm modes: at {} rad: {}\n", format_angles(p.pose_rad), f);
  }
  return rows;
}

/// The runs without a lightly damped mode, per pose (JSON).
nlohmann::ordered_json map_failures(const arm::ModeMap& map) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& p : map.points) {
    for (const auto& f : p.failures) {
      out.push_back({{"pose_rad", std::vector<double>(p.pose_rad.data(), p.pose_rad.data() + p.pose_rad.size())},
                     {"run", f}});
    }
  }
  return out;
}

std::vector<std::string> column_names(const arm::ArmModel& model) {
  std::vector<std::string> names;
  for (const auto& j : model.joints) names.push_back(j.name + "_rad");
  for (const char* n : {"linear_mode", "frequency_hz", "frequency_std_hz", "damping_ratio", "damping_ratio_std", "runs",
                        "linear_frequency_hz", "linear_damping_ratio", "relative_frequency_error", "harmonic"}) {
    names.emplace_back(n);
  }
  return names;
}

std::vector<std::vector<double>> columns(const std::vector<ModeRow>& rows, int dof) {
  std::vector<std::vector<double>> c(static_cast<std::size_t>(dof) + 10);
  for (const ModeRow& r : rows) {
    for (int i = 0; i < dof; ++i) c[static_cast<std::size_t>(i)].push_back(r.pose(i));
    const double values[] = {static_cast<double>(r.mode), r.f_hz, r.f_std_hz, r.zeta, r.zeta_std,
                             static_cast<double>(r.runs), r.linear_f_hz, r.linear_zeta, r.relative_error,
                             static_cast<double>(r.harmonic)};
    for (std::size_t k = 0; k < 10; ++k) c[static_cast<std::size_t>(dof) + k].push_back(values[k]);
  }
  return c;
}

nlohmann::ordered_json to_json(const arm::ArmModel& model, const std::vector<ModeRow>& rows, const std::string& source,
                               const nlohmann::ordered_json* failures) {
  const bool identified = failures != nullptr;
  nlohmann::ordered_json doc = io::make_document();
  doc["arm"] = model.name;
  doc["source"] = source;
  const auto names = column_names(model);
  const auto c = columns(rows, model.dof());
  doc["modes"] = nlohmann::ordered_json::array();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    nlohmann::ordered_json row;
    for (std::size_t k = 0; k < names.size(); ++k) {
      const bool count = names[k] == "linear_mode" || names[k] == "runs" || names[k] == "harmonic";
      if (count && (identified || names[k] == "linear_mode")) row[names[k]] = static_cast<int>(c[k][r]);
      if (!count && std::isfinite(c[k][r])) row[names[k]] = c[k][r];
    }
    doc["modes"].push_back(row);
  }
  if (failures != nullptr) doc["failures"] = *failures;
  return doc;
}

void print_table(const std::vector<ModeRow>& rows, bool identified) {
  fmt::print("{}", identified ? "pose_rad                   mode  identified_hz (1σ)     zeta (1σ)            linear_hz  "
                          "linear_zeta  error_%  note\n"
                        : "pose_rad                   mode  frequency_hz  damping_ratio\n");
  for (const ModeRow& r : rows) {
    if (identified) {
      fmt::print("{:<26} {:>4}  {:>9.3f} ({:.3f})  {:.5f} ({:.5f})  {:>9.3f}  {:.5f}  {:>+7.3f}  {}\n",
                 format_angles(r.pose), r.mode, r.f_hz, r.f_std_hz, r.zeta, r.zeta_std, r.linear_f_hz, r.linear_zeta,
                 100 * r.relative_error, r.harmonic == 0 ? "" : fmt::format("harmonic {} of a lower mode", r.harmonic));
    } else {
      fmt::print("{:<26} {:>4}  {:>12.3f}  {:.3g}\n", format_angles(r.pose), r.mode, r.linear_f_hz, r.linear_zeta);
    }
  }
}

arm::ModeMapOptions map_options(const ModesState& st) {
  arm::ModeMapOptions o;
  o.step_deg = st.step_deg;
  o.identification.max_damping_ratio = st.max_damping;
  o.excitation = st.excitation == "step" ? arm::ModeMapExcitation::step : arm::ModeMapExcitation::loaded_ramp;
  o.sensor = st.sensor == "gyro" ? arm::ModeMapSensor::last_link_gyro : arm::ModeMapSensor::link_rates;
  o.ramp_velocity_rad_s = st.ramp_velocity;
  return o;
}

/// The map from --recordings, or simulated on --grid (written as recordings with --write-recordings).
arm::ModeMap identified_map(const arm::ArmModel& model, const ModesState& st, std::string& source) {
  const arm::ModeMapOptions o = map_options(st);
  if (!st.recordings.empty()) {
    source = "identified from the recorded runs of " + st.recordings + " (arm::mode_map_from_recordings)";
    return arm::mode_map_from_recordings(model, arm::read_mode_recordings(st.recordings, model), o);
  }
  source = "identified from simulated " + st.excitation + " runs (arm::identify_mode_map)";
  const auto simulated = arm::simulate_mode_runs(model, arm::pose_grid(model, st.grid), o);
  if (!st.write_recordings.empty()) {
    const auto manifest = arm::write_mode_recordings(st.write_recordings, model, simulated);
    fmt::print(stderr, "clearshape arm modes: wrote the runs as recordings, {}\n", manifest.string());
  }
  return arm::mode_map_from_runs(model, arm::simulated_windows(simulated), o);
}

void run_modes(const ModesState& st) {
  const arm::ArmModel model = load_arm(st.source);
  if (st.identify && !st.pose.empty()) throw InvalidArgument("--pose and --identify: give one (--identify uses --grid)");
  const bool identified = st.identify || !st.recordings.empty();
  std::vector<ModeRow> rows;
  std::optional<nlohmann::ordered_json> failures;
  std::string source = "linearised (arm::joint_modes)";
  if (identified) {
    const arm::ModeMap map = identified_map(model, st, source);
    rows = map_rows(map);
    failures = map_failures(map);
  } else {
    const Eigen::VectorXd q = st.pose.empty() ? arm::workspace_centre(model) : parse_angles(st.pose, "--pose", model);
    rows = linear_rows(arm::joint_modes(model, q));
  }
  const std::string kind = st.out.empty() ? "" : output_kind(st.out);
  if (st.json) {
    print_json(to_json(model, rows, source, failures ? &*failures : nullptr));
  } else {
    print_table(rows, identified);
  }
  if (kind == ".json") io::write_json(st.out, to_json(model, rows, source, failures ? &*failures : nullptr));
  if (kind == ".csv") {
    const auto c = columns(rows, model.dof());
    std::vector<const std::vector<double>*> pointers;
    for (const auto& col : c) pointers.push_back(&col);
    io::write_csv(st.out, column_names(model), pointers);
  }
}

}  // namespace

void setup_arm_modes(CLI::App& parent) {
  auto st = std::make_shared<ModesState>();
  CLI::App* sub = add_arm_subcommand(
      parent, "modes", "The arm's modes at a pose, linearised on closed plays; --identify: identified from simulated "
               "runs on a grid of poses, --recordings: from recorded runs, beside the linearised ones (docs/arm.md §7)",
      st->source);
  CLI::Option* pose = sub->add_option("--pose", st->pose, "One angle per joint, comma-separated (rad); default the workspace centre");
  CLI::Option* identify = sub->add_flag("--identify", st->identify, "Identify the modes from simulated runs at every pose of --grid");
  CLI::Option* grid = sub->add_option("--grid", st->grid, "Poses per joint of the identification grid (1-10; cell centres of the ranges)")
      ->check(CLI::Range(1, 10))->capture_default_str();
  CLI::Option* step = sub->add_option("--step-deg", st->step_deg, "Each identification run's step of one joint at the link (deg, 0.01-30)")
      ->check(CLI::Range(0.01, 30.0))->capture_default_str();
  sub->add_option("--sensor", st->sensor,
                  "--identify or --recordings from: links (every link's rate) or gyro (the last link's 3-axis "
                  "gyroscope alone)")
      ->check(CLI::IsMember({"links", "gyro"}))
      ->capture_default_str();
  CLI::Option* excitation = sub->add_option("--excitation", st->excitation,
                  "step: a step of each joint in turn; loaded-ramp: all joints ramp slowly, friction keeps "
                  "every link on a flank (for arms with play)")
      ->check(CLI::IsMember({"step", "loaded-ramp"}))
      ->capture_default_str();
  CLI::Option* ramp = sub->add_option("--ramp-velocity", st->ramp_velocity, "loaded-ramp: every joint's rate (rad/s, 1e-3-1)")
      ->check(CLI::Range(1e-3, 1.0))->capture_default_str();
  sub->add_option("--write-recordings", st->write_recordings,
                  "--identify: also write the simulated runs as recordings (CSV per run + manifest.toml) into this "
                  "folder: the template for --recordings")
      ->needs(identify);
  sub->add_option("--recordings", st->recordings,
                  "Identify the map from recorded runs listed in this manifest (TOML; docs/arm.md §7, \"From recorded "
                  "runs\")")
      ->excludes(pose)->excludes(identify)->excludes(grid)->excludes(step)->excludes(excitation)->excludes(ramp);
  sub->add_option("--max-damping", st->max_damping, "Report identified modes with damping ratio below this (0.001-1)")
      ->check(CLI::Range(0.001, 1.0))->capture_default_str();
  sub->add_flag("--json", st->json, "Print JSON instead of the table");
  sub->add_option("-o,--out", st->out, "Also write the rows: a .csv or .json file");
  sub->callback([st] { run_modes(*st); });
}

}  // namespace clearshape::cli
