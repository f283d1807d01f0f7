// SerialRig's real-time side: the receive thread (bytes → frames → ring), read() and write().
// Nothing here allocates, locks or throws.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "clearshape/core/units.hpp"
#include "serial_rig_impl.hpp"

namespace clearshape::rig {

double encoder_counts_to_rad(std::int64_t counts, int counts_per_rev) noexcept {
  return static_cast<double>(counts) * kTwoPi / counts_per_rev;  // one count = 2π / counts per rev
}

std::int32_t motor_rad_to_pulses(double angle_rad, int pulses_per_rev) noexcept {
  // One pulse (A/B edge) turns the motor 2π / pulses_per_rev (the drive's electronic gear).
  const double pulses = std::round(angle_rad * pulses_per_rev / kTwoPi);
  constexpr double lo = std::numeric_limits<std::int32_t>::min();
  constexpr double hi = std::numeric_limits<std::int32_t>::max();
  return static_cast<std::int32_t>(std::fmin(std::fmax(pulses, lo), hi));
}

double pulses_to_motor_rad(std::int32_t pulses, int pulses_per_rev) noexcept {
  return static_cast<double>(pulses) * kTwoPi / pulses_per_rev;
}

double gyro_raw_to_rad_s(std::int16_t raw, double sensitivity_lsb_per_dps) noexcept {
  return deg_to_rad(raw / sensitivity_lsb_per_dps);  // ITG-3205 datasheet: 14.375 LSB/(°/s)
}

std::uint16_t volts_to_dac_code(double volts, double min_v, double max_v, bool& clipped) noexcept {
  // 12-bit MCP4725 behind a level shift: code 0 ↔ min_v, code 4095 ↔ max_v (docs/realtime.md).
  clipped = !(volts >= min_v && volts <= max_v);
  const double code = std::round((volts - min_v) / (max_v - min_v) * 4095.0);
  return static_cast<std::uint16_t>(std::fmin(std::fmax(std::isnan(code) ? 0.0 : code, 0.0), 4095.0));
}

double dac_code_to_volts(std::uint16_t code, double min_v, double max_v) noexcept {
  return min_v + static_cast<double>(code) / 4095.0 * (max_v - min_v);
}

std::uint32_t measurement_flags_of_sample(std::uint8_t f) noexcept {
  std::uint32_t out = 0;
  if (f & CS_SAMPLE_GYRO_SATURATED) out |= bit(MeasurementFlag::gyro_saturated);
  if (f & CS_SAMPLE_COMMAND_LIMITED) out |= bit(MeasurementFlag::command_limited);
  if (f & CS_SAMPLE_WATCHDOG) out |= bit(MeasurementFlag::watchdog);
  if (f & CS_SAMPLE_TWI_ERROR) out |= bit(MeasurementFlag::sensor_error);
  if (f & CS_SAMPLE_TX_OVERFLOW) out |= bit(MeasurementFlag::samples_lost);
  if (f & CS_SAMPLE_LATE) out |= bit(MeasurementFlag::overrun);
  if (f & CS_SAMPLE_RX_REJECTED) out |= bit(MeasurementFlag::commands_lost);
  return out;
}


void SerialRig::Impl::handle_sample(const cs_frame& frame, std::int64_t arrival_ns, std::int64_t period_ns,
                                    std::int64_t tolerance_ns) noexcept {
  if (frame.length != CS_SAMPLE_BYTES) {
    corrupted.fetch_add(1, std::memory_order_relaxed);  // a well-formed frame of the wrong size
    return;
  }
  const ReceivedSample s = cs_sample_decode(frame.payload);
  samples.fetch_add(1, std::memory_order_relaxed);
  if (s.flags & CS_SAMPLE_TX_OVERFLOW) board_tx_overflows.fetch_add(1, std::memory_order_relaxed);
  // Deadline of tick k: anchor + k·T, the anchor being the earliest (arrival − k·T) seen, so a
  // late first sample or a board clock slightly fast never makes every later sample "late".
  const std::int64_t offset = arrival_ns - static_cast<std::int64_t>(s.tick) * period_ns;
  if (!anchored || offset < anchor_ns) {
    anchor_ns = offset;
    anchored = true;
  } else {
    // A board clock slower than the host's (a crystal is within ±100 ppm) raises every offset a
    // little per tick: the anchor follows by up to 500 ppm of a period per sample, so a long run
    // is not counted late for the crystal, while a host stall (milliseconds) still is.
    anchor_ns += std::min(offset - anchor_ns, period_ns / 2000);
  }
  const std::int64_t lateness = offset - anchor_ns;
  if (lateness > max_lateness_ns.load(std::memory_order_relaxed)) {
    max_lateness_ns.store(lateness, std::memory_order_relaxed);
  }
  if (lateness > tolerance_ns) late.fetch_add(1, std::memory_order_relaxed);
  if (!ring.push(s)) ring_overflows.fetch_add(1, std::memory_order_relaxed);
}

void SerialRig::Impl::receive_loop(std::int64_t period_ns, std::int64_t tolerance_ns) noexcept {
  std::uint8_t buffer[512];
  cs_frame frame{};
  auto feed = [&](const std::uint8_t* bytes, std::size_t n, std::int64_t arrival_ns) {
    for (std::size_t i = 0; i < n; ++i) {
      if (cs_decoder_push(&decoder, bytes[i], &frame) == 1 && frame.type == CS_MSG_SAMPLE) {
        handle_sample(frame, arrival_ns, period_ns, tolerance_ns);
      }
    }
    corrupted.store(decoder.corrupted - corrupted_at_start, std::memory_order_relaxed);
  };
  feed(pending_rx + pending_rx_begin, pending_rx_end - pending_rx_begin, now_ns());
  pending_rx_begin = pending_rx_end = 0;
  while (!stop_receiver.load(std::memory_order_acquire)) {
    const long n = port.read_some(buffer, sizeof buffer, 20);
    if (n < 0) {
      port_failed.store(true, std::memory_order_release);
      return;
    }
    if (n > 0) feed(buffer, static_cast<std::size_t>(n), now_ns());
  }
}

LinkCounters SerialRig::link_counters() const noexcept {
  const SerialRigStats s = stats();
  return {s.samples, s.samples_lost, s.frames_corrupted, s.samples_late};
}

std::size_t SerialRig::samples_waiting() const noexcept { return impl_ ? impl_->ring.size() : 0; }

SerialRigStats SerialRig::stats() const noexcept {
  SerialRigStats s;
  if (!impl_) return s;
  const Impl& m = *impl_;
  s.samples = m.samples.load(std::memory_order_relaxed);
  s.samples_lost = m.lost.load(std::memory_order_relaxed);
  s.frames_corrupted = m.corrupted.load(std::memory_order_relaxed);
  s.samples_late = m.late.load(std::memory_order_relaxed);
  s.ring_overflows = m.ring_overflows.load(std::memory_order_relaxed);
  s.commands_sent = m.commands_sent.load(std::memory_order_relaxed);
  s.commands_dropped = m.commands_dropped.load(std::memory_order_relaxed);
  s.board_tx_overflows = m.board_tx_overflows.load(std::memory_order_relaxed);
  s.commands_rejected = m.commands_rejected.load(std::memory_order_relaxed);
  s.watchdog_samples = m.watchdog_samples.load(std::memory_order_relaxed);
  s.rx_rejected_samples = m.rx_rejected_samples.load(std::memory_order_relaxed);
  s.max_lateness_s = static_cast<double>(m.max_lateness_ns.load(std::memory_order_relaxed)) * 1e-9;
  return s;
}

Status SerialRig::on_read(Measurement& out) noexcept {
  Impl& m = *impl_;
  ReceivedSample s{};
  const auto deadline = Impl::Clock::now() + std::chrono::duration_cast<Impl::Clock::duration>(
                                                  std::chrono::duration<double>(options_.read_timeout_s));
  while (!m.ring.pop(s)) {
    if (m.port_failed.load(std::memory_order_acquire)) {
      m.read_failure = Impl::ReadFailure::port_failed;
      return Status::device_error;
    }
    if (Impl::Clock::now() >= deadline) {
      m.read_failure = Impl::ReadFailure::timeout;
      return Status::device_error;
    }
    const timespec pause{0, 50'000};  // 50 µs: well under one sample period
    nanosleep(&pause, nullptr);
  }
  // The 32-bit tick unwrapped to 64 bits (it wraps after 49 days at 1 kHz). A tick that does
  // not advance means the board restarted or repeats itself: the run cannot go on.
  const auto step = static_cast<std::int32_t>(s.tick - m.last_tick);
  if (m.have_tick && step <= 0) {
    m.read_failure = Impl::ReadFailure::tick_repeated;
    return Status::device_error;
  }
  const std::uint64_t tick = m.have_tick ? m.next_tick - 1 + static_cast<std::uint64_t>(step) : s.tick;
  std::uint32_t flags = measurement_flags_of_sample(s.flags) | m.pending_flags;
  m.pending_flags = 0;
  const std::uint64_t expected = m.have_tick ? m.next_tick : 0;
  if (tick != expected) {
    m.lost.store(m.lost.load(std::memory_order_relaxed) + (tick - expected), std::memory_order_relaxed);
    flags |= bit(MeasurementFlag::samples_lost);
    if (options_.lost_samples == LostSamples::fail) return Status::device_error;
  }
  if ((flags & bit(MeasurementFlag::watchdog)) != 0) m.watchdog_samples.fetch_add(1, std::memory_order_relaxed);
  if ((flags & bit(MeasurementFlag::commands_lost)) != 0) m.rx_rejected_samples.fetch_add(1, std::memory_order_relaxed);
  // A run that must be complete must also be the commanded one: a sample taken while the
  // board's watchdog held the command at its safe value, or after the board rejected host
  // frames (a COMMAND may be missing), ends it as well.
  if (options_.lost_samples == LostSamples::fail &&
      (flags & (bit(MeasurementFlag::watchdog) | bit(MeasurementFlag::commands_lost))) != 0) {
    return Status::device_error;
  }
  m.have_tick = true;
  m.last_tick = s.tick;
  m.next_tick = tick + 1;
  out.time_s = static_cast<double>(tick) * sample_time_s();
  out.sequence = tick;
  out.encoder_counts = s.encoder_count;
  out.motor_angle_rad = encoder_counts_to_rad(s.encoder_count, options_.counts_per_rev);
  out.gyro_raw = s.gyro_raw;
  out.gyro_rate_rad_s = gyro_raw_to_rad_s(s.gyro_raw, options_.gyro_sensitivity_lsb_per_dps);
  out.command_applied = options_.mode == CommandMode::position
                            ? pulses_to_motor_rad(s.pulses_emitted, options_.pulses_per_rev)
                            : dac_code_to_volts(s.dac_code, options_.dac_min_v, options_.dac_max_v);
  out.flags = flags;
  return Status::ok;
}

Status SerialRig::on_write(const Command& command) noexcept {
  Impl& m = *impl_;
  if (const Status rejected = check_command(command, options_.mode); rejected != Status::ok) {
    m.pending_flags |= bit(MeasurementFlag::command_rejected);
    m.commands_rejected.fetch_add(1, std::memory_order_relaxed);
    return rejected;
  }
  Status status = Status::ok;
  std::int32_t value = 0;
  if (options_.mode == CommandMode::position) {
    value = motor_rad_to_pulses(command.value, options_.pulses_per_rev);
  } else {
    bool clipped = false;
    value = volts_to_dac_code(command.value, options_.dac_min_v, options_.dac_max_v, clipped);
    if (clipped) {
      m.pending_flags |= bit(MeasurementFlag::command_limited);
      status = Status::out_of_range;
    }
  }
  // First the rest of a frame the port could not take last time (a frame is never cut).
  if (m.tx_pending_size > 0) {
    const long n = m.port.write_some(m.tx_pending, m.tx_pending_size);
    if (n < 0) return Status::device_error;
    const auto sent = static_cast<std::size_t>(n);
    for (std::size_t i = sent; i < m.tx_pending_size; ++i) m.tx_pending[i - sent] = m.tx_pending[i];
    m.tx_pending_size -= sent;
    if (m.tx_pending_size > 0) {
      m.commands_dropped.fetch_add(1, std::memory_order_relaxed);
      return Status::overrun;
    }
  }
  std::uint8_t payload[CS_COMMAND_BYTES];
  cs_put_u32(payload + 0, m.last_tick);
  cs_put_i32(payload + 4, value);
  std::uint8_t frame[CS_WIRE_MAX_FRAME];
  const std::size_t size = cs_frame_encode(frame, CS_MSG_COMMAND, m.tx_seq++, payload, CS_COMMAND_BYTES);
  const long n = m.port.write_some(frame, size);
  if (n < 0) return Status::device_error;
  const auto sent = static_cast<std::size_t>(n);
  for (std::size_t i = sent; i < size; ++i) m.tx_pending[m.tx_pending_size++] = frame[i];
  m.commands_sent.fetch_add(1, std::memory_order_relaxed);
  return status;
}

}  // namespace clearshape::rig
