// The mode map from recorded runs: the manifest, the runs' windows, the simulated runs written
// as recordings (arm/mode_recordings.hpp; docs/arm.md §7, "From recorded runs").
#include "clearshape/arm/mode_recordings.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/toml_section.hpp"

namespace clearshape::arm {
namespace {

using io::TomlSection;

std::string joint_list(const ArmModel& arm) {
  std::string out;
  for (const ArmJoint& j : arm.joints) out += (out.empty() ? "" : ", ") + j.name;
  return out;
}

std::vector<std::string> default_link_rate_columns(const ArmModel& arm) {
  std::vector<std::string> names;
  for (const ArmJoint& j : arm.joints) names.push_back(j.name + "_link_rate_rad_s");
  return names;
}

ModeRecordingColumns read_recording_columns(const TomlSection& top, const ArmModel& arm) {
  ModeRecordingColumns c;
  c.link_rates = default_link_rate_columns(arm);
  const auto t = top.table("columns");
  if (!t) return c;
  c.time = t->text("time", c.time);
  if (t->has("link_rates")) c.link_rates = t->texts("link_rates");
  if (c.link_rates.size() != static_cast<std::size_t>(arm.dof())) {
    t->fail("link_rates", fmt::format("has {} names; allowed: one per joint ({}: {})", c.link_rates.size(),
                                      arm.dof(), joint_list(arm)));
  }
  if (t->has("gyro")) c.gyro = t->texts("gyro");
  if (c.gyro.size() != 3 || std::all_of(c.gyro.begin(), c.gyro.end(), [](const std::string& n) { return n.empty(); })) {
    t->fail("gyro", fmt::format("has {} names; allowed: 3, for the x, y, z axes of the last link's gyro (\"\": an axis "
                                "not read), at least one not empty", c.gyro.size()));
  }
  const std::string unit = t->text("rate_unit", "rad/s");
  if (unit != "rad/s" && unit != "deg/s") t->fail("rate_unit", fmt::format("is '{}'; allowed: rad/s, deg/s", unit));
  c.rate_scale = unit == "rad/s" ? 1.0 : std::numbers::pi / 180.0;
  t->finish("time, link_rates, gyro, rate_unit");
  return c;
}

/// pose_rad: one finite angle per joint, within each limited joint's URDF range.
Eigen::VectorXd read_pose(const TomlSection& run, const ArmModel& arm) {
  const std::vector<double> q = run.numbers("pose_rad");
  if (q.size() != static_cast<std::size_t>(arm.dof())) {
    run.fail("pose_rad", fmt::format("has {} angles; allowed: {} (one per joint: {}; rad)", q.size(), arm.dof(),
                                     joint_list(arm)));
  }
  for (std::size_t i = 0; i < q.size(); ++i) {
    const ChainJoint& j = arm.chain.joints()[i];
    if (j.limited && (q[i] < j.lower_rad || q[i] > j.upper_rad)) {
      run.fail("pose_rad", fmt::format("{} = {} rad is outside the joint's range; allowed: [{}, {}] rad (the URDF's "
                                       "limits)", arm.joints[i].name, q[i], j.lower_rad, j.upper_rad));
    }
  }
  return Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size()));
}

int read_stepped_joint(const TomlSection& run, const ArmModel& arm) {
  const std::string name = run.text("joint");
  for (int i = 0; i < arm.dof(); ++i) {
    if (arm.joints[static_cast<std::size_t>(i)].name == name) return i;
  }
  run.fail("joint", fmt::format("'{}' is not a joint of {}; allowed: {}", name, arm.name, joint_list(arm)));
}

RecordedRun read_run(const TomlSection& run, const ArmModel& arm, const std::filesystem::path& folder) {
  RecordedRun r;
  r.manifest_line = run.line();
  const std::filesystem::path rel = run.text("file");
  r.file = rel.is_absolute() ? rel : folder / rel;
  if (const std::string problem = io::regular_file_problem(r.file); !problem.empty()) {
    run.fail("file", fmt::format("'{}' {}", r.file.string(), problem));
  }
  r.pose_rad = read_pose(run, arm);
  const std::string excitation = run.text("excitation");
  if (excitation != "loaded-ramp" && excitation != "step") {
    run.fail("excitation", fmt::format("is '{}'; allowed: loaded-ramp, step (with joint = the stepped joint)", excitation));
  }
  r.excitation = excitation == "step" ? ModeMapExcitation::step : ModeMapExcitation::loaded_ramp;
  if (r.excitation == ModeMapExcitation::step) r.joint = read_stepped_joint(run, arm);
  if (r.excitation == ModeMapExcitation::loaded_ramp && run.has("joint")) {
    run.fail("joint", "a loaded ramp moves every joint; allowed only with excitation = \"step\"");
  }
  if (run.has("window_start_s")) {
    r.window_start_s = run.number("window_start_s");
    if (r.window_start_s < 0.0) run.fail("window_start_s", fmt::format("= {} is out of range; allowed: >= 0 (s)", r.window_start_s));
  }
  if (run.has("window_s")) r.window_s = run.positive("window_s", 1.0);
  run.finish("file, pose_rad, excitation, joint, window_start_s, window_s");
  io::note_input(r.file);  // a recording is never overwritten by this job's outputs
  return r;
}

