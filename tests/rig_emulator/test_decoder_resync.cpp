// The protocol decoder's resynchronisation (wire_protocol.h): a frame whose LEN byte was
// damaged upward swallows the frames after it; after the resync those must come out whole,
// in order, and none may be lost beyond the damaged one.
#include <gtest/gtest.h>

#include <vector>

#include "clearshape/rig/wire_protocol.h"

namespace {

std::vector<std::uint8_t> ack_frame(std::uint8_t seq, std::uint8_t acked) {
  std::uint8_t payload[CS_ACK_BYTES] = {acked, CS_OK, 0, 0};
  std::uint8_t out[CS_WIRE_MAX_FRAME];
  const std::size_t n = cs_frame_encode(out, CS_MSG_ACK, seq, payload, CS_ACK_BYTES);
  return {out, out + n};
}

TEST(WireDecoderResync, FramesSwallowedByADamagedLengthAreRecovered) {
  std::vector<std::uint8_t> stream = ack_frame(0, 1);
  stream[3] = 24;  // LEN damaged 4 -> 24: the candidate spans the next frames
  for (std::uint8_t seq = 1; seq <= 5; ++seq) {
    const std::vector<std::uint8_t> f = ack_frame(seq, static_cast<std::uint8_t>(seq + 1));
    stream.insert(stream.end(), f.begin(), f.end());
  }
  cs_decoder d;
  cs_decoder_reset(&d);
  cs_frame frame{};
  std::vector<std::uint8_t> seqs;
  for (std::uint8_t byte : stream) {
    if (cs_decoder_push(&d, byte, &frame)) seqs.push_back(frame.seq);
  }
  // A frame still pending in the buffer comes out on the next push (a lone SYNC here); in this
  // stream the one-byte lag closes within frame 3, so nothing is pending any more.
  if (cs_decoder_push(&d, CS_WIRE_SYNC, &frame)) seqs.push_back(frame.seq);
  EXPECT_EQ(d.corrupted, 1u);
  ASSERT_GE(seqs.size(), 4u);
  for (std::size_t i = 0; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], i + 1);
  EXPECT_EQ(seqs.size(), 5u);
}

TEST(WireDecoderResync, CleanStreamDecodesEveryFrame) {
  std::vector<std::uint8_t> stream;
  for (std::uint8_t seq = 0; seq < 50; ++seq) {
    const std::vector<std::uint8_t> f = ack_frame(seq, 3);
    stream.insert(stream.end(), f.begin(), f.end());
  }
  cs_decoder d;
  cs_decoder_reset(&d);
  cs_frame frame{};
  unsigned n = 0;
  for (std::uint8_t byte : stream) n += static_cast<unsigned>(cs_decoder_push(&d, byte, &frame));
  EXPECT_EQ(n, 50u);
  EXPECT_EQ(d.corrupted, 0u);
  EXPECT_EQ(d.skipped_bytes, 0u);
}

// The table CRC against the CRC catalogue's check value for CRC-16/CCITT-FALSE ("123456789" →
// 0x29B1) and against the bitwise definition (poly 0x1021, init 0xFFFF, MSB first) on seeded data.
TEST(WireCrc, TableCrcEqualsTheBitwiseDefinition) {
  const char* check = "123456789";
  EXPECT_EQ(cs_crc16(reinterpret_cast<const std::uint8_t*>(check), 9), 0x29B1u);
  std::uint32_t state = 12345;
  std::vector<std::uint8_t> data(300);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::size_t n = static_cast<std::size_t>(trial) % data.size();
    for (std::size_t i = 0; i < n; ++i) {
      state = state * 1664525u + 1013904223u;  // Numerical Recipes LCG
      data[i] = static_cast<std::uint8_t>(state >> 24);
    }
    std::uint16_t bitwise = 0xFFFF;
    for (std::size_t i = 0; i < n; ++i) {
      bitwise = static_cast<std::uint16_t>(bitwise ^ (data[i] << 8));
      for (int bit = 0; bit < 8; ++bit) {
        bitwise = static_cast<std::uint16_t>((bitwise & 0x8000u) ? ((bitwise << 1) ^ 0x1021u) : (bitwise << 1));
      }
    }
    ASSERT_EQ(cs_crc16(data.data(), n), bitwise) << "length " << n;
  }
}

}  // namespace
