// rig::RealtimeRunner on rig::SimRig (wall-clock pacing, short runs) and on SerialRig with the
// board double: the loop feeds the rig exactly as a plain read/write loop does, online shaping
// equals shape_offline, the statistics count what happened, the real-time set-up falls back with
// a warning when it is not permitted, and the cycle allocates nothing.
#include <gtest/gtest.h>

#include <linux/capability.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/board_double.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using cs::Status;

namespace {

std::vector<double> step_deg(std::size_t n, std::size_t at, double amplitude) {
  std::vector<double> v(n, 0.0);
  for (std::size_t k = at; k < n; ++k) v[k] = amplitude;
  return v;
}

rig::SimRigOptions wall_clock(rig::CommandMode mode = rig::CommandMode::position) {
  rig::SimRigOptions o;
  o.mode = mode;
  o.pacing = rig::Pacing::wall_clock;
  o.seed = 7;
  return o;
}

// A rig that reads slowly on some cycles (overruns) and fails on one (the loop stops).
class SlowRig final : public rig::Rig {
 public:
  int slow_cycle = -1;
  int fail_cycle = -1;
  int deactivations = 0;
  double sample_time_s() const noexcept override { return 1e-3; }
  rig::CommandMode mode() const noexcept override { return rig::CommandMode::position; }
  std::string_view name() const noexcept override { return "slow"; }

 protected:
  void on_configure() override {}
  void on_activate() override { k_ = 0; }
  void on_deactivate() noexcept override { ++deactivations; }
  void on_cleanup() noexcept override {}
  Status on_read(rig::Measurement& m) noexcept override {
    if (k_ == fail_cycle) return Status::device_error;
    if (k_ == slow_cycle) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    m.sequence = static_cast<std::uint64_t>(k_++);
    return Status::ok;
  }
  Status on_write(const rig::Command&) noexcept override { return Status::ok; }

 private:
  int k_ = 0;
};

// A device that queues its samples, as the serial rig's receive ring does: the test sets how
// many wait; each read takes the oldest; the commands written are kept (storage reserved by the
// test, so the cycle still allocates nothing).
class QueueRig final : public rig::Rig {
 public:
  std::size_t queued = 0;
  std::vector<double> written_rad;
  double sample_time_s() const noexcept override { return 1e-3; }
  rig::CommandMode mode() const noexcept override { return rig::CommandMode::position; }
  std::string_view name() const noexcept override { return "queue"; }
  std::size_t samples_waiting() const noexcept override { return queued; }

 protected:
  void on_configure() override {}
  void on_activate() override { k_ = 0; }
  void on_deactivate() noexcept override {}
  void on_cleanup() noexcept override {}
  Status on_read(rig::Measurement& m) noexcept override {
    if (queued == 0) return Status::device_error;
    --queued;
    m.sequence = k_++;
    return Status::ok;
  }
  Status on_write(const rig::Command& c) noexcept override {
    written_rad.push_back(c.value);
    return Status::ok;
  }

