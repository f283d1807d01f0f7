#pragma once
// Wall-clock pacing of a periodic loop (docs/design.md §3): absolute
// deadlines next = start + k·T on std::chrono::steady_clock, std::this_thread::sleep_until;
// a cycle that finds its deadline already passed is an overrun. When a cycle is late by whole
// periods those periods are counted as missed and the schedule skips ahead (ros2_control's
// policy: no catch-up burst). wait() is noexcept and allocation-free.
#include <chrono>
#include <cstdint>

#include "clearshape/core/status.hpp"

namespace clearshape::rig {

struct PacerStats {
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;         ///< cycles that found their deadline passed
  std::uint64_t missed_periods = 0;   ///< whole periods skipped after overruns
  double max_lateness_s = 0.0;        ///< largest (now − deadline) at a wait
};

class Pacer {
 public:
  using Clock = std::chrono::steady_clock;

  /// Throws InvalidArgument unless period_s is finite and in (0, 10] s.
  explicit Pacer(double period_s);

  /// Sets the schedule origin: the first wait() returns at once (deadline = now).
  void start() noexcept;
  /// Sleeps until the next deadline. Returns Status::overrun if it had already passed
  /// (and skips whole missed periods), Status::not_ready before start().
  Status wait() noexcept;

  double period_s() const noexcept { return period_s_; }
  const PacerStats& stats() const noexcept { return stats_; }

 private:
  double period_s_;
  Clock::duration period_;
  Clock::time_point next_{};
  bool started_ = false;
  PacerStats stats_{};
};

}  // namespace clearshape::rig
