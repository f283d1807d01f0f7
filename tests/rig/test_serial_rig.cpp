// rig::SerialRig against a board double on a pseudo-terminal pair (board_double.hpp): the
// handshake and its errors, the unit conversions, the lost/corrupted/late counters, and
// read()/write() being noexcept and allocation-free.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>

#include "support/board_double.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using cs::Status;
using cs::testing::BoardDouble;

namespace {

rig::SerialRigOptions options_for(const BoardDouble& board, rig::CommandMode mode = rig::CommandMode::position) {
  rig::SerialRigOptions o;
  o.port = board.path();
  o.mode = mode;
  o.handshake_timeout_s = 1.0;
  o.read_timeout_s = 0.5;
  return o;
}

std::string configure_error(rig::SerialRig& r) {
  try {
    r.configure();
  } catch (const cs::RuntimeError& e) {
    return e.what();
  }
  return "";
}

TEST(SerialRigOptions, ValidateNamesTheFieldAndRange) {
  rig::SerialRigOptions o;
  o.port = "/dev/null";
  EXPECT_NO_THROW(o.validate());
  auto message = [](rig::SerialRigOptions bad) {
    try {
      bad.validate();
    } catch (const cs::InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  rig::SerialRigOptions bad = o;
  bad.sample_rate_hz = 2500;
  EXPECT_NE(message(bad).find("sample_rate_hz"), std::string::npos);
  EXPECT_NE(message(bad).find("100 … 2000"), std::string::npos);
  bad = o;
  bad.update_rate_hz = 30.5;
  EXPECT_NE(message(bad).find("update_rate_hz"), std::string::npos);
  bad = o;
  bad.watchdog_ms = 3;
  EXPECT_NE(message(bad).find("watchdog_ms"), std::string::npos);
  bad = o;
  bad.max_pulse_rate_hz = CS_MAX_PULSE_RATE_HZ + 1;
  EXPECT_NE(message(bad).find("max_pulse_rate_hz"), std::string::npos);
  EXPECT_NE(message(bad).find("1 … 45000"), std::string::npos);
  bad = o;
  bad.port.clear();
  EXPECT_NE(message(bad).find("port"), std::string::npos);
  bad = o;
  bad.gyro_dlpf_cfg = 7;
  EXPECT_NE(message(bad).find("gyro_dlpf_cfg"), std::string::npos);
  // The timeouts' range as it is (issue 21: "-0 … [-60, 0)", a flipped sign).
  bad = o;
  bad.handshake_timeout_s = 0.0;
  EXPECT_NE(message(bad).find("handshake_timeout_s = 0 is out of range; allowed: (0, 60] s"), std::string::npos)
      << message(bad);
  bad = o;
  bad.read_timeout_s = 61.0;
  EXPECT_NE(message(bad).find("read_timeout_s = 61 is out of range; allowed: (0, 60] s"), std::string::npos);
  bad = o;
  bad.max_late_fraction = 1.5;
  EXPECT_NE(message(bad).find("max_late_fraction"), std::string::npos);
}

// The pulse-rate cap is the edge rate the board sustains at 1 kHz with a COMMAND per tick
// (docs/hardware.md: 46 000 edges/s computed, 45 000 measured clean in the emulator); the
// default is that limit and one edge/s more is refused before anything reaches the board.
TEST(SerialRigOptions, PulseRateDefaultIsTheBoardsMeasuredLimit) {
  EXPECT_EQ(CS_MAX_PULSE_RATE_HZ, 45000u);
  rig::SerialRigOptions o;
  o.port = "/dev/null";
  EXPECT_EQ(o.max_pulse_rate_hz, CS_MAX_PULSE_RATE_HZ);
  EXPECT_NO_THROW(o.validate());
  o.max_pulse_rate_hz = 45001;
  EXPECT_THROW(o.validate(), cs::InvalidArgument);
}

TEST(SerialRigConversions, MatchTheirDefinitions) {
  // 3000 lines × 4 = 12000 counts per revolution: 3000 counts are a quarter turn.
  EXPECT_DOUBLE_EQ(rig::encoder_counts_to_rad(3000, 12000), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(rig::encoder_counts_to_rad(-12000, 12000), -2 * std::numbers::pi);
  EXPECT_EQ(rig::motor_rad_to_pulses(cs::deg_to_rad(90.0), 12000), 3000);
  EXPECT_EQ(rig::motor_rad_to_pulses(cs::deg_to_rad(-0.02), 12000), -1);  // 0.03°/pulse, rounded
  EXPECT_EQ(rig::motor_rad_to_pulses(1e12, 12000), 2147483647);
  EXPECT_DOUBLE_EQ(rig::pulses_to_motor_rad(6000, 12000), std::numbers::pi);
  // ITG-3205: 14.375 LSB per °/s, so 1437.5 LSB would be 100 °/s; 1438 LSB = 100.0348 °/s.
  EXPECT_NEAR(cs::rad_to_deg(rig::gyro_raw_to_rad_s(1438, 14.375)), 1438 / 14.375, 1e-12);
  EXPECT_EQ(rig::measurement_flags_of_sample(CS_SAMPLE_WATCHDOG | CS_SAMPLE_GYRO_SATURATED | CS_SAMPLE_LATE),
            rig::bit(rig::MeasurementFlag::watchdog) | rig::bit(rig::MeasurementFlag::gyro_saturated) |
                rig::bit(rig::MeasurementFlag::overrun));
  EXPECT_EQ(rig::measurement_flags_of_sample(CS_SAMPLE_SERVO_ON), 0u);
  bool clipped = true;
  EXPECT_EQ(rig::volts_to_dac_code(-10.0, -10.0, 10.0, clipped), 0);
  EXPECT_FALSE(clipped);
  EXPECT_EQ(rig::volts_to_dac_code(10.0, -10.0, 10.0, clipped), 4095);
  EXPECT_EQ(rig::volts_to_dac_code(10.5, -10.0, 10.0, clipped), 4095);
  EXPECT_TRUE(clipped);
  EXPECT_EQ(rig::volts_to_dac_code(std::nan(""), -10.0, 10.0, clipped), 0);
  EXPECT_TRUE(clipped);
  for (int code : {0, 1, 2047, 2048, 4094, 4095}) {  // code → volts → code is the identity
    const double v = rig::dac_code_to_volts(static_cast<std::uint16_t>(code), -10.0, 10.0);
    EXPECT_EQ(rig::volts_to_dac_code(v, -10.0, 10.0, clipped), code);
  }
  EXPECT_DOUBLE_EQ(rig::dac_code_to_volts(4095, -10.0, 10.0), 10.0);
}

TEST(SerialRig, NoSuchPortListsThePortsItSees) {
  rig::SerialRigOptions o;
  o.port = "/dev/ttyCLEARSHAPE_NONE";
  rig::SerialRig r(o);
  const std::string e = configure_error(r);
  EXPECT_NE(e.find("/dev/ttyCLEARSHAPE_NONE"), std::string::npos) << e;
  EXPECT_NE(e.find("no such port"), std::string::npos) << e;
  EXPECT_NE(e.find("libserialport sees"), std::string::npos) << e;
  EXPECT_EQ(r.state(), rig::LifecycleState::unconfigured);
}

TEST(SerialRig, SilentBoardTimesOutNamingWhatWasExpected) {
  BoardDouble board;
  board.silent = true;
  board.start();
  auto o = options_for(board);
  o.handshake_timeout_s = 0.4;
  rig::SerialRig r(o);
  const std::string e = configure_error(r);
  EXPECT_NE(e.find(board.path()), std::string::npos) << e;
  EXPECT_NE(e.find("no HELLO_ACK within 0.4 s"), std::string::npos) << e;
  EXPECT_NE(e.find("flash firmware/"), std::string::npos) << e;
  board.stop();
  EXPECT_GE(board.received.size(), 2u);  // HELLO repeated while waiting (boot-loader delay)
}

TEST(SerialRig, WrongWireVersionNamesBothAndTheRemedy) {
  BoardDouble board;
  board.wire_version = CS_WIRE_VERSION + 1;
  board.start();
  rig::SerialRig r(options_for(board));
  const std::string e = configure_error(r);
  EXPECT_NE(e.find("v" + std::to_string(CS_WIRE_VERSION + 1)), std::string::npos) << e;
  EXPECT_NE(e.find("expects v" + std::to_string(CS_WIRE_VERSION)), std::string::npos) << e;
  EXPECT_NE(e.find("flash firmware/"), std::string::npos) << e;
  EXPECT_NE(e.find("1.2.3"), std::string::npos) << e;
}

TEST(SerialRig, MissingCapabilityIsRefused) {
  BoardDouble board;
  board.capabilities = CS_CAP_ENCODER_QUADRATURE | CS_CAP_GYRO_ITG3205 | CS_CAP_PULSE_AB;  // no DAC
  board.start();
  rig::SerialRig r(options_for(board, rig::CommandMode::speed));
  const std::string e = configure_error(r);
  EXPECT_NE(e.find("lacks capabilities 0x04"), std::string::npos) << e;
}

TEST(SerialRig, ConfigureRefusalNamesTheField) {
  struct Case {
    std::uint8_t result;
    std::uint16_t detail;
    const char* says;
  };
  const Case cases[] = {{CS_ERR_VALUE, 4, "sample_rate_hz"},
                        // A board still in a run that STOP did not end: how to recover.
                        {CS_ERR_STATE, 0, "not allowed in the board's state; the board is still running a previous "
                                          "session and did not leave it on STOP: reset the board"}};
  for (const Case& c : cases) {
    BoardDouble board;
    board.configure_result = c.result;
    board.configure_detail = c.detail;
    board.start();
    rig::SerialRig r(options_for(board));
    const std::string e = configure_error(r);
    EXPECT_NE(e.find("refused CONFIGURE"), std::string::npos) << e;
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
  }
}

TEST(SerialRig, HandshakeSendsTheConfigurationAndReadsTheBoard) {
  BoardDouble board;
  board.start();
  auto o = options_for(board, rig::CommandMode::speed);
  o.sample_rate_hz = 500;
  o.update_rate_hz = 25;
  o.watchdog_ms = 250;
  o.gyro_dlpf_cfg = 2;
  o.selftest = true;
  rig::SerialRig r(o);
  ASSERT_EQ(r.configure(), Status::ok);
  EXPECT_EQ(r.board().firmware_version(), "1.2.3");
  EXPECT_EQ(r.board().encoder_lines_hint, 3000u);
  EXPECT_EQ(r.board().cpu_hz, 16000000u);
  ASSERT_TRUE(r.board().selftest.has_value());
  EXPECT_EQ(r.board().selftest->gyro_who_am_i, 0x69u);
  EXPECT_EQ(r.board().selftest->gyro_raw_at_rest, -2);
  EXPECT_DOUBLE_EQ(r.sample_time_s(), 0.002);
  const rig::BoardStats stats = r.board_stats();
  EXPECT_EQ(stats.samples_sent, 1234u);
  EXPECT_EQ(stats.watchdog_trips, 2u);
  EXPECT_EQ(r.backend(), "termios (pseudo-terminal)");
  board.stop();
  const auto& c = board.configure_payload;
  ASSERT_EQ(c.size(), CS_CONFIGURE_BYTES);
  EXPECT_EQ(c[0], CS_MODE_SPEED);
  EXPECT_EQ(c[1], 3);
  EXPECT_EQ(c[2], 2);
  EXPECT_EQ(cs_get_u16(c.data() + 4), 500);
  EXPECT_EQ(cs_get_u16(c.data() + 6), 25);
  EXPECT_EQ(cs_get_u32(c.data() + 8), 45000u);  // the default, CS_MAX_PULSE_RATE_HZ
  EXPECT_EQ(cs_get_u16(c.data() + 12), 250);
  EXPECT_EQ(cs_get_u16(c.data() + 14), 2048);  // 0 V: round(10/20 · 4095) = round(2047.5)
}

TEST(SerialRig, PositionRunConvertsSamplesAndCommands) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& s) {
    if (s.tick == 10) s.flags |= CS_SAMPLE_WATCHDOG | CS_SAMPLE_GYRO_SATURATED;
    return true;
  };
  board.start();
  rig::SerialRig r(options_for(board));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  const int n = 120;
  for (int k = 0; k < n; ++k) {
    ASSERT_EQ(r.read(m), Status::ok) << k;
    EXPECT_EQ(m.sequence, static_cast<std::uint64_t>(k));
    EXPECT_DOUBLE_EQ(m.time_s, k * 1e-3);
    EXPECT_EQ(m.encoder_counts, 3 * k);
    EXPECT_DOUBLE_EQ(m.motor_angle_rad, 3.0 * k * 2 * std::numbers::pi / 12000);
    EXPECT_EQ(m.gyro_raw, 7 * k - 1000);
    EXPECT_DOUBLE_EQ(m.gyro_rate_deg_s(), (7 * k - 1000) / 14.375);
    if (k == 10) {
      EXPECT_TRUE(m.has(rig::MeasurementFlag::watchdog));
      EXPECT_TRUE(m.has(rig::MeasurementFlag::gyro_saturated));
    } else {
      EXPECT_EQ(m.flags, 0u) << k;
    }
    ASSERT_EQ(r.write(rig::Command::position_deg(90.0)), Status::ok);
  }
  // The board echoes the last target in pulses_emitted: 3000 pulses = 90° at 12000 per rev.
  for (int k = 0; k < 50; ++k) ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_NEAR(cs::rad_to_deg(m.command_applied), 90.0, 1e-12);
  // A command in the wrong mode is refused and flagged on the next sample.
  EXPECT_EQ(r.write(rig::Command::speed_v(1.0)), Status::out_of_range);
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::command_rejected));
  EXPECT_EQ(r.deactivate(), Status::ok);
  EXPECT_EQ(r.last_stop_problem(), "");
  const rig::SerialRigStats s = r.stats();
  EXPECT_EQ(s.samples_lost, 0u);
  EXPECT_EQ(s.frames_corrupted, 0u);
  EXPECT_EQ(s.commands_sent, static_cast<std::uint64_t>(n));
  board.stop();
  ASSERT_EQ(board.commands.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(board.commands.front(), 3000);
  EXPECT_EQ(board.command_ticks.front(), 0u);  // COMMAND carries the last tick the host had
  EXPECT_EQ(board.command_ticks.back(), static_cast<std::uint32_t>(n - 1));
  EXPECT_FALSE(board.servo_on);
  // STOP ends the run; only GET_STATS (the board's counters after the run) follows it.
  ASSERT_GE(board.received.size(), 2u);
  EXPECT_EQ(board.received[board.received.size() - 2], CS_MSG_STOP);
  EXPECT_EQ(board.received.back(), CS_MSG_GET_STATS);
}

TEST(SerialRig, SpeedRunMapsVoltsToDacCodes) {
  BoardDouble board;
  board.start();
  rig::SerialRig r(options_for(board, rig::CommandMode::speed));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  ASSERT_EQ(r.read(m), Status::ok);
  ASSERT_EQ(r.write(rig::Command::speed_v(5.0)), Status::ok);
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.write(rig::Command::speed_v(12.0)), Status::out_of_range);  // clipped to 4095, flagged
  for (int k = 0; k < 30; ++k) ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_DOUBLE_EQ(m.command_applied, 10.0);  // code 4095 is +10 V
  r.deactivate();
  board.stop();
  ASSERT_EQ(board.commands.size(), 2u);
  EXPECT_EQ(board.commands[0], 3071);  // round(15/20 · 4095) = round(3071.25)
  EXPECT_EQ(board.commands[1], 4095);
}

