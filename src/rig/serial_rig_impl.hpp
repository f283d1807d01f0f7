#pragma once
// SerialRig's state shared by its two source files (internal): serial_rig.cpp (options, the
// handshake and the lifecycle) and serial_rig_loop.cpp (the receive thread, read() and write()).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/rig/spsc_ring.hpp"
#include "clearshape/rig/wire_protocol.h"
#include "serial_port.hpp"

namespace clearshape::rig {

/// One SAMPLE frame as received (the protocol's own decoded layout).
using ReceivedSample = cs_sample;

struct SerialRig::Impl {
  using Clock = std::chrono::steady_clock;

  explicit Impl(const SerialRigOptions& o) : ring(o.ring_capacity) {}

  detail::SerialPort port;
  cs_decoder decoder{};
  // Bytes read by the handshake but not yet decoded (handed to the receive thread).
  std::uint8_t pending_rx[256]{};
  std::size_t pending_rx_begin = 0, pending_rx_end = 0;
  std::uint8_t tx_seq = 0;

  SpscRing<ReceivedSample> ring;
  std::thread receiver;
  std::atomic<bool> stop_receiver{false};
  std::atomic<bool> port_failed{false};

  // Receive-thread counters (single writer; read from any thread).
  std::atomic<std::uint64_t> samples{0}, corrupted{0}, late{0}, ring_overflows{0}, board_tx_overflows{0};
  std::atomic<std::int64_t> max_lateness_ns{0};
  std::int64_t anchor_ns = 0;  // earliest (arrival − tick·T) seen: tick 0's deadline
  bool anchored = false;
  std::uint32_t corrupted_at_start = 0;

  // Real-time side (single writer: the thread calling read()/write()).
  std::atomic<std::uint64_t> lost{0}, commands_sent{0}, commands_dropped{0}, commands_rejected{0},
      watchdog_samples{0}, rx_rejected_samples{0};
  std::uint64_t next_tick = 0;     // the tick expected next
  bool have_tick = false;
  std::uint32_t last_tick = 0;     // the last tick read (COMMAND.tick)
  std::uint32_t pending_flags = 0; // MeasurementFlag bits for the next sample (rejected writes)
  /// Why read() last returned device_error outside the record's own checks (for degradation()).
  enum class ReadFailure : std::uint8_t { none, timeout, port_failed, tick_repeated } read_failure = ReadFailure::none;
  std::uint8_t tx_pending[2 * CS_WIRE_MAX_FRAME]{};
  std::size_t tx_pending_size = 0;

  static std::int64_t now_ns() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
  }
  /// The receive thread's body (serial_rig_loop.cpp).
  void receive_loop(std::int64_t period_ns, std::int64_t tolerance_ns) noexcept;
  void handle_sample(const cs_frame& frame, std::int64_t arrival_ns, std::int64_t period_ns,
                     std::int64_t tolerance_ns) noexcept;
};

}  // namespace clearshape::rig
