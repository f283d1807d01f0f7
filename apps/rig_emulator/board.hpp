#pragma once
// The simulated rig board: the firmware ELF running in simavr (ATmega2560, 16 MHz), its UART0
// on a pty, the ITG-3205 and MCP4725 models on TWI, the pulse and servo-on pins read, the
// encoder pins driven from the plant, all in lockstep with the AVR clock.
//
// Lockstep: every plant step (default 100 µs of AVR time) a cycle timer advances the plant with
// the input held since the previous step (A/B edges counted x4 from pins 22/23, the DAC code,
// servo-on from pin 24), latches the gyro word at the ITG-3205's output rate and spreads the
// encoder edges towards the new count evenly over the next step on pins 2/3.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pty_link.hpp"
#include "rig_plant.hpp"
#include "twi_devices.hpp"

struct avr_t;
struct avr_irq_t;

namespace clearshape::emulator {

struct BoardOptions {
  std::string elf_path;
  double plant_step_s = 100e-6;
  double speed = 1.0;      ///< AVR seconds per wall second; 0 = as fast as possible
  double duration_s = 0.0; ///< 0 = until SIGINT/SIGTERM
  DamageOptions damage{};
  bool isr_profile = false; ///< measure every interrupt's cycles (slower); printed at exit
};

/// Cycles of one interrupt vector, from the vector fetch to the end of its reti (the AVR adds
/// 5 cycles of interrupt response before the fetch, datasheet §7.8).
struct IsrProfile {
  int vector = 0;
  std::uint64_t count = 0;
  std::uint64_t min_cycles = 0;
  std::uint64_t max_cycles = 0;
  std::uint64_t total_cycles = 0;
};

struct BoardStats {
  double simulated_s = 0.0;
  double wall_s = 0.0;
  std::int64_t pulse_edges = 0;
  std::int64_t pulse_illegal = 0;
  std::int64_t encoder_edges = 0;
  std::uint64_t gyro_samples = 0;
  std::uint64_t dac_writes = 0;
  bool servo_on = false;
};

class Board {
 public:
  /// Loads the ELF (throws InvalidArgument naming the file if it cannot be read or is not an
  /// ATmega2560 image) and builds the devices; throws RuntimeError on pty failures.
  Board(const BoardOptions& options, const rig::RigTruth& truth, const RigPlantOptions& plant);
  ~Board();
  Board(const Board&) = delete;
  Board& operator=(const Board&) = delete;

  const std::string& pty_path() const;
  /// Runs until the duration, a stop request or a firmware crash. Returns 0, or 1 on a crash or
  /// a plant failure (message on stderr).
  int run(const volatile int& stop_requested);
  BoardStats stats() const;
  /// Per-vector cycle counts (empty unless BoardOptions::isr_profile).
  std::vector<IsrProfile> isr_profile() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clearshape::emulator
