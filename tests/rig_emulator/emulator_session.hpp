#pragma once
// Test support (header-only: the test folder compiles test_*.cpp): starts clearshape-rig-emulator, opens its pty and talks the wire protocol with
// the protocol's own encoder and decoder (include/clearshape/rig/wire_protocol.h).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "clearshape/rig/wire_protocol.h"

extern char** environ;

// Paths given by tests/CMakeLists.txt; empty when the emulator was not built (no simavr or no
// avr-gcc): the tests that need it skip.
#ifndef CLEARSHAPE_RIG_EMULATOR
#define CLEARSHAPE_RIG_EMULATOR ""
#endif
#ifndef CLEARSHAPE_FIRMWARE_ELF
#define CLEARSHAPE_FIRMWARE_ELF ""
#endif
#ifndef CLEARSHAPE_AVR_SIZE
#define CLEARSHAPE_AVR_SIZE "avr-size"
#endif

namespace clearshape::test {

inline bool emulator_available() { return CLEARSHAPE_RIG_EMULATOR[0] != '\0'; }

/// Skips a test (gtest) when the emulator was not built.
#define REQUIRE_EMULATOR()                                                     \
  if (!emulator_available()) GTEST_SKIP() << "clearshape-rig-emulator was not built (needs avr-gcc and simavr)"

/// A COMMAND payload: the tick it applies at and a signed 32-bit value (pulses or DAC code).
inline std::vector<std::uint8_t> i32_command(std::uint32_t tick, std::int32_t value) {
  std::vector<std::uint8_t> p(CS_COMMAND_BYTES);
  cs_put_u32(p.data(), tick);
  cs_put_i32(p.data() + 4, value);
  return p;
}

using Sample = cs_sample;  // the protocol's decoded SAMPLE
Sample parse_sample(const cs_frame& frame);

struct Configure {
  std::uint8_t mode = CS_MODE_POSITION;
  std::uint8_t gyro_fs_sel = 3;
  std::uint8_t gyro_dlpf_cfg = 3;  // 42 Hz, the thesis's setting
  std::uint8_t reserved = 0;
  std::uint16_t sample_rate_hz = 1000;
  std::uint16_t update_rate_hz = 30;
  std::uint32_t max_pulse_rate_hz = CS_MAX_PULSE_RATE_HZ;
  std::uint16_t watchdog_ms = 0;
  std::uint16_t dac_safe_code = 2048;
  std::vector<std::uint8_t> payload() const;
};

class EmulatorSession {
 public:
  /// Starts the emulator with `args` plus --elf (and --free unless `args` has --speed); throws
  /// on failure.
  explicit EmulatorSession(const std::vector<std::string>& args);
  ~EmulatorSession();
  EmulatorSession(const EmulatorSession&) = delete;
  EmulatorSession& operator=(const EmulatorSession&) = delete;

  /// Sends a frame; returns the SEQ it used.
  std::uint8_t send(std::uint8_t type, const std::vector<std::uint8_t>& payload = {});
  /// Writes raw bytes (a damaged frame, line noise).
  void send_bytes(const std::vector<std::uint8_t>& bytes);
  /// The pty path (for another program, e.g. the clearshape CLI, to open).
  const std::string& path() const noexcept { return path_; }
  /// The next good frame within `timeout_ms` of wall time.
  std::optional<cs_frame> next(int timeout_ms = 2000);
  /// The next frame of `type` (others are skipped; SAMPLEs are kept in skipped_samples()).
  std::optional<cs_frame> next_of(std::uint8_t type, int timeout_ms = 2000);
  /// Sends and waits for the answer of `reply_type`, resending up to `attempts` times.
  std::optional<cs_frame> request(std::uint8_t type, const std::vector<std::uint8_t>& payload,
                                  std::uint8_t reply_type, int attempts = 1);
  /// ACK for `type`: {result, detail}, or nullopt.
  std::optional<std::pair<std::uint8_t, std::uint16_t>> ack(std::uint8_t type,
                                                            const std::vector<std::uint8_t>& payload = {},
                                                            int attempts = 1);
  /// The next SAMPLE.
  std::optional<Sample> sample(int timeout_ms = 2000);
  /// HELLO, CONFIGURE, SERVO on, START; true when every answer was OK.
  bool start_run(const Configure& configure);

  const cs_decoder& decoder() const noexcept { return decoder_; }
  std::vector<Sample>& skipped_samples() noexcept { return skipped_samples_; }