TEST(SerialRig, CountsLostSamplesAndFlagsTheNextOne) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& s) { return s.tick < 50 || s.tick > 52; };
  board.start();
  rig::SerialRig r(options_for(board));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  for (int k = 0; k < 50; ++k) ASSERT_EQ(r.read(m), Status::ok);
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(m.sequence, 53u);
  EXPECT_DOUBLE_EQ(m.time_s, 0.053);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::samples_lost));
  EXPECT_EQ(r.stats().samples_lost, 3u);
  EXPECT_EQ(r.link_counters().samples_lost, 3u);
  r.deactivate();
}

TEST(SerialRig, LostSamplesFailTheRunWhenAsked) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& s) { return s.tick != 20; };
  board.start();
  auto o = options_for(board);
  o.lost_samples = rig::LostSamples::fail;
  rig::SerialRig r(o);
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  for (int k = 0; k < 20; ++k) ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.read(m), Status::device_error);
  EXPECT_EQ(r.state(), rig::LifecycleState::error);
  EXPECT_EQ(r.deactivate(), Status::ok);
}

TEST(SerialRig, WatchdogFailsTheRunWhenLostSamplesFail) {
  // The command of a study run must be the one written: a sample flagged CS_SAMPLE_WATCHDOG
  // (the board held the command safe) ends a run that must be complete; flagged otherwise.
  for (const auto policy : {rig::LostSamples::flag, rig::LostSamples::fail}) {
    BoardDouble board;
    board.on_sample = [](BoardDouble::Sample& s) {
      if (s.tick >= 20) s.flags |= CS_SAMPLE_WATCHDOG;
      return true;
    };
    board.start();
    auto o = options_for(board);
    o.lost_samples = policy;
    rig::SerialRig r(o);
    ASSERT_EQ(r.configure(), Status::ok);
    ASSERT_EQ(r.activate(), Status::ok);
    rig::Measurement m;
    for (int k = 0; k < 20; ++k) ASSERT_EQ(r.read(m), Status::ok);
    if (policy == rig::LostSamples::fail) {
      EXPECT_EQ(r.read(m), Status::device_error);
    } else {
      ASSERT_EQ(r.read(m), Status::ok);
      EXPECT_TRUE(m.has(rig::MeasurementFlag::watchdog));
    }
    EXPECT_EQ(r.deactivate(), Status::ok);
  }
}

