#pragma once
// The serial-rig options shared by `clearshape rig probe|stream|run` and `study --rig serial:PORT`:
// one flag per field of rig::SerialRigOptions that a user chooses.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "clearshape/rig/board_run.hpp"
#include "clearshape/rig/serial_rig.hpp"

namespace clearshape::cli {

struct SerialCliOptions {
  std::string port;
  int baud = 1'000'000;
  std::string mode = "position";
  double rate_hz = 1000.0;
  double update_hz = 30.0;
  long long max_pulse_hz = 45'000;  // CS_MAX_PULSE_RATE_HZ; signed so -1 is named with the real range
  int gyro_dlpf = 0;
  int watchdog_ms = 100;
  double handshake_timeout_s = 3.0;
  double max_late_fraction = 0.01;
  int counts_per_rev = 12'000;
  int pulses_per_rev = 12'000;
  CLI::Option* watchdog_option = nullptr;  ///< whether --watchdog-ms was given

  /// Adds --port (required), --baud, --rate, --update-hz, --max-pulse-hz, --gyro-dlpf,
  /// --watchdog-ms, --handshake-timeout-s, --max-late-fraction, --counts-per-rev, --pulses-per-rev and, with
  /// `with_mode`, --mode.
  void add_to(CLI::App& sub, bool with_mode);
  /// The rig options (validated: InvalidArgument names the command-line option).
  rig::SerialRigOptions build() const;
};

/// "serial:/dev/ttyACM0", "serial:/dev/ttyACM0?baud=115200" or with "&max_late_fraction=0.05" →
/// port, baud and the late-sample tolerance in `options`. Throws InvalidArgument naming --rig
/// and the accepted forms.
void parse_serial_rig_spec(const std::string& spec, rig::SerialRigOptions& options);

/// A run's progress on stderr for rig::BoardRunOptions::progress: one line rewritten about 5 times a
/// second on a terminal, once a second otherwise (time, samples, lost/corrupted/late, motor, gyro).
std::function<void(const rig::RunStatistics&, const rig::BoardRecord&)> board_progress_printer(
    const rig::SerialRig& rig, double duration_s);
/// Ends the rewritten progress line (a newline on a terminal).
void end_progress_line();

}  // namespace clearshape::cli