 private:
  pid_t pid_ = -1;
  std::string path_;
  int out_pipe_ = -1;
  int fd_ = -1;
  std::uint8_t seq_ = 0;
  cs_decoder decoder_{};
  std::vector<std::uint8_t> pending_;
  std::vector<Sample> skipped_samples_;
};

// ---- implementation ----


inline Sample parse_sample(const cs_frame& f) { return cs_sample_decode(f.payload); }

inline std::vector<std::uint8_t> Configure::payload() const {
  std::vector<std::uint8_t> p(CS_CONFIGURE_BYTES);
  p[0] = mode;
  p[1] = gyro_fs_sel;
  p[2] = gyro_dlpf_cfg;
  p[3] = reserved;
  cs_put_u16(p.data() + 4, sample_rate_hz);
  cs_put_u16(p.data() + 6, update_rate_hz);
  cs_put_u32(p.data() + 8, max_pulse_rate_hz);
  cs_put_u16(p.data() + 12, watchdog_ms);
  cs_put_u16(p.data() + 14, dac_safe_code);
  return p;
}

inline EmulatorSession::EmulatorSession(const std::vector<std::string>& args) {
  cs_decoder_reset(&decoder_);
  std::vector<std::string> argv_s = {CLEARSHAPE_RIG_EMULATOR, "--elf", CLEARSHAPE_FIRMWARE_ELF};
  if (std::find(args.begin(), args.end(), "--speed") == args.end()) argv_s.push_back("--free");
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) throw std::runtime_error("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  out_pipe_ = pipe_fds[0];
  if (rc != 0) throw std::runtime_error("cannot start " + argv_s[0]);
  std::string line;
  char c = 0;
  pollfd p{out_pipe_, POLLIN, 0};
  while (poll(&p, 1, 10000) > 0 && read(out_pipe_, &c, 1) == 1 && c != '\n') line += c;
  if (line.rfind("/dev/", 0) != 0) throw std::runtime_error("emulator printed no pty path: '" + line + "'");
  path_ = line;
  fd_ = open(line.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd_ < 0) throw std::runtime_error("cannot open " + line);
  termios tio{};
  tcgetattr(fd_, &tio);
  cfmakeraw(&tio);
  tcsetattr(fd_, TCSANOW, &tio);
}

inline EmulatorSession::~EmulatorSession() {
  if (fd_ >= 0) close(fd_);
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  if (out_pipe_ >= 0) close(out_pipe_);
}

inline std::uint8_t EmulatorSession::send(std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  std::uint8_t out[CS_WIRE_MAX_FRAME];
  const std::uint8_t seq = seq_++;
  const std::size_t n = cs_frame_encode(out, type, seq, payload.data(), static_cast<std::uint8_t>(payload.size()));
  send_bytes(std::vector<std::uint8_t>(out, out + n));
  return seq;
}

inline void EmulatorSession::send_bytes(const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t w = write(fd_, bytes.data() + done, bytes.size() - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
    } else {
      pollfd p{fd_, POLLOUT, 0};
      poll(&p, 1, 100);
    }
  }
}

inline std::optional<cs_frame> EmulatorSession::next(int timeout_ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  cs_frame frame{};
  for (;;) {
    while (!pending_.empty()) {
      const std::uint8_t byte = pending_.front();
      pending_.erase(pending_.begin());
      if (cs_decoder_push(&decoder_, byte, &frame)) return frame;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
    std::uint8_t buffer[4096];
    const ssize_t n = read(fd_, buffer, sizeof buffer);
    if (n > 0) pending_.insert(pending_.end(), buffer, buffer + n);
  }
}

inline std::optional<cs_frame> EmulatorSession::next_of(std::uint8_t type, int timeout_ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    std::optional<cs_frame> f = next(static_cast<int>(left.count()));
    if (!f) return std::nullopt;
    if (f->type == type) return f;
    if (f->type == CS_MSG_SAMPLE) skipped_samples_.push_back(parse_sample(*f));
  }
}

inline std::optional<cs_frame> EmulatorSession::request(std::uint8_t type, const std::vector<std::uint8_t>& payload,
                                                 std::uint8_t reply_type, int attempts) {
  for (int i = 0; i < attempts; ++i) {
    send(type, payload);
    for (;;) {
      std::optional<cs_frame> f = next_of(reply_type, 1000);
      if (!f) break;
      if (reply_type != CS_MSG_ACK || f->payload[0] == type) return f;
    }
  }
  return std::nullopt;
}

inline std::optional<std::pair<std::uint8_t, std::uint16_t>> EmulatorSession::ack(
    std::uint8_t type, const std::vector<std::uint8_t>& payload, int attempts) {
  std::optional<cs_frame> f = request(type, payload, CS_MSG_ACK, attempts);
  if (!f) return std::nullopt;
  return std::make_pair(f->payload[1], cs_get_u16(f->payload + 2));
}

inline std::optional<Sample> EmulatorSession::sample(int timeout_ms) {
  std::optional<cs_frame> f = next_of(CS_MSG_SAMPLE, timeout_ms);
  if (!f) return std::nullopt;
  return parse_sample(*f);
}

inline bool EmulatorSession::start_run(const Configure& configure) {
  std::vector<std::uint8_t> hello(CS_HELLO_BYTES);
  cs_put_u16(hello.data(), CS_WIRE_VERSION);
  if (!request(CS_MSG_HELLO, hello, CS_MSG_HELLO_ACK, 3)) return false;
  const auto ok = [](const auto& a) { return a && a->first == CS_OK; };
  return ok(ack(CS_MSG_CONFIGURE, configure.payload(), 3)) && ok(ack(CS_MSG_SERVO, {1}, 3)) &&
         ok(ack(CS_MSG_START, {}, 3));
}

}  // namespace clearshape::test
