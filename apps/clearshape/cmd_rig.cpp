// `clearshape rig probe|stream|run`: the physical rig (the thesis's Arduino Mega board, or the
// emulator running its firmware) over a serial port — rig::SerialRig driven by the real-time
// runner (rig/realtime.hpp). docs/hardware.md ("Host side") describes the set-up.
//   probe   handshake, firmware version, capabilities, self-test, the board's counters
//   stream  log the sensors for --duration s (no commands; servo off unless --servo-on)
//   run     one run of a command signal, optionally shaped online, logged to a CSV + sidecar
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/interrupt.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/wire_protocol.h"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/signal.hpp"
#include "command.hpp"
#include "rig_serial_options.hpp"
#include "run_json.hpp"
#include "signal_options.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using json = nlohmann::ordered_json;

namespace {

std::string capability_names(std::uint32_t caps) {
  const std::pair<std::uint32_t, const char*> names[] = {
      {CS_CAP_ENCODER_QUADRATURE, "encoder-quadrature"}, {CS_CAP_PULSE_AB, "pulse-ab"},
      {CS_CAP_DAC_MCP4725, "dac-mcp4725"},               {CS_CAP_GYRO_ITG3205, "gyro-itg3205"},
      {CS_CAP_SERVO_ON, "servo-on"},                     {CS_CAP_WATCHDOG, "watchdog"}};
  std::string out;
  for (const auto& [bit, name] : names) {
    if (caps & bit) out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out.empty() ? "none" : out;
}

json board_json(const rig::SerialRig& r) {
  const rig::BoardInfo& b = r.board();
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

json board_stats_json(const rig::BoardStats& s) {
  return {{"samples_sent", s.samples_sent}, {"samples_dropped", s.samples_dropped}, {"rx_corrupted", s.rx_corrupted},
          {"watchdog_trips", s.watchdog_trips}, {"late_ticks", s.late_ticks}};
}

// --- probe -----------------------------------------------------------------------------------

struct ProbeState {
  cs::cli::SerialCliOptions serial;
  bool json = false;
};

void probe(const ProbeState& st) {
  rig::SerialRigOptions o = st.serial.build();
  o.selftest = true;
  rig::SerialRig r(o);
  r.configure();
  const rig::BoardStats stats = r.board_stats();
  const auto& t = *r.board().selftest;
  const bool ok = t.gyro_ok && t.dac_ok;
  if (st.json) {
    auto doc = cs::io::make_document();
    doc["command"] = "rig probe";
    doc["board"] = board_json(r);
    doc["board_stats"] = board_stats_json(stats);
    doc["selftest_passed"] = ok;
    cs::cli::print_json(doc);
  } else {
    const rig::BoardInfo& b = r.board();
    fmt::print("{:<16}{} ({})\n", "port", o.port, r.backend());
    fmt::print("{:<16}{}\n", "firmware", b.firmware_version());
    fmt::print("{:<16}v{}\n", "wire protocol", b.wire_version);
    fmt::print("{:<16}{} (0x{:02x})\n", "capabilities", capability_names(b.capabilities), b.capabilities);
    fmt::print("{:<16}{:g} MHz\n", "cpu", b.cpu_hz / 1e6);
    fmt::print("{:<16}{}\n", "encoder lines", b.encoder_lines_hint == 0 ? std::string("unknown") : std::to_string(b.encoder_lines_hint));
    fmt::print("{:<16}gyro WHO_AM_I 0x{:02x} {}, DAC {}, gyro at rest {} LSB ({:.3g} deg/s)\n", "self-test",
               t.gyro_who_am_i, t.gyro_ok ? "ok" : "FAILED", t.dac_ok ? "ok" : "FAILED", t.gyro_raw_at_rest,
               t.gyro_raw_at_rest / o.gyro_sensitivity_lsb_per_dps);
    fmt::print("{:<16}samples sent {}, dropped {}, rx corrupted {}, watchdog trips {}, late ticks {}\n",
               "board counters", stats.samples_sent, stats.samples_dropped, stats.rx_corrupted, stats.watchdog_trips,
               stats.late_ticks);
  }
  r.cleanup();
  if (!ok) {
    throw cs::RuntimeError(fmt::format("rig probe: the board's self-test failed on {} ({}); check the TWI wiring "
                                       "(docs/hardware.md)", o.port,
                                       !t.gyro_ok ? "gyroscope" : "DAC"));
  }
}

// --- stream and run --------------------------------------------------------------------------

struct RunState {
  cs::cli::SerialCliOptions serial;
  double duration_s = 5.0;
  std::string output;
  bool json = false;
  bool no_realtime = false;
  bool servo_on = false;  // stream only
  // run only
  std::string type;
  cs::cli::SignalOptions signal_options;
  // The shaper flags of `clearshape simulate` (--frequency-hz belongs to the sine signal).
  std::string shaper;
  double shaper_frequency_hz = 0.0;
  double shaper_zeta = 0.0;
  CLI::Option* shaper_frequency_option = nullptr;
  CLI::Option* shaper_zeta_option = nullptr;
};

std::optional<cs::shaping::Shaper> shaper_of(const RunState& st) {
  const bool mode_given = st.shaper_frequency_option->count() > 0 || st.shaper_zeta_option->count() > 0;
  if (st.shaper.empty()) {
    if (mode_given) throw cs::InvalidArgument("rig run: --shaper-frequency-hz and --shaper-zeta need --shaper METHOD");
    return std::nullopt;
  }
  if (st.shaper_frequency_option->count() == 0 || st.shaper_zeta_option->count() == 0) {
    throw cs::InvalidArgument("rig run: --shaper needs --shaper-frequency-hz and --shaper-zeta (the mode to cancel)");
  }
  cs::require_positive("--shaper-frequency-hz", st.shaper_frequency_hz);
  cs::require_in_half_open("--shaper-zeta", st.shaper_zeta, 0.0, 1.0);
  cs::shaping::DesignRequest request;
  request.method = cs::shaping::method_from_string(st.shaper);
  request.mode = cs::shaping::Mode::from_hz(st.shaper_frequency_hz, st.shaper_zeta);
  return cs::shaping::design(request);
}

// --- plan: the board's options and the command --------------------------------------------------

struct RunPlan {
  rig::SerialRigOptions options;
  std::size_t samples = 0;       ///< cycles: samples at 0 … duration
  std::vector<double> command;   ///< deg (position) or V (speed); zeros for `stream`
  std::optional<cs::shaping::Shaper> shaper;
  json signal = nullptr;
  json shaper_json = nullptr;
  bool position() const { return options.mode == rig::CommandMode::position; }
};

RunPlan plan(const RunState& st, const std::string& name, bool is_run) {
  if (st.output.empty()) throw cs::InvalidArgument(fmt::format("rig {}: --output FILE.csv is required", name));
  if (std::filesystem::path(st.output).extension() == ".json") {
    throw cs::InvalidArgument(fmt::format("rig {}: --output must not end in .json (the sidecar takes that name)", name));
  }
  cs::require_in_closed("--duration", st.duration_s, 1e-3, 86400.0);
  RunPlan p;
  p.options = st.serial.build();
  p.samples = static_cast<std::size_t>(std::llround(st.duration_s * p.options.sample_rate_hz)) + 1;
  p.command.assign(p.samples, 0.0);
  if (is_run) {
    const cs::signal::Signal signal = st.signal_options.build(st.type);
    p.command = cs::signal::sample(signal, p.options.sample_rate_hz, st.duration_s).values;
    p.command.resize(p.samples, p.command.empty() ? 0.0 : p.command.back());
    p.signal = {{"type", st.type}, {"parameters", cs::cli::signal_parameters_json(signal)}};
    p.shaper = shaper_of(st);
    if (p.shaper) {
      p.shaper_json = cs::cli::shaper_json(*p.shaper, st.shaper_frequency_hz, st.shaper_zeta);
      p.shaper_json["applied"] = "online (shaping::StreamingShaper, one sample per cycle)";
    }
  } else {
    p.options.servo_on = st.servo_on;
    if (st.serial.watchdog_option->count() == 0) p.options.watchdog_ms = 0;  // nothing is commanded: no watchdog by default
  }
  return p;
}

// --- run: the real-time loop on the board, its records collected by the logging thread ------------

// Collected by the logging thread (it may allocate; the loop never waits for it).
struct Columns {
  std::vector<double> time_s, command, shaped, applied, counts, motor_deg, gyro_raw, gyro_deg_s, flags, latency_s;
  rig::Measurement last{};

  void reserve(std::size_t n) {
    for (auto* v : {&time_s, &command, &shaped, &applied, &counts, &motor_deg, &gyro_raw, &gyro_deg_s, &flags,
                    &latency_s}) {
      v->reserve(n);
    }
  }
  void add(const rig::LogRecord& rec, bool position) {
    if (rec.read_status != cs::Status::ok) return;
    const rig::Measurement& m = rec.measurement;
    time_s.push_back(m.time_s);
    command.push_back(rec.command);
    shaped.push_back(rec.command_shaped);
    applied.push_back(position ? cs::rad_to_deg(m.command_applied) : m.command_applied);
    counts.push_back(static_cast<double>(m.encoder_counts));
    motor_deg.push_back(m.motor_angle_deg());
    gyro_raw.push_back(m.gyro_raw);
    gyro_deg_s.push_back(m.gyro_rate_deg_s());
    flags.push_back(m.flags);
    latency_s.push_back(rec.latency_s);
    last = m;
  }
};

struct Outcome {
  rig::RunStatistics stats;
  rig::SerialRigStats link;
  std::string stop_problem;  ///< empty when the board confirmed STOP
  std::vector<std::string> warnings;
  /// What the board counted during the run (its STATS before and after); empty when unknown.
  std::optional<rig::BoardStats> board_during_run;
  /// Why the record is not complete (the loop's stop, the rig's degradation); empty: complete.
  std::vector<std::string> degraded;
  int interrupted_by = 0;  ///< the signal that ended the run (0: none)
  bool complete() const { return degraded.empty(); }
};

// Samples carrying each MeasurementFlag (rig/types.hpp), from the record's flags column.
json flag_counts_json(const std::vector<double>& flags) {
  const std::pair<rig::MeasurementFlag, const char*> names[] = {
      {rig::MeasurementFlag::gyro_saturated, "gyro_saturated"}, {rig::MeasurementFlag::command_limited, "command_limited"},
      {rig::MeasurementFlag::overrun, "overrun"},               {rig::MeasurementFlag::command_rejected, "command_rejected"},
      {rig::MeasurementFlag::watchdog, "watchdog"},             {rig::MeasurementFlag::sensor_error, "sensor_error"},
      {rig::MeasurementFlag::samples_lost, "samples_lost"},     {rig::MeasurementFlag::commands_lost, "commands_lost"}};
  json j = json::object();
  for (const auto& [flag, name] : names) {
    j[name] = std::count_if(flags.begin(), flags.end(), [flag](double f) {
      return (static_cast<std::uint32_t>(f) & rig::bit(flag)) != 0;
    });
  }
  return j;
}

// What the board counted during the run (after − before; the counters are cumulative since reset).
json board_delta_json(const Outcome& out) {
  return out.board_during_run ? board_stats_json(*out.board_during_run) : json(nullptr);
}

// A run whose samples the watchdog flagged did not follow its command there (docs/hardware.md).
void warn_watchdog(const Columns& c, bool is_run, Outcome& out) {
  const auto held = [](double f) { return (static_cast<std::uint32_t>(f) & rig::bit(rig::MeasurementFlag::watchdog)) != 0; };
  const auto first = std::find_if(c.flags.begin(), c.flags.end(), held);
  if (!is_run || first == c.flags.end()) return;
  const auto k = static_cast<std::size_t>(first - c.flags.begin());
  out.warnings.push_back(fmt::format(
      "the board's watchdog held the command safe on {} sample(s), the first at t = {:.3f} s: the record does not "
      "follow the command there (flags bit 16; a host that stalled longer than --watchdog-ms)",
      std::count_if(c.flags.begin(), c.flags.end(), held), c.time_s[k]));
  fmt::print(stderr, "clearshape: warning: {}\n", out.warnings.back());
}

// Host frames the board rejected during the run (RX overruns when COMMANDs arrive in a burst after
// a host stall, docs/hardware.md "COMMAND bursts"): those commands never reached the drive.
void warn_rejected_frames(Outcome& out) {
  if (!out.board_during_run) {
    out.warnings.push_back("the board's counters could not be read before and after the run");
    fmt::print(stderr, "clearshape: warning: {}\n", out.warnings.back());
    return;
  }
  const std::uint32_t n = out.board_during_run->rx_corrupted;
  if (n == 0) return;
  out.warnings.push_back(fmt::format(
      "the board rejected {} host frame(s) during the run (its receive buffer overran under a burst of COMMANDs): "
      "those commands were not applied; the command_applied column is what the drive received", n));
  fmt::print(stderr, "clearshape: warning: {}\n", out.warnings.back());
}

Outcome run_on_board(const RunState& st, const std::string& name, bool is_run, const RunPlan& p, rig::SerialRig& r,
                     Columns& c) {
  const rig::SerialRigOptions& o = p.options;
  rig::CommandSource source(p.command, o.mode);
  if (p.shaper) source.set_shaper(*p.shaper, r.sample_time_s());
  Outcome out;
  rig::RealtimeOptions ro;
  ro.realtime_scheduling = !st.no_realtime;
  ro.write_commands = is_run;
  ro.stop_flag = &cs::io::interrupt_requested();  // SIGINT/SIGTERM/SIGHUP: the loop ends, STOP is sent
  ro.warn = [&out](const std::string& w) {
    out.warnings.push_back(w);
    fmt::print(stderr, "clearshape: warning: {}\n", w);
  };
  r.configure();
  fmt::print(stderr, "clearshape rig {}: {} firmware {} ({}), {} mode at {:g} Hz, {:g} s\n", name, o.port,
             r.board().firmware_version(), r.backend(), rig::to_string(o.mode), o.sample_rate_hz, st.duration_s);
  rig::RealtimeRunner runner(r, source, ro);
  c.reserve(p.samples);
  const bool position = p.position();
  const auto sink = [&](const rig::LogRecord& rec) { c.add(rec, position); };
  const bool tty = isatty(fileno(stderr)) != 0;
  int status_calls = 0;
  const auto status = [&](const rig::RunStatistics& s) {
    // ~5 Hz on a terminal (one line, rewritten); once a second otherwise.
    if (!tty && (status_calls++ % 5) != 0) return;
    const rig::SerialRigStats link = r.stats();
    fmt::print(stderr, "{}t {:7.2f}/{:g} s  samples {}  lost {}  corrupted {}  late {}  overruns {}  motor {:9.3f} deg  "
                       "gyro {:8.2f} deg/s{}",
               tty ? "\r" : "", c.last.time_s, st.duration_s, s.samples, link.samples_lost, link.frames_corrupted,
               link.samples_late, s.overruns, c.last.motor_angle_deg(), c.last.gyro_rate_deg_s(), tty ? "" : "\n");
  };
  out.stats = runner.run(p.samples, sink, status);
  if (tty) fmt::print(stderr, "\n");
  out.link = r.stats();
  out.stop_problem = r.last_stop_problem();
  out.board_during_run = r.board_during_run();
  out.interrupted_by = cs::io::pending_interrupt();
  if (!out.stats.stopped_by.empty()) {
    out.degraded.push_back(out.interrupted_by != 0 ? fmt::format("interrupted by {} at t = {:.3f} s",
                                                                 cs::io::interrupt_name(out.interrupted_by), c.last.time_s)
                                                   : out.stats.stopped_by);
  }
  for (std::string& why : r.degradation()) out.degraded.push_back(std::move(why));
  r.cleanup();
  warn_watchdog(c, is_run, out);
  warn_rejected_frames(out);
  return out;
}

// --- write: the CSV with its sidecar, stdout, the verdict -----------------------------------------

struct Table {
  std::vector<std::string> names;
  std::vector<const std::vector<double>*> columns;
};

Table table(const Columns& c, const RunPlan& p, bool is_run) {
  const std::string u = p.position() ? "deg" : "v";
  Table t{{"time_s"}, {&c.time_s}};
  if (is_run) {
    t.names.push_back("command_" + u);
    t.columns.push_back(&c.command);
    if (p.shaper) {
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

json statistics_json(const Outcome& out, const Columns& c, const rig::SerialRigOptions& o) {
  const rig::RunStatistics& s = out.stats;
  const rig::SerialRigStats& link = out.link;
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
          {"board_during_run", board_delta_json(out)}};
}

json units_json(const rig::SerialRigOptions& o) {
  const bool position = o.mode == rig::CommandMode::position;
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

json configuration_json(const rig::SerialRigOptions& o, const RunState& st) {
  return {{"mode", std::string(rig::to_string(o.mode))},
          {"sample_rate_hz", o.sample_rate_hz},
          {"update_rate_hz", o.update_rate_hz},
          {"max_pulse_rate_hz", o.max_pulse_rate_hz},
          {"baud", o.baud},
          {"gyro_fs_sel", o.gyro_fs_sel},
          {"gyro_dlpf_cfg", o.gyro_dlpf_cfg},
          {"watchdog_ms", o.watchdog_ms},
          {"counts_per_rev", o.counts_per_rev},
          {"pulses_per_rev", o.pulses_per_rev},
          {"servo_on", o.servo_on},
          {"duration_s", st.duration_s},
          {"realtime_scheduling", !st.no_realtime}};
}

// Where the record goes: --output when it is complete; otherwise `<stem>.incomplete.csv` beside
// it, so a failed run never replaces a previous good record of the same name.
std::filesystem::path record_path(const RunState& st, const Outcome& out) {
  if (out.complete()) return st.output;
  std::filesystem::path p = st.output;
  const std::string ext = p.extension().string();
  p.replace_filename(p.stem().string() + ".incomplete" + (ext.empty() ? std::string(".csv") : ext));
  return p;
}

void write_files(const std::filesystem::path& csv, const std::string& name, const RunState& st, const RunPlan& p,
                 const rig::SerialRig& r, const Table& t, const Outcome& out, const json& statistics) {
  auto doc = cs::io::make_document();
  doc["command"] = "rig " + name;
  doc["csv"] = csv.string();
  doc["complete"] = out.complete();
  doc["degraded"] = out.degraded;
  doc["columns"] = t.names;
  doc["units"] = units_json(p.options);
  doc["rig"] = {{"kind", "physical"}, {"board", board_json(r)}};
  doc["configuration"] = configuration_json(p.options, st);
  doc["signal"] = p.signal;
  doc["shaper"] = p.shaper_json;
  doc["statistics"] = statistics;
  doc["warnings"] = out.warnings;
  const auto sidecar = cs::cli::sidecar_path(csv);
  cs::io::AtomicBatch batch;
  batch.add(csv, cs::io::format_csv(t.names, t.columns));
  batch.add(sidecar, doc.dump(2) + "\n");
  batch.commit();
  fmt::print(stderr, "clearshape rig {}: wrote {} ({} rows) and {}\n", name, csv.string(), t.columns[0]->size(),
             sidecar.string());
}

void print_summary(const std::filesystem::path& csv, const RunState& st, const std::string& name, const RunPlan& p,
                   const Outcome& out, const json& statistics) {
  const rig::RunStatistics& s = out.stats;
  if (st.json) {
    auto doc = cs::io::make_document();
    doc["command"] = "rig " + name;
    doc["output"] = csv.string();
    doc["complete"] = out.complete();
    doc["degraded"] = out.degraded;
    doc["statistics"] = statistics;
    cs::cli::print_json(doc);
    return;
  }
  fmt::print("{:<14}{} of {} ({} lost, {} corrupted frames, {} late beyond {:g} ms)\n", "samples", s.samples, s.cycles,
             s.samples_lost, s.frames_corrupted, s.samples_late, p.options.late_tolerance_s * 1e3);
  fmt::print("{:<14}p50 {:.1f} us, p99 {:.1f} us, max {:.1f} us; {} overruns, {} late commands coalesced{}\n",
             "loop latency", s.latency_p50_s * 1e6, s.latency_p99_s * 1e6, s.latency_max_s * 1e6, s.overruns,
             s.commands_coalesced, s.sched_fifo ? " (SCHED_FIFO)" : " (normal priority)");
  fmt::print("{:<14}{}\n", "record", out.complete() ? "complete" : "INCOMPLETE");
  fmt::print("{:<14}{}\n", "output", csv.string());
}

// A record that is not complete (a stop, an interrupt, lost or late samples, commands that did not
// reach the drive) is a failure: exit 1, naming why and where it was written instead.
void check_outcome(const std::filesystem::path& csv, const std::string& name, const RunState& st, const RunPlan& p,
                   const Outcome& out) {
  if (!out.stop_problem.empty()) {
    fmt::print(stderr, "clearshape: warning: STOP was not confirmed: {}; switch the drive off by hand\n",
               out.stop_problem);
  }
  if (out.complete()) return;
  const std::string what = fmt::format(
      "rig {}: the record from {} is not complete: {}; written to {} and its sidecar (\"complete\": false) — "
      "{} was left as it was; record the run again",
      name, p.options.port, fmt::join(out.degraded, "; "), csv.string(), st.output);
  if (out.interrupted_by != 0) {
    fmt::print(stderr, "clearshape: {} ({}; the board was sent STOP: command safe, servo off)\n", what,
               out.stop_problem.empty() ? "STOP confirmed" : "STOP NOT confirmed");
    return;  // the caller ends the process by the signal
  }
  throw cs::RuntimeError(what);
}

void execute(const RunState& st, const std::string& name, bool is_run) {
  const RunPlan p = plan(st, name, is_run);
  // From here until the record is written, SIGINT/SIGTERM/SIGHUP/SIGPIPE end the loop instead of
  // the process: the board is sent STOP (servo off) on every way out, then the signal ends it.
  cs::io::DeferredInterrupts interrupts;
  Outcome out;
  std::filesystem::path csv;
  {
    rig::SerialRig r(p.options);  // its destructor sends STOP if an exception leaves it active
    Columns c;
    out = run_on_board(st, name, is_run, p, r, c);
    const Table t = table(c, p, is_run);
    const json statistics = statistics_json(out, c, p.options);
    csv = record_path(st, out);
    write_files(csv, name, st, p, r, t, out, statistics);
    print_summary(csv, st, name, p, out, statistics);
  }
  check_outcome(csv, name, st, p, out);
  interrupts.end_process_if_interrupted();
}

void add_run_options(CLI::App& sub, RunState& st) {
  sub.add_option("--duration", st.duration_s, "Duration (s); samples at 0 … duration")->capture_default_str();
  sub.add_option("--output,-o", st.output, "CSV of the run; a JSON sidecar (same name, .json) holds the statistics")
      ->required();
  sub.add_flag("--no-realtime", st.no_realtime, "Skip SCHED_FIFO and mlockall (run at normal priority)");
  sub.add_flag("--json", st.json, "Print a JSON summary on stdout");
}

void setup(CLI::App& sub) {
  sub.require_subcommand(1);
  {
    auto st = std::make_shared<ProbeState>();
    CLI::App* p = sub.add_subcommand("probe", "Handshake with the rig board: firmware, capabilities, self-test");
    st->serial.add_to(*p, true);
    p->add_flag("--json", st->json, "Print JSON on stdout");
    p->callback([st] { probe(*st); });
  }
  {
    auto st = std::make_shared<RunState>();
    CLI::App* p = sub.add_subcommand("stream", "Log the rig's sensors (no commands) to a CSV");
    st->serial.add_to(*p, true);
    add_run_options(*p, *st);
    p->add_flag("--servo-on", st->servo_on, "Switch the servo on while streaming (default off)");
    p->callback([st] { execute(*st, "stream", false); });
  }
  {
    auto st = std::make_shared<RunState>();
    CLI::App* p = sub.add_subcommand("run", "One run of a command signal (optionally shaped online) on the rig");
    st->serial.add_to(*p, true);
    add_run_options(*p, *st);
    p->add_option("--signal", st->type, "Command signal: " + cs::cli::SignalOptions::type_list())
        ->check(cs::cli::SignalOptions::type_check())
        ->required();
    st->signal_options.add_to(*p, "--signal");
    p->add_option("--shaper", st->shaper,
                  "Shape the command online with this shaper (zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, um-zv); "
                  "default: unshaped");
    st->shaper_frequency_option = p->add_option("--shaper-frequency-hz", st->shaper_frequency_hz,
                                                "Natural frequency of the mode to cancel (Hz)");
    st->shaper_zeta_option = p->add_option("--shaper-zeta", st->shaper_zeta, "Damping ratio of that mode, [0, 1)");
    p->footer(
        "Examples:\n"
        "  clearshape rig run --port /dev/ttyACM0 --signal step --amplitude 20 --start-s 0.5 --duration 3 -o step.csv\n"
        "  clearshape rig run --port /dev/ttyACM0 --mode speed --signal step --amplitude 1 --shaper zvdd \\\n"
        "      --shaper-frequency-hz 3.32 --shaper-zeta 0.288 --duration 3 -o zvdd.csv");
    p->callback([st] { execute(*st, "run", true); });
  }
}

const bool registered = cs::cli::register_command(
    {"rig", "The physical rig over a serial port: probe, stream the sensors, run a command", 45, setup});

}  // namespace
