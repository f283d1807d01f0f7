// rig_soak: rig::RealtimeRunner at 1 kHz for a long time over one rig — the simulated thesis
// rig (rig::SimRig) or the board over a serial port (rig::SerialRig, e.g. clearshape-rig-emulator's
// pty) — with a repeating ±10° position square wave of 2 s period as the command. Prints one
// JSON object: lost samples, overruns, loop latency p50/p99/max and the link's counters.
// Driven by bench/rig-soak.sh (not part of `make test` or `make bench`).
//
//   rig_soak --rig sim|serial:PORT [--duration-s 600] [--rate-hz 1000] [--no-realtime]
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/sim_rig.hpp"

namespace rig = clearshape::rig;

namespace {

struct SoakOptions {
  std::string rig_spec;
  double duration_s = 600.0;
  double rate_hz = 1000.0;
  bool no_realtime = false;
};

// The rig under test; `serial` points into `rig` when it is a SerialRig (its counters are reported).
struct SoakRig {
  std::unique_ptr<rig::Rig> rig;
  rig::SerialRig* serial = nullptr;
};

// Parses the command line into `o`; returns the exit code when the program is to stop (--help or
// a bad option), nothing to go on.
std::optional<int> parse_options(int argc, char** argv, SoakOptions& o) {
  CLI::App app{"rig_soak: the real-time runner over a rig for a long run (bench/rig-soak.sh)"};
  app.add_option("--rig", o.rig_spec, "sim (rig::SimRig, thesis truth) or serial:PORT")->required();
  app.add_option("--duration-s", o.duration_s, "run length, s")->check(CLI::Range(1.0, 1e6))->capture_default_str();
  app.add_option("--rate-hz", o.rate_hz, "loop rate, Hz")->check(CLI::Range(100.0, 2000.0))->capture_default_str();
  app.add_flag("--no-realtime", o.no_realtime, "skip SCHED_FIFO and mlockall");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return std::nullopt;
}

SoakRig make_rig(const SoakOptions& o) {
  SoakRig r;
  if (o.rig_spec == "sim") {
    rig::SimRigOptions so;
    so.sample_rate_hz = o.rate_hz;
    r.rig = rig::make_sim_rig_with_truth(so, rig::builtin_truth("thesis", "--rig"));
  } else if (o.rig_spec.rfind("serial:", 0) == 0) {
    rig::SerialRigOptions so;
    so.port = o.rig_spec.substr(7);
    so.sample_rate_hz = o.rate_hz;
    so.read_timeout_s = 2.0;
    auto s = std::make_unique<rig::SerialRig>(so);
    r.serial = s.get();
    r.rig = std::move(s);
  } else {
    throw clearshape::InvalidArgument("--rig " + o.rig_spec + ": allowed: sim, serial:PORT");
  }
  return r;
}

// The runner over the rig for duration_s with a ±10° square wave of 2 s period as the command (a
// move every second, like a repeated study trial).
rig::RunStatistics run_soak(const SoakOptions& o, rig::Rig& r) {
  const auto cycles = static_cast<std::uint64_t>(o.duration_s * o.rate_hz + 0.5);
  std::vector<double> values(static_cast<std::size_t>(cycles));
  const auto half = static_cast<std::uint64_t>(o.rate_hz);
  for (std::uint64_t k = 0; k < cycles; ++k) values[k] = (k / half) % 2 == 0 ? 10.0 : -10.0;
  rig::CommandSource source(std::move(values), rig::CommandMode::position);
  rig::RealtimeOptions ro;
  ro.realtime_scheduling = !o.no_realtime;
  rig::RealtimeRunner runner(r, source, ro);
  return runner.run(cycles, [](const rig::LogRecord&) {});
}

nlohmann::ordered_json run_report(const SoakOptions& o, const rig::RunStatistics& s) {
  nlohmann::ordered_json j;
  j["rig"] = o.rig_spec;
  j["duration_s"] = o.duration_s;
  j["rate_hz"] = o.rate_hz;
  j["cycles"] = s.cycles;
  j["samples"] = s.samples;
  j["samples_lost"] = s.samples_lost;
  j["frames_corrupted"] = s.frames_corrupted;
  j["samples_late"] = s.samples_late;
  j["overruns"] = s.overruns;
  j["commands_coalesced"] = s.commands_coalesced;  // late cycles whose command a newer one superseded
  j["read_failures"] = s.read_failures;
  j["write_failures"] = s.write_failures;
  j["log_dropped"] = s.log_dropped;
  j["latency_p50_us"] = s.latency_p50_s * 1e6;
  j["latency_p99_us"] = s.latency_p99_s * 1e6;
  j["latency_max_us"] = s.latency_max_s * 1e6;
  j["latency_overflows"] = s.latency_overflows;
  j["sched_fifo"] = s.sched_fifo;
  j["memory_locked"] = s.memory_locked;
  j["stopped_by"] = s.stopped_by;
  j["complete"] = s.complete();
  return j;
}

// The host's link counters and the board's own (read from the board after the run).
void add_serial_report(nlohmann::ordered_json& j, rig::SerialRig& serial) {
  const rig::SerialRigStats l = serial.stats();
  j["link"] = {{"samples_lost", l.samples_lost},       {"frames_corrupted", l.frames_corrupted},
               {"samples_late", l.samples_late},       {"max_lateness_ms", l.max_lateness_s * 1e3},
               {"ring_overflows", l.ring_overflows},   {"commands_dropped", l.commands_dropped},
               {"board_tx_overflows", l.board_tx_overflows}};
  const rig::BoardStats b = serial.board_stats();
  j["board"] = {{"samples_sent", b.samples_sent},   {"samples_dropped", b.samples_dropped},
                {"rx_corrupted", b.rx_corrupted},   {"watchdog_trips", b.watchdog_trips},
                {"late_ticks", b.late_ticks}};
}

}  // namespace

int main(int argc, char** argv) {
  SoakOptions o;
  if (const auto exit_code = parse_options(argc, argv, o)) return *exit_code;
  try {
    SoakRig r = make_rig(o);
    const rig::RunStatistics s = run_soak(o, *r.rig);
    nlohmann::ordered_json j = run_report(o, s);
    if (r.serial != nullptr) add_serial_report(j, *r.serial);
    std::printf("%s\n", j.dump().c_str());
    return s.complete() ? 0 : 1;
  } catch (const clearshape::InvalidArgument& e) {
    std::fprintf(stderr, "rig_soak: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rig_soak: %s\n", e.what());
    return 1;
  }
}
