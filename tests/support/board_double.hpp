#pragma once
// A test double of the rig board: speaks the wire protocol (rig/wire_protocol.h, with its own
// encoder and decoder) on the master side of a pseudo-terminal pair, in a thread. SerialRig
// opens the slave side (path()). It answers HELLO/CONFIGURE/SERVO/START/STOP/SELFTEST/GET_STATS
// and, while started, sends one SAMPLE per period: encoder = 3·tick, gyro = 7·tick − 1000,
// pulses_emitted / dac_code = the last COMMAND value. Hooks let a test drop, damage, delay or
// flag samples, or refuse and misreport in the handshake. Deliberately small: not a firmware model.
#include <pty.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "clearshape/rig/wire_protocol.h"

namespace clearshape::testing {

class BoardDouble {
 public:
  struct Sample {
    std::uint32_t tick = 0;
    std::int32_t encoder = 0;
    std::int16_t gyro = 0;
    std::uint8_t flags = 0;
    std::int32_t pulses = 0;
    std::uint16_t dac = 0;
  };
  // Settings (set before the host connects).
  std::uint16_t wire_version = CS_WIRE_VERSION;
  std::uint32_t capabilities = 0x3F;
  bool silent = false;                 // never answer anything
  std::uint8_t configure_result = CS_OK;
  std::uint16_t configure_detail = 0;
  double sample_rate_hz = 1000.0;      // overwritten by CONFIGURE
  /// Called per tick; return false to skip sending it. May edit the sample.
  std::function<bool(Sample&)> on_sample;
  /// Called with each encoded SAMPLE frame before it is written (damage it here).
  std::function<void(std::uint32_t tick, std::uint8_t* frame, std::size_t size)> on_frame;
  /// Extra sleep before sending a tick (s).
  std::function<double(std::uint32_t tick)> delay_before_s;

  BoardDouble() {
    if (openpty(&master_, &slave_, nullptr, nullptr, nullptr) != 0) throw std::runtime_error("openpty failed");
    termios t{};
    tcgetattr(slave_, &t);
    cfmakeraw(&t);
    tcsetattr(slave_, TCSANOW, &t);
    path_ = ttyname(slave_);
    // Room for every message of a test, so that the double allocates nothing while it runs
    // (the allocation test counts every thread's allocations).
    commands.reserve(1 << 16);
    command_ticks.reserve(1 << 16);
    received.reserve(1 << 16);
  }
  ~BoardDouble() {
    stop();
    if (master_ >= 0) ::close(master_);
    ::close(slave_);
  }
  void start() { thread_ = std::thread([this] { loop(); }); }
  void stop() {
    quit_ = true;
    if (thread_.joinable()) thread_.join();
  }
  /// Closes the board's end: the host sees the port fail.
  void unplug() {
    stop();
    ::close(master_);
    master_ = -1;
  }
  const std::string& path() const { return path_; }

  // What the host sent (read after stop() or under the lock).
  std::mutex mutex;
  std::vector<std::uint8_t> configure_payload;
  std::vector<std::int32_t> commands;
  std::vector<std::uint32_t> command_ticks;
  std::vector<std::uint8_t> received;  // message types, in order
  bool servo_on = false;
  std::atomic<bool> started{false};

