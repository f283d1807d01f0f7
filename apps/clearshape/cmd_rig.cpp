// `clearshape rig probe|stream|run`: the physical rig (the thesis's Arduino Mega board, or the
// emulator running its firmware) over a serial port — rig::SerialRig driven by the real-time
// runner (rig/realtime.hpp). docs/hardware.md ("Host side") describes the set-up.
//   probe   handshake, firmware version, capabilities, self-test, the board's counters
//   stream  log the sensors for --duration s (no commands; servo off unless --servo-on)
//   run     one run of a command signal, optionally shaped online, logged to a CSV + sidecar
//   calibrate  excite, record, recommend and export in one command (cmd_rig_calibrate.cpp)
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
#include "clearshape/rig/board_run.hpp"
#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/wire_protocol.h"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/signal.hpp"
#include "cmd_rig_calibrate.hpp"
#include "command.hpp"
#include "rig_serial_options.hpp"
#include "run_json.hpp"
#include "signal_options.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using json = nlohmann::ordered_json;

namespace {

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
    doc["board"] = rig::board_json(r);
    doc["board_stats"] = rig::board_stats_json(stats);
    doc["selftest_passed"] = ok;
    cs::cli::print_json(doc);
  } else {
    const rig::BoardInfo& b = r.board();
    fmt::print("{:<16}{} ({})\n", "port", o.port, r.backend());
    fmt::print("{:<16}{}\n", "firmware", b.firmware_version());
    fmt::print("{:<16}v{}\n", "wire protocol", b.wire_version);
    fmt::print("{:<16}{} (0x{:02x})\n", "capabilities", rig::capability_names(b.capabilities), b.capabilities);
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

// --- write: the CSV with its sidecar, stdout, the verdict -----------------------------------------

json configuration_json(const rig::SerialRigOptions& o, const RunState& st) {
  json j = rig::board_configuration_json(o);
  j["duration_s"] = st.duration_s;
  j["realtime_scheduling"] = !st.no_realtime;
  return j;
}

void write_files(const std::filesystem::path& csv, const std::string& name, const RunState& st, const RunPlan& p,
                 const rig::SerialRig& r, const rig::RecordColumns& t, const rig::BoardRunOutcome& out,
                 const json& statistics) {
  auto doc = cs::io::make_document();
  doc["command"] = "rig " + name;
  doc["csv"] = csv.string();
  doc["complete"] = out.complete();
  doc["degraded"] = out.degraded;
  doc["columns"] = t.names;
  doc["units"] = rig::record_units_json(p.options);
  doc["rig"] = {{"kind", "physical"}, {"board", rig::board_json(r)}};
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
                   const rig::BoardRunOutcome& out, const json& statistics) {
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
                   const rig::BoardRunOutcome& out) {
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

// The options of the board run: the plan's command, warnings and progress on stderr.
rig::BoardRunOptions board_run_options(const RunState& st, const std::string& name, bool is_run, const RunPlan& p,
                                       const rig::SerialRig& r) {
  rig::BoardRunOptions o;
  o.command = p.command;
  o.shaper = p.shaper;
  o.write_commands = is_run;
  o.realtime_scheduling = !st.no_realtime;
  o.stop_flag = &cs::io::interrupt_requested();  // SIGINT/SIGTERM/SIGHUP: the loop ends, STOP is sent
  o.warn = [](const std::string& w) { fmt::print(stderr, "clearshape: warning: {}\n", w); };
  o.configured = [&st, name](const rig::SerialRig& b) {
    const rig::SerialRigOptions& so = b.options();
    fmt::print(stderr, "clearshape rig {}: {} firmware {} ({}), {} mode at {:g} Hz, {:g} s\n", name, so.port,
               b.board().firmware_version(), b.backend(), rig::to_string(so.mode), so.sample_rate_hz, st.duration_s);
  };
  o.progress = cs::cli::board_progress_printer(r, st.duration_s);
  return o;
}

void execute(const RunState& st, const std::string& name, bool is_run) {
  const RunPlan p = plan(st, name, is_run);
  // From here until the record is written, SIGINT/SIGTERM/SIGHUP/SIGPIPE end the loop instead of
  // the process: the board is sent STOP (servo off) on every way out, then the signal ends it.
  cs::io::DeferredInterrupts interrupts;
  rig::BoardRunOutcome out;
  std::filesystem::path csv;
  {
    rig::SerialRig r(p.options);  // its destructor sends STOP if an exception leaves it active
    rig::BoardRecord c;
    out = rig::run_on_board(r, board_run_options(st, name, is_run, p, r), c);
    cs::cli::end_progress_line();
    const rig::RecordColumns t = rig::record_columns(c, p.options.mode, is_run, p.shaper.has_value());
    const json statistics = rig::run_statistics_json(out, c, p.options);
    csv = rig::record_path_for(st.output, out.complete());
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

void setup_rig(CLI::App& sub) {
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
  cs::cli::add_rig_calibrate(sub);
}

const bool rig_registered = cs::cli::register_command(
    {"rig", "The physical rig over a serial port: probe, stream the sensors, run a command, calibrate a shaper", 45, setup_rig});

}  // namespace
