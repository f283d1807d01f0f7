#include "pty_link.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <simavr/avr_uart.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_io.h>
#include <simavr/sim_irq.h>

#include "clearshape/core/error.hpp"

namespace clearshape::emulator {

namespace {
constexpr std::size_t kOutputLimit = 4096;  // bytes held for a slow reader before waiting
}

PtyLink::PtyLink(avr_t* avr, const DamageOptions& damage) : avr_(avr), damage_(damage) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) {
    throw RuntimeError(std::string("cannot open a pseudo-terminal: ") + std::strerror(errno));
  }
  slave_path_ = ptsname(master_);
  slave_ = open(slave_path_.c_str(), O_RDWR | O_NOCTTY);
  if (slave_ < 0) throw RuntimeError("cannot open " + slave_path_ + ": " + std::strerror(errno));
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);
  tcsetattr(slave_, TCSANOW, &tio);
  fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  cs_decoder_reset(&host_decoder_);

  uart_input_ = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
                          &PtyLink::on_uart_output, this);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON),
                          &PtyLink::on_xon, this);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF),
                          &PtyLink::on_xoff, this);
  // No "print to the console" behaviour: the bytes are the protocol's.
  std::uint32_t flags = 0;
  avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~static_cast<std::uint32_t>(AVR_UART_FLAG_STDIO);
  avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
}

PtyLink::~PtyLink() {
  if (slave_ >= 0) close(slave_);
  if (master_ >= 0) close(master_);
}

void PtyLink::on_uart_output(avr_irq_t*, std::uint32_t value, void* param) {
  auto* self = static_cast<PtyLink*>(param);
  auto byte = static_cast<std::uint8_t>(value);
  const std::uint64_t n = ++self->board_bytes_;
  if (self->damage_.drop_every != 0 && n % self->damage_.drop_every == 0) {
    ++self->dropped_;
    return;
  }
  if (self->damage_.corrupt_every != 0 && n % self->damage_.corrupt_every == 0) {
    byte ^= 0x5Au;
    ++self->corrupted_;
  }
  self->to_host_.push_back(byte);
}

void PtyLink::on_xon(avr_irq_t*, std::uint32_t, void* param) { static_cast<PtyLink*>(param)->xon_ = true; }
void PtyLink::on_xoff(avr_irq_t*, std::uint32_t, void* param) { static_cast<PtyLink*>(param)->xon_ = false; }

void PtyLink::flush_output(bool wait) {
  while (!to_host_.empty()) {
    std::uint8_t chunk[512];
    std::size_t n = 0;
    for (auto it = to_host_.begin(); it != to_host_.end() && n < sizeof chunk; ++it) chunk[n++] = *it;
    const ssize_t written = write(master_, chunk, n);
    if (written > 0) {
      to_host_.erase(to_host_.begin(), to_host_.begin() + written);
      sent_ += static_cast<std::uint64_t>(written);
      continue;
    }
    if (!wait || to_host_.size() <= kOutputLimit || (stop_ != nullptr && *stop_)) return;
    pollfd p{master_, POLLOUT, 0};
    poll(&p, 1, 50);
  }
}

void PtyLink::service() {
  flush_output(true);
  std::uint8_t buffer[256];
  for (;;) {
    const ssize_t n = read(master_, buffer, sizeof buffer);
    if (n <= 0) break;
    received_ += static_cast<std::uint64_t>(n);
    for (ssize_t i = 0; i < n; ++i) {
      to_board_.push_back(buffer[i]);
      if (cs_decoder_push(&host_decoder_, buffer[i], &host_frame_) &&
          host_frame_.type == CS_MSG_CONFIGURE && host_frame_.length == CS_CONFIGURE_BYTES) {
        configured_mode_ = host_frame_.payload[0];
      }
    }
    if (static_cast<std::size_t>(n) < sizeof buffer) break;
  }
  // Bytes wait until the firmware has enabled its receiver (UCSR0B.RXEN0; the C start-up
  // takes ~0.2 ms of AVR time, and the UART model drops bytes that arrive before).
  constexpr std::size_t kUcsr0b = 0xC1;  // ATmega2560 data-space address
  constexpr std::uint8_t kRxen0 = 1u << 4;
  if ((avr_->data[kUcsr0b] & kRxen0) == 0) return;
  while (xon_ && !to_board_.empty()) {
    const std::uint8_t byte = to_board_.front();
    to_board_.pop_front();
    avr_raise_irq(uart_input_, byte);
  }
}

int PtyLink::take_configured_mode() noexcept {
  const int mode = configured_mode_;
  configured_mode_ = -1;
  return mode;
}

}  // namespace clearshape::emulator