 private:
  void send(std::uint8_t type, const std::uint8_t* payload, std::uint8_t n) {
    std::uint8_t frame[CS_WIRE_MAX_FRAME];
    const std::size_t size = cs_frame_encode(frame, type, seq_++, payload, n);
    write_all(frame, size);
  }
  void write_all(const std::uint8_t* p, std::size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(master_, p, n);
      if (w <= 0) return;
      p += w;
      n -= static_cast<std::size_t>(w);
    }
  }
  void ack(std::uint8_t type, std::uint8_t result = CS_OK, std::uint16_t detail = 0) {
    std::uint8_t a[CS_ACK_BYTES] = {type, result, 0, 0};
    cs_put_u16(a + 2, detail);
    send(CS_MSG_ACK, a, CS_ACK_BYTES);
  }
  void handle(const cs_frame& f) {
    std::lock_guard<std::mutex> lock(mutex);
    received.push_back(f.type);
    if (silent) return;
    switch (f.type) {
      case CS_MSG_HELLO: {
        std::uint8_t p[CS_HELLO_ACK_BYTES] = {};
        cs_put_u16(p, wire_version);
        p[2] = 1;
        p[3] = 2;
        cs_put_u16(p + 4, 3);
        cs_put_u16(p + 6, 3000);
        cs_put_u32(p + 8, capabilities);
        cs_put_u32(p + 12, 16000000u);
        send(CS_MSG_HELLO_ACK, p, CS_HELLO_ACK_BYTES);
        break;
      }
      case CS_MSG_CONFIGURE:
        configure_payload.assign(f.payload, f.payload + f.length);
        sample_rate_hz = cs_get_u16(f.payload + 4);
        ack(f.type, configure_result, configure_detail);
        break;
      case CS_MSG_SERVO:
        servo_on = f.payload[0] != 0;
        ack(f.type);
        break;
      case CS_MSG_START:
        ack(f.type);
        tick_ = 0;
        next_ = std::chrono::steady_clock::now();
        started = true;
        break;
      case CS_MSG_STOP:
        started = false;
        servo_on = false;
        ack(f.type);
        break;
      case CS_MSG_COMMAND:
        command_ticks.push_back(cs_get_u32(f.payload));
        commands.push_back(cs_get_i32(f.payload + 4));
        last_command_ = cs_get_i32(f.payload + 4);
        break;
      case CS_MSG_SELFTEST: {
        const std::uint8_t p[CS_SELFTEST_RESULT_BYTES] = {0x69, 1, 1, 0, 0xFE, 0xFF};
        send(CS_MSG_SELFTEST_RESULT, p, CS_SELFTEST_RESULT_BYTES);
        break;
      }
      case CS_MSG_GET_STATS: {
        std::uint8_t p[CS_STATS_BYTES] = {};
        cs_put_u32(p, 1234);
        cs_put_u32(p + 12, 2);
        send(CS_MSG_STATS, p, CS_STATS_BYTES);
        break;
      }
      default: ack(f.type, CS_ERR_UNKNOWN);
    }
  }
  void emit_due() {
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / sample_rate_hz));
    while (started && std::chrono::steady_clock::now() >= next_) {
      const std::uint32_t tick = tick_++;
      next_ += period;
      if (delay_before_s) {
        const double d = delay_before_s(tick);
        if (d > 0) std::this_thread::sleep_for(std::chrono::duration<double>(d));
      }
      Sample s{tick, static_cast<std::int32_t>(3 * tick), static_cast<std::int16_t>(7 * static_cast<int>(tick) - 1000),
               CS_SAMPLE_SERVO_ON, last_command_, static_cast<std::uint16_t>(last_command_)};
      if (on_sample && !on_sample(s)) continue;
      std::uint8_t p[CS_SAMPLE_BYTES] = {};
      const cs_sample wire{s.tick, s.encoder, s.gyro, s.flags, 0, s.pulses, s.dac, 0};
      cs_sample_encode(p, &wire);
      std::uint8_t frame[CS_WIRE_MAX_FRAME];
      const std::size_t size = cs_frame_encode(frame, CS_MSG_SAMPLE, seq_++, p, CS_SAMPLE_BYTES);
      if (on_frame) on_frame(tick, frame, size);
      write_all(frame, size);
    }
  }
  void loop() {
    cs_decoder d;
    cs_decoder_reset(&d);
    cs_frame f{};
    std::uint8_t buf[256];
    while (!quit_) {
      pollfd p{master_, POLLIN, 0};
      if (::poll(&p, 1, started ? 0 : 5) > 0 && (p.revents & POLLIN)) {
        const ssize_t n = ::read(master_, buf, sizeof buf);
        for (ssize_t i = 0; i < n; ++i) {
          if (cs_decoder_push(&d, buf[i], &f) == 1) handle(f);
        }
      }
      emit_due();
      if (started) std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  }

  int master_ = -1, slave_ = -1;
  std::string path_;
  std::thread thread_;
  std::atomic<bool> quit_{false};
  std::uint8_t seq_ = 0;
  std::uint32_t tick_ = 0;
  std::int32_t last_command_ = 0;
  std::chrono::steady_clock::time_point next_{};
};

}  // namespace clearshape::testing
