#pragma once
// The physical rig: the thesis's Arduino Mega 2560 board (encoder counting, A/B pulse train for
// position mode, 12-bit DAC for speed mode, ITG-3205 gyroscope) behind the Rig interface,
// over a serial port and the wire protocol of rig/wire_protocol.h (docs/hardware.md).
//
//   configure():  open the port, HELLO → HELLO_ACK (wire version checked), CONFIGURE → ACK,
//                 optionally SELFTEST → SELFTEST_RESULT
//   activate():   SERVO on (unless servo_on = false) → ACK, START → ACK; a receive thread decodes the board's SAMPLE
//                 frames into a preallocated lock-free ring
//   read():       the next sample from the ring (waits up to read_timeout_s; a timeout or a
//                 dead port → Status::device_error), converted to SI
//   write():      one COMMAND frame (position: motor angle → pulse target; speed: V → DAC
//                 code), written without blocking
//   deactivate(): STOP → ACK (the board drops the command to its safe value, servo off)
//
// Errors name the port, what was expected and the remedy. read()/write() are noexcept and
// allocation-free. Counters: samples, lost (gaps in the board's tick), corrupted (frames the
// decoder rejected) and late (arrival later than tick·T after tick 0's arrival, plus
// late_tolerance_s) are kept separately (stats(), link_counters()).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clearshape/rig/rig.hpp"

namespace clearshape::rig {

/// What to do when the board's tick skips (samples lost on the link or on the board).
enum class LostSamples : std::uint8_t {
  flag,  ///< return the next sample, flagged MeasurementFlag::samples_lost, and count the gap
  fail,  ///< read() returns Status::device_error (a study run must be complete); so does a
         ///< sample taken while the board's watchdog held the command safe or after the board
         ///< rejected host frames (MeasurementFlag::commands_lost)
};

struct SerialRigOptions {
  std::string port;                         ///< e.g. /dev/ttyACM0 or the emulator's /dev/pts/N
  int baud = 1'000'000;                     ///< 9600 … 2,000,000 (a standard termios rate)
  CommandMode mode = CommandMode::position;
  double sample_rate_hz = 1000.0;           ///< whole Hz in [100, 2000] (board tick)
  double update_rate_hz = 30.0;             ///< position-mode pulse updates, whole Hz in [1, sample rate]
  std::uint32_t max_pulse_rate_hz = 45'000;  ///< A/B edges/s, [1, CS_MAX_PULSE_RATE_HZ = 45 000]
  int gyro_fs_sel = 3;                      ///< ITG-3205 FS_SEL, 3 = ±2000 °/s (the only documented one)
  int gyro_dlpf_cfg = 0;                    ///< ITG-3205 DLPF_CFG 0…6 (0 = 256 Hz)
  int watchdog_ms = 100;                    ///< 0 = off, else [5, 60000]
  double handshake_timeout_s = 2.0;         ///< each handshake step, (0, 60]
  double read_timeout_s = 0.5;              ///< read()'s bounded wait, (0, 60]
  double late_tolerance_s = 0.005;          ///< a sample is late beyond its deadline + this, [0, 10]
  /// A run with more late samples than this fraction of its samples is degraded, [0, 1]
  /// (degradation()): its commands reached the board late.
  double max_late_fraction = 0.01;
  int counts_per_rev = 12'000;              ///< motor encoder counts per revolution (3000 lines × 4)
  int pulses_per_rev = 12'000;              ///< command pulses per motor revolution (electronic gear)
  double gyro_sensitivity_lsb_per_dps = 14.375;  ///< ITG-3205 at FS_SEL = 3
  double dac_min_v = -10.0;                 ///< speed command: DAC code 0 ↔ dac_min_v
  double dac_max_v = 10.0;                  ///< … and code 4095 ↔ dac_max_v (MCP4725 + level shift)
  bool selftest = false;                    ///< run the board's self-test in configure()
  bool servo_on = true;                     ///< activate() switches the servo on (off: sensors only)
  LostSamples lost_samples = LostSamples::flag;
  std::size_t ring_capacity = 8192;         ///< samples buffered between the threads, [16, 2^20]
  /// Throws InvalidArgument naming the field and its allowed range.
  void validate() const;
};

/// What the board says about itself (HELLO_ACK, SELFTEST_RESULT).
struct BoardInfo {
  unsigned wire_version = 0;
  unsigned firmware_major = 0, firmware_minor = 0, firmware_patch = 0;
  unsigned encoder_lines_hint = 0;  ///< 0 = unknown
  std::uint32_t capabilities = 0;   ///< CS_CAP_* bits
  std::uint32_t cpu_hz = 0;
  struct SelfTest {
    unsigned gyro_who_am_i = 0;
    bool gyro_ok = false;
    bool dac_ok = false;
    std::int16_t gyro_raw_at_rest = 0;
  };
  std::optional<SelfTest> selftest;
  std::string firmware_version() const;  ///< "major.minor.patch"
};

/// The link's counters (cumulative over the rig's life, reset by activate()).
struct SerialRigStats {
  std::uint64_t samples = 0;           ///< SAMPLE frames received
  std::uint64_t samples_lost = 0;      ///< ticks missing between received samples
  std::uint64_t frames_corrupted = 0;  ///< frames the decoder rejected
  std::uint64_t samples_late = 0;      ///< arrivals later than deadline + late_tolerance_s
  std::uint64_t ring_overflows = 0;    ///< samples dropped because read() fell behind
  std::uint64_t commands_sent = 0;
  std::uint64_t commands_dropped = 0;  ///< write() found the port's buffer full
  std::uint64_t board_tx_overflows = 0;  ///< samples flagged CS_SAMPLE_TX_OVERFLOW
  std::uint64_t commands_rejected = 0;   ///< write() refused (wrong mode, not finite)
  std::uint64_t watchdog_samples = 0;    ///< samples read while the board's watchdog held
  std::uint64_t rx_rejected_samples = 0; ///< samples flagged CS_SAMPLE_RX_REJECTED (commands lost)
  double max_lateness_s = 0.0;         ///< largest arrival − deadline
};

/// The board's own counters (STATS), cumulative since its reset.
struct BoardStats {
  std::uint32_t samples_sent = 0;
  std::uint32_t samples_dropped = 0;  ///< samples the board could not queue for sending
  std::uint32_t rx_corrupted = 0;     ///< host frames the board rejected
  std::uint32_t watchdog_trips = 0;
  std::uint32_t late_ticks = 0;       ///< ticks whose work overran the period on the board
};

class SerialRig final : public Rig {
 public:
  explicit SerialRig(const SerialRigOptions& options);
  ~SerialRig() override;

