/* The serial wire protocol between the rig firmware (firmware/, avr-gcc, C99) and the host
 * (rig::SerialRig, C++20). One header for both sides: plain C99, no allocation, no I/O.
 * docs/hardware.md describes it for people; this file is the contract.
 *
 * Frame (every message, both directions; multi-byte fields little endian):
 *
 *   offset  0      1      2      3      4 … 4+len−1   4+len  5+len
 *           SYNC   TYPE   SEQ    LEN    PAYLOAD        CRC lo CRC hi
 *
 *   SYNC = 0xA5. SEQ counts the sender's frames modulo 256 (each direction its own counter).
 *   LEN <= CS_WIRE_MAX_PAYLOAD. CRC = CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection,
 *   no final xor; check value of "123456789" = 0x29B1) over TYPE, SEQ, LEN and PAYLOAD.
 *
 * A receiver that meets a bad LEN or a bad CRC counts the frame as corrupted and resumes the
 * search for SYNC at the byte after the failed SYNC, so one damaged byte never costs more than
 * the frames it touched and never turns into a wrong sample. A gap in SEQ is a lost frame; a gap
 * in a SAMPLE's tick is a lost sample (the board counts the samples it could not queue itself,
 * CS_SAMPLE_TX_OVERFLOW).
 *
 * Session: HELLO → HELLO_ACK (versions, capabilities) → CONFIGURE → ACK → [SELFTEST →
 * SELFTEST_RESULT] → SERVO(on) → ACK → START → ACK, then one SAMPLE per tick (tick 0, 1, …) while
 * the host sends COMMAND frames; STOP → ACK ends the run (command to its safe value, servo off).
 * STOP is accepted in every state, so a host that finds a board still running (its previous host
 * was killed mid-run) sends STOP before CONFIGURE and the board is usable again.
 * While started, a board that has not received a valid COMMAND for CONFIGURE.watchdog_ms drops
 * the command to its safe value (position: the pulse output stops where it is; speed:
 * dac_safe_code) and flags every following sample with CS_SAMPLE_WATCHDOG until the next COMMAND.
 */
#ifndef CLEARSHAPE_RIG_WIRE_PROTOCOL_H
#define CLEARSHAPE_RIG_WIRE_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CS_WIRE_VERSION 1u
#define CS_WIRE_SYNC 0xA5u
#define CS_WIRE_HEADER_BYTES 4u
#define CS_WIRE_CRC_BYTES 2u
#define CS_WIRE_MAX_PAYLOAD 32u
#define CS_WIRE_MAX_FRAME (CS_WIRE_HEADER_BYTES + CS_WIRE_MAX_PAYLOAD + CS_WIRE_CRC_BYTES)

/* Message types. Host → board below 0x80, board → host from 0x80. */
enum cs_wire_type {
  CS_MSG_HELLO = 0x01,           /* cs_msg_hello */
  CS_MSG_CONFIGURE = 0x02,       /* cs_msg_configure; only while stopped */
  CS_MSG_START = 0x03,           /* no payload: tick := 0, sampling starts */
  CS_MSG_STOP = 0x04,            /* no payload: sampling stops, command safe, servo off */
  CS_MSG_COMMAND = 0x05,         /* cs_msg_command; feeds the watchdog */
  CS_MSG_SERVO = 0x06,           /* cs_msg_servo */
  CS_MSG_SELFTEST = 0x07,        /* no payload; only while stopped */
  CS_MSG_GET_STATS = 0x08,       /* no payload */
  CS_MSG_HELLO_ACK = 0x81,       /* cs_msg_hello_ack */
  CS_MSG_ACK = 0x82,             /* cs_msg_ack: the result of CONFIGURE, START, STOP, SERVO */
  CS_MSG_SAMPLE = 0x83,          /* cs_msg_sample */
  CS_MSG_SELFTEST_RESULT = 0x84, /* cs_msg_selftest_result */
  CS_MSG_STATS = 0x85            /* cs_msg_stats */
};

/* ACK results. */
enum cs_wire_result {
  CS_OK = 0,
  CS_ERR_LENGTH = 1,      /* payload length wrong for the type */
  CS_ERR_VALUE = 2,       /* a field out of range; cs_msg_ack.detail = the field's byte offset */
  CS_ERR_STATE = 3,       /* not allowed now (e.g. CONFIGURE while started, START unconfigured) */
  CS_ERR_UNKNOWN = 4,     /* unknown message type */
  CS_ERR_DEVICE = 5       /* a TWI device did not answer; detail = its 7-bit address */
};

