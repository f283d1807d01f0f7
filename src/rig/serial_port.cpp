#include "serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <libserialport.h>

#include "clearshape/core/error.hpp"

namespace clearshape::rig::detail {
namespace {

std::string port_list_text() {
  const auto ports = SerialPort::list_ports();
  if (ports.empty()) return "libserialport sees no serial ports";
  std::string text = "ports libserialport sees: ";
  for (std::size_t i = 0; i < ports.size(); ++i) text += (i > 0 ? ", " : "") + ports[i];
  return text;
}

speed_t termios_speed(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 2000000: return B2000000;
    default: return B0;
  }
}

// A pseudo-terminal slave: a character device that is a terminal, under /dev/pts.
bool is_pseudo_terminal(const std::string& name) {
  char resolved[4096];
  if (realpath(name.c_str(), resolved) == nullptr) return false;
  struct stat st {};
  return std::strncmp(resolved, "/dev/pts/", 9) == 0 && stat(resolved, &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

std::vector<std::string> SerialPort::list_ports() {
  std::vector<std::string> out;
  sp_port** list = nullptr;
  if (sp_list_ports(&list) != SP_OK) return out;
  for (int i = 0; list[i] != nullptr; ++i) out.emplace_back(sp_get_port_name(list[i]));
  sp_free_port_list(list);
  return out;
}

void SerialPort::open(const std::string& name, int baud) {
  close();
  if (is_pseudo_terminal(name)) {
    const speed_t speed = termios_speed(baud);
    if (speed == B0) throw RuntimeError(fmt::format("serial port {}: baud {} has no termios speed", name, baud));
    const int fd = ::open(name.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      throw RuntimeError(fmt::format("serial port {}: cannot open the pseudo-terminal: {}; is the emulator "
                                     "still running?", name, std::strerror(errno)));
    }
    termios t{};
    if (tcgetattr(fd, &t) != 0) {
      ::close(fd);
      throw RuntimeError(fmt::format("serial port {}: not a terminal: {}", name, std::strerror(errno)));
    }
    cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
    cfsetispeed(&t, speed);
    cfsetospeed(&t, speed);
    if (tcsetattr(fd, TCSANOW, &t) != 0) {
      ::close(fd);
      throw RuntimeError(fmt::format("serial port {}: cannot set raw 8N1 at {} baud: {}", name, baud,
                                     std::strerror(errno)));
    }
    fd_ = fd;
    return;
  }
  // A path that exists is named for what it is, not as a missing port.
  struct stat st {};
  const bool exists = ::stat(name.c_str(), &st) == 0;
  if (exists && !S_ISCHR(st.st_mode)) {
    throw RuntimeError(fmt::format("serial port {}: is {}, not a serial device; name one of the ports ({})", name,
                                   S_ISDIR(st.st_mode) ? "a folder" : S_ISREG(st.st_mode) ? "a regular file"
                                                                                          : "not a character device",
                                   port_list_text()));
  }
  sp_port* port = nullptr;
  if (sp_get_port_by_name(name.c_str(), &port) != SP_OK) {
    if (exists) {
      throw RuntimeError(fmt::format("serial port {}: is a character device but not a serial port (no serial "
                                     "driver behind it); name one of the ports ({})",
                                     name, port_list_text()));
    }
    throw RuntimeError(fmt::format("serial port {}: no such port ({}); check the cable and name one of "
                                   "those",
                                   name, port_list_text()));
  }
  if (sp_open(port, SP_MODE_READ_WRITE) != SP_OK) {
    const std::string why = sp_last_error_message();
    sp_free_port(port);
    throw RuntimeError(fmt::format("serial port {}: cannot open: {}; is another program using it, and may "
                                   "this user open it (group dialout)?", name, why));
  }
  const bool configured = sp_set_baudrate(port, baud) == SP_OK && sp_set_bits(port, 8) == SP_OK &&
                          sp_set_parity(port, SP_PARITY_NONE) == SP_OK && sp_set_stopbits(port, 1) == SP_OK &&
                          sp_set_flowcontrol(port, SP_FLOWCONTROL_NONE) == SP_OK;
  int fd = -1;
  if (!configured || sp_get_port_handle(port, &fd) != SP_OK || fd < 0) {
    const std::string why = sp_last_error_message();
    sp_close(port);
    sp_free_port(port);
    throw RuntimeError(fmt::format("serial port {}: cannot configure 8N1 at {} baud: {}", name, baud, why));
  }
  // Our I/O polls and never blocks on the descriptor itself.
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
  sp_ = port;
  fd_ = fd;
}

void SerialPort::close() noexcept {
  if (sp_ != nullptr) {
    sp_close(sp_);
    sp_free_port(sp_);
    sp_ = nullptr;
  } else if (fd_ >= 0) {
    ::close(fd_);
  }
  fd_ = -1;
}

long SerialPort::read_some(std::uint8_t* buffer, std::size_t capacity, int timeout_ms) noexcept {
  if (fd_ < 0) return -1;
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) return errno == EINTR ? 0 : -1;
  if (ready == 0) return 0;
  if ((p.revents & POLLIN) == 0) return (p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0 ? -1 : 0;
  const ssize_t n = ::read(fd_, buffer, capacity);
  if (n < 0) return errno == EAGAIN || errno == EINTR ? 0 : -1;
  return static_cast<long>(n);
}

long SerialPort::write_some(const std::uint8_t* data, std::size_t size) noexcept {
  if (fd_ < 0) return -1;
  const ssize_t n = ::write(fd_, data, size);
  if (n < 0) return errno == EAGAIN || errno == EINTR ? 0 : -1;
  return static_cast<long>(n);
}

void SerialPort::flush_input() noexcept {
  if (fd_ >= 0) tcflush(fd_, TCIFLUSH);
}

}  // namespace clearshape::rig::detail