 private:
  std::uint64_t k_ = 0;
};

// Cycles 0–9 on time, one sample each; then the loop stalls 30 ms and 30 samples wait. The
// catch-up cycles 10–39 each find their deadline passed; 10–31 also find 8 or more newer samples
// waiting: their commands are coalesced (not written); 32–39 write theirs, the newest 8. Returns
// the written commands (deg) and the statistics; the catch-up allocates nothing.
struct CatchUp {
  std::vector<double> written_deg;
  std::vector<bool> coalesced;
  rig::RunStatistics stats;
  std::size_t allocations = 0;
};
CatchUp catch_up_after_a_stall(std::size_t backlog_samples) {
  QueueRig q;
  q.written_rad.reserve(64);
  std::vector<double> ramp(40);
  for (std::size_t k = 0; k < ramp.size(); ++k) ramp[k] = static_cast<double>(k);
  rig::CommandSource source(ramp, rig::CommandMode::position);
  rig::RealtimeOptions options;
  options.realtime_scheduling = false;
  options.coalesce_backlog_samples = backlog_samples;
  rig::RealtimeRunner runner(q, source, options);
  runner.begin();
  for (int k = 0; k < 10; ++k) {
    q.queued = 1;
    EXPECT_TRUE(runner.cycle());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  q.queued = 30;
  CatchUp out;
  {
    cs::testing::AllocationCounter counter;
    for (int k = 0; k < 30; ++k) EXPECT_TRUE(runner.cycle());
    out.allocations = counter.allocations();
  }
  out.stats = runner.end();
  rig::LogRecord r;
  while (runner.pop(r)) out.coalesced.push_back(r.command_coalesced);
  for (const double v : q.written_rad) out.written_deg.push_back(cs::rad_to_deg(v));
  return out;
}

TEST(RealtimeRunner, CoalescingDecision) {
  EXPECT_FALSE(rig::coalesce_command(false, 0, 8));
  EXPECT_FALSE(rig::coalesce_command(false, 500, 8));  // on time, device ahead (clock drift): write
  EXPECT_FALSE(rig::coalesce_command(true, 0, 8));     // late, but this is the newest sample: write
  EXPECT_FALSE(rig::coalesce_command(true, 7, 8));     // late, among the newest 8: write
  EXPECT_TRUE(rig::coalesce_command(true, 8, 8));      // late, 8 newer samples wait: coalesce
  EXPECT_TRUE(rig::coalesce_command(true, 1, 1));
  EXPECT_FALSE(rig::coalesce_command(true, 500, 0));   // 0: never
}

TEST(RealtimeRunner, ALateLoopWritesOnlyItsNewestCommands) {
  const CatchUp c = catch_up_after_a_stall(8);
  EXPECT_EQ(c.allocations, 0u);
  EXPECT_EQ(c.stats.samples, 40u);
  EXPECT_EQ(c.stats.commands_coalesced, 22u);
  EXPECT_EQ(c.stats.write_failures, 0u);
  ASSERT_EQ(c.written_deg.size(), 18u);
  for (std::size_t k = 0; k < 10; ++k) EXPECT_NEAR(c.written_deg[k], static_cast<double>(k), 1e-9) << k;
  for (std::size_t k = 10; k < 18; ++k) EXPECT_NEAR(c.written_deg[k], static_cast<double>(k + 22), 1e-9) << k;
  ASSERT_EQ(c.coalesced.size(), 40u);
  for (std::size_t k = 0; k < 40; ++k) EXPECT_EQ(c.coalesced[k], k >= 10 && k < 32) << "cycle " << k;
  // Only the newest: a backlog of 1 keeps cycle 39's command alone.
  const CatchUp newest = catch_up_after_a_stall(1);
  EXPECT_EQ(newest.stats.commands_coalesced, 29u);
  ASSERT_EQ(newest.written_deg.size(), 11u);
  EXPECT_NEAR(newest.written_deg[10], 39.0, 1e-9);
  // The control: without coalescing the catch-up writes one command per cycle (the burst).
  const CatchUp every = catch_up_after_a_stall(0);
  EXPECT_EQ(every.stats.commands_coalesced, 0u);
  EXPECT_EQ(every.written_deg.size(), 40u);
}

TEST(RealtimeRunner, FeedsTheRigLikeAPlainLoopAndPacesOnTheWallClock) {
  const std::size_t n = 300;
  const auto command = step_deg(n, 20, 5.0);
  // Reference: the same rig and seed in a plain read → write loop, as fast as possible.
  rig::SimRigOptions fast = wall_clock();
  fast.pacing = rig::Pacing::as_fast_as_possible;
  rig::SimRig reference(fast);
  reference.configure();
  reference.activate();
  std::vector<std::int64_t> counts;
  std::vector<std::int16_t> gyro;
  rig::Measurement m;
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(reference.read(m), Status::ok);
    counts.push_back(m.encoder_counts);
    gyro.push_back(m.gyro_raw);
    reference.write(rig::Command::position_deg(command[k]));
  }

  rig::SimRig sim(wall_clock());
  rig::CommandSource source(command, rig::CommandMode::position);
  rig::RealtimeOptions options;
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  rig::RealtimeRunner runner(sim, source, options);
  std::vector<rig::LogRecord> log;
  log.reserve(n);
  int status_calls = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const rig::RunStatistics s = runner.run(
      n, [&](const rig::LogRecord& r) { log.push_back(r); }, [&](const rig::RunStatistics&) { ++status_calls; });
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  EXPECT_GE(elapsed_s, 0.299);  // 300 periods of 1 ms on absolute deadlines
  EXPECT_TRUE(s.complete()) << s.stopped_by;
  EXPECT_EQ(s.cycles, n);
  EXPECT_EQ(s.samples, n);
  EXPECT_EQ(s.samples_lost, 0u);
  EXPECT_EQ(s.log_dropped, 0u);
  EXPECT_DOUBLE_EQ(s.period_s, 1e-3);
  EXPECT_LE(s.latency_p50_s, s.latency_p99_s);
  EXPECT_LE(s.latency_p99_s, s.latency_max_s + 1e-6);
  EXPECT_GT(s.latency_max_s, 0.0);
  EXPECT_GE(status_calls, 2);  // ~5 Hz during 0.3 s, plus the final one
  ASSERT_EQ(log.size(), n);
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(log[k].cycle, k);
    EXPECT_EQ(log[k].measurement.encoder_counts, counts[k]) << k;
    EXPECT_EQ(log[k].measurement.gyro_raw, gyro[k]) << k;
    EXPECT_EQ(log[k].command, command[k]);
    EXPECT_EQ(log[k].command_shaped, command[k]);
  }
  if (geteuid() == 0) {  // root may lock memory and use SCHED_FIFO
    EXPECT_TRUE(s.sched_fifo);
    EXPECT_TRUE(s.memory_locked);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }

