// The real-time runner (rig/realtime.hpp): the loop thread, the logger side and the statistics.
#include "clearshape/rig/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::rig {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

std::int64_t monotonic_ns() noexcept {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * kNsPerS + t.tv_nsec;
}

void sleep_until_ns(std::int64_t deadline_ns) noexcept {
  const timespec t{static_cast<time_t>(deadline_ns / kNsPerS), static_cast<long>(deadline_ns % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

}  // namespace

// --- CommandSource ---------------------------------------------------------------------------

CommandSource::CommandSource(std::vector<double> values, CommandMode mode) : values_(std::move(values)), mode_(mode) {
  if (values_.empty()) throw InvalidArgument("CommandSource: the command series is empty");
  for (std::size_t k = 0; k < values_.size(); ++k) {
    if (!std::isfinite(values_[k])) throw InvalidArgument(fmt::format("CommandSource: sample {} is not finite", k));
  }
}

void CommandSource::set_shaper(const shaping::Shaper& shaper, double sample_time_s) {
  shaper_ = std::make_unique<shaping::StreamingShaper>(shaper, sample_time_s, values_.front());
  k_ = 0;
}

void CommandSource::reset() noexcept {
  k_ = 0;
  if (shaper_) shaper_->reset(values_.front());
}

void CommandSource::next(double& requested, double& shaped) noexcept {
  requested = values_[k_ < values_.size() ? k_ : values_.size() - 1];
  ++k_;
  shaped = shaper_ ? shaper_->step(requested) : requested;
}

Command CommandSource::command(double value) const noexcept {
  return mode_ == CommandMode::position ? Command::position_deg(value) : Command::speed_v(value);
}

// --- options ---------------------------------------------------------------------------------

void RealtimeOptions::validate() const {
  if (priority < 1 || priority > 99) throw_invalid("priority", priority, "1 … 99");
  if (log_capacity < 16 || log_capacity > (1u << 24)) throw_invalid("log_capacity", static_cast<double>(log_capacity), "16 … 16777216");
  if (!(std::isfinite(latency_range_s) && latency_range_s > 0.0 && latency_range_s <= 1.0)) {
    throw_invalid("latency_range_s", latency_range_s, "(0, 1] s");
  }
  if (!(std::isfinite(status_interval_s) && status_interval_s > 0.0 && status_interval_s <= 60.0)) {
    throw_invalid("status_interval_s", status_interval_s, "(0, 60] s");
  }
  if (coalesce_backlog_samples > (1u << 20)) {
    throw_invalid("coalesce_backlog_samples", static_cast<double>(coalesce_backlog_samples), "0 (never) … 1048576");
  }
}

// --- runner ----------------------------------------------------------------------------------

struct RealtimeRunner::State {
  State(std::size_t log_capacity, std::size_t bins) : ring(log_capacity), histogram(bins, 0) {}
  SpscRing<LogRecord> ring;
  std::vector<std::uint32_t> histogram;  // 1 µs bins
  std::int64_t period_ns = 0;
  std::int64_t start_ns = 0;
  std::atomic<std::uint64_t> cycles{0}, samples{0}, overruns{0}, read_failures{0}, write_failures{0}, log_dropped{0},
      latency_overflows{0}, coalesced{0};
  std::atomic<std::int64_t> latency_max_ns{0};
  std::atomic<bool> sched_fifo{false};
  bool memory_locked = false;
  std::atomic<bool> abort{false};              // run() ends the loop (the sink threw)
  std::atomic<bool> stopped_on_request{false};  // the options' stop flag ended it
  std::string stopped_by;
  Status failed_read = Status::ok;
};

RealtimeRunner::RealtimeRunner(Rig& rig, CommandSource& source, const RealtimeOptions& options)
    : rig_(rig), source_(source), options_(options) {
  options_.validate();
  const auto bins = static_cast<std::size_t>(std::ceil(options_.latency_range_s * 1e6));
  state_ = std::make_unique<State>(options_.log_capacity, bins);
  if (source_.mode() != rig_.mode()) {
    throw InvalidArgument(fmt::format("realtime runner: the command is for {} mode but the rig runs in {} mode",
                                      to_string(source_.mode()), to_string(rig_.mode())));
  }
}

RealtimeRunner::~RealtimeRunner() = default;

void RealtimeRunner::begin() {
  State& s = *state_;
  if (rig_.state() == LifecycleState::unconfigured && rig_.configure() != Status::ok) {
    throw RuntimeError(fmt::format("realtime runner: the rig '{}' did not configure", rig_.name()));
  }
  if (rig_.activate() != Status::ok) {
    throw RuntimeError(fmt::format("realtime runner: the rig '{}' did not activate (state {})", rig_.name(),
                                   to_string(rig_.state())));
  }
  source_.reset();
  s.ring.clear();
  std::fill(s.histogram.begin(), s.histogram.end(), 0u);
  s.cycles = s.samples = s.overruns = s.read_failures = s.write_failures = s.log_dropped = s.latency_overflows = 0;
  s.coalesced = 0;
  s.latency_max_ns = 0;
  s.stopped_by.clear();
  s.abort = false;
  s.stopped_on_request = false;
  s.failed_read = Status::ok;
  s.period_ns = static_cast<std::int64_t>(std::llround(rig_.sample_time_s() * 1e9));
  s.start_ns = monotonic_ns();  // t = 0 at activation: a self-pacing rig (the board) starts its clock there
}

bool RealtimeRunner::cycle() noexcept {
  State& s = *state_;
  const std::uint64_t k = s.cycles.load(std::memory_order_relaxed);
  const std::int64_t deadline = s.start_ns + static_cast<std::int64_t>(k) * s.period_ns;
  const bool late = monotonic_ns() > deadline;
  if (late) {
    s.overruns.fetch_add(1, std::memory_order_relaxed);  // no catch-up skipping: every sample is read
  } else {
    sleep_until_ns(deadline);
  }
  LogRecord r;
  r.cycle = k;
  r.read_status = rig_.read(r.measurement);
  source_.next(r.command, r.command_shaped);
  if (r.read_status == Status::ok) {
    s.samples.fetch_add(1, std::memory_order_relaxed);
    r.command_coalesced = options_.write_commands &&
                          coalesce_command(late, rig_.samples_waiting(), options_.coalesce_backlog_samples);
    if (r.command_coalesced) s.coalesced.fetch_add(1, std::memory_order_relaxed);
    const bool write = options_.write_commands && !r.command_coalesced;
    r.write_status = write ? rig_.write(source_.command(r.command_shaped)) : Status::ok;
    if (r.write_status != Status::ok) s.write_failures.fetch_add(1, std::memory_order_relaxed);
  } else {
    s.read_failures.fetch_add(1, std::memory_order_relaxed);
    r.write_status = Status::not_ready;
  }
  const std::int64_t latency = monotonic_ns() - deadline;
  r.latency_s = static_cast<double>(latency) * 1e-9;
  const auto bin = static_cast<std::size_t>(latency < 0 ? 0 : latency / 1000);
  if (bin < s.histogram.size()) {
    ++s.histogram[bin];
  } else {
    s.latency_overflows.fetch_add(1, std::memory_order_relaxed);
  }
  if (latency > s.latency_max_ns.load(std::memory_order_relaxed)) s.latency_max_ns.store(latency, std::memory_order_relaxed);
  if (!s.ring.push(r)) s.log_dropped.fetch_add(1, std::memory_order_relaxed);
  s.cycles.store(k + 1, std::memory_order_release);
  if (r.read_status == Status::device_error || r.read_status == Status::not_ready) {
    s.failed_read = r.read_status;
    return false;
  }
  return true;
}

bool RealtimeRunner::pop(LogRecord& record) noexcept { return state_->ring.pop(record); }

RunStatistics RealtimeRunner::statistics() const noexcept {
  const State& s = *state_;
  RunStatistics out;
  out.cycles = s.cycles.load(std::memory_order_acquire);
  out.samples = s.samples.load(std::memory_order_relaxed);
  const LinkCounters link = rig_.link_counters();
  out.samples_lost = link.samples_lost;
  out.frames_corrupted = link.frames_corrupted;
  out.samples_late = link.samples_late;
  out.overruns = s.overruns.load(std::memory_order_relaxed);
  out.read_failures = s.read_failures.load(std::memory_order_relaxed);
  out.write_failures = s.write_failures.load(std::memory_order_relaxed);
  out.log_dropped = s.log_dropped.load(std::memory_order_relaxed);
  out.commands_coalesced = s.coalesced.load(std::memory_order_relaxed);
  out.latency_overflows = s.latency_overflows.load(std::memory_order_relaxed);
  out.latency_max_s = static_cast<double>(s.latency_max_ns.load(std::memory_order_relaxed)) * 1e-9;
  out.sched_fifo = s.sched_fifo.load(std::memory_order_relaxed);
  out.memory_locked = s.memory_locked;
  out.period_s = static_cast<double>(s.period_ns) * 1e-9;
  return out;
}

RunStatistics RealtimeRunner::end() {
  State& s = *state_;
  rig_.deactivate();
  RunStatistics out = statistics();
  // Percentiles from the histogram: the upper edge of the bin holding the q-th latency.
  std::uint64_t total = out.latency_overflows;
  for (const auto c : s.histogram) total += c;
  auto percentile = [&](double q) {
    if (total == 0) return 0.0;
    const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total)));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < s.histogram.size(); ++b) {
      seen += s.histogram[b];
      if (seen >= rank) return static_cast<double>(b + 1) * 1e-6;
    }
    return out.latency_max_s;  // in the overflow
  };
  out.latency_p50_s = percentile(0.50);
  out.latency_p99_s = percentile(0.99);
  out.stopped_by = s.stopped_by;
  out.stopped_on_request = s.stopped_on_request.load();
  return out;
}

