// The board refuses a pulse-rate cap above the edge rate it sustains (CS_MAX_PULSE_RATE_HZ =
// 45 000 edges/s at 1 kHz, docs/hardware.md) and accepts the limit itself.
#include <gtest/gtest.h>

#include "emulator_session.hpp"

namespace clearshape::test {
namespace {

TEST(RigFirmwarePulseRate, RefusesMoreThanTheMeasuredLimit) {
  if (!emulator_available()) GTEST_SKIP() << "clearshape-rig-emulator was not built (needs avr-gcc and simavr)";
  EmulatorSession s({"--duration-s", "5"});
  std::vector<std::uint8_t> hello(CS_HELLO_BYTES);
  cs_put_u16(hello.data(), CS_WIRE_VERSION);
  ASSERT_TRUE(s.request(CS_MSG_HELLO, hello, CS_MSG_HELLO_ACK, 3));
  Configure c;
  c.max_pulse_rate_hz = 45001;
  auto r = s.ack(CS_MSG_CONFIGURE, c.payload());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->first, CS_ERR_VALUE);
  EXPECT_EQ(r->second, 8u);  // the field's byte offset: max_pulse_rate_hz @8
  c.max_pulse_rate_hz = 45000;
  r = s.ack(CS_MSG_CONFIGURE, c.payload());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->first, CS_OK);
}

}  // namespace
}  // namespace clearshape::test
