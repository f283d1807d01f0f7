#pragma once
// Device models on simavr's TWI bus (the IRQ protocol of simavr's avr_twi: the master raises
// START with the address byte, WRITE with a data byte, READ for a byte wanted, STOP; a device
// answers ACK or READ with data on the TWI input IRQ).
//   Itg3205: register file after the ITG-3205 datasheet (PS-ITG-3205A-00 §8): WHO_AM_I 0x00
//            = 0x68, SMPLRT_DIV 0x15, DLPF_FS 0x16, INT_CFG 0x17, INT_STATUS 0x1A, TEMP_OUT
//            0x1B/0x1C, GYRO_X/Y/ZOUT 0x1D…0x22 (big endian), PWR_MGM 0x3E; burst reads and
//            writes auto-increment the register pointer.
//   Mcp4725: fast-mode write (two bytes: 0 0 PD1 PD0 D11…D8, D7…D0), MCP4725 datasheet §6.1.
#include <array>
#include <cstdint>

struct avr_t;
struct avr_irq_t;

namespace clearshape::emulator {

class TwiDevice {
 public:
  TwiDevice(avr_t* avr, std::uint8_t address7, const char* name);
  virtual ~TwiDevice() = default;
  TwiDevice(const TwiDevice&) = delete;
  TwiDevice& operator=(const TwiDevice&) = delete;
  std::uint8_t address() const noexcept { return address_; }

 protected:
  virtual void on_start(bool read) = 0;
  virtual void on_write(std::uint8_t byte) = 0;
  virtual std::uint8_t on_read() = 0;
  virtual void on_stop() {}

 private:
  static void hook(avr_irq_t* irq, std::uint32_t value, void* param);
  void reply(std::uint8_t msg, std::uint8_t data);
  avr_irq_t* irq_ = nullptr;
  std::uint8_t address_;
  bool selected_ = false;
};

class Itg3205 final : public TwiDevice {
 public:
  explicit Itg3205(avr_t* avr);
  /// Output data rate the firmware configured (8 kHz at DLPF_CFG 0, else 1 kHz, / (div + 1)).
  double output_rate_hz() const noexcept;
  std::uint8_t dlpf_fs() const noexcept { return registers_[0x16]; }
  /// Latches a new Z-axis word (the other axes stay 0).
  void set_z(std::int16_t word) noexcept;
  std::uint64_t reads() const noexcept { return reads_; }

 private:
  void on_start(bool read) override;
  void on_write(std::uint8_t byte) override;
  std::uint8_t on_read() override;
  std::array<std::uint8_t, 0x40> registers_{};
  std::uint8_t pointer_ = 0;
  bool pointer_set_ = false;
  std::uint64_t reads_ = 0;
};

class Mcp4725 final : public TwiDevice {
 public:
  explicit Mcp4725(avr_t* avr);
  std::uint16_t code() const noexcept { return code_; }
  std::uint64_t writes() const noexcept { return writes_; }

 private:
  void on_start(bool read) override;
  void on_write(std::uint8_t byte) override;
  std::uint8_t on_read() override;
  std::uint16_t code_ = 2048;  // power-on: mid-scale (0 V after the level shift)
  std::uint8_t high_ = 0;
  int index_ = 0;
  std::uint64_t writes_ = 0;
};

}  // namespace clearshape::emulator
