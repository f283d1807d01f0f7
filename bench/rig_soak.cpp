// rig_soak: rig::RealtimeRunner at 1 kHz for a long time over one rig — the simulated thesis
// rig (rig::SimRig) or the board over a serial port (rig::SerialRig, e.g. clearshape-rig-emulator's
// pty) — with a repeating ±10° position square wave of 2 s period as the command. Prints one
// JSON object: lost samples, overruns, loop latency p50/p99/max and the link's counters.
// Driven by bench/rig-soak.sh (not part of `make test` or `make bench`).
//
//   rig_soak --rig sim|serial:PORT [--duration-s 600] [--rate-hz 1000] [--no-realtime]
#include <cstdio>
#include <memory>
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

int main(int argc, char** argv) {
  CLI::App app{"rig_soak: the real-time runner over a rig for a long run (bench/rig-soak.sh)"};
  std::string rig_spec;
  double duration_s = 600.0;
  double rate_hz = 1000.0;
  bool no_realtime = false;
  app.add_option("--rig", rig_spec, "sim (rig::SimRig, thesis truth) or serial:PORT")->required();
  app.add_option("--duration-s", duration_s, "run length, s")->check(CLI::Range(1.0, 1e6))->capture_default_str();
  app.add_option("--rate-hz", rate_hz, "loop rate, Hz")->check(CLI::Range(100.0, 2000.0))->capture_default_str();
  app.add_flag("--no-realtime", no_realtime, "skip SCHED_FIFO and mlockall");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    std::unique_ptr<rig::Rig> r;
    rig::SerialRig* serial = nullptr;
    if (rig_spec == "sim") {
      rig::SimRigOptions o;
      o.sample_rate_hz = rate_hz;
      r = rig::make_sim_rig_with_truth(o, rig::builtin_truth("thesis", "--rig"));
    } else if (rig_spec.rfind("serial:", 0) == 0) {
      rig::SerialRigOptions o;
      o.port = rig_spec.substr(7);
      o.sample_rate_hz = rate_hz;
      o.read_timeout_s = 2.0;
      auto s = std::make_unique<rig::SerialRig>(o);
      serial = s.get();
      r = std::move(s);
    } else {
      std::fprintf(stderr, "rig_soak: --rig %s: allowed: sim, serial:PORT\n", rig_spec.c_str());
      return 2;
    }
    const auto cycles = static_cast<std::uint64_t>(duration_s * rate_hz + 0.5);
    // ±10° square wave, 2 s period (a move every second, like a repeated study trial).
    std::vector<double> values(static_cast<std::size_t>(cycles));
    const auto half = static_cast<std::uint64_t>(rate_hz);
    for (std::uint64_t k = 0; k < cycles; ++k) values[k] = (k / half) % 2 == 0 ? 10.0 : -10.0;
    rig::CommandSource source(std::move(values), rig::CommandMode::position);
    rig::RealtimeOptions ro;
    ro.realtime_scheduling = !no_realtime;
    rig::RealtimeRunner runner(*r, source, ro);
    const rig::RunStatistics s = runner.run(cycles, [](const rig::LogRecord&) {});
    nlohmann::ordered_json j;
    j["rig"] = rig_spec;
    j["duration_s"] = duration_s;
    j["rate_hz"] = rate_hz;
    j["cycles"] = s.cycles;
    j["samples"] = s.samples;
    j["samples_lost"] = s.samples_lost;
    j["frames_corrupted"] = s.frames_corrupted;
    j["samples_late"] = s.samples_late;
    j["overruns"] = s.overruns;
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
    if (serial != nullptr) {
      const rig::SerialRigStats l = serial->stats();
      j["link"] = {{"samples_lost", l.samples_lost},       {"frames_corrupted", l.frames_corrupted},
                   {"samples_late", l.samples_late},       {"max_lateness_ms", l.max_lateness_s * 1e3},
                   {"ring_overflows", l.ring_overflows},   {"commands_dropped", l.commands_dropped},
                   {"board_tx_overflows", l.board_tx_overflows}};
      const rig::BoardStats b = serial->board_stats();
      j["board"] = {{"samples_sent", b.samples_sent},   {"samples_dropped", b.samples_dropped},
                    {"rx_corrupted", b.rx_corrupted},   {"watchdog_trips", b.watchdog_trips},
                    {"late_ticks", b.late_ticks}};
    }
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
