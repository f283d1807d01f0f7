// SerialRig's configuration side: options, the handshake and the lifecycle (configuration time:
// may allocate, block and throw). The real-time side is serial_rig_loop.cpp.
#include <array>
#include <cmath>
#include <cstring>
#include <thread>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "serial_rig_impl.hpp"

namespace clearshape::rig {
namespace {

bool whole_in(double v, double lo, double hi) { return std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi; }

const char* message_name(std::uint8_t type) {
  switch (type) {
    case CS_MSG_HELLO: return "HELLO";
    case CS_MSG_CONFIGURE: return "CONFIGURE";
    case CS_MSG_START: return "START";
    case CS_MSG_STOP: return "STOP";
    case CS_MSG_COMMAND: return "COMMAND";
    case CS_MSG_SERVO: return "SERVO";
    case CS_MSG_SELFTEST: return "SELFTEST";
    case CS_MSG_GET_STATS: return "GET_STATS";
    case CS_MSG_HELLO_ACK: return "HELLO_ACK";
    case CS_MSG_ACK: return "ACK";
    case CS_MSG_SAMPLE: return "SAMPLE";
    case CS_MSG_SELFTEST_RESULT: return "SELFTEST_RESULT";
    case CS_MSG_STATS: return "STATS";
    default: return "unknown message";
  }
}

const char* result_name(std::uint8_t result) {
  switch (result) {
    case CS_OK: return "ok";
    case CS_ERR_LENGTH: return "wrong payload length";
    case CS_ERR_VALUE: return "a field out of range";
    case CS_ERR_STATE: return "not allowed in the board's state";
    case CS_ERR_UNKNOWN: return "unknown message type";
    case CS_ERR_DEVICE: return "a device on the TWI bus did not answer";
    default: return "unknown result";
  }
}

// CONFIGURE's field at a byte offset (an ACK's detail for CS_ERR_VALUE).
const char* configure_field(unsigned offset) {
  switch (offset) {
    case 0: return "mode";
    case 1: return "gyro_fs_sel";
    case 2: return "gyro_dlpf_cfg";
    case 3: return "reserved";
    case 4: return "sample_rate_hz";
    case 6: return "update_rate_hz";
    case 8: return "max_pulse_rate_hz";
    case 12: return "watchdog_ms";
    case 14: return "dac_safe_code";
    default: return "unknown field";
  }
}

}  // namespace

std::string BoardInfo::firmware_version() const {
  return fmt::format("{}.{}.{}", firmware_major, firmware_minor, firmware_patch);
}

void SerialRigOptions::validate() const {
  if (port.empty()) throw InvalidArgument("port is empty; allowed: a serial device path, e.g. /dev/ttyACM0");
  if (baud < 9600 || baud > 2'000'000) throw_invalid("baud", baud, "9600 … 2000000");
  if (!whole_in(sample_rate_hz, 100, 2000)) throw_invalid("sample_rate_hz", sample_rate_hz, "whole Hz in 100 … 2000");
  if (!whole_in(update_rate_hz, 1, sample_rate_hz)) {
    throw_invalid("update_rate_hz", update_rate_hz, fmt::format("whole Hz in 1 … sample_rate_hz ({:g})", sample_rate_hz));
  }
  if (max_pulse_rate_hz < 1 || max_pulse_rate_hz > CS_MAX_PULSE_RATE_HZ) {
    throw_invalid("max_pulse_rate_hz", max_pulse_rate_hz, fmt::format("1 … {}", CS_MAX_PULSE_RATE_HZ));
  }
  if (gyro_fs_sel < 0 || gyro_fs_sel > 3) throw_invalid("gyro_fs_sel", gyro_fs_sel, "0 … 3 (3 = ±2000 °/s)");
  if (gyro_dlpf_cfg < 0 || gyro_dlpf_cfg > 6) throw_invalid("gyro_dlpf_cfg", gyro_dlpf_cfg, "0 … 6");
  if (watchdog_ms != 0 && (watchdog_ms < 5 || watchdog_ms > 60000)) {
    throw_invalid("watchdog_ms", watchdog_ms, "0 (off) or 5 … 60000");
  }
  for (const auto& [name, value] : {std::pair{"handshake_timeout_s", handshake_timeout_s},
                                     std::pair{"read_timeout_s", read_timeout_s}}) {
    if (!(std::isfinite(value) && value > 0.0 && value <= 60.0)) throw_invalid(name, value, "(0, 60] s");
  }
  require_in_closed("late_tolerance_s", late_tolerance_s, 0.0, 10.0);
  require_in_closed("max_late_fraction", max_late_fraction, 0.0, 1.0);
  if (counts_per_rev < 1) throw_invalid("counts_per_rev", counts_per_rev, ">= 1");
  if (pulses_per_rev < 1) throw_invalid("pulses_per_rev", pulses_per_rev, ">= 1");
  require_positive("gyro_sensitivity_lsb_per_dps", gyro_sensitivity_lsb_per_dps);
  if (!(dac_min_v < dac_max_v) || !std::isfinite(dac_min_v) || !std::isfinite(dac_max_v)) {
    throw InvalidArgument(fmt::format("dac_min_v = {}, dac_max_v = {}: allowed: finite, dac_min_v < dac_max_v",
                                      dac_min_v, dac_max_v));
  }
  if (ring_capacity < 16 || ring_capacity > (1u << 20)) throw_invalid("ring_capacity", static_cast<double>(ring_capacity), "16 … 1048576");
}

namespace {

// Blocking helpers for the handshake (configuration time).
struct Session {
  const SerialRigOptions& o;
  SerialRig::Impl& m;
  std::uint64_t bytes_seen = 0;