const std::vector<double>& recorded_column(const io::Table& t, const std::string& name, const char* key) {
  if (const auto i = t.find(name)) return t.columns[*i];
  std::string available;
  for (const std::string& n : t.names) available += (available.empty() ? "" : ", ") + n;
  throw InputError(t.source, 1, name, fmt::format("no such column (the manifest's [columns] {}); available: {}", key, available));
}

/// The samples [k0, k1) of the run's window: from the first at or after window_start_s (the
/// simulated path's rule), window_s long or to the file's end.
std::pair<std::size_t, std::size_t> window_rows(const RecordedRun& run, const std::vector<double>& time, double dt) {
  const double start_s = run.window_start_s < 0.0 ? time.front() : run.window_start_s;
  const auto k0 = static_cast<std::size_t>(std::lower_bound(time.begin(), time.end(), start_s - 1e-12) - time.begin());
  if (run.window_s <= 0.0 || k0 >= time.size()) return {k0, time.size()};
  const double end_s = time[k0] + run.window_s + 1e-6 * dt;
  return {k0, static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), end_s) - time.begin())};
}

std::string run_name(const ArmModel& arm, ModeMapExcitation excitation, int joint) {
  return excitation == ModeMapExcitation::loaded_ramp ? "loaded ramp"
                                                      : "step of " + arm.joints[static_cast<std::size_t>(joint)].name;
}

std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

std::string file_safe(const std::string& s) {
  std::string out = s;
  for (char& c : out) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) c = '_';
  }
  return out;
}

/// time_s, every <joint>_link_rate_rad_s, gyro_x|y|z_rad_s of a simulated trace.
std::string trace_csv(const ArmModel& arm, const ArmTrace& trace) {
  std::vector<std::string> names{"time_s"};
  std::vector<std::vector<double>> columns{trace.time_s};
  const auto add = [&](std::string name, const Eigen::VectorXd& v) {
    names.push_back(std::move(name));
    columns.emplace_back(v.data(), v.data() + v.size());
  };
  const std::vector<std::string> link = default_link_rate_columns(arm);
  for (int i = 0; i < arm.dof(); ++i) add(link[static_cast<std::size_t>(i)], trace.link_rate_rad_s.col(i));
  const ModeRecordingColumns defaults;
  for (int c = 0; c < 3; ++c) add(defaults.gyro[static_cast<std::size_t>(c)], trace.gyro_rad_s.col(c));
  std::vector<const std::vector<double>*> pointers;
  for (const auto& c : columns) pointers.push_back(&c);
  return io::format_csv(names, pointers);
}

std::string manifest_run(const std::string& file, const Eigen::VectorXd& pose, const SimulatedRun& run,
                         const ArmModel& arm) {
  std::string q;
  for (Eigen::Index i = 0; i < pose.size(); ++i) q += fmt::format("{}{}", i ? ", " : "", pose(i));
  std::string out = fmt::format("\n[[run]]\nfile = {}\npose_rad = [{}]\n", toml_string(file), q);
  if (run.excitation == ModeMapExcitation::loaded_ramp) return out + fmt::format("excitation = \"loaded-ramp\"\nwindow_start_s = {}\n", run.window_start_s);
  return out + fmt::format("excitation = \"step\"\njoint = {}\nwindow_start_s = {}\n",
                           toml_string(arm.joints[static_cast<std::size_t>(run.joint)].name), run.window_start_s);
}

}  // namespace