TEST(SerialRig, CorruptedFramesAreCountedApartFromLostSamples) {
  BoardDouble board;
  board.on_frame = [](std::uint32_t tick, std::uint8_t* frame, std::size_t) {
    if (tick == 30 || tick == 31) frame[CS_WIRE_HEADER_BYTES + 5] ^= 0x10;  // one bit of the encoder
  };
  board.start();
  rig::SerialRig r(options_for(board));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  for (int k = 0; k < 100; ++k) {
    ASSERT_EQ(r.read(m), Status::ok);
    EXPECT_EQ(m.encoder_counts, 3 * static_cast<std::int64_t>(m.sequence));  // never a damaged value
  }
  const rig::SerialRigStats s = r.stats();
  EXPECT_EQ(s.frames_corrupted, 2u);
  EXPECT_EQ(s.samples_lost, 2u);
  EXPECT_GE(s.samples, 100u);  // received so far: the 100 read and any already queued behind them
  r.deactivate();
}

TEST(SerialRig, LateArrivalsAreCountedBeyondTheTolerance) {
  BoardDouble board;
  board.delay_before_s = [](std::uint32_t tick) { return tick == 100 ? 0.080 : 0.0; };
  board.start();
  auto o = options_for(board);
  o.late_tolerance_s = 0.020;
  rig::SerialRig r(o);
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  for (int k = 0; k < 300; ++k) ASSERT_EQ(r.read(m), Status::ok);
  const rig::SerialRigStats s = r.stats();
  // Ticks 100 … ~159 go out in one burst 80 ms after tick 100's deadline: tick k is late by
  // 80 − (k − 100) ms, beyond the 20 ms tolerance for k < 160 — about 60 samples.
  EXPECT_GE(s.samples_late, 45u);
  EXPECT_LE(s.samples_late, 100u);  // room for the scheduling jitter of a loaded machine
  EXPECT_GE(s.max_lateness_s, 0.075);
  EXPECT_EQ(s.samples_lost, 0u);
  r.deactivate();
}