/* HELLO_ACK.capabilities bits. */
enum cs_wire_capability {
  CS_CAP_ENCODER_QUADRATURE = 1u << 0, /* A/B encoder input with illegal-transition counting */
  CS_CAP_PULSE_AB = 1u << 1,           /* position mode: A/B pulse train ("pulse logic 0") */
  CS_CAP_DAC_MCP4725 = 1u << 2,        /* speed mode: 12-bit MCP4725 on TWI */
  CS_CAP_GYRO_ITG3205 = 1u << 3,       /* ITG-3205 on TWI */
  CS_CAP_SERVO_ON = 1u << 4,           /* servo-on digital output */
  CS_CAP_WATCHDOG = 1u << 5            /* command watchdog */
};

/* CONFIGURE.mode */
enum cs_wire_mode { CS_MODE_POSITION = 0, CS_MODE_SPEED = 1 };

/* SAMPLE.flags bits. */
enum cs_sample_flag {
  CS_SAMPLE_GYRO_SATURATED = 1u << 0, /* the gyro word hit ±32767/−32768 */
  CS_SAMPLE_COMMAND_LIMITED = 1u << 1,/* the pulse rate was capped or the DAC code clipped */
  CS_SAMPLE_WATCHDOG = 1u << 2,       /* the watchdog holds the command at its safe value */
  CS_SAMPLE_TWI_ERROR = 1u << 3,      /* the gyro read failed; gyro_raw repeats the last word */
  CS_SAMPLE_TX_OVERFLOW = 1u << 4,    /* samples before this one were dropped on the board */
  CS_SAMPLE_SERVO_ON = 1u << 5,       /* the servo-on output is active */
  CS_SAMPLE_LATE = 1u << 6,           /* the tick's work overran its period on the board */
  CS_SAMPLE_RX_REJECTED = 1u << 7     /* since the previous sample the board rejected host bytes
                                         (a damaged frame or an RX-ring overrun): a COMMAND may
                                         not have arrived */
};

/* Payloads: the byte offset of each field is given; encode/decode with cs_put_* / cs_get_*. */
#define CS_HELLO_BYTES 2u           /* u16 wire_version @0 */
#define CS_HELLO_ACK_BYTES 16u      /* u16 wire_version @0, u8 fw_major @2, u8 fw_minor @3,
                                       u16 fw_patch @4, u16 encoder_lines_hint @6 (0 = unknown),
                                       u32 capabilities @8, u32 cpu_hz @12 */
#define CS_CONFIGURE_BYTES 16u      /* u8 mode @0, u8 gyro_fs_sel @1 (0..3; 3 = ±2000 °/s),
                                       u8 gyro_dlpf_cfg @2 (0..6), u8 reserved @3 (0),
                                       u16 sample_rate_hz @4 (100..2000),
                                       u16 update_rate_hz @6 (1..sample_rate; position mode),
                                       u32 max_pulse_rate_hz @8 (1..CS_MAX_PULSE_RATE_HZ),
                                       u16 watchdog_ms @12 (0 = off, else 5..60000),
                                       u16 dac_safe_code @14 (0..4095) */
#define CS_COMMAND_BYTES 8u         /* u32 tick @0 (the last sample the host had),
                                       i32 value @4: position = absolute pulse target (A/B edges),
                                       speed = DAC code 0..4095 (clipped, flagged) */
#define CS_SERVO_BYTES 1u           /* u8 on @0 (0/1) */
#define CS_ACK_BYTES 4u             /* u8 acked_type @0, u8 result @1, u16 detail @2 */
#define CS_SAMPLE_BYTES 20u         /* u32 tick @0, i32 encoder_count @4, i16 gyro_raw @8,
                                       u8 flags @10, u8 command_seq @11 (SEQ of the last
                                       COMMAND applied), i32 pulses_emitted @12,
                                       u16 dac_code @16, u16 illegal_transitions @18
                                       (cumulative, wraps) */
#define CS_SELFTEST_RESULT_BYTES 6u /* u8 gyro_who_am_i @0 (ITG-3205: 0x68 or 0x69), u8 gyro_ok @1,
                                       u8 dac_ok @2, u8 reserved @3, i16 gyro_raw_at_rest @4 */
#define CS_STATS_BYTES 20u          /* u32 samples_sent @0, u32 samples_dropped @4,
                                       u32 rx_corrupted @8, u32 watchdog_trips @12,
                                       u32 late_ticks @16 */

/* The A/B edge rate the board sustains while it also counts the motor's encoder edges and
 * samples at 1 kHz with a COMMAND per tick (docs/hardware.md, "Position moves": 46 000 edges/s
 * computed, 45 000 measured clean in the emulator); the board refuses more. */
#define CS_MAX_PULSE_RATE_HZ 45000u