  EXPECT_EQ(sim.state(), rig::LifecycleState::inactive);
}

TEST(RealtimeRunner, PacesARigThatDoesNotPaceItself) {
  // SimRig as fast as possible: the runner's deadlines alone pace the loop.
  rig::SimRigOptions fast = wall_clock();
  fast.pacing = rig::Pacing::as_fast_as_possible;
  rig::SimRig sim(fast);
  const std::size_t n = 400;
  rig::CommandSource source(step_deg(n, 50, 10.0), rig::CommandMode::position);
  rig::RealtimeRunner runner(sim, source, {});
  std::vector<double> latency;
  latency.reserve(n);
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = runner.run(n, [&](const rig::LogRecord& r) { latency.push_back(r.latency_s); });
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(elapsed_s, 0.399);
  EXPECT_TRUE(s.complete());
  EXPECT_GE(s.latency_p50_s, *std::min_element(latency.begin(), latency.end()));
  EXPECT_LE(s.latency_p50_s, *std::max_element(latency.begin(), latency.end()) + 1e-6);
  if (s.sched_fifo) {
    // Under SCHED_FIFO the typical cycle wakes and finishes well within its period.
    EXPECT_LT(s.latency_p50_s, 0.5e-3);
    EXPECT_LT(s.overruns, n / 10);
  }
}

TEST(RealtimeRunner, OptionSkipsRealtimeSetUpWithoutWarnings) {
  rig::SimRig sim(wall_clock(rig::CommandMode::speed));
  rig::CommandSource source(std::vector<double>(50, 1.0), rig::CommandMode::speed);
  rig::RealtimeOptions options;
  options.realtime_scheduling = false;
  std::vector<std::string> warnings;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  rig::RealtimeRunner runner(sim, source, options);
  const auto s = runner.run(50, [](const rig::LogRecord&) {});
  EXPECT_FALSE(s.sched_fifo);
  EXPECT_FALSE(s.memory_locked);
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(s.complete());
}

// Drops this thread's effective capabilities (threads made from it inherit the set): SCHED_FIFO
// then needs RLIMIT_RTPRIO, which is 0 by default, so it is refused as for an ordinary user.
bool drop_thread_capabilities() {
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[2]{};
  if (syscall(SYS_capget, &header, data) != 0) return false;
  data[0].effective = 0;
  data[1].effective = 0;
  return syscall(SYS_capset, &header, data) == 0;
}