  double sample_time_s() const noexcept override { return 1.0 / options_.sample_rate_hz; }
  CommandMode mode() const noexcept override { return options_.mode; }
  std::string_view name() const noexcept override { return "serial"; }
  LinkCounters link_counters() const noexcept override;
  /// SAMPLEs in the receive ring, not yet read.
  std::size_t samples_waiting() const noexcept override;

  const SerialRigOptions& options() const noexcept { return options_; }
  /// Valid after configure().
  const BoardInfo& board() const noexcept { return board_; }
  SerialRigStats stats() const noexcept;
  /// Which I/O backend opened the port ("libserialport" or "termios (pseudo-terminal)").
  std::string_view backend() const noexcept;
  /// The board's own counters (GET_STATS → STATS); only while inactive. Throws RuntimeError.
  BoardStats board_stats();
  /// Why the last deactivate() could not confirm STOP (empty when it could).
  const std::string& last_stop_problem() const noexcept { return stop_problem_; }
  /// The board's own counters during the last run (STATS read by activate() and by
  /// deactivate() after STOP, subtracted); nothing when either could not be read.
  const std::optional<BoardStats>& board_during_run() const noexcept { return board_during_run_; }
  /// Why the last run's record is degraded, one reason each (empty: not degraded): samples lost
  /// on the link or dropped on the board, samples the watchdog held, commands the host or the
  /// board rejected, more late samples than max_late_fraction, STOP not confirmed.
  std::vector<std::string> degradation() const override;

  struct Impl;  ///< implementation detail (src/rig/serial_rig_impl.hpp)

 protected:
  void on_configure() override;
  void on_activate() override;
  void on_deactivate() noexcept override;
  void on_cleanup() noexcept override;
  Status on_read(Measurement& measurement) noexcept override;
  Status on_write(const Command& command) noexcept override;

 private:
  SerialRigOptions options_;
  BoardInfo board_;
  std::string stop_problem_;
  std::optional<BoardStats> board_before_, board_during_run_;
  std::unique_ptr<Impl> impl_;
};

// Conversions (exposed for tests and the docs; formulas in docs/hardware.md "Host side").
/// Motor angle of an encoder count: counts · 2π / counts_per_rev.
double encoder_counts_to_rad(std::int64_t counts, int counts_per_rev) noexcept;
/// Absolute pulse target of a motor-angle command: round(angle · pulses_per_rev / 2π), saturated
/// to int32.
std::int32_t motor_rad_to_pulses(double angle_rad, int pulses_per_rev) noexcept;
/// Motor angle of a pulse count: pulses · 2π / pulses_per_rev.
double pulses_to_motor_rad(std::int32_t pulses, int pulses_per_rev) noexcept;
/// Gyro rate of a raw word: raw / sensitivity (°/s) in rad/s.
double gyro_raw_to_rad_s(std::int16_t raw, double sensitivity_lsb_per_dps) noexcept;
/// DAC code of a speed command: round((v − min)/(max − min) · 4095), clamped to 0…4095.
/// `clipped` tells whether v lay outside [min, max].
std::uint16_t volts_to_dac_code(double volts, double min_v, double max_v, bool& clipped) noexcept;
/// Volts of a DAC code: min + code/4095 · (max − min).
double dac_code_to_volts(std::uint16_t code, double min_v, double max_v) noexcept;
/// MeasurementFlag bits of the board's CS_SAMPLE_* flags.
std::uint32_t measurement_flags_of_sample(std::uint8_t sample_flags) noexcept;

}  // namespace clearshape::rig
