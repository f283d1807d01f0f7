#include "clearshape/study/record.hpp"

#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/rig/realtime.hpp"

namespace clearshape::study {

using json = nlohmann::ordered_json;

std::uint64_t run_seed(std::uint64_t study_seed, std::string_view run_id) noexcept {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64
  for (const unsigned char c : run_id) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  // SplitMix64 (Steele, Lea & Flood 2014) of the combination.
  std::uint64_t z = study_seed + 0x9E3779B97F4A7C15ULL * (h | 1ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::vector<std::string> record_columns(rig::CommandMode mode) {
  const char* u = mode == rig::CommandMode::position ? "deg" : "v";
  return {"time_s",
          fmt::format("command_{}", u),
          fmt::format("command_applied_{}", u),
          "encoder_counts",
          "motor_angle_deg",
          "gyro_raw",
          "link_rate_deg_s",
          "flags"};
}

namespace {

std::string file_stem(std::string_view id) {
  std::string s(id);
  for (auto pos = s.find('/'); pos != std::string::npos; pos = s.find('/')) s.replace(pos, 1, "__");
  return s;
}

double command_at(const UniformSeries& command, std::size_t k) {
  if (command.values.empty()) return 0.0;
  return command.values[std::min(k, command.values.size() - 1)];
}

}  // namespace

std::filesystem::path record_csv_path(const std::filesystem::path& runs_dir, std::string_view id) {
  return runs_dir / (file_stem(id) + ".csv");
}
std::filesystem::path record_sidecar_path(const std::filesystem::path& runs_dir, std::string_view id) {
  return runs_dir / (file_stem(id) + ".json");
}

Record execute_run(rig::Rig& rig, const RunRequest& request) {
  const double ts = rig.sample_time_s();
  if (std::abs(ts - request.command.sample_time_s) > 1e-9 * ts) {
    throw InvalidArgument(fmt::format("run {}: the rig samples every {} s but the command every {} s; "
                                      "set the protocol's sample_rate_hz to the rig's", request.id, ts,
                                      request.command.sample_time_s));
  }
  if (rig.state() == rig::LifecycleState::unconfigured && rig.configure() != Status::ok) {
    throw RuntimeError(fmt::format("run {}: the rig '{}' did not configure", request.id, rig.name()));
  }
  if (rig.activate() != Status::ok) {
    throw RuntimeError(fmt::format("run {}: the rig '{}' did not activate (state {})", request.id,
                                   rig.name(), rig::to_string(rig.state())));
  }
  const rig::CommandMode mode = rig.mode();
  const bool position = mode == rig::CommandMode::position;
  const std::size_t n = sample_count(request.record_s, ts);
  Record r;
  r.id = request.id;
  r.mode = mode;
  r.sample_time_s = ts;
  for (auto* v : {&r.time_s, &r.command, &r.command_applied, &r.encoder_counts, &r.motor_angle_deg,
                  &r.gyro_raw, &r.link_rate_deg_s, &r.flags}) {
    v->resize(n);
  }
  rig::Measurement m;
  const std::size_t backlog = rig::RealtimeOptions{}.coalesce_backlog_samples;
  for (std::size_t k = 0; k < n; ++k) {
    const Status status = rig.read(m);
    if (status != Status::ok) {
      rig.deactivate();
      const std::vector<std::string> why = rig.degradation();  // what the rig saw, for the user
      throw RuntimeError(fmt::format("run {}: the rig's read failed at sample {} (t = {} s): {}{}{}", request.id, k,
                                     static_cast<double>(k) * ts, to_string(status), why.empty() ? "" : "; ",
                                     fmt::join(why, "; ")));
    }
    const double u = command_at(request.command, k);
    r.time_s[k] = static_cast<double>(k) * ts;
    r.command[k] = u;
    r.command_applied[k] = position ? rad_to_deg(m.command_applied) : m.command_applied;
    r.encoder_counts[k] = static_cast<double>(m.encoder_counts);
    r.motor_angle_deg[k] = m.motor_angle_deg();
    r.gyro_raw[k] = static_cast<double>(m.gyro_raw);
    r.link_rate_deg_s[k] = m.gyro_rate_deg_s();
    r.flags[k] = static_cast<double>(m.flags);
    // The command for the next interval (a rejected or clipped command is flagged by the rig).
    // A loop that fell behind the board (8 or more of its samples already waiting) writes only the
    // newest commands of its catch-up, as the real-time runner does (rig/realtime.hpp): the older
    // ones would only fill the board's receive queue, whose updates take the newest.
    if (rig::coalesce_command(true, rig.samples_waiting(), backlog)) continue;
    (void)rig.write(position ? rig::Command::position_deg(u) : rig::Command::speed_v(u));
  }
  rig.deactivate();
  // A degraded record (late or lost commands, a board that was not stopped) is never a run.
  if (const auto why = rig.degradation(); !why.empty()) {
    throw RuntimeError(fmt::format("run {}: the rig's record is degraded ({}); it is not used — run the study "
                                   "again on an idle machine", request.id, fmt::join(why, "; ")));
  }
  return r;
}

void write_record(const std::filesystem::path& runs_dir, const Record& record,
                  const RunRequest& request, std::string_view protocol_hash,
                  std::string_view rig_description, const json& rig_counters) {
  const auto names = record_columns(record.mode);
  io::write_csv(record_csv_path(runs_dir, record.id), names,
                {&record.time_s, &record.command, &record.command_applied, &record.encoder_counts,
                 &record.motor_angle_deg, &record.gyro_raw, &record.link_rate_deg_s, &record.flags});
  json doc = io::make_document();
  doc["id"] = record.id;
  doc["protocol_hash"] = protocol_hash;
  doc["rig"] = rig_description;
  doc["mode"] = rig::to_string(record.mode);
  doc["stage"] = request.stage;
  doc["input"] = request.input;
  doc["column"] = request.column;
  doc["repetition"] = request.repetition;
  doc["seed"] = request.seed;
  doc["sample_time_s"] = record.sample_time_s;
  doc["samples"] = record.size();
  doc["csv"] = record_csv_path(runs_dir, record.id).filename().string();
  json shaper = nullptr;
  if (request.shaper) {
    shaper = json::object();
    shaper["method"] = request.shaper->method();
    json imps = json::array();
    for (const auto& i : request.shaper->impulses()) imps.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
    shaper["impulses"] = imps;
  }
  doc["shaper"] = shaper;
  const char* u = record.mode == rig::CommandMode::position ? "deg" : "V";
  doc["units"] = {{"time_s", "s"},
                  {names[1], u},
                  {names[2], u},
                  {"encoder_counts", "counts (3000 lines decoded x4)"},
                  {"motor_angle_deg", "deg"},
                  {"gyro_raw", "LSB (14.375 LSB per deg/s)"},
                  {"link_rate_deg_s", "deg/s"},
                  {"flags", "rig::MeasurementFlag bits"}};
  doc["rig_counters"] = rig_counters;
  io::write_json(record_sidecar_path(runs_dir, record.id), doc);
}

std::optional<Record> read_record(const std::filesystem::path& runs_dir, const RunRequest& request,
                                  rig::CommandMode mode, std::string_view protocol_hash) {
  const auto sidecar = record_sidecar_path(runs_dir, request.id);
  const auto csv = record_csv_path(runs_dir, request.id);
  std::error_code ec;
  if (!std::filesystem::exists(sidecar, ec) || !std::filesystem::exists(csv, ec)) return std::nullopt;
  try {
    // The study's own files: read back without registering them as inputs, so a stale run can be
    // replaced by the rerun.
    const json doc = json::parse(io::read_own_output_file(sidecar));
    if (doc.value("protocol_hash", std::string()) != protocol_hash) return std::nullopt;
    if (doc.value("id", std::string()) != request.id) return std::nullopt;
    const io::Table t = io::parse_table(io::read_own_output_file(csv), csv.string());
    const auto names = record_columns(mode);
    Record r;
    r.id = request.id;
    r.mode = mode;
    r.time_s = t.column(names[0]);
    r.command = t.column(names[1]);
    r.command_applied = t.column(names[2]);
    r.encoder_counts = t.column(names[3]);
    r.motor_angle_deg = t.column(names[4]);
    r.gyro_raw = t.column(names[5]);
    r.link_rate_deg_s = t.column(names[6]);
    r.flags = t.column(names[7]);
    r.sample_time_s = doc.value("sample_time_s", 0.0);
    if (r.size() != doc.value("samples", std::size_t{0}) || r.size() < 2) return std::nullopt;
    return r;
  } catch (const std::exception&) {
    return std::nullopt;  // a damaged run is simply run again
  }
}

}  // namespace clearshape::study