TEST(SerialRig, ReadFailsWhenThePortDies) {
  BoardDouble board;
  board.start();
  rig::SerialRig r(options_for(board));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  ASSERT_EQ(r.read(m), Status::ok);
  board.unplug();
  Status status = Status::ok;
  for (int k = 0; k < 2000 && status == Status::ok; ++k) status = r.read(m);
  EXPECT_EQ(status, Status::device_error);
  EXPECT_EQ(r.deactivate(), Status::ok);
  EXPECT_NE(r.last_stop_problem(), "");  // STOP could not be confirmed
  // and the run says why it ended (the study's error quotes it): a pseudo-terminal whose other end
  // closed reads as silence, so the wait for the next sample is what ends it
  const auto why = r.degradation();
  ASSERT_FALSE(why.empty());
  EXPECT_NE(why.back().find("no sample came within 0.5 s"), std::string::npos) << why.back();
}

TEST(SerialRig, ABoardThatFallsSilentEndsTheReadWithTheTimeoutNamed) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& s) { return s.tick < 20; };  // then nothing
  board.start();
  auto o = options_for(board);
  o.read_timeout_s = 0.2;
  rig::SerialRig r(o);
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  Status status = Status::ok;
  int reads = 0;
  for (; reads < 100 && status == Status::ok; ++reads) status = r.read(m);
  EXPECT_EQ(status, Status::device_error);
  EXPECT_EQ(reads, 21);  // ticks 0–19, then the wait that timed out
  r.deactivate();
  const auto why = r.degradation();
  ASSERT_FALSE(why.empty());
  EXPECT_NE(why.back().find("no sample came within 0.2 s (read_timeout_s)"), std::string::npos) << why.back();
}

