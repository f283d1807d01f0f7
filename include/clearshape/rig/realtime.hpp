#pragma once
// A real-time runner for any rig: a fixed-period loop on absolute deadlines
// (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), deadline k = start + k·T), in its own thread
// under SCHED_FIFO with the process's memory locked (mlockall) when permitted — otherwise one
// warning line and the same loop at normal priority. Each cycle:
//
//   wait for deadline k → rig.read() → command source (a precomputed series, optionally shaped
//   online by shaping::StreamingShaper) → rig.write() → push a LogRecord to a lock-free SPSC ring
//
// A logging thread (the caller's) pops the ring and hands each record to a sink (formatting,
// files): disk I/O never blocks the loop; a full ring drops the record and counts it. The cycle
// is noexcept and allocation-free. Statistics: samples, lost, corrupted, late (the rig's link
// counters), overruns (a cycle that found its deadline passed), read/write failures, dropped log
// records and the cycle latency (deadline → write done) p50/p99/max from a preallocated
// histogram of 1 µs bins. A late loop catching up sends only its newest commands: a cycle that
// found its deadline passed while the rig already holds coalesce_backlog_samples or more newer
// samples writes nothing (a newer cycle's command follows at once; counted as
// commands_coalesced), so a host stall never becomes a burst of COMMAND frames that overruns the
// board's receive queue.
//
//   rig::CommandSource source(values, rig::CommandMode::position);    // deg or V per sample
//   rig::RealtimeRunner runner(rig, source, {});
//   const rig::RunStatistics s = runner.run(cycles, [&](const rig::LogRecord& r) { ... });
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clearshape/rig/rig.hpp"
#include "clearshape/rig/spsc_ring.hpp"
#include "clearshape/shaping/streaming.hpp"

namespace clearshape::rig {

/// The command of each cycle: values[k] at cycle k (the last value held after the end), in
/// command units — deg in position mode, V in speed mode — optionally through a shaper.
class CommandSource {
 public:
  CommandSource(std::vector<double> values, CommandMode mode);
  /// Shapes the series online (StreamingShaper at `sample_time_s`, history at values[0]).
  void set_shaper(const shaping::Shaper& shaper, double sample_time_s);
  /// Rewinds to cycle 0 (and refills the shaper's history).
  void reset() noexcept;
  /// The command of the next cycle (unshaped, shaped). Real-time safe.
  void next(double& requested, double& shaped) noexcept;
  Command command(double value) const noexcept;
  CommandMode mode() const noexcept { return mode_; }
  std::size_t size() const noexcept { return values_.size(); }
  bool shaped() const noexcept { return shaper_ != nullptr; }