ModeRecordings read_mode_recordings(const std::filesystem::path& manifest, const ArmModel& arm) {
  const std::string file = manifest.string();
  if (const std::string problem = io::regular_file_problem(manifest); !problem.empty()) {
    throw InputError(file, 0, "", fmt::format("cannot read the arm recordings manifest: it {}; write a template with "
                                              "`clearshape arm modes --identify --write-recordings DIR`", problem));
  }
  const toml::table root = io::parse_toml(io::read_text_file(manifest), file);
  const TomlSection top(root, "", file);
  const std::string format = top.text("format");
  if (format != kModeRecordingsFormat) {
    top.fail("format", fmt::format("is '{}'; allowed: '{}'", format, kModeRecordingsFormat));
  }
  if (top.has("arm") && top.text("arm") != arm.name) {
    top.fail("arm", fmt::format("is '{}'; allowed: '{}', the arm the map is identified for", top.text("arm"), arm.name));
  }
  ModeRecordings r{manifest, top.text("description", ""), read_recording_columns(top, arm), {}};
  for (const TomlSection& run : top.tables("run")) r.runs.push_back(read_run(run, arm, manifest.parent_path()));
  if (r.runs.empty()) top.fail("run", "no [[run]]; allowed: one or more (file, pose_rad, excitation)");
  top.finish("format, arm, description, columns, run");
  return r;
}

RunRecord read_recorded_run(const RecordedRun& run, const ModeRecordingColumns& columns, const ArmModel& arm,
                            ModeMapSensor sensor) {
  const io::Table t = io::read_table(run.file);
  const std::vector<double>& time = recorded_column(t, columns.time, "time");
  const double dt = io::uniform_sample_time(t, columns.time);  // InputError at the first irregular line
  const auto [k0, k1] = window_rows(run, time, dt);
  const std::size_t n = k1 > k0 ? k1 - k0 : 0;
  if (n < 50) {
    throw InputError(t.source, 0, columns.time,
                     fmt::format("the window from {} s holds {} samples (the file spans {} to {} s); allowed: at least "
                                 "50 (the identification needs them)",
                                 run.window_start_s < 0.0 ? time.front() : run.window_start_s, n, time.front(), time.back()));
  }
  const bool gyro = sensor == ModeMapSensor::last_link_gyro;
  const std::vector<std::string>& names = gyro ? columns.gyro : columns.link_rates;
  Eigen::MatrixXd rates(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(names.size()));
  rates.setZero();
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (names[c].empty()) continue;  // a gyro axis not read: zeros, which mode_map_from_runs skips
    const std::vector<double>& v = recorded_column(t, names[c], gyro ? "gyro" : "link_rates");
    for (std::size_t k = 0; k < n; ++k) {
      rates(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = columns.rate_scale * v[k0 + k];
    }
  }
  RunRecord r{run_name(arm, run.excitation, run.joint), time[k0], dt, {}, {}};
  (gyro ? r.gyro_rad_s : r.link_rate_rad_s) = std::move(rates);
  return r;
}

ModeMap mode_map_from_recordings(const ArmModel& arm, const ModeRecordings& recordings, const ModeMapOptions& options) {
  options.validate(arm.dof());
  std::vector<PoseRuns> poses;
  for (const RecordedRun& run : recordings.runs) {
    auto same = std::find_if(poses.begin(), poses.end(), [&](const PoseRuns& p) {
      return (p.pose_rad - run.pose_rad).cwiseAbs().maxCoeff() <= 1e-9;
    });
    if (same == poses.end()) same = poses.insert(poses.end(), PoseRuns{run.pose_rad, {}, {}});
    same->runs.push_back(read_recorded_run(run, recordings.columns, arm, options.sensor));
  }
  return mode_map_from_runs(arm, poses, options);
}

std::filesystem::path write_mode_recordings(const std::filesystem::path& folder, const ArmModel& arm,
                                            const std::vector<SimulatedPose>& simulated) {
  std::string manifest = fmt::format(
      "# Runs for `clearshape arm modes --recordings` (docs/arm.md §7, \"From recorded runs\"), written by\n"
      "# clearshape from simulated runs: record the same excitation at these poses on your arm.\n"
      "format = \"{}\"\narm = {}\n",
      kModeRecordingsFormat, toml_string(arm.name));
  io::AtomicBatch batch;
  for (std::size_t p = 0; p < simulated.size(); ++p) {
    for (const SimulatedRun& run : simulated[p].runs) {
      const std::string kind = run.excitation == ModeMapExcitation::loaded_ramp
                                   ? "loaded-ramp"
                                   : "step-" + file_safe(arm.joints[static_cast<std::size_t>(run.joint)].name);
      const std::string file = fmt::format("pose{:02}-{}.csv", p + 1, kind);
      batch.add(folder / file, trace_csv(arm, run.trace));
      manifest += manifest_run(file, simulated[p].pose_rad, run, arm);
    }
  }
  batch.add(folder / "manifest.toml", manifest);
  batch.commit();
  return folder / "manifest.toml";
}

}  // namespace clearshape::arm