namespace {

void warn(const RealtimeOptions& o, const std::string& text) {
  if (o.warn) {
    o.warn(text);
  } else {
    fmt::print(stderr, "clearshape: warning: {}\n", text);
  }
}

std::string fifo_refused(int error) {
  return fmt::format("real-time scheduling not permitted (SCHED_FIFO: {}); the loop runs at normal priority",
                     std::strerror(error));
}

// mlockall when real-time scheduling is asked for; a warning (the same loop) when refused.
bool lock_memory(const RealtimeOptions& o) {
  if (!o.realtime_scheduling) return false;
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return true;
  warn(o, fmt::format("memory not locked (mlockall: {}); page faults may delay the loop", std::strerror(errno)));
  return false;
}

// Shared by the loop thread and the logger while a run starts and goes.
struct Handshake {
  std::atomic<bool> done{false};
  std::atomic<int> phase{0};  // 0: wait, 1: run, 2: give up (activation failed)
  int sched_error = 0;        // pthread_setschedparam's result in the loop thread
};

// The loop thread: SCHED_FIFO when asked, then it waits for the go and runs `cycles` cycles
// (until one fails, the stop flag is raised or run() aborts).
void run_loop(RealtimeRunner& runner, const RealtimeOptions& o, std::uint64_t cycles, Handshake& h,
              std::atomic<bool>& sched_fifo, const std::atomic<bool>& abort,
              std::atomic<bool>& stopped_on_request) noexcept {
  if (o.realtime_scheduling) {
    sched_param p{};
    p.sched_priority = o.priority;
    h.sched_error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    sched_fifo = h.sched_error == 0;
  }
  while (h.phase.load(std::memory_order_acquire) == 0) {
    const timespec pause{0, 20'000};
    nanosleep(&pause, nullptr);
  }
  if (h.phase.load(std::memory_order_acquire) == 1) {
    for (std::uint64_t k = 0; k < cycles; ++k) {
      if (o.stop_flag != nullptr && o.stop_flag->load(std::memory_order_relaxed)) {
        stopped_on_request.store(true, std::memory_order_relaxed);
        break;
      }
      if (abort.load(std::memory_order_relaxed) || !runner.cycle()) break;
    }
  }
  h.done.store(true, std::memory_order_release);
}

void drain(RealtimeRunner& runner, const RealtimeRunner::Sink& sink) {
  LogRecord r;
  while (runner.pop(r)) sink(r);
}

// The logger: drains the ring into the sink until the loop is done, calls `status` about every
// interval and warns once the loop has run if SCHED_FIFO was refused. Returns whether it warned.
bool log_until_done(RealtimeRunner& runner, const RealtimeOptions& o, const Handshake& h,
                    const std::atomic<std::uint64_t>& ran, const RealtimeRunner::Sink& sink,
                    const RealtimeRunner::StatusFn& status) {
  const auto interval_ns = static_cast<std::int64_t>(o.status_interval_s * 1e9);
  std::int64_t next_status = monotonic_ns() + interval_ns;
  bool warned = false;
  while (!h.done.load(std::memory_order_acquire)) {
    drain(runner, sink);
    if (!warned && o.realtime_scheduling && ran.load(std::memory_order_acquire) > 0) {
      warned = true;
      if (h.sched_error != 0) warn(o, fifo_refused(h.sched_error));
    }
    if (status && monotonic_ns() >= next_status) {
      status(runner.statistics());
      next_status += interval_ns;
    }
    const timespec pause{0, 2'000'000};
    nanosleep(&pause, nullptr);
  }
  return warned;
}

}  // namespace

RunStatistics RealtimeRunner::run(std::uint64_t cycles, const Sink& sink, const StatusFn& status) {
  State& s = *state_;
  s.sched_fifo = false;
  s.memory_locked = lock_memory(options_);
  // The loop thread is made and set up (scheduling, its stack locked) before the rig is
  // activated, so that its first cycle follows activation at once: a rig that paces itself (the
  // board, a wall-clock SimRig) starts its clock at activation, and the schedule starts there too.
  Handshake h;
  std::thread loop([&] { run_loop(*this, options_, cycles, h, s.sched_fifo, s.abort, s.stopped_on_request); });
  try {
    begin();
  } catch (...) {
    h.phase.store(2, std::memory_order_release);
    loop.join();
    if (s.memory_locked) munlockall();
    throw;
  }
  h.phase.store(1, std::memory_order_release);
  bool warned = false;
  try {
    warned = log_until_done(*this, options_, h, s.cycles, sink, status);
    loop.join();
    drain(*this, sink);
  } catch (...) {
    // The logger failed (the sink or status threw): the loop stops and the rig is deactivated
    // (the serial rig: STOP, servo off) before the exception leaves.
    s.abort.store(true);
    if (loop.joinable()) loop.join();
    (void)end();
    if (s.memory_locked) munlockall();
    throw;
  }
  if (!warned && options_.realtime_scheduling && h.sched_error != 0) warn(options_, fifo_refused(h.sched_error));
  const std::uint64_t ran = s.cycles.load(std::memory_order_acquire);
  if (s.stopped_on_request.load()) {
    s.stopped_by = fmt::format("stopped on request (an interrupt) after {} of {} cycles", ran, cycles);
  } else if (ran < cycles) {
    s.stopped_by = fmt::format("the rig's read failed at cycle {} ({})", ran - 1, to_string(s.failed_read));
  }
  RunStatistics out = end();
  if (s.memory_locked) munlockall();
  if (status) status(out);
  return out;
}

}  // namespace clearshape::rig
