#pragma once
// UART0 of the simulated board as a pseudo-terminal. Board → host bytes can be damaged
// deterministically for tests (every Nth byte XOR 0x5A, every Mth byte dropped). Host → board
// bytes enter the AVR's UART only while its receive FIFO has room (simavr's XON/XOFF IRQs);
// they are also decoded here so that the emulator follows the host's CONFIGURE (mode).
// Nothing is ever lost on the pty itself: when the host reads slowly the simulation waits.
#include <cstdint>
#include <deque>
#include <string>

#include "clearshape/rig/wire_protocol.h"

struct avr_t;
struct avr_irq_t;

namespace clearshape::emulator {

struct DamageOptions {
  std::uint64_t corrupt_every = 0;  ///< 0 = never
  std::uint64_t drop_every = 0;     ///< 0 = never
};

class PtyLink {
 public:
  /// Opens the pty (throws RuntimeError) and hooks UART0.
  PtyLink(avr_t* avr, const DamageOptions& damage);
  ~PtyLink();
  PtyLink(const PtyLink&) = delete;
  PtyLink& operator=(const PtyLink&) = delete;

  const std::string& slave_path() const noexcept { return slave_path_; }
  /// Moves bytes between the pty and the UART; waits while more than 4 kB wait for the host
  /// (the simulation never outruns its reader, and no byte is lost).
  void service();
  /// A CONFIGURE frame the host sent since the last call: its mode byte, else -1.
  int take_configured_mode() noexcept;
  /// A flag that ends the wait for a slow reader (SIGINT/SIGTERM).
  void set_stop_flag(const volatile int* stop) noexcept { stop_ = stop; }

  std::uint64_t bytes_to_host() const noexcept { return sent_; }
  std::uint64_t bytes_from_host() const noexcept { return received_; }
  std::uint64_t bytes_corrupted() const noexcept { return corrupted_; }
  std::uint64_t bytes_dropped() const noexcept { return dropped_; }

 private:
  static void on_uart_output(avr_irq_t* irq, std::uint32_t value, void* param);
  static void on_xon(avr_irq_t* irq, std::uint32_t value, void* param);
  static void on_xoff(avr_irq_t* irq, std::uint32_t value, void* param);
  void flush_output(bool wait);

  avr_t* avr_;
  DamageOptions damage_;
  const volatile int* stop_ = nullptr;
  int master_ = -1;
  int slave_ = -1;  // kept open: the line settings stay raw and reads never see EIO
  std::string slave_path_;
  avr_irq_t* uart_input_ = nullptr;
  bool xon_ = true;
  std::deque<std::uint8_t> to_host_;
  std::deque<std::uint8_t> to_board_;
  cs_decoder host_decoder_{};
  cs_frame host_frame_{};
  int configured_mode_ = -1;
  std::uint64_t board_bytes_ = 0;
  std::uint64_t sent_ = 0;
  std::uint64_t received_ = 0;
  std::uint64_t corrupted_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace clearshape::emulator
