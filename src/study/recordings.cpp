// A study on recorded runs: the manifest, the conversion of a recording to a run's records and
// the recordings-backed run source (study/recordings.hpp, docs/recordings.md).
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/study/recordings.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/io/time_column.hpp"
#include "recording_checks.hpp"
#include "toml_reader.hpp"

namespace clearshape::study {

namespace {

using detail::TomlSection;

constexpr const char* kColumnKeys =
    "time, time_unit, command, command_unit, command_applied, motor_angle, motor_angle_unit, counts_per_rev, "
    "link_rate, link_rate_unit, lsb_per_deg_s, gyro_full_scale_deg_s";

std::string fnv_hex(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64
  for (const unsigned char c : text) h = (h ^ c) * 0x100000001b3ULL;
  return fmt::format("{:016x}", h);
}

RecordingColumns default_columns(const Protocol& p) {
  const auto names = record_columns(p.mode);
  RecordingColumns c;
  c.command = names[1];
  c.command_unit = p.mode == rig::CommandMode::position ? "deg" : "V";
  return c;
}

std::string one_of(const TomlSection& t, std::string_view key, std::string fallback,
                   std::initializer_list<std::string_view> allowed) {
  const std::string v = t.text(key, std::move(fallback));
  for (const auto a : allowed) {
    if (v == a) return v;
  }
  std::string list;
  for (const auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  t.fail(key, fmt::format("'{}' is not a unit here; allowed: {}", v, list));
}

// The keys of [columns] (or a [[run]]'s overrides) on top of `base`.
RecordingColumns read_columns(const TomlSection& t, RecordingColumns c, rig::CommandMode mode) {
  c.time = t.text("time", c.time);
  c.time_unit = one_of(t, "time_unit", c.time_unit, {"s", "ms"});
  c.command = t.text("command", c.command);
  c.command_unit = mode == rig::CommandMode::position ? one_of(t, "command_unit", c.command_unit, {"deg", "rad"})
                                                      : one_of(t, "command_unit", c.command_unit, {"V"});
  c.command_applied = t.text("command_applied", c.command_applied);
  c.motor_angle = t.text("motor_angle", c.motor_angle);
  c.motor_angle_unit = one_of(t, "motor_angle_unit", c.motor_angle_unit, {"deg", "rad", "counts"});
  c.counts_per_rev = t.positive("counts_per_rev", c.counts_per_rev);
  c.link_rate = t.text("link_rate", c.link_rate);
  c.link_rate_unit = one_of(t, "link_rate_unit", c.link_rate_unit, {"deg/s", "rad/s", "lsb"});
  c.lsb_per_deg_s = t.positive("lsb_per_deg_s", c.lsb_per_deg_s);
  c.gyro_full_scale_deg_s = t.positive("gyro_full_scale_deg_s", c.gyro_full_scale_deg_s);
  return c;
}

std::vector<double> to_command_units(std::vector<double> v, const std::string& unit) {
  if (unit == "rad") {
    for (auto& x : v) x = rad_to_deg(x);
  }
  return v;
}

class RecordingsRunSource final : public RunSource {
 public:
  RecordingsRunSource(RecordingsManifest m, const Protocol& p) : m_(std::move(m)), p_(p) {}
  std::string kind() const override { return "recordings"; }
  std::string description() const override {
    return fmt::format("recordings {} (manifest {}){}", m_.dir.string(), m_.hash,
                       m_.description.empty() ? "" : ": " + m_.description);
  }
  int parallel_runs() const override { return 64; }
  bool reuse_finished_runs() const override { return false; }
  bool has(const PlannedRun& run) const override { return m_.runs.count(run.id) > 0; }
  ObtainedRun obtain(const RunRequest& request) const override {
    const auto it = m_.runs.find(request.id);
    if (it == m_.runs.end()) {
      throw RuntimeError(fmt::format("run {} is not in the recordings manifest {}", request.id, m_.path.string()));
    }
    ObtainedRun out{read_recording(it->second, p_, request.record_s), {}};
    out.counters = {{"source", "recording"}, {"file", it->second.file.string()}};
    return out;
  }

 private:
  RecordingsManifest m_;
  Protocol p_;
};

}  // namespace

RecordingsManifest load_recordings_manifest(const std::filesystem::path& dir, const Protocol& protocol) {
  RecordingsManifest m;
  m.dir = dir;
  m.path = dir / "manifest.toml";
  const std::string file = m.path.string();
  if (const std::string problem = io::regular_file_problem(m.path); !problem.empty()) {
    throw InputError(file, 0, "", fmt::format("cannot read the recordings manifest: it {}; write one with "
                                              "`clearshape study PROTOCOL --print-manifest > DIR/manifest.toml`",
                                              problem));
  }
  const std::string text = io::read_text_file(m.path);
  m.hash = fnv_hex(text);
  const toml::table root = detail::parse_toml(text, file);
  const TomlSection top(root, "", file);
  const std::string format = top.text("format");
  if (format != kRecordingsFormat) {
    top.fail("format", fmt::format("is '{}'; this clearshape reads '{}'", format, kRecordingsFormat));
  }
  m.description = top.text("description", "");
  RecordingColumns base = default_columns(protocol);
  if (const auto cols = top.table("columns")) {
    base = read_columns(*cols, base, protocol.mode);
    cols->finish(kColumnKeys);
  }
  std::map<std::string, PlannedRun> expected;
  for (const auto& r : distinct_runs(protocol)) expected.emplace(r.id, r);
  for (const auto& run : top.tables("run")) {
    RecordingEntry e;
    e.id = run.text("id");
    e.manifest_line = run.line();
    if (!expected.count(e.id)) {
      run.fail("id", fmt::format("'{}' is not a run of protocol '{}' (`clearshape study PROTOCOL "
                                 "--print-manifest` lists them)", e.id, protocol.name));
    }
    if (m.runs.count(e.id)) run.fail("id", fmt::format("run '{}' is listed twice", e.id));
    const std::string rel = run.text("file");
    e.file = std::filesystem::path(rel).is_absolute() ? std::filesystem::path(rel) : dir / rel;
    if (const std::string problem = io::regular_file_problem(e.file); !problem.empty()) {
      run.fail("file", fmt::format("'{}' {}", e.file.string(), problem));
    }
    // One recording is one run: the same file under two ids would count one trial twice.
    for (const auto& [other_id, other] : m.runs) {
      std::error_code ec;
      if (std::filesystem::equivalent(other.file, e.file, ec)) {
        run.fail("file", fmt::format("'{}' is already the recording of run '{}' (manifest line {}); each run needs "
                                     "its own recording", e.file.string(), other_id, other.manifest_line));
      }
    }
    // The recording and its sidecar are inputs: no output of this job (`--fresh` included) touches them.
    io::note_input(e.file);
    std::filesystem::path sidecar = e.file;
    sidecar.replace_extension(".json");
    if (sidecar != e.file) io::note_input(sidecar);
    e.columns = read_columns(run, base, protocol.mode);
    run.finish(fmt::format("id, file, {}", kColumnKeys));
    m.runs.emplace(e.id, std::move(e));
  }
  top.finish("format, description, columns, run");
  return m;
}

namespace {

// A record of `clearshape rig run|stream` says in its sidecar (same name, .json) whether it is
// complete; one with lost samples is refused by name, never used with its holes.
void refuse_incomplete_record(const std::filesystem::path& csv) {
  std::filesystem::path sidecar = csv;
  sidecar.replace_extension(".json");
  std::error_code ec;
  if (sidecar == csv || !std::filesystem::is_regular_file(sidecar, ec)) return;
  const auto doc = nlohmann::json::parse(io::read_text_file(sidecar), nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("complete") || !doc["complete"].is_boolean()) return;
  if (doc["complete"].get<bool>()) return;
  const auto& stats = doc.contains("statistics") ? doc["statistics"] : nlohmann::json::object();
  throw InputError(sidecar.string(), 0, "complete",
                   fmt::format("the record {} is incomplete ({} sample(s) lost, stopped by: {}); record the run again",
                               csv.filename().string(), stats.value("samples_lost", 0),
                               stats.contains("stopped_by") && stats["stopped_by"].is_string()
                                   ? stats["stopped_by"].get<std::string>()
                                   : std::string("—")));
}

// A measured value beyond ±1e9 (deg, deg/s, V or counts) comes from no rig: refused with its
// file, line and column before it reaches a model fit (a row of 1e308 used to end as "every one
// of 9 model simulations failed", naming nothing).
constexpr double kLargestMeasurement = 1e9;

void refuse_absurd_values(const io::Table& t, std::size_t rows, std::initializer_list<std::string_view> columns) {
  for (const std::string_view name : columns) {
    if (name.empty()) continue;
    const auto& v = t.column(name);
    for (std::size_t k = 0; k < std::min(rows, v.size()); ++k) {
      if (!(std::abs(v[k]) <= kLargestMeasurement)) {
        throw InputError(t.source, t.line_of_row(k), std::string(name),
                         fmt::format("value {:g} is not a measurement; allowed: within ±{:g}", v[k],
                                     kLargestMeasurement));
      }
    }
  }
}

}  // namespace

Record read_recording(const RecordingEntry& e, const Protocol& p, double record_s) {
  refuse_incomplete_record(e.file);
  const io::Table t = io::read_table(e.file);
  const RecordingColumns& c = e.columns;
  const std::string time = io::require_time_column(t, c.time);
  const double time_scale = c.time_unit == "ms" ? 1e-3 : 1.0;
  const double ts = io::uniform_sample_time(t, time) * time_scale;
  const double want = p.sample_time_s();
  detail::check_time_spacing(t, time, c.time_unit, ts, want, p.name, p.sample_rate_hz);
  const std::size_t n = sample_count(record_s, want);
  if (t.rows() < n) {
    throw InputError(t.source, 0, time,
                     fmt::format("holds {} samples ({} s); the protocol records {} s ({} samples)", t.rows(),
                                 static_cast<double>(t.rows()) * ts, record_s, n));
  }
  refuse_absurd_values(t, n, {c.command, c.command_applied, c.motor_angle, c.link_rate});
  Record r;
  r.id = e.id;
  r.mode = p.mode;
  r.sample_time_s = want;
  const auto& tv = t.column(time);
  r.time_s.resize(n);
  for (std::size_t k = 0; k < n; ++k) r.time_s[k] = (tv[k] - tv[0]) * time_scale;
  r.command = to_command_units(t.column(c.command), c.command_unit);
  r.command_applied =
      c.command_applied.empty() ? r.command : to_command_units(t.column(c.command_applied), c.command_unit);
  const auto& motor = t.column(c.motor_angle);
  const double counts_per_deg = c.counts_per_rev / 360.0;
  r.motor_angle_deg.resize(motor.size());
  r.encoder_counts.resize(motor.size());
  for (std::size_t k = 0; k < motor.size(); ++k) {
    const double x = motor[k];
    r.motor_angle_deg[k] = c.motor_angle_unit == "deg" ? x : c.motor_angle_unit == "rad" ? rad_to_deg(x) : x / counts_per_deg;
    r.encoder_counts[k] = c.motor_angle_unit == "counts" ? x : std::round(r.motor_angle_deg[k] * counts_per_deg);
  }
  const auto& rate = t.column(c.link_rate);
  r.link_rate_deg_s.resize(rate.size());
  r.gyro_raw.resize(rate.size());
  for (std::size_t k = 0; k < rate.size(); ++k) {
    const double x = rate[k];
    r.link_rate_deg_s[k] = c.link_rate_unit == "deg/s" ? x : c.link_rate_unit == "rad/s" ? rad_to_deg(x) : x / c.lsb_per_deg_s;
    r.gyro_raw[k] = c.link_rate_unit == "lsb" ? x : std::round(r.link_rate_deg_s[k] * c.lsb_per_deg_s);
  }
  // Travel first: a deg/rad mistake in either column shows there with the column it is in.
  detail::check_link_travel(t.source, c, r.command_applied, r.motor_angle_deg, r.link_rate_deg_s, want, n);
  detail::check_gyro_full_scale(t, c, r.link_rate_deg_s, n);
  r.flags.assign(n, 0.0);
  for (auto* v : {&r.command, &r.command_applied, &r.motor_angle_deg, &r.encoder_counts, &r.link_rate_deg_s,
                  &r.gyro_raw}) {
    v->resize(n);
  }
  return r;
}

std::string recordings_manifest_template(const Protocol& p) {
  const auto names = record_columns(p.mode);
  const RecordingColumns c = default_columns(p);
  std::string s;
  s += fmt::format("# Recordings of protocol '{}' ({} mode): map each run to a CSV in this folder.\n", p.name,
                   rig::to_string(p.mode));
  s += "# Runs you did not record: delete their run entries (the stages needing them are skipped).\n";
  s += fmt::format("format = \"{}\"\ndescription = \"\"\n\n", kRecordingsFormat);
  s += "[columns]  # every run's columns; a run entry may override any of these keys\n";
  s += "time = \"time_s\"  # default: the first of time_s, time, t\ntime_unit = \"s\"  # s | ms\n";
  s += fmt::format("command = \"{}\"\ncommand_unit = \"{}\"  # {}\n", c.command, c.command_unit,
                   p.mode == rig::CommandMode::position ? "deg | rad" : "V");
  s += fmt::format("command_applied = \"{}\"  # what the drive received; delete the key to use the command\n",
                   names[2]);
  s += "motor_angle = \"motor_angle_deg\"\nmotor_angle_unit = \"deg\"  # deg | rad | counts\n";
  s += "counts_per_rev = 12000  # with motor_angle_unit = \"counts\"\n";
  s += "link_rate = \"link_rate_deg_s\"  # the gyroscope on the link\nlink_rate_unit = \"deg/s\"  # deg/s | rad/s | lsb\n";
  s += "lsb_per_deg_s = 14.375  # with link_rate_unit = \"lsb\"\n";
  s += "gyro_full_scale_deg_s = 2000  # the gyroscope's range (ITG-3205: ±2000 deg/s); a rate beyond it is refused\n";
  std::map<std::string, std::vector<std::string>> users;
  for (const auto& stage : plan_runs(p)) {
    for (const auto& r : stage.runs) {
      auto& u = users[r.id];
      if (u.empty() || u.back() != stage.stage) u.push_back(stage.stage);
    }
  }
  for (const auto& r : distinct_runs(p)) {
    std::string used;
    for (const auto& st : users[r.id]) used += (used.empty() ? "" : ", ") + st;
    const std::string what = r.stage == "rest" ? std::string("rest trial (zero command: nothing moves)")
                             : fmt::format("input {}, {}", r.input,
                                           r.column == "none" ? std::string("unshaped") : "shaped " + r.column);
    s += fmt::format("\n[[run]]  # {}, repetition {}; used by: {}\nid = \"{}\"\nfile = \"{}\"\n", what,
                     r.repetition, used, r.id,
                     record_csv_path("", r.id).filename().string());
  }
  return s;
}

std::shared_ptr<const RunSource> recordings_run_source(RecordingsManifest manifest, const Protocol& protocol) {
  return std::make_shared<RecordingsRunSource>(std::move(manifest), protocol);
}

}  // namespace clearshape::study