 private:
  std::vector<double> values_;
  CommandMode mode_;
  std::unique_ptr<shaping::StreamingShaper> shaper_;
  std::size_t k_ = 0;
};

struct RealtimeOptions {
  bool realtime_scheduling = true;  ///< try SCHED_FIFO and mlockall (false: skip both, no warning)
  int priority = 80;                ///< SCHED_FIFO priority, [1, 99]
  std::size_t log_capacity = 1u << 15;  ///< records between the loop and the logger, [16, 2^24]
  double latency_range_s = 0.02;    ///< histogram range (1 µs bins; beyond it counts as overflow), (0, 1]
  double status_interval_s = 0.2;   ///< status callback period (~5 Hz), (0, 60]
  bool write_commands = true;       ///< false: read only (sensor logging; the rig holds its safe command)
  /// A late cycle writes no command while at least this many newer samples wait in the rig
  /// (coalesce_command()); 0: never coalesce. [0, 2^20]. The default, 8, keeps the newest 8
  /// commands of a catch-up: more than the 5 the board's next updates choose from (each update
  /// plans to the newest COMMAND at least 4 ticks old, docs/hardware.md), so the board applies
  /// what it would have without coalescing, in 112 bytes, an eighth of its receive queue; and
  /// samples that merely arrive 2–3 at a time (a pty, a USB bridge) are never coalesced.
  std::size_t coalesce_backlog_samples = 8;
  /// Polled before every cycle (a lock-free load): once it reads true the loop ends, the rig is
  /// deactivated as after the last cycle (the serial rig: STOP, servo off) and stopped_by says
  /// so. The CLI passes io::interrupt_requested(), so SIGINT/SIGTERM end a run this way.
  const std::atomic<bool>* stop_flag = nullptr;
  /// Where warnings go (default: one line on stderr, "clearshape: warning: …").
  std::function<void(const std::string&)> warn;
  void validate() const;            ///< throws InvalidArgument naming the field
};

/// One cycle, as the loop logged it.
struct LogRecord {
  std::uint64_t cycle = 0;
  double command = 0.0;          ///< requested (command units)
  double command_shaped = 0.0;   ///< written (= command without a shaper)
  Measurement measurement;
  Status read_status = Status::ok;
  Status write_status = Status::ok;
  double latency_s = 0.0;        ///< deadline → write() returned
  bool command_coalesced = false;  ///< not written: the loop was late, newer cycles followed at once
};

/// The coalescing decision of one cycle: its command is not written when the loop is behind its
/// schedule (the deadline had passed) and the rig already holds `backlog_samples` (> 0) or more
/// newer samples — the next cycles run at once and write newer commands. A device merely ahead
/// of an on-time loop (a standing backlog from clock drift) is never coalesced, so commands keep
/// flowing.
constexpr bool coalesce_command(bool behind_schedule, std::size_t samples_waiting,
                                std::size_t backlog_samples) noexcept {
  return behind_schedule && backlog_samples > 0 && samples_waiting >= backlog_samples;
}

struct RunStatistics {
  std::uint64_t cycles = 0;             ///< cycles run
  std::uint64_t samples = 0;            ///< successful reads
  std::uint64_t samples_lost = 0;       ///< from the rig's link (gaps in the device's tick)
  std::uint64_t frames_corrupted = 0;   ///< from the rig's link
  std::uint64_t samples_late = 0;       ///< from the rig's link
  std::uint64_t overruns = 0;           ///< cycles that found their deadline already passed
  std::uint64_t read_failures = 0;
  std::uint64_t write_failures = 0;     ///< write() other than ok (clipped, rejected, port busy)
  std::uint64_t log_dropped = 0;        ///< records the full ring could not take
  std::uint64_t commands_coalesced = 0; ///< late cycles whose command newer ones superseded (not written)
  double latency_p50_s = 0.0, latency_p99_s = 0.0, latency_max_s = 0.0;
  std::uint64_t latency_overflows = 0;  ///< latencies beyond latency_range_s
  bool sched_fifo = false;              ///< the loop ran under SCHED_FIFO
  bool memory_locked = false;           ///< mlockall succeeded
  double period_s = 0.0;
  std::string stopped_by;               ///< "" (all cycles), or why the loop stopped early
  bool stopped_on_request = false;      ///< the stop flag ended the loop (an interrupt)
  /// True when the record is complete: every cycle read a sample and none was lost.
  bool complete() const noexcept { return stopped_by.empty() && samples == cycles && samples_lost == 0; }
};

class RealtimeRunner {
 public:
  using Sink = std::function<void(const LogRecord&)>;
  using StatusFn = std::function<void(const RunStatistics&)>;

  /// Allocates the ring and the histogram; throws InvalidArgument on bad options.
  RealtimeRunner(Rig& rig, CommandSource& source, const RealtimeOptions& options);
  ~RealtimeRunner();

  /// Runs `cycles` cycles: configure (if needed) and activate the rig, the loop in a real-time
  /// thread, the sink and `status` (every status_interval_s) in this thread, then deactivate.
  /// Throws RuntimeError when the rig does not configure or activate; a failing read or the
  /// stop flag ends the loop early (statistics().stopped_by says why). Whatever ends the run —
  /// an exception from the sink or `status` included — the loop is stopped and the rig
  /// deactivated before run() returns or throws.
  RunStatistics run(std::uint64_t cycles, const Sink& sink, const StatusFn& status = {});

  // The steps run() takes, for tests and custom loops.
  void begin();                        ///< configure/activate the rig, clock at t = 0
  bool cycle() noexcept;               ///< one period; false when the rig failed (stop)
  bool pop(LogRecord& record) noexcept;///< the logger's side of the ring
  RunStatistics end();                 ///< deactivate; the statistics of the run
  RunStatistics statistics() const noexcept;  ///< so far (any thread; approximate while running)

 private:
  struct State;
  Rig& rig_;
  CommandSource& source_;
  RealtimeOptions options_;
  std::unique_ptr<State> state_;
};

}  // namespace clearshape::rig