  void send(std::uint8_t type, const std::uint8_t* payload, std::uint8_t length) {
    std::uint8_t frame[CS_WIRE_MAX_FRAME];
    const std::size_t size = cs_frame_encode(frame, type, m.tx_seq++, payload, length);
    std::size_t done = 0;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.handshake_timeout_s);
    while (done < size) {
      const long n = m.port.write_some(frame + done, size - done);
      if (n < 0) throw RuntimeError(fmt::format("serial port {}: writing {} failed; is the board still connected?", o.port, message_name(type)));
      done += static_cast<std::size_t>(n);
      if (done < size) {
        if (std::chrono::steady_clock::now() > give_up) {
          throw RuntimeError(fmt::format("serial port {}: the port did not take {} within {} s", o.port, message_name(type), o.handshake_timeout_s));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    }
  }

  // The next frame of `type` (others are skipped), or nothing within timeout_s.
  std::optional<cs_frame> await(std::uint8_t type, double timeout_s) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    cs_frame frame{};
    for (;;) {
      while (m.pending_rx_begin < m.pending_rx_end) {
        if (cs_decoder_push(&m.decoder, m.pending_rx[m.pending_rx_begin++], &frame) == 1 && frame.type == type) {
          return frame;
        }
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(give_up - std::chrono::steady_clock::now()).count();
      if (left <= 0) return std::nullopt;
      const long n = m.port.read_some(m.pending_rx, sizeof m.pending_rx, static_cast<int>(std::min<long long>(left, 50)));
      if (n < 0) throw RuntimeError(fmt::format("serial port {}: reading failed; is the board still connected?", o.port));
      bytes_seen += static_cast<std::uint64_t>(n);
      m.pending_rx_begin = 0;
      m.pending_rx_end = static_cast<std::size_t>(n);
    }
  }

  // Sends `type` and waits for its ACK; a refusal throws naming the reason.
  void request(std::uint8_t type, const std::uint8_t* payload, std::uint8_t length) {
    send(type, payload, length);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.handshake_timeout_s);
    for (;;) {
      const double left = std::chrono::duration<double>(give_up - std::chrono::steady_clock::now()).count();
      const auto ack = left > 0 ? await(CS_MSG_ACK, left) : std::nullopt;
      if (!ack) {
        throw RuntimeError(fmt::format("serial port {}: no ACK to {} within {} s; the board stopped answering "
                                       "(reset it and check the cable)", o.port, message_name(type), o.handshake_timeout_s));
      }
      if (ack->length != CS_ACK_BYTES || ack->payload[0] != type) continue;  // an ACK of something else
      const std::uint8_t result = ack->payload[1];
      if (result == CS_OK) return;
      const unsigned detail = cs_get_u16(ack->payload + 2);
      std::string what = result_name(result);
      if (type == CS_MSG_CONFIGURE && result == CS_ERR_VALUE) what += fmt::format(" ({})", configure_field(detail));
      if (result == CS_ERR_DEVICE) what += fmt::format(" (address 0x{:02x})", detail);
      if (result == CS_ERR_STATE) {
        what += "; the board is still running a previous session and did not leave it on STOP: reset the board "
                "(its reset button, or unplug and replug its USB cable) and try again";
      }
      throw RuntimeError(fmt::format("serial port {}: the board refused {}: {}", o.port, message_name(type), what));
    }
  }
};

// CONFIGURE's payload (wire_protocol.h: mode, gyro settings, rates, watchdog, the DAC's safe code).
using ConfigurePayload = std::array<std::uint8_t, CS_CONFIGURE_BYTES>;

// HELLO, repeated until HELLO_ACK: an Arduino resets when its port opens and spends a second in
// its boot loader.
cs_frame await_hello_ack(Session& s) {
  std::uint8_t hello[CS_HELLO_BYTES];
  cs_put_u16(hello, CS_WIRE_VERSION);
  std::optional<cs_frame> ack;
  int hellos = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(s.o.handshake_timeout_s);
  while (!ack && std::chrono::steady_clock::now() < give_up) {
    s.send(CS_MSG_HELLO, hello, CS_HELLO_BYTES);
    ++hellos;
    const double left = std::chrono::duration<double>(give_up - std::chrono::steady_clock::now()).count();
    ack = s.await(CS_MSG_HELLO_ACK, std::min(0.25, std::max(left, 0.0)));
  }
  if (!ack) {
    throw RuntimeError(fmt::format(
        "serial port {}: no HELLO_ACK within {} s ({} HELLO sent; {} bytes and {} corrupted frames received); "
        "expected the clearshape firmware (wire protocol v{}) at {} baud: flash firmware/ (docs/hardware.md), "
        "check the baud rate and that no other program holds the port",
        s.o.port, s.o.handshake_timeout_s, hellos, s.bytes_seen, s.m.decoder.corrupted, CS_WIRE_VERSION, s.o.baud));
  }
  return *ack;
}

// The board's identity from HELLO_ACK; a wrong length or wire version throws.
BoardInfo parse_hello_ack(const cs_frame& ack, const SerialRigOptions& o) {
  if (ack.length != CS_HELLO_ACK_BYTES) {
    throw RuntimeError(fmt::format("serial port {}: HELLO_ACK has {} bytes, expected {}; flash the firmware of this "
                                   "release (firmware/, docs/hardware.md)", o.port, ack.length, CS_HELLO_ACK_BYTES));
  }
  BoardInfo b;
  b.wire_version = cs_get_u16(ack.payload + 0);
  b.firmware_major = ack.payload[2];
  b.firmware_minor = ack.payload[3];
  b.firmware_patch = cs_get_u16(ack.payload + 4);
  b.encoder_lines_hint = cs_get_u16(ack.payload + 6);
  b.capabilities = cs_get_u32(ack.payload + 8);
  b.cpu_hz = cs_get_u32(ack.payload + 12);
  if (b.wire_version != CS_WIRE_VERSION) {
    throw RuntimeError(fmt::format("serial port {}: the board speaks wire protocol v{} (firmware {}), this host expects "
                                   "v{}; flash firmware/ of this release onto the board (docs/hardware.md)",
                                   o.port, b.wire_version, b.firmware_version(), CS_WIRE_VERSION));
  }
  return b;
}

// The encoder and gyroscope always; pulses (position mode) or the DAC (speed mode).
void require_capabilities(const BoardInfo& b, const SerialRigOptions& o) {
  const std::uint32_t needed = CS_CAP_ENCODER_QUADRATURE | CS_CAP_GYRO_ITG3205 |
                               (o.mode == CommandMode::position ? CS_CAP_PULSE_AB : CS_CAP_DAC_MCP4725);
  if ((b.capabilities & needed) != needed) {
    throw RuntimeError(fmt::format("serial port {}: the board (firmware {}) lacks capabilities 0x{:02x} that {} mode "
                                   "needs (it has 0x{:02x}); flash firmware/ with them enabled (docs/hardware.md)",
                                   o.port, b.firmware_version(), needed & ~b.capabilities, to_string(o.mode),
                                   b.capabilities));
  }
}

ConfigurePayload configure_payload(const SerialRigOptions& o) {
  ConfigurePayload config{};
  config[0] = o.mode == CommandMode::position ? CS_MODE_POSITION : CS_MODE_SPEED;
  config[1] = static_cast<std::uint8_t>(o.gyro_fs_sel);
  config[2] = static_cast<std::uint8_t>(o.gyro_dlpf_cfg);
  cs_put_u16(config.data() + 4, static_cast<std::uint16_t>(o.sample_rate_hz));
  cs_put_u16(config.data() + 6, static_cast<std::uint16_t>(o.update_rate_hz));
  cs_put_u32(config.data() + 8, o.max_pulse_rate_hz);
  cs_put_u16(config.data() + 12, static_cast<std::uint16_t>(o.watchdog_ms));
  bool clipped = false;
  cs_put_u16(config.data() + 14, volts_to_dac_code(0.0, o.dac_min_v, o.dac_max_v, clipped));
  return config;
}

// GET_STATS → STATS: the board's counters since its reset.
BoardStats request_stats(Session& s) {
  s.send(CS_MSG_GET_STATS, nullptr, 0);
  const auto f = s.await(CS_MSG_STATS, s.o.handshake_timeout_s);
  if (!f || f->length != CS_STATS_BYTES) {
    throw RuntimeError(fmt::format("serial port {}: no STATS within {} s", s.o.port, s.o.handshake_timeout_s));
  }
  return {cs_get_u32(f->payload + 0), cs_get_u32(f->payload + 4), cs_get_u32(f->payload + 8),
          cs_get_u32(f->payload + 12), cs_get_u32(f->payload + 16)};
}

// What the board counted since `before` (after − before), or nothing when it cannot be read.
std::optional<BoardStats> stats_since(Session& s, const std::optional<BoardStats>& before) noexcept {
  if (!before) return std::nullopt;
  try {
    const BoardStats& a = *before;
    const BoardStats b = request_stats(s);
    return BoardStats{b.samples_sent - a.samples_sent, b.samples_dropped - a.samples_dropped,
                      b.rx_corrupted - a.rx_corrupted, b.watchdog_trips - a.watchdog_trips, b.late_ticks - a.late_ticks};
  } catch (...) {
    return std::nullopt;
  }
}

// SELFTEST and its result (the gyroscope's WHO_AM_I and reading at rest, the DAC's answer).
BoardInfo::SelfTest run_selftest(Session& s) {
  s.send(CS_MSG_SELFTEST, nullptr, 0);
  const auto result = s.await(CS_MSG_SELFTEST_RESULT, s.o.handshake_timeout_s);
  if (!result || result->length != CS_SELFTEST_RESULT_BYTES) {
    throw RuntimeError(fmt::format("serial port {}: no SELFTEST_RESULT within {} s", s.o.port, s.o.handshake_timeout_s));
  }
  BoardInfo::SelfTest t;
  t.gyro_who_am_i = result->payload[0];
  t.gyro_ok = result->payload[1] != 0;
  t.dac_ok = result->payload[2] != 0;
  t.gyro_raw_at_rest = cs_get_i16(result->payload + 4);
  return t;
}

}  // namespace

SerialRig::SerialRig(const SerialRigOptions& options) : options_(options) {}

SerialRig::~SerialRig() {
  if (state() == LifecycleState::active || state() == LifecycleState::error) on_deactivate();
  if (impl_) impl_->port.close();
}

std::string_view SerialRig::backend() const noexcept { return impl_ ? impl_->port.backend() : ""; }

void SerialRig::on_configure() {
  options_.validate();
  auto m = std::make_unique<Impl>(options_);
  m->port.open(options_.port, options_.baud);
  m->port.flush_input();
  cs_decoder_reset(&m->decoder);
  Session s{options_, *m};
  BoardInfo b = parse_hello_ack(await_hello_ack(s), options_);
  require_capabilities(b, options_);
  // A board its previous host left running (killed mid-run: servo on, sampling) refuses
  // CONFIGURE; STOP, accepted in every state, brings it back (command safe, servo off).
  s.request(CS_MSG_STOP, nullptr, 0);
  const ConfigurePayload config = configure_payload(options_);
  s.request(CS_MSG_CONFIGURE, config.data(), CS_CONFIGURE_BYTES);
  if (options_.selftest) b.selftest = run_selftest(s);
  board_ = b;
  impl_ = std::move(m);
}

BoardStats SerialRig::board_stats() {
  if (state() != LifecycleState::inactive || !impl_) {
    throw RuntimeError(fmt::format("serial port {}: board statistics are read while the rig is configured and "
                                   "not running", options_.port));
  }
  Session s{options_, *impl_};
  return request_stats(s);
}

void SerialRig::on_activate() {
  Impl& m = *impl_;
  Session s{options_, m};
  m.ring.clear();
  m.samples = m.late = m.ring_overflows = m.board_tx_overflows = m.lost = m.commands_sent = m.commands_dropped = 0;
  m.corrupted = 0;
  m.max_lateness_ns = 0;
  m.anchored = false;
  m.have_tick = false;
  m.next_tick = 0;
  m.last_tick = 0;
  m.pending_flags = 0;
  m.read_failure = Impl::ReadFailure::none;
  m.tx_pending_size = 0;
  m.port_failed = false;
  m.stop_receiver = false;
  m.commands_rejected = m.watchdog_samples = m.rx_rejected_samples = 0;
  m.corrupted_at_start = m.decoder.corrupted;
  stop_problem_.clear();
  board_during_run_.reset();
  board_before_.reset();
  try {
    board_before_ = request_stats(s);
  } catch (const RuntimeError&) {
    // The run's record says the board's counters are unknown; the run itself can go on.
  }
  const std::uint8_t on = options_.servo_on ? 1 : 0;
  try {
    s.request(CS_MSG_SERVO, &on, CS_SERVO_BYTES);
    s.request(CS_MSG_START, nullptr, 0);
  } catch (...) {
    try {
      s.send(CS_MSG_STOP, nullptr, 0);  // servo off again, whichever step failed
    } catch (...) {
    }
    throw;
  }
  const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 / options_.sample_rate_hz));
  const auto tolerance_ns = static_cast<std::int64_t>(std::llround(options_.late_tolerance_s * 1e9));
  m.receiver = std::thread([&m, period_ns, tolerance_ns] { m.receive_loop(period_ns, tolerance_ns); });
}