TEST(SerialRig, ReadAndWriteAreNoexceptAndAllocationFree) {
  BoardDouble board;
  board.start();
  rig::SerialRig r(options_for(board));
  rig::Measurement m;
  static_assert(noexcept(r.read(m)));
  static_assert(noexcept(r.write(rig::Command::position_deg(1.0))));
  static_assert(noexcept(r.samples_waiting()));
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  ASSERT_EQ(r.read(m), Status::ok);
  std::size_t allocations = 0;
  int reads = 0;
  {
    cs::testing::AllocationCounter counter;  // counts every thread: the receiver's and the double's too
    while (reads < 200 && r.read(m) == Status::ok) {
      (void)r.samples_waiting();  // the runner's coalescing question
      (void)r.write(rig::Command::position_deg(0.01 * reads));
      ++reads;
    }
    allocations = counter.allocations();
  }
  EXPECT_EQ(reads, 200);
  EXPECT_EQ(allocations, 0u);
  r.deactivate();
}

// samples_waiting() is what the receive thread queued and read() has not taken: a host that
// stops reading for 30 ms (1 kHz samples) finds them waiting, and reading them drains it.
TEST(SerialRig, SamplesWaitingCountsTheReceivedSamplesNotYetRead) {
  BoardDouble board;
  board.start();
  rig::SerialRig r(options_for(board));
  EXPECT_EQ(r.samples_waiting(), 0u);  // not configured: no ring
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  ASSERT_EQ(r.read(m), Status::ok);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  const std::size_t waiting = r.samples_waiting();
  EXPECT_GE(waiting, 10u);
  for (std::size_t k = 0; k < waiting; ++k) ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(m.sequence, waiting);  // the newest of them: nothing was skipped
  EXPECT_LT(r.samples_waiting(), waiting);
  r.deactivate();
}

}  // namespace

