#include "twi_devices.hpp"

#include <simavr/avr_twi.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_io.h>
#include <simavr/sim_irq.h>

namespace clearshape::emulator {

TwiDevice::TwiDevice(avr_t* avr, std::uint8_t address7, const char* name) : address_(address7) {
  const char* names[2] = {name, name};
  irq_ = avr_alloc_irq(&avr->irq_pool, 0, 2, names);
  avr_irq_register_notify(irq_ + TWI_IRQ_OUTPUT, &TwiDevice::hook, this);
  avr_connect_irq(irq_ + TWI_IRQ_INPUT, avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT));
  avr_connect_irq(avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), irq_ + TWI_IRQ_OUTPUT);
}

void TwiDevice::reply(std::uint8_t msg, std::uint8_t data) {
  avr_raise_irq(irq_ + TWI_IRQ_INPUT, avr_twi_irq_msg(msg, static_cast<std::uint8_t>(address_ << 1), data));
}

void TwiDevice::hook(avr_irq_t*, std::uint32_t value, void* param) {
  auto* self = static_cast<TwiDevice*>(param);
  avr_twi_msg_irq_t v;
  v.u.v = value;
  if (v.u.twi.msg & TWI_COND_STOP) {
    if (self->selected_) self->on_stop();
    self->selected_ = false;
  }
  if (v.u.twi.msg & TWI_COND_START) {
    self->selected_ = (v.u.twi.addr >> 1) == self->address_;
    if (self->selected_) {
      self->on_start((v.u.twi.addr & 1u) != 0);
      self->reply(TWI_COND_ACK, 1);
    }
    return;
  }
  if (!self->selected_) return;
  if (v.u.twi.msg & TWI_COND_WRITE) {
    self->reply(TWI_COND_ACK, 1);
    self->on_write(v.u.twi.data);
  }
  if (v.u.twi.msg & TWI_COND_READ) self->reply(TWI_COND_READ, self->on_read());
}

Itg3205::Itg3205(avr_t* avr) : TwiDevice(avr, 0x68, "itg3205") {
  registers_[0x00] = 0x68;  // WHO_AM_I: ID bits 6:1 = 110100, AD0 low
  registers_[0x1B] = 0xF2;  // TEMP_OUT −13200 LSB ≈ 35 °C (−13200 + 280 · (T − 35))
  registers_[0x1C] = 0x70;
}

double Itg3205::output_rate_hz() const noexcept {
  const double internal_hz = (registers_[0x16] & 0x07u) == 0 ? 8000.0 : 1000.0;
  return internal_hz / (1.0 + registers_[0x15]);
}

void Itg3205::set_z(std::int16_t word) noexcept {
  registers_[0x21] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(word) >> 8);
  registers_[0x22] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(word) & 0xFFu);
}

void Itg3205::on_start(bool read) {
  if (!read) pointer_set_ = false;
}

void Itg3205::on_write(std::uint8_t byte) {
  if (!pointer_set_) {
    pointer_ = static_cast<std::uint8_t>(byte & 0x3Fu);
    pointer_set_ = true;
    return;
  }
  // Writable: SMPLRT_DIV, DLPF_FS, INT_CFG, PWR_MGM (the others are read-only).
  if (pointer_ == 0x15 || pointer_ == 0x16 || pointer_ == 0x17 || pointer_ == 0x3E) {
    registers_[pointer_] = byte;
  }
  pointer_ = static_cast<std::uint8_t>((pointer_ + 1u) & 0x3Fu);
}

std::uint8_t Itg3205::on_read() {
  const std::uint8_t value = registers_[pointer_];
  pointer_ = static_cast<std::uint8_t>((pointer_ + 1u) & 0x3Fu);
  ++reads_;
  return value;
}

Mcp4725::Mcp4725(avr_t* avr) : TwiDevice(avr, 0x60, "mcp4725") {}

void Mcp4725::on_start(bool) { index_ = 0; }

void Mcp4725::on_write(std::uint8_t byte) {
  if (index_ == 0) {
    high_ = byte;
  } else if (index_ == 1 && (high_ & 0xC0u) == 0) {  // fast mode: C2 C1 = 0 0
    code_ = static_cast<std::uint16_t>(((high_ & 0x0Fu) << 8) | byte);
    ++writes_;
  }
  ++index_;
}

std::uint8_t Mcp4725::on_read() {
  // Read-back (datasheet Fig. 6-3): status byte, then the DAC register's D11…D4, D3…D0 << 4.
  const std::uint8_t bytes[3] = {0xC0u, static_cast<std::uint8_t>(code_ >> 4),
                                 static_cast<std::uint8_t>((code_ & 0x0Fu) << 4)};
  return bytes[(index_++) % 3];
}

}  // namespace clearshape::emulator