TEST(RealtimeRunner, FallsBackWithOneWarningWhenSchedFifoIsRefused) {
  rig::RunStatistics s;
  std::vector<std::string> warnings;
  bool dropped = false;
  std::thread unprivileged([&] {
    dropped = drop_thread_capabilities();
    rig::SimRig sim(wall_clock());
    rig::CommandSource source(step_deg(100, 10, 2.0), rig::CommandMode::position);
    rig::RealtimeOptions options;
    options.warn = [&](const std::string& w) { warnings.push_back(w); };
    rig::RealtimeRunner runner(sim, source, options);
    s = runner.run(100, [](const rig::LogRecord&) {});
  });
  unprivileged.join();
  if (!dropped) GTEST_SKIP() << "cannot drop capabilities here";
  if (s.sched_fifo) GTEST_SKIP() << "SCHED_FIFO allowed without capabilities (RLIMIT_RTPRIO > 0)";
  EXPECT_TRUE(s.complete());
  int sched_warnings = 0;
  for (const auto& w : warnings) sched_warnings += w.find("real-time scheduling not permitted") != std::string::npos;
  EXPECT_EQ(sched_warnings, 1);
  // A memory warning exactly when memory could not be locked.
  EXPECT_EQ(warnings.size(), s.memory_locked ? 1u : 2u);
}

TEST(RealtimeRunner, OnlineShapingEqualsOfflineShaping) {
  const std::size_t n = 400;
  const auto command = step_deg(n, 50, 10.0);
  const cs::shaping::Shaper zvd = cs::shaping::design_zvd(cs::shaping::Mode::from_hz(12.0, 0.05));
  cs::UniformSeries series{0.0, 1e-3, command};
  const cs::UniformSeries offline = cs::shaping::shape_offline(zvd, series, false);

  rig::SimRigOptions fast;
  fast.seed = 3;
  rig::SimRig sim(fast);
  rig::CommandSource source(command, rig::CommandMode::position);
  source.set_shaper(zvd, 1e-3);
  rig::RealtimeOptions options;
  options.realtime_scheduling = false;
  rig::RealtimeRunner runner(sim, source, options);
  std::vector<double> shaped;
  runner.run(n, [&](const rig::LogRecord& r) { shaped.push_back(r.command_shaped); });
  ASSERT_EQ(shaped.size(), n);
  for (std::size_t k = 0; k < n; ++k) EXPECT_NEAR(shaped[k], offline.values[k], 1e-12) << k;
  EXPECT_LT(shaped[60], 10.0);  // the shaper delays and splits the step
  EXPECT_NEAR(shaped.back(), 10.0, 1e-12);
}

TEST(RealtimeRunner, CountsOverrunsAndStopsWhenTheRigFails) {
  SlowRig slow;
  slow.slow_cycle = 10;
  slow.fail_cycle = 40;
  rig::CommandSource source(std::vector<double>(100, 0.0), rig::CommandMode::position);
  rig::RealtimeOptions options;
  options.realtime_scheduling = false;
  rig::RealtimeRunner runner(slow, source, options);
  const auto s = runner.run(100, [](const rig::LogRecord&) {});
  EXPECT_EQ(s.cycles, 41u);
  EXPECT_EQ(s.samples, 40u);
  EXPECT_EQ(s.read_failures, 1u);
  EXPECT_GE(s.overruns, 3u);  // 5 ms at a 1 ms period: the next cycles find their deadlines passed
  EXPECT_GE(s.latency_max_s, 0.005);
  EXPECT_FALSE(s.complete());
  EXPECT_NE(s.stopped_by.find("cycle 40"), std::string::npos) << s.stopped_by;
}

TEST(RealtimeRunner, ReportsTheSerialLinksLostSamples) {
  cs::testing::BoardDouble board;
  board.on_sample = [](cs::testing::BoardDouble::Sample& smp) { return smp.tick != 30; };
  board.start();
  rig::SerialRigOptions o;
  o.port = board.path();
  rig::SerialRig serial(o);
  rig::CommandSource source(step_deg(100, 10, 1.0), rig::CommandMode::position);
  rig::RealtimeOptions options;
  options.realtime_scheduling = false;
  rig::RealtimeRunner runner(serial, source, options);
  std::vector<std::uint64_t> sequence;
  const auto s = runner.run(100, [&](const rig::LogRecord& r) { sequence.push_back(r.measurement.sequence); });
  EXPECT_EQ(s.samples, 100u);
  EXPECT_EQ(s.samples_lost, 1u);
  EXPECT_FALSE(s.complete());  // a record with a hole says so
  ASSERT_EQ(sequence.size(), 100u);
  EXPECT_EQ(sequence[30], 31u);
}

