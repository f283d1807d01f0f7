#include "clearshape/rig/board_run.hpp"

#include <algorithm>
#include <filesystem>
#include <utility>

#include <fmt/format.h>

#include "clearshape/core/units.hpp"
#include "clearshape/io/interrupt.hpp"
#include "clearshape/rig/wire_protocol.h"

namespace clearshape::rig {

using json = nlohmann::ordered_json;

void BoardRecord::reserve(std::size_t n) {
  for (auto* v : {&time_s, &command, &shaped, &applied, &counts, &motor_deg, &gyro_raw, &gyro_deg_s, &flags, &latency_s}) {
    v->reserve(n);
  }
}

void BoardRecord::add(const LogRecord& rec, bool position) {
  if (rec.read_status != Status::ok) return;
  const Measurement& m = rec.measurement;
  time_s.push_back(m.time_s);
  command.push_back(rec.command);
  shaped.push_back(rec.command_shaped);
  applied.push_back(position ? rad_to_deg(m.command_applied) : m.command_applied);
  counts.push_back(static_cast<double>(m.encoder_counts));
  motor_deg.push_back(m.motor_angle_deg());
  gyro_raw.push_back(m.gyro_raw);
  gyro_deg_s.push_back(m.gyro_rate_deg_s());
  flags.push_back(m.flags);
  latency_s.push_back(rec.latency_s);
  last = m;
}

namespace {

bool has_flag(double flags, MeasurementFlag flag) {
  return (static_cast<std::uint32_t>(flags) & bit(flag)) != 0;
}

void warn(const BoardRunOptions& options, BoardRunOutcome& out, std::string what) {
  out.warnings.push_back(std::move(what));
  if (options.warn) options.warn(out.warnings.back());
}

// A run whose samples the watchdog flagged did not follow its command there (docs/hardware.md).
void warn_watchdog(const BoardRecord& c, const BoardRunOptions& options, BoardRunOutcome& out) {
  const auto held = [](double f) { return has_flag(f, MeasurementFlag::watchdog); };
  const auto first = std::find_if(c.flags.begin(), c.flags.end(), held);
  if (!options.write_commands || first == c.flags.end()) return;
  const auto k = static_cast<std::size_t>(first - c.flags.begin());
  warn(options, out,
       fmt::format("the board's watchdog held the command safe on {} sample(s), the first at t = {:.3f} s: the record "
                   "does not follow the command there (flags bit 16; a host that stalled longer than --watchdog-ms)",
                   std::count_if(c.flags.begin(), c.flags.end(), held), c.time_s[k]));
}

// Host frames the board rejected during the run (RX overruns when COMMANDs arrive in a burst after
// a host stall, docs/hardware.md "COMMAND bursts"): those commands never reached the drive.
void warn_rejected_frames(const BoardRunOptions& options, BoardRunOutcome& out) {
  if (!out.board_during_run) {
    warn(options, out, "the board's counters could not be read before and after the run");
    return;
  }
  const std::uint32_t n = out.board_during_run->rx_corrupted;
  if (n == 0) return;
  warn(options, out,
       fmt::format("the board rejected {} host frame(s) during the run (its receive buffer overran under a burst of "
                   "COMMANDs): those commands were not applied; the command_applied column is what the drive received",
                   n));
}

// Samples carrying each MeasurementFlag (rig/types.hpp), from the record's flags column.
json flag_counts_json(const std::vector<double>& flags) {
  const std::pair<MeasurementFlag, const char*> names[] = {
      {MeasurementFlag::gyro_saturated, "gyro_saturated"}, {MeasurementFlag::command_limited, "command_limited"},
      {MeasurementFlag::overrun, "overrun"},               {MeasurementFlag::command_rejected, "command_rejected"},
      {MeasurementFlag::watchdog, "watchdog"},             {MeasurementFlag::sensor_error, "sensor_error"},
      {MeasurementFlag::samples_lost, "samples_lost"},     {MeasurementFlag::commands_lost, "commands_lost"}};
  json j = json::object();
  for (const auto& [flag, name] : names) {
    j[name] = std::count_if(flags.begin(), flags.end(), [flag](double f) { return has_flag(f, flag); });
  }
  return j;
}

}  // namespace

BoardRunOutcome run_on_board(SerialRig& rig, const BoardRunOptions& options, BoardRecord& record) {
  const bool position = rig.options().mode == CommandMode::position;
  CommandSource source(options.command, rig.options().mode);
  if (options.shaper) source.set_shaper(*options.shaper, rig.sample_time_s());
  BoardRunOutcome out;
  RealtimeOptions ro;
  ro.realtime_scheduling = options.realtime_scheduling;
  ro.write_commands = options.write_commands;
  ro.stop_flag = options.stop_flag;
  ro.warn = [&](const std::string& w) { warn(options, out, w); };
  rig.configure();
  if (options.configured) options.configured(rig);
  RealtimeRunner runner(rig, source, ro);
  record.reserve(options.command.size());
  const auto sink = [&](const LogRecord& rec) { record.add(rec, position); };
  const auto status = [&](const RunStatistics& s) {
    if (options.progress) options.progress(s, record);
  };
  out.stats = runner.run(options.command.size(), sink, status);
  out.link = rig.stats();
  out.stop_problem = rig.last_stop_problem();
  out.board_during_run = rig.board_during_run();
  out.interrupted_by = io::pending_interrupt();
  if (!out.stats.stopped_by.empty()) {
    out.degraded.push_back(out.interrupted_by != 0 ? fmt::format("interrupted by {} at t = {:.3f} s",
                                                                 io::interrupt_name(out.interrupted_by),
                                                                 record.last.time_s)
                                                   : out.stats.stopped_by);
  }
  for (std::string& why : rig.degradation()) out.degraded.push_back(std::move(why));
  rig.cleanup();
  warn_watchdog(record, options, out);
  warn_rejected_frames(options, out);
  return out;
}

RecordColumns record_columns(const BoardRecord& c, CommandMode mode, bool with_command, bool shaped) {
  const std::string u = mode == CommandMode::position ? "deg" : "v";
  RecordColumns t{{"time_s"}, {&c.time_s}};
  if (with_command) {
    t.names.push_back("command_" + u);
    t.columns.push_back(&c.command);
    if (shaped) {
      t.names.push_back("command_shaped_" + u);
      t.columns.push_back(&c.shaped);
    }
  }
  for (const auto& [col, v] : std::initializer_list<std::pair<std::string, const std::vector<double>*>>{
           {"command_applied_" + u, &c.applied}, {"encoder_counts", &c.counts},  {"motor_deg", &c.motor_deg},
           {"gyro_raw", &c.gyro_raw},            {"gyro_deg_s", &c.gyro_deg_s}, {"flags", &c.flags},
           {"latency_s", &c.latency_s}}) {
    t.names.push_back(col);
    t.columns.push_back(v);
  }
  return t;
}

json record_units_json(const SerialRigOptions& o) {
  const bool position = o.mode == CommandMode::position;
  return {{"time_s", "s (board tick × sample time)"},
          {"command", position ? "deg (motor-angle target)" : "V (driver speed input)"},
          {"command_applied", position ? "deg (pulses emitted × 360 / pulses_per_rev)" : "V (DAC code)"},
          {"encoder_counts", fmt::format("counts ({} per revolution)", o.counts_per_rev)},
          {"motor_deg", "deg"},
          {"gyro_raw", fmt::format("LSB ({} LSB per deg/s)", o.gyro_sensitivity_lsb_per_dps)},
          {"gyro_deg_s", "deg/s"},
          {"flags", "rig::MeasurementFlag bits (rig/types.hpp)"},
          {"latency_s", "s (cycle deadline → command written)"}};
}

json board_stats_json(const BoardStats& s) {
  return {{"samples_sent", s.samples_sent}, {"samples_dropped", s.samples_dropped}, {"rx_corrupted", s.rx_corrupted},
          {"watchdog_trips", s.watchdog_trips}, {"late_ticks", s.late_ticks}};
}

json run_statistics_json(const BoardRunOutcome& out, const BoardRecord& c, const SerialRigOptions& o) {
  const RunStatistics& s = out.stats;
  const SerialRigStats& link = out.link;
  return {{"cycles", s.cycles},
          {"samples", s.samples},
          {"samples_lost", s.samples_lost},
          {"frames_corrupted", s.frames_corrupted},
          {"samples_late", s.samples_late},
          {"late_tolerance_s", o.late_tolerance_s},
          {"max_lateness_s", link.max_lateness_s},
          {"overruns", s.overruns},
          {"read_failures", s.read_failures},
          {"write_failures", s.write_failures},
          {"log_dropped", s.log_dropped},
          {"ring_overflows", link.ring_overflows},
          {"commands_sent", link.commands_sent},
          {"commands_coalesced", s.commands_coalesced},
          {"commands_dropped", link.commands_dropped},
          {"board_tx_overflows", link.board_tx_overflows},
          {"commands_rejected", link.commands_rejected},
          {"watchdog_samples", link.watchdog_samples},
          {"rx_rejected_samples", link.rx_rejected_samples},
          {"latency_p50_s", s.latency_p50_s},
          {"latency_p99_s", s.latency_p99_s},
          {"latency_max_s", s.latency_max_s},
          {"latency_overflows", s.latency_overflows},
          {"sched_fifo", s.sched_fifo},
          {"memory_locked", s.memory_locked},
          {"stopped_by", s.stopped_by.empty() ? json(nullptr) : json(s.stopped_by)},
          {"stop_confirmed", out.stop_problem.empty()},
          {"flagged_samples", flag_counts_json(c.flags)},
          {"board_during_run", out.board_during_run ? board_stats_json(*out.board_during_run) : json(nullptr)}};
}

std::string capability_names(std::uint32_t caps) {
  const std::pair<std::uint32_t, const char*> names[] = {
      {CS_CAP_ENCODER_QUADRATURE, "encoder-quadrature"}, {CS_CAP_PULSE_AB, "pulse-ab"},
      {CS_CAP_DAC_MCP4725, "dac-mcp4725"},               {CS_CAP_GYRO_ITG3205, "gyro-itg3205"},
      {CS_CAP_SERVO_ON, "servo-on"},                     {CS_CAP_WATCHDOG, "watchdog"}};
  std::string out;
  for (const auto& [b, name] : names) {
    if (caps & b) out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out.empty() ? "none" : out;
}

json board_json(const SerialRig& r) {
  const BoardInfo& b = r.board();
  json j = {{"firmware_version", b.firmware_version()},
            {"wire_version", b.wire_version},
            {"capabilities", b.capabilities},
            {"capability_names", capability_names(b.capabilities)},
            {"cpu_hz", b.cpu_hz},
            {"encoder_lines_hint", b.encoder_lines_hint},
            {"port", r.options().port},
            {"backend", std::string(r.backend())}};
  if (b.selftest) {
    j["selftest"] = {{"gyro_who_am_i", b.selftest->gyro_who_am_i},
                     {"gyro_ok", b.selftest->gyro_ok},
                     {"dac_ok", b.selftest->dac_ok},
                     {"gyro_raw_at_rest", b.selftest->gyro_raw_at_rest},
                     {"gyro_at_rest_deg_s", b.selftest->gyro_raw_at_rest / r.options().gyro_sensitivity_lsb_per_dps}};
  }
  return j;
}

json board_configuration_json(const SerialRigOptions& o) {
  return {{"mode", std::string(to_string(o.mode))},
          {"sample_rate_hz", o.sample_rate_hz},
          {"update_rate_hz", o.update_rate_hz},
          {"max_pulse_rate_hz", o.max_pulse_rate_hz},
          {"baud", o.baud},
          {"gyro_fs_sel", o.gyro_fs_sel},
          {"gyro_dlpf_cfg", o.gyro_dlpf_cfg},
          {"watchdog_ms", o.watchdog_ms},
          {"counts_per_rev", o.counts_per_rev},
          {"pulses_per_rev", o.pulses_per_rev},
          {"servo_on", o.servo_on}};
}

std::string record_path_for(const std::string& requested, bool complete) {
  if (complete) return requested;
  std::filesystem::path p = requested;
  const std::string ext = p.extension().string();
  p.replace_filename(p.stem().string() + ".incomplete" + (ext.empty() ? std::string(".csv") : ext));
  return p.string();
}

}  // namespace clearshape::rig
