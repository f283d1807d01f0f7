// Issue 21 item 6 against the firmware in the emulator: COMMAND frames are no longer lost to the
// board's receive queue after a host stall. rig::RealtimeRunner over rig::SerialRig, its loop
// stalled 300 ms, sends only its newest 8 commands when it catches up, so no COMMAND is lost; the
// same stall without coalescing (the control) still overruns the board, so the scenario can
// fail. The same end to end: `clearshape rig run`, the whole process stopped (SIGSTOP) 300 ms.
// (The board's deeper queue is tested in test_sample_loss.cpp.)
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/rig/realtime.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "emulator_session.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

namespace clearshape::test {
namespace {

namespace rig = clearshape::rig;

// The runner's loop, stalled once for stall_ms in one cycle's read (the host thread held up: a
// page fault, a preempted thread, a loaded machine) while the receive thread keeps queueing the
// board's samples. Everything else is SerialRig's.
class StallingRig final : public rig::Rig {
 public:
  StallingRig(rig::SerialRig& inner, std::uint64_t stall_cycle, int stall_ms)
      : inner_(inner), stall_cycle_(stall_cycle), stall_ms_(stall_ms) {}
  double sample_time_s() const noexcept override { return inner_.sample_time_s(); }
  rig::CommandMode mode() const noexcept override { return inner_.mode(); }
  std::string_view name() const noexcept override { return "stalling serial"; }
  rig::LinkCounters link_counters() const noexcept override { return inner_.link_counters(); }
  std::size_t samples_waiting() const noexcept override { return inner_.samples_waiting(); }

 protected:
  void on_configure() override { inner_.configure(); }
  void on_activate() override {
    cycle_ = 0;
    inner_.activate();
  }
  void on_deactivate() noexcept override { inner_.deactivate(); }
  void on_cleanup() noexcept override { inner_.cleanup(); }
  Status on_read(rig::Measurement& m) noexcept override {
    if (cycle_++ == stall_cycle_) std::this_thread::sleep_for(std::chrono::milliseconds(stall_ms_));
    return inner_.read(m);
  }
  Status on_write(const rig::Command& c) noexcept override { return inner_.write(c); }

