// The serial wire protocol (rig/wire_protocol.h): the CRC against its published check value,
// frames round-trip, and a damaged byte stream is counted, resynchronised and never yields a
// frame that was not sent.
#include "clearshape/rig/wire_protocol.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace {

std::vector<std::uint8_t> encode(std::uint8_t type, std::uint8_t seq,
                                 const std::vector<std::uint8_t>& payload) {
  std::array<std::uint8_t, CS_WIRE_MAX_FRAME> buffer{};
  const std::size_t n = cs_frame_encode(buffer.data(), type, seq, payload.data(),
                                        static_cast<std::uint8_t>(payload.size()));
  return {buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n)};
}

std::vector<std::uint8_t> sample_payload(std::uint32_t tick) {
  std::vector<std::uint8_t> p(CS_SAMPLE_BYTES, 0);
  cs_put_u32(p.data(), tick);
  cs_put_i32(p.data() + 4, -static_cast<std::int32_t>(tick) * 7);
  cs_put_i16(p.data() + 8, static_cast<std::int16_t>(tick % 30000));
  return p;
}

}  // namespace

TEST(WireProtocol, CrcMatchesTheCcittFalseCheckValue) {
  // CRC-16/CCITT-FALSE check value (the CRC catalogue's "check" of the ASCII string 123456789).
  const std::uint8_t text[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(cs_crc16(text, sizeof text), 0x29B1u);
}

TEST(WireProtocol, LittleEndianFieldsRoundTrip) {
  std::array<std::uint8_t, 4> b{};
  cs_put_i32(b.data(), -123456789);
  EXPECT_EQ(cs_get_i32(b.data()), -123456789);
  EXPECT_EQ(b[0], 0xEBu);  // −123456789 = 0xF8A432EB
  cs_put_i16(b.data(), -2);
  EXPECT_EQ(cs_get_i16(b.data()), -2);
  cs_put_u32(b.data(), 0xDEADBEEFu);
  EXPECT_EQ(cs_get_u32(b.data()), 0xDEADBEEFu);
}

TEST(WireProtocol, FramesDecodeBackToWhatWasSent) {
  cs_decoder decoder;
  cs_decoder_reset(&decoder);
  cs_frame frame{};
  int decoded = 0;
  for (std::uint32_t tick = 0; tick < 300; ++tick) {
    const auto payload = sample_payload(tick);
    for (const std::uint8_t byte : encode(CS_MSG_SAMPLE, static_cast<std::uint8_t>(tick), payload)) {
      if (cs_decoder_push(&decoder, byte, &frame) != 0) {
        ASSERT_EQ(frame.type, CS_MSG_SAMPLE);
        ASSERT_EQ(frame.seq, static_cast<std::uint8_t>(tick));
        ASSERT_EQ(frame.length, CS_SAMPLE_BYTES);
        ASSERT_EQ(cs_get_u32(frame.payload), tick);
        ++decoded;
      }
    }
  }
  EXPECT_EQ(decoded, 300);
  EXPECT_EQ(decoder.corrupted, 0u);
  EXPECT_EQ(decoder.skipped_bytes, 0u);
  EXPECT_EQ(cs_frame_encode(nullptr, 0, 0, nullptr, CS_WIRE_MAX_PAYLOAD + 1), 0u);
}

TEST(WireProtocol, AFlippedByteCostsOnlyItsOwnFrame) {
  std::vector<std::uint8_t> stream;
  for (std::uint32_t tick = 0; tick < 3; ++tick) {
    const auto f = encode(CS_MSG_SAMPLE, static_cast<std::uint8_t>(tick), sample_payload(tick));
    stream.insert(stream.end(), f.begin(), f.end());
  }
  const std::size_t frame_bytes = stream.size() / 3;
  stream[frame_bytes + 9] ^= 0x10;  // a payload byte of the second frame
  cs_decoder decoder;
  cs_decoder_reset(&decoder);
  cs_frame frame{};
  std::vector<std::uint32_t> ticks;
  for (const std::uint8_t byte : stream) {
    if (cs_decoder_push(&decoder, byte, &frame) != 0) ticks.push_back(cs_get_u32(frame.payload));
  }
  EXPECT_EQ(ticks, (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(decoder.corrupted, 1u);
}

TEST(WireProtocol, AnOversizedLengthIsRejectedAndTheNextFrameStillDecodes) {
  std::vector<std::uint8_t> stream = {CS_WIRE_SYNC, CS_MSG_SAMPLE, 0, CS_WIRE_MAX_PAYLOAD + 1};
  const auto good = encode(CS_MSG_ACK, 5, {CS_MSG_START, CS_OK, 0, 0});
  stream.insert(stream.end(), good.begin(), good.end());
  cs_decoder decoder;
  cs_decoder_reset(&decoder);
  cs_frame frame{};
  int decoded = 0;
  for (const std::uint8_t byte : stream) decoded += cs_decoder_push(&decoder, byte, &frame);
  EXPECT_EQ(decoded, 1);
  EXPECT_EQ(frame.type, CS_MSG_ACK);
  EXPECT_EQ(frame.seq, 5);
  EXPECT_EQ(decoder.corrupted, 1u);
}

// Property: over a seeded stream of 2000 frames with random byte flips, drops and insertions,
// every decoded frame is one that was sent, in order, and every frame left untouched arrives.
TEST(WireProtocol, DamagedStreamsNeverYieldAFrameThatWasNotSent) {
  std::mt19937 rng(20261125);
  std::uniform_int_distribution<int> damage(0, 99);
  std::uniform_int_distribution<int> any_byte(0, 255);
  std::vector<std::uint8_t> stream;
  std::vector<bool> intact;
  for (std::uint32_t tick = 0; tick < 2000; ++tick) {
    auto f = encode(CS_MSG_SAMPLE, static_cast<std::uint8_t>(tick), sample_payload(tick));
    bool untouched = true;
    const int roll = damage(rng);
    if (roll < 5) {  // flip a bit
      f[static_cast<std::size_t>(any_byte(rng)) % f.size()] ^= static_cast<std::uint8_t>(1u << (roll % 8));
      untouched = false;
    } else if (roll < 8) {  // drop a byte
      f.erase(f.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(any_byte(rng)) % f.size()));
      untouched = false;
    } else if (roll < 10) {  // a stray byte before the frame (may be a SYNC)
      f.insert(f.begin(), static_cast<std::uint8_t>(roll == 8 ? CS_WIRE_SYNC : any_byte(rng)));
      untouched = false;
    }
    stream.insert(stream.end(), f.begin(), f.end());
    intact.push_back(untouched);
  }
  cs_decoder decoder;
  cs_decoder_reset(&decoder);
  cs_frame frame{};
  std::vector<std::uint32_t> ticks;
  for (const std::uint8_t byte : stream) {
    if (cs_decoder_push(&decoder, byte, &frame) != 0) {
      const std::uint32_t tick = cs_get_u32(frame.payload);
      ASSERT_LT(tick, 2000u);
      ASSERT_EQ(frame.payload[4 + 0], sample_payload(tick)[4]) << "tick " << tick;
      ASSERT_TRUE(ticks.empty() || tick > ticks.back()) << "out of order at " << tick;
      ticks.push_back(tick);
    }
  }
  std::size_t intact_seen = 0;
  std::size_t intact_total = 0;
  for (std::uint32_t tick = 0; tick < 2000; ++tick) {
    if (!intact[tick]) continue;
    ++intact_total;
    // The decoder rescans every buffered byte after a failed SYNC, so a damaged neighbour never
    // swallows an intact frame.
    intact_seen += std::binary_search(ticks.begin(), ticks.end(), tick) ? 1u : 0u;
  }
  EXPECT_GT(decoder.corrupted, 0u);
  EXPECT_EQ(intact_seen, intact_total);
}