/* Little-endian field access. */
static inline void cs_put_u16(uint8_t* p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)(v >> 8);
}
static inline void cs_put_u32(uint8_t* p, uint32_t v) {
  cs_put_u16(p, (uint16_t)(v & 0xFFFFu));
  cs_put_u16(p + 2, (uint16_t)(v >> 16));
}
static inline uint16_t cs_get_u16(const uint8_t* p) {
  return (uint16_t)((uint16_t)p[0] | (uint16_t)((uint16_t)p[1] << 8));
}
static inline uint32_t cs_get_u32(const uint8_t* p) {
  return (uint32_t)cs_get_u16(p) | ((uint32_t)cs_get_u16(p + 2) << 16);
}
static inline void cs_put_i16(uint8_t* p, int16_t v) { cs_put_u16(p, (uint16_t)v); }
static inline void cs_put_i32(uint8_t* p, int32_t v) { cs_put_u32(p, (uint32_t)v); }
static inline int16_t cs_get_i16(const uint8_t* p) { return (int16_t)cs_get_u16(p); }
static inline int32_t cs_get_i32(const uint8_t* p) { return (int32_t)cs_get_u32(p); }

/* A SAMPLE payload, field by field (layout: CS_SAMPLE_BYTES above). The one encoder and decoder
 * of that layout, used by the firmware, the host and the tests. */
typedef struct cs_sample {
  uint32_t tick;
  int32_t encoder_count;
  int16_t gyro_raw;
  uint8_t flags;
  uint8_t command_seq;
  int32_t pulses_emitted;
  uint16_t dac_code;
  uint16_t illegal_transitions;
} cs_sample;

static inline void cs_sample_encode(uint8_t* p, const cs_sample* s) {
  cs_put_u32(p + 0, s->tick);
  cs_put_i32(p + 4, s->encoder_count);
  cs_put_i16(p + 8, s->gyro_raw);
  p[10] = s->flags;
  p[11] = s->command_seq;
  cs_put_i32(p + 12, s->pulses_emitted);
  cs_put_u16(p + 16, s->dac_code);
  cs_put_u16(p + 18, s->illegal_transitions);
}
static inline cs_sample cs_sample_decode(const uint8_t* p) {
  cs_sample s;
  s.tick = cs_get_u32(p + 0);
  s.encoder_count = cs_get_i32(p + 4);
  s.gyro_raw = cs_get_i16(p + 8);
  s.flags = p[10];
  s.command_seq = p[11];
  s.pulses_emitted = cs_get_i32(p + 12);
  s.dac_code = cs_get_u16(p + 16);
  s.illegal_transitions = cs_get_u16(p + 18);
  return s;
}

/* CRC-16/CCITT-FALSE, one byte at a time, four bits per step from a 16-entry table (entry n =
 * the CRC register after shifting nibble n through the polynomial): the bitwise CRC's result
 * in about a quarter of its cycles, which the board needs to decode back-to-back COMMANDs at
 * 1 Mbaud (docs/hardware.md); 32 bytes of table. */
static inline uint16_t cs_crc16_update(uint16_t crc, uint8_t byte) {
  static const uint16_t nibble[16] = {0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u,
                                      0x60C6u, 0x70E7u, 0x8108u, 0x9129u, 0xA14Au, 0xB16Bu,
                                      0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu};
  crc = (uint16_t)((uint16_t)(crc << 4) ^ nibble[(uint8_t)((crc >> 12) ^ (byte >> 4))]);
  return (uint16_t)((uint16_t)(crc << 4) ^ nibble[(uint8_t)((crc >> 12) ^ (byte & 0x0Fu))]);
}
static inline uint16_t cs_crc16(const uint8_t* data, size_t length) {
  uint16_t crc = 0xFFFFu;
  size_t i;
  for (i = 0; i < length; ++i) crc = cs_crc16_update(crc, data[i]);
  return crc;
}

/* Writes one frame into out (at least CS_WIRE_HEADER_BYTES + length + CS_WIRE_CRC_BYTES bytes).
 * Returns the frame's size, or 0 when length > CS_WIRE_MAX_PAYLOAD. */
static inline size_t cs_frame_encode(uint8_t* out, uint8_t type, uint8_t seq,
                                     const uint8_t* payload, uint8_t length) {
  size_t i;
  uint16_t crc;
  if (length > CS_WIRE_MAX_PAYLOAD) return 0;
  out[0] = (uint8_t)CS_WIRE_SYNC;
  out[1] = type;
  out[2] = seq;
  out[3] = length;
  for (i = 0; i < length; ++i) out[CS_WIRE_HEADER_BYTES + i] = payload[i];
  crc = cs_crc16(out + 1, (size_t)(3u + length));
  cs_put_u16(out + CS_WIRE_HEADER_BYTES + length, crc);
  return CS_WIRE_HEADER_BYTES + (size_t)length + CS_WIRE_CRC_BYTES;
}

