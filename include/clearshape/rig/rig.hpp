#pragma once
// The hardware abstraction of a test rig, after ros2_control's hardware_interface
// (docs/design.md §3): a lifecycle run outside the real-time loop, and
// read()/write() inside it.
//
//            configure()           activate()
//   unconfigured ───────► inactive ─────────► active
//        ▲      cleanup()    ▲  ◄───────────  │  │ read/write report device_error
//        └──────────────────┘   deactivate()  │  ▼
//                                 ◄────────────── error
//
// Lifecycle calls are configuration-time: a bad configuration throws (InvalidArgument,
// RuntimeError) and leaves the state unchanged; a call in the wrong state returns
// Status::not_ready. read() and write() are noexcept, never allocate, and return a Status:
// not_ready outside `active`; device_error moves the rig to `error` (leave it with deactivate()).
//
// Loop contract: after activate() the clock is at t = 0. Each read() returns the next sample
// (t = 0, T, 2T, …; T = sample_time_s()); a write() holds its command from the time of the
// last read until the next write.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/core/status.hpp"
#include "clearshape/rig/types.hpp"

namespace clearshape::rig {

enum class LifecycleState : std::uint8_t { unconfigured, inactive, active, error };
std::string_view to_string(LifecycleState state) noexcept;

/// Counters kept by the base class (real-time safe: plain integers).
struct CycleCounters {
  std::uint64_t reads = 0;
  std::uint64_t writes = 0;
  std::uint64_t failed_reads = 0;   ///< read() returned other than ok
  std::uint64_t failed_writes = 0;  ///< write() returned other than ok
  Status last_read = Status::ok;
  Status last_write = Status::ok;
};

/// Counters of the link between the host and a rig's device (zero for a rig without one).
struct LinkCounters {
  std::uint64_t samples = 0;           ///< samples received
  std::uint64_t samples_lost = 0;      ///< samples missing (gaps in the device's tick)
  std::uint64_t frames_corrupted = 0;  ///< frames rejected (bad length or checksum)
  std::uint64_t samples_late = 0;      ///< samples that arrived later than deadline + tolerance
};

class Rig {
 public:
  virtual ~Rig() = default;
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  /// unconfigured → inactive: validate the configuration, open devices, allocate buffers.
  Status configure();
  /// inactive → active: reset the clock to t = 0 and start sampling.
  Status activate();
  /// active or error → inactive: stop (the command goes to a safe value).
  Status deactivate();
  /// inactive → unconfigured: release devices and buffers.
  Status cleanup();

  /// The next sample (see the loop contract). Real-time safe.
  Status read(Measurement& measurement) noexcept;
  /// The command to hold from now on. Real-time safe.
  Status write(const Command& command) noexcept;

  LifecycleState state() const noexcept { return state_; }
  const CycleCounters& counters() const noexcept { return counters_; }
  /// Sample period T of read(), in s.
  virtual double sample_time_s() const noexcept = 0;
  /// The mode the rig was configured for (write() rejects the other one).
  virtual CommandMode mode() const noexcept = 0;
  virtual std::string_view name() const noexcept = 0;
  /// The link's counters since activation (real-time safe).
  virtual LinkCounters link_counters() const noexcept { return {}; }
  /// Samples already received and not yet read (real-time safe; 0 for a rig that queues none):
  /// while this is above 0 the loop is behind the device (RealtimeRunner coalesces then).
  virtual std::size_t samples_waiting() const noexcept { return 0; }
  /// After deactivate(): why the last run's record is degraded — it did not follow its command
  /// or has holes (e.g. "3 sample(s) lost on the link") — one reason each; empty when it is
  /// whole. A degraded record is never used as a complete run. Configuration time.
  virtual std::vector<std::string> degradation() const { return {}; }

 protected:
  Rig() = default;
  virtual void on_configure() = 0;          ///< may throw; state stays unconfigured then
  virtual void on_activate() = 0;           ///< may throw; state stays inactive then
  virtual void on_deactivate() noexcept = 0;
  virtual void on_cleanup() noexcept = 0;
  virtual Status on_read(Measurement& measurement) noexcept = 0;
  virtual Status on_write(const Command& command) noexcept = 0;

 private:
  LifecycleState state_ = LifecycleState::unconfigured;
  CycleCounters counters_{};
};

}  // namespace clearshape::rig