void SerialRig::on_deactivate() noexcept {
  Impl& m = *impl_;
  m.stop_receiver.store(true, std::memory_order_release);
  if (m.receiver.joinable()) m.receiver.join();
  // STOP twice at most: an ACK lost in the stream of samples still queued must not leave the
  // servo on without saying so.
  for (int attempt = 0; attempt < 2; ++attempt) {
    try {
      stop_problem_.clear();
      Session s{options_, m};
      s.request(CS_MSG_STOP, nullptr, 0);
      board_during_run_ = stats_since(s, board_before_);
      return;
    } catch (const std::exception& e) {
      try {
        stop_problem_ = e.what();
      } catch (...) {
      }
    }
  }
}

std::vector<std::string> SerialRig::degradation() const {
  std::vector<std::string> why;
  const SerialRigStats st = stats();
  if (st.samples_lost > 0) why.push_back(fmt::format("{} sample(s) lost on the link", st.samples_lost));
  if (board_during_run_ && board_during_run_->samples_dropped > 0) {
    why.push_back(fmt::format("{} sample(s) dropped on the board", board_during_run_->samples_dropped));
  }
  if (st.watchdog_samples > 0 && st.commands_sent > 0) {  // a stream commands nothing: its watchdog is idle
    why.push_back(fmt::format("{} sample(s) taken while the board's watchdog held the command safe",
                              st.watchdog_samples));
  }
  if (st.commands_rejected > 0) why.push_back(fmt::format("{} command(s) refused by the host", st.commands_rejected));
  const std::uint64_t board_rejected = board_during_run_ ? board_during_run_->rx_corrupted : 0;
  if (board_rejected > 0 || st.rx_rejected_samples > 0) {
    why.push_back(fmt::format("the board rejected {} host frame(s) (COMMANDs lost; {} sample(s) flagged)",
                              board_rejected, st.rx_rejected_samples));
  }
  if (st.samples > 0 &&
      static_cast<double>(st.samples_late) > options_.max_late_fraction * static_cast<double>(st.samples)) {
    why.push_back(fmt::format("{} of {} samples arrived later than {:g} ms (allowed: {:g} %); the commands "
                              "answering them were late", st.samples_late, st.samples,
                              options_.late_tolerance_s * 1e3, options_.max_late_fraction * 100.0));
  }
  if (!stop_problem_.empty()) why.push_back("STOP was not confirmed: " + stop_problem_);
  if (impl_) {
    switch (impl_->read_failure) {
      case Impl::ReadFailure::timeout:
        why.push_back(fmt::format("no sample came within {:g} s (read_timeout_s): the board stopped sending or "
                                  "the host fell that far behind", options_.read_timeout_s));
        break;
      case Impl::ReadFailure::port_failed: why.push_back("the serial port failed (unplugged or closed)"); break;
      case Impl::ReadFailure::tick_repeated: why.push_back("the board's tick went back (it restarted)"); break;
      case Impl::ReadFailure::none: break;
    }
  }
  return why;
}

void SerialRig::on_cleanup() noexcept {
  if (impl_) impl_->port.close();
  impl_.reset();
}

}  // namespace clearshape::rig