// Issue 21 item 4: a board its previous host left running refuses CONFIGURE. The host sends
// STOP (accepted in every state) after HELLO_ACK and before CONFIGURE (should CONFIGURE still be
// refused for the board's state, ConfigureRefusalNamesTheField checks the remedy is named).
TEST(SerialRig, ConfigureStopsABoardLeftRunning) {
  BoardDouble board;
  board.start();
  rig::SerialRig r(options_for(board));
  ASSERT_EQ(r.configure(), Status::ok);
  board.stop();
  const auto& got = board.received;
  const auto stop = std::find(got.begin(), got.end(), CS_MSG_STOP);
  const auto configure = std::find(got.begin(), got.end(), CS_MSG_CONFIGURE);
  ASSERT_NE(stop, got.end());
  ASSERT_NE(configure, got.end());
  EXPECT_LT(stop - got.begin(), configure - got.begin());
}

// Issue 21 item 5: a run whose samples came late beyond max_late_fraction, or after which the
// board had rejected host frames, is degraded — and with LostSamples::fail (the study) the
// flagged sample ends the run at once.
TEST(SerialRig, DegradationListsLateSamplesAndRejectedFrames) {
  const auto rejected_at = [](std::uint32_t tick) {
    return [tick](BoardDouble::Sample& smp) {
      if (smp.tick == tick) smp.flags |= CS_SAMPLE_RX_REJECTED;
      return true;
    };
  };
  BoardDouble board;
  board.delay_before_s = [](std::uint32_t tick) { return tick == 100 ? 0.060 : 0.0; };
  board.on_sample = rejected_at(150);
  BoardDouble strict_board;
  strict_board.on_sample = rejected_at(20);
  board.start();
  strict_board.start();
  auto strict_options = options_for(strict_board);
  strict_options.lost_samples = rig::LostSamples::fail;
  rig::SerialRig r(options_for(board)), strict(strict_options);
  for (rig::SerialRig* each : {&r, &strict}) {
    ASSERT_EQ(each->configure(), Status::ok);
    ASSERT_EQ(each->activate(), Status::ok);
  }
  rig::Measurement m;
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(r.read(m), Status::ok);
    if (k == 150) {
      EXPECT_NE(m.flags & rig::bit(rig::MeasurementFlag::commands_lost), 0u);
    }
    (void)r.write(rig::Command::position_deg(1.0));
  }
  ASSERT_EQ(r.deactivate(), Status::ok);
  std::string all;
  for (const auto& w : r.degradation()) all += w + "\n";
  EXPECT_NE(all.find("samples arrived later than 5 ms (allowed: 1 %)"), std::string::npos) << all;
  EXPECT_NE(all.find("the board rejected 0 host frame(s) (COMMANDs lost; 1 sample(s) flagged)"), std::string::npos)
      << all;
  EXPECT_EQ(r.stats().rx_rejected_samples, 1u);
  ASSERT_TRUE(r.board_during_run().has_value());  // the double's STATS do not change
  EXPECT_EQ(r.board_during_run()->rx_corrupted, 0u);

  // The study's strict mode: the flagged sample ends the run.
  Status status = Status::ok;
  int k = 0;
  for (; k < 100 && status == Status::ok; ++k) status = strict.read(m);
  EXPECT_EQ(status, Status::device_error);
  EXPECT_EQ(k, 21);
}