 private:
  rig::SerialRig& inner_;
  std::uint64_t stall_cycle_;
  int stall_ms_;
  std::uint64_t cycle_ = 0;
};

struct StallOutcome {
  rig::RunStatistics run;
  rig::SerialRigStats link;
  rig::BoardStats board;
};

// 1000 cycles of a 10° step at 1 kHz with a 300 ms stall at cycle 300 (the board's watchdog at
// 1 s, so the stall itself does not trip it).
StallOutcome run_with_stall(std::size_t backlog_samples) {
  EmulatorSession s({"--duration-s", "30", "--no-noise", "--speed", "1"});
  rig::SerialRigOptions o;
  o.port = s.path();
  o.watchdog_ms = 1000;
  o.handshake_timeout_s = 5.0;
  rig::SerialRig serial(o);
  StallingRig stalling(serial, 300, 300);
  std::vector<double> step(1000, 0.0);
  for (std::size_t k = 100; k < step.size(); ++k) step[k] = 10.0;
  rig::CommandSource source(step, rig::CommandMode::position);
  rig::RealtimeOptions ro;
  ro.realtime_scheduling = false;
  ro.coalesce_backlog_samples = backlog_samples;
  rig::RealtimeRunner runner(stalling, source, ro);
  StallOutcome out;
  out.run = runner.run(1000, [](const rig::LogRecord&) {});
  out.link = serial.stats();
  if (!serial.board_during_run()) throw std::runtime_error("the board's STATS could not be read");
  out.board = *serial.board_during_run();
  std::printf("300 ms host stall, coalesce_backlog_samples = %zu: %llu COMMANDs sent, %llu coalesced, %u rejected by the board, "
              "%llu samples flagged commands_lost, %llu samples lost, %u watchdog trips\n",
              backlog_samples, static_cast<unsigned long long>(out.link.commands_sent),
              static_cast<unsigned long long>(out.run.commands_coalesced), out.board.rx_corrupted,
              static_cast<unsigned long long>(out.link.rx_rejected_samples),
              static_cast<unsigned long long>(out.link.samples_lost), out.board.watchdog_trips);
  return out;
}

TEST(RigCommandCoalescing, AHostStallLosesNoCommand) {
  REQUIRE_EMULATOR();
  const StallOutcome on = run_with_stall(rig::RealtimeOptions{}.coalesce_backlog_samples);
  EXPECT_EQ(on.run.samples, 1000u);
  EXPECT_EQ(on.link.samples_lost, 0u);
  EXPECT_EQ(on.board.rx_corrupted, 0u) << "COMMAND frames lost on the board";
  EXPECT_EQ(on.link.rx_rejected_samples, 0u);
  EXPECT_EQ(on.board.watchdog_trips, 0u);
  // ~300 catch-up cycles; all but the newest 8 of them are coalesced.
  EXPECT_GE(on.run.commands_coalesced, 250u);
  EXPECT_EQ(on.link.commands_sent + on.run.commands_coalesced, 1000u);
}

// The control: the same stall with one COMMAND per cycle (the code before issue 21 item 6)
// writes a 4 kB burst that no receive queue of this board holds; COMMANDs are lost.
TEST(RigCommandCoalescing, WithoutCoalescingTheSameStallLosesCommands) {
  REQUIRE_EMULATOR();
  const StallOutcome off = run_with_stall(0);
  EXPECT_EQ(off.run.commands_coalesced, 0u);
  EXPECT_GT(off.board.rx_corrupted, 0u) << "the stall did not overrun the board: the coalescing test proves nothing";
  EXPECT_GT(off.link.rx_rejected_samples, 0u);
}

// `clearshape rig run` against the firmware, the whole process stopped 300 ms (SIGSTOP, then
// SIGCONT: its receive thread stalls too, the bytes wait in the pty) half a second into a 3 s
// run. The watchdog is at 2 s and late samples are allowed, so the record stays complete and
// the sidecar's counts show what happened: the catch-up was coalesced, no frame was lost.
TEST(RigCommandCoalescing, ARunWhoseProcessWasStoppedLosesNoCommand) {
  REQUIRE_EMULATOR();
  EmulatorSession s({"--duration-s", "30", "--no-noise", "--speed", "1"});
  const std::filesystem::path dir = clearshape::testing::fresh_temp_dir("clearshape_rig_sigstop");
  const std::string err = (dir / "err.txt").string();
  // The shell starts the run, waits for its first status (the handshake is done), stops it.
  const auto r = clearshape::testing::run_cli(
      "rig run --port " + s.path() + " --signal step --amplitude 10 --start-s 0.2 --duration 3 --no-realtime "
      "--watchdog-ms 2000 --max-late-fraction 1 --json -o " + (dir / "run.csv").string() + " 2>" + err +
      " & pid=$!; for i in $(seq 400); do grep -q 'position mode' " + err + " && break; sleep 0.05; done; "
      "sleep 0.5; kill -STOP $pid; sleep 0.3; kill -CONT $pid; wait $pid");
  const std::string text = clearshape::testing::read_bytes(err);
  ASSERT_EQ(r.exit_code, 0) << text << r.out;
  const auto stats = nlohmann::json::parse(r.out)["statistics"];
  std::printf("rig run stopped 300 ms: %d COMMANDs sent, %d coalesced, board rx_corrupted %d, %d samples late\n",
              stats["commands_sent"].get<int>(), stats["commands_coalesced"].get<int>(),
              stats["board_during_run"]["rx_corrupted"].get<int>(), stats["samples_late"].get<int>());
  EXPECT_GE(stats["commands_coalesced"].get<int>(), 200) << text;
  EXPECT_EQ(stats["commands_sent"].get<int>() + stats["commands_coalesced"].get<int>(), 3001);
  EXPECT_EQ(stats["board_during_run"]["rx_corrupted"].get<int>(), 0);
  EXPECT_EQ(stats["rx_rejected_samples"].get<int>(), 0);
  EXPECT_EQ(stats["samples_lost"].get<int>(), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clearshape::test