/* Incremental frame decoder: feed bytes one at a time; a complete, CRC-checked frame is then
 * in `frame` (type, seq, length, payload). Fixed-size state, no allocation. On a bad length or
 * CRC the decoder counts `corrupted` and rescans the buffered bytes after the failed SYNC. */
typedef struct cs_frame {
  uint8_t type;
  uint8_t seq;
  uint8_t length;
  uint8_t payload[CS_WIRE_MAX_PAYLOAD];
} cs_frame;

typedef struct cs_decoder {
  uint8_t buffer[CS_WIRE_MAX_FRAME];
  uint8_t fill;            /* bytes of the candidate frame held in buffer (buffer[0] = SYNC) */
  uint32_t frames;         /* good frames decoded */
  uint32_t corrupted;      /* candidate frames rejected (bad LEN or CRC) */
  uint32_t skipped_bytes;  /* bytes discarded while searching for SYNC */
} cs_decoder;

static inline void cs_decoder_reset(cs_decoder* d) {
  d->fill = 0;
  d->frames = 0;
  d->corrupted = 0;
  d->skipped_bytes = 0;
}

/* Internal: after a rejected candidate, restart the search at the byte after its SYNC. */
static inline void cs_decoder_resync_(cs_decoder* d) {
  uint8_t i;
  uint8_t start = 0;
  for (i = 1; i < d->fill; ++i) {
    if (d->buffer[i] == CS_WIRE_SYNC) {
      start = i;
      break;
    }
  }
  if (start == 0) {
    d->skipped_bytes += (uint32_t)(d->fill > 0 ? d->fill - 1u : 0u);
    d->fill = 0;
    return;
  }
  d->skipped_bytes += (uint32_t)(start - 1u);
  for (i = start; i < d->fill; ++i) d->buffer[i - start] = d->buffer[i];
  d->fill = (uint8_t)(d->fill - start);
}

/* Internal: after a good frame of `used` bytes, keep what follows it (from its first SYNC). */
static inline void cs_decoder_keep_rest_(cs_decoder* d, uint8_t used) {
  uint8_t i;
  uint8_t start = used;
  while (start < d->fill && d->buffer[start] != CS_WIRE_SYNC) ++start;
  d->skipped_bytes += (uint32_t)(start - used);
  for (i = start; i < d->fill; ++i) d->buffer[i - start] = d->buffer[i];
  d->fill = (uint8_t)(start < d->fill ? (uint8_t)(d->fill - start) : 0u);
}

/* Feeds one byte. Returns 1 when `frame` now holds a complete good frame, else 0. A frame
 * that was already complete in the buffer (possible only after a resync) is returned on the
 * next push, before the new byte is considered. */
static inline int cs_decoder_push(cs_decoder* d, uint8_t byte, cs_frame* frame) {
  uint8_t length;
  uint8_t i;
  size_t total;
  if (d->fill == 0) {
    if (byte != CS_WIRE_SYNC) {
      ++d->skipped_bytes;
      return 0;
    }
  }
  d->buffer[d->fill++] = byte;
  for (;;) {
    if (d->fill < CS_WIRE_HEADER_BYTES) return 0;
    length = d->buffer[3];
    if (length > CS_WIRE_MAX_PAYLOAD) {
      ++d->corrupted;
      cs_decoder_resync_(d);
      continue;
    }
    total = CS_WIRE_HEADER_BYTES + (size_t)length + CS_WIRE_CRC_BYTES;
    if (d->fill < total) return 0;
    if (cs_crc16(d->buffer + 1, (size_t)(3u + length)) !=
        cs_get_u16(d->buffer + CS_WIRE_HEADER_BYTES + length)) {
      ++d->corrupted;
      cs_decoder_resync_(d);
      continue;
    }
    frame->type = d->buffer[1];
    frame->seq = d->buffer[2];
    frame->length = length;
    for (i = 0; i < length; ++i) frame->payload[i] = d->buffer[CS_WIRE_HEADER_BYTES + i];
    ++d->frames;
    /* After a resync the buffer can hold bytes beyond this frame (the start of the next one,
     * or all of it): keep them as the next candidate, from its SYNC on; a complete frame among
     * them comes out on the next push. */
    cs_decoder_keep_rest_(d, (uint8_t)total);
    return 1;
  }
}

#ifdef __cplusplus
}  /* extern "C" */
#endif

#endif /* CLEARSHAPE_RIG_WIRE_PROTOCOL_H */