TEST(RealtimeRunner, CycleIsNoexceptAndAllocationFree) {
  rig::SimRig sim(wall_clock());
  rig::CommandSource source(step_deg(200, 20, 15.0), rig::CommandMode::position);
  source.set_shaper(cs::shaping::design_zv(cs::shaping::Mode::from_hz(10.0, 0.1)), 1e-3);
  rig::RealtimeOptions options;
  rig::RealtimeRunner runner(sim, source, options);
  static_assert(noexcept(runner.cycle()));
  runner.begin();
  rig::LogRecord r;
  std::size_t popped = 0;
  std::size_t allocations = 0;
  {
    cs::testing::AllocationCounter counter;
    for (int k = 0; k < 200; ++k) {
      ASSERT_TRUE(runner.cycle());
      while (runner.pop(r)) ++popped;
    }
    allocations = counter.allocations();
  }
  const auto s = runner.end();
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(popped, 200u);
  EXPECT_EQ(s.samples, 200u);
}

TEST(RealtimeRunner, RejectsBadOptionsAndAModeMismatch) {
  rig::SimRig sim(wall_clock());
  rig::CommandSource speed(std::vector<double>(3, 0.0), rig::CommandMode::speed);
  EXPECT_THROW(rig::RealtimeRunner(sim, speed, {}), cs::InvalidArgument);
  rig::CommandSource position(std::vector<double>(3, 0.0), rig::CommandMode::position);
  rig::RealtimeOptions bad;
  bad.priority = 0;
  EXPECT_THROW(rig::RealtimeRunner(sim, position, bad), cs::InvalidArgument);
  rig::RealtimeOptions backlog;
  backlog.coalesce_backlog_samples = (1u << 20) + 1;
  try {
    rig::RealtimeRunner runner(sim, position, backlog);
    ADD_FAILURE() << "accepted";
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("coalesce_backlog_samples"), std::string::npos) << e.what();
  }
  EXPECT_THROW(rig::CommandSource({}, rig::CommandMode::position), cs::InvalidArgument);
}

}  // namespace

// Issue 21 item 4: the stop flag (io::interrupt_requested() in the CLI, set by SIGINT/SIGTERM)
// ends the loop within a few cycles; the rig is deactivated as after a full run and the
// statistics say the run was stopped on request (so the record is not complete).
TEST(RealtimeRunner, StopFlagEndsTheRunAndDeactivatesTheRig) {
  SlowRig r;
  std::atomic<bool> stop{false};
  rig::CommandSource source(step_deg(20000, 0, 1.0), rig::CommandMode::position);
  rig::RealtimeOptions o;
  o.realtime_scheduling = false;
  o.stop_flag = &stop;
  rig::RealtimeRunner runner(r, source, o);
  const rig::RunStatistics s = runner.run(20000, [&](const rig::LogRecord& rec) {
    if (rec.cycle == 50) stop = true;
  });
  EXPECT_TRUE(s.stopped_on_request);
  EXPECT_GE(s.cycles, 51u);
  EXPECT_LT(s.cycles, 2000u);
  EXPECT_FALSE(s.complete());
  EXPECT_NE(s.stopped_by.find("stopped on request"), std::string::npos) << s.stopped_by;
  EXPECT_EQ(r.deactivations, 1);
  EXPECT_EQ(r.state(), rig::LifecycleState::inactive);
}

// An exception from the logging side (a full disk in the sink) used to leave run() with the loop
// thread still joinable — std::terminate, the rig never deactivated (a serial rig: no STOP).
// Now the loop stops, the rig is deactivated, and the exception reaches the caller.
TEST(RealtimeRunner, AThrowingSinkStillDeactivatesTheRig) {
  SlowRig r;
  rig::CommandSource source(step_deg(20000, 0, 1.0), rig::CommandMode::position);
  rig::RealtimeOptions o;
  o.realtime_scheduling = false;
  rig::RealtimeRunner runner(r, source, o);
  EXPECT_THROW(runner.run(20000,
                          [](const rig::LogRecord& rec) {
                            if (rec.cycle == 20) throw std::runtime_error("disk full");
                          }),
               std::runtime_error);
  EXPECT_EQ(r.deactivations, 1);
  EXPECT_EQ(r.state(), rig::LifecycleState::inactive);
  EXPECT_LT(runner.statistics().cycles, 2000u);
}
