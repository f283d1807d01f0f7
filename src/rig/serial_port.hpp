#pragma once
// The serial port under rig::SerialRig (internal). libserialport opens and configures a
// hardware port (8N1, no flow control, the baud rate) and lists the ports it sees; a
// pseudo-terminal (the firmware emulator's, the tests' board double), for which libserialport
// has no device metadata and refuses the name, is opened with termios directly (raw, same
// settings). Either way the I/O then goes through the file descriptor: read_some() waits with
// poll() up to a timeout, write_some() never blocks. Neither allocates.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

struct sp_port;

namespace clearshape::rig::detail {

class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort() { close(); }
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Opens and configures `name` at `baud`. Throws RuntimeError naming the port and the
  /// remedy (for an unknown port: the ports libserialport sees).
  void open(const std::string& name, int baud);
  void close() noexcept;
  bool is_open() const noexcept { return fd_ >= 0; }
  /// "libserialport" or "termios (pseudo-terminal)".
  const char* backend() const noexcept { return sp_ != nullptr ? "libserialport" : "termios (pseudo-terminal)"; }

  /// Reads what is available, waiting up to timeout_ms for the first byte. Returns the byte
  /// count (0 on timeout), or −1 when the port failed (closed, unplugged).
  long read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms) noexcept;
  /// Writes without blocking. Returns the bytes written (possibly fewer), or −1 on failure.
  long write_some(const std::uint8_t* data, std::size_t size) noexcept;
  /// Discards unread input.
  void flush_input() noexcept;

  /// The ports libserialport sees (for error messages), e.g. {"/dev/ttyACM0", "/dev/ttyS0"}.
  static std::vector<std::string> list_ports();

 private:
  sp_port* sp_ = nullptr;
  int fd_ = -1;
};

}  // namespace clearshape::rig::detail
