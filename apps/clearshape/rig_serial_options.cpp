#include "rig_serial_options.hpp"

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <memory>
#include <string_view>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/wire_protocol.h"

namespace clearshape::cli {

void SerialCliOptions::add_to(CLI::App& sub, bool with_mode) {
  sub.add_option("--port", port, "Serial port of the rig board, e.g. /dev/ttyACM0 (or the emulator's /dev/pts/N)")
      ->required();
  sub.add_option("--baud", baud, "Baud rate, 9600 … 2000000")->capture_default_str();
  if (with_mode) {
    sub.add_option("--mode", mode, "Drive mode: position (pulse train, deg) or speed (analog, V)")
        ->check(CLI::IsMember({"position", "speed"}))
        ->capture_default_str();
  }
  sub.add_option("--rate", rate_hz, "Sample rate of the board (whole Hz, 100 … 2000)")->capture_default_str();
  sub.add_option("--update-hz", update_hz, "Position mode: pulse-train updates per second (whole Hz)")
      ->capture_default_str();
  sub.add_option("--max-pulse-hz", max_pulse_hz, "Position mode: pulse-rate cap (A/B edges/s, 1 … 45000: the board's limit at 1 kHz)")->capture_default_str();
  sub.add_option("--gyro-dlpf", gyro_dlpf, "ITG-3205 DLPF_CFG, 0 … 6 (0 = 256 Hz)")->capture_default_str();
  watchdog_option = sub.add_option("--watchdog-ms", watchdog_ms, "Command watchdog (ms; 0 = off, else 5 … 60000)")->capture_default_str();
  sub.add_option("--handshake-timeout-s", handshake_timeout_s, "Wait for each handshake answer (s, (0, 60])")
      ->capture_default_str();
  sub.add_option("--max-late-fraction", max_late_fraction,
                 "A run with more samples later than 5 ms than this fraction of its samples is degraded "
                 "(not complete), 0 … 1")
      ->capture_default_str();
  sub.add_option("--counts-per-rev", counts_per_rev, "Motor encoder counts per revolution (3000 lines x4)")
      ->capture_default_str();
  sub.add_option("--pulses-per-rev", pulses_per_rev, "Command pulses per motor revolution (the drive's electronic gear)")
      ->capture_default_str();
}

rig::SerialRigOptions SerialCliOptions::build() const {
  rig::SerialRigOptions o;
  o.port = port;
  o.baud = baud;
  o.mode = rig::command_mode_from_string(mode);
  o.sample_rate_hz = rate_hz;
  o.update_rate_hz = update_hz;
  if (max_pulse_hz < 1 || max_pulse_hz > CS_MAX_PULSE_RATE_HZ) {
    throw InvalidArgument(fmt::format("--max-pulse-hz = {} is out of range; allowed: 1 … {} (A/B edges/s, the "
                                      "board's limit at 1 kHz)", max_pulse_hz, CS_MAX_PULSE_RATE_HZ));
  }
  o.max_pulse_rate_hz = static_cast<std::uint32_t>(max_pulse_hz);
  o.max_late_fraction = max_late_fraction;
  o.gyro_dlpf_cfg = gyro_dlpf;
  o.watchdog_ms = watchdog_ms;
  o.handshake_timeout_s = handshake_timeout_s;
  o.counts_per_rev = counts_per_rev;
  o.pulses_per_rev = pulses_per_rev;
  try {
    o.validate();
  } catch (const InvalidArgument& e) {
    // The field names map to the options: sample_rate_hz → --rate, the rest by their own names.
    const std::string text = e.what();
    const std::string_view fields[][2] = {{"sample_rate_hz", "--rate"},           {"update_rate_hz", "--update-hz"},
                                          {"max_pulse_rate_hz", "--max-pulse-hz"}, {"gyro_dlpf_cfg", "--gyro-dlpf"},
                                          {"watchdog_ms", "--watchdog-ms"},       {"handshake_timeout_s", "--handshake-timeout-s"},
                                          {"max_late_fraction", "--max-late-fraction"},
                                          {"counts_per_rev", "--counts-per-rev"}, {"pulses_per_rev", "--pulses-per-rev"},
                                          {"baud", "--baud"},                     {"port", "--port"}};
    for (const auto& f : fields) {
      if (text.rfind(f[0], 0) == 0) throw InvalidArgument(std::string(f[1]) + text.substr(f[0].size()));
    }
    throw;
  }
  return o;
}

void parse_serial_rig_spec(const std::string& spec, rig::SerialRigOptions& options) {
  constexpr std::string_view prefix = "serial:";
  const auto fail = [&spec]() {
    throw InvalidArgument(fmt::format("--rig {}: allowed: serial:PORT, serial:PORT?baud=N (N in 9600 … 2000000) and "
                                      "&max_late_fraction=F (F in 0 … 1), e.g. serial:/dev/ttyACM0?baud=1000000",
                                      spec));
  };
  if (spec.rfind(prefix, 0) != 0) fail();
  std::string rest = spec.substr(prefix.size());
  const auto q = rest.find('?');
  if (q != std::string::npos) {
    std::string_view query(rest);
    query.remove_prefix(q + 1);
    while (!query.empty()) {
      const auto amp = query.find('&');
      const std::string_view item = query.substr(0, amp);
      query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
      const auto eq = item.find('=');
      if (eq == std::string_view::npos) fail();
      const std::string_view key = item.substr(0, eq);
      const std::string_view text = item.substr(eq + 1);
      if (key == "baud") {
        int value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || end != text.data() + text.size() || value < 9600 || value > 2'000'000) fail();
        options.baud = value;
      } else if (key == "max_late_fraction") {
        double value = 0.0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || end != text.data() + text.size() || !(value >= 0.0 && value <= 1.0)) fail();
        options.max_late_fraction = value;
      } else {
        fail();
      }
    }
    rest = rest.substr(0, q);
  }
  if (rest.empty()) fail();
  options.port = rest;
}

std::function<void(const rig::RunStatistics&, const rig::BoardRecord&)> board_progress_printer(
    const rig::SerialRig& rig, double duration_s) {
  const bool tty = isatty(fileno(stderr)) != 0;
  auto calls = std::make_shared<int>(0);
  return [&rig, duration_s, tty, calls](const rig::RunStatistics& s, const rig::BoardRecord& c) {
    if (!tty && ((*calls)++ % 5) != 0) return;  // ~5 Hz on a terminal (one line, rewritten); 1 Hz otherwise
    const rig::SerialRigStats link = rig.stats();
    fmt::print(stderr, "{}t {:7.2f}/{:g} s  samples {}  lost {}  corrupted {}  late {}  overruns {}  motor {:9.3f} deg  "
                       "gyro {:8.2f} deg/s{}",
               tty ? "\r" : "", c.last.time_s, duration_s, s.samples, link.samples_lost, link.frames_corrupted,
               link.samples_late, s.overruns, c.last.motor_angle_deg(), c.last.gyro_rate_deg_s(), tty ? "" : "\n");
  };
}

void end_progress_line() {
  if (isatty(fileno(stderr)) != 0) fmt::print(stderr, "\n");
}

}  // namespace clearshape::cli
