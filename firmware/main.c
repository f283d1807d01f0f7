/* clearshape rig firmware (ATmega2560, 16 MHz): the board side of
 * include/clearshape/rig/wire_protocol.h. docs/hardware.md gives wiring, limits and flashing.
 *
 * Timing: Timer1 (CTC, /8) interrupts at the sample rate and snapshots the encoder count and
 * the emitted pulse count at the tick instant; the main loop then reads the gyro (polled TWI),
 * re-plans the pulse train or writes the DAC, runs the watchdog and queues the tick's SAMPLE.
 * The ISR queues each tick's snapshot (TICK_QUEUE deep), so a main loop held up by a burst of
 * received frames catches up tick by tick instead of skipping ticks; only a tick that finds the
 * queue full, or a SAMPLE that finds the TX ring full, is dropped — counted and flagged.
 * Everything that must be exact in time (tick, encoder edges, pulse edges) is in short ISRs. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#include "board.h"
#include "clearshape/rig/wire_protocol.h"
#include "quadrature.h"
#include "twi.h"
#include "uart.h"

/* ---- configuration and run state ---- */
typedef struct config {
  uint8_t mode;
  uint8_t gyro_fs_sel;
  uint8_t gyro_dlpf_cfg;
  uint16_t sample_rate_hz;
  uint16_t update_rate_hz;
  uint32_t max_pulse_rate_hz;
  uint16_t watchdog_ms;
  uint16_t dac_safe_code;
} config;

static config cfg;
static uint8_t configured;
static uint8_t started;
static uint8_t servo_on;
static uint8_t tx_seq;
static cs_decoder decoder;
static cs_frame frame;

/* Tick ISR -> main loop: a queue of the ticks' snapshots, so that every tick's SAMPLE is sent
 * even when the main loop falls behind (a COMMAND burst, a slow TWI read); a tick that finds
 * the queue full is not lost silently: the next sample's tick jumps, it is counted in
 * STATS.samples_dropped and flagged CS_SAMPLE_TX_OVERFLOW. */
#define TICK_QUEUE 8u /* power of two; 8 ms of catch-up at 1 kHz */
typedef struct tick_snapshot {
  uint32_t tick;
  int32_t encoder;
  int32_t pulses;
  uint16_t illegal;
} tick_snapshot;
static volatile tick_snapshot tick_queue[TICK_QUEUE];
static volatile uint8_t tick_head;    /* written by the ISR */
static volatile uint8_t tick_tail;    /* written by the main loop */
static volatile uint32_t tick_isr;    /* ticks since START, counted by the ISR */
static uint32_t tick_next;            /* the tick the main loop expects next */

/* Commands. */
static int32_t position_target;
/* The latest position COMMANDs with the tick they answer (the host's last sample, so they are
 * meant from the next tick on): the update at tick U plans to the newest one whose tick is
 * before U − COMMAND_LATENCY_TICKS. The host's round trip (sample out, COMMAND back: ~0.8 ms
 * through the emulator's pty, 1–3 ms through a USB bridge) thus never decides which update a
 * COMMAND makes, and a shaper's impulses, which sit on the update grid, land on the same
 * update in every run — one update after rig::SimRig applies them, whose pulse train takes a
 * command at the next sample. */
#define COMMAND_LATENCY_TICKS 4u
#define TARGET_HISTORY 16u /* power of two; > the tick queue's 8 ticks of lateness */
static int32_t target_value[TARGET_HISTORY];
static uint32_t target_tick[TARGET_HISTORY];
static uint8_t target_count; /* COMMANDs stored since START (saturates at TARGET_HISTORY) */
static uint8_t target_head;  /* next slot */
static uint16_t dac_code;
static uint8_t dac_dirty;
static uint8_t command_seq;
static uint8_t command_limited;
static uint16_t update_accumulator; /* += update_rate each tick; >= sample_rate: re-plan */
static uint32_t tick_cycles; /* CPU cycles per tick */
static int32_t max_edges_per_update;
static uint32_t watchdog_ticks;
static uint32_t ticks_since_command;
static uint8_t watchdog_active;
static int16_t gyro_last;
static uint8_t pending_flags; /* TX_OVERFLOW, LATE: carried to the next queued sample */
static uint32_t rx_rejected_seen; /* decoder.corrupted + RX overruns at the last sample */

/* STATS. */
static uint32_t samples_sent;
static uint32_t samples_dropped;
static uint32_t watchdog_trips;
static uint32_t late_ticks;

ISR(TIMER1_COMPA_vect) {
  const uint8_t head = tick_head;
  const uint32_t tick = tick_isr;
  quad_fold_counts();
  tick_isr = tick + 1u;
  if ((uint8_t)(head - tick_tail) < TICK_QUEUE) {
    volatile tick_snapshot* s = &tick_queue[head & (TICK_QUEUE - 1u)];
    s->tick = tick;
    s->encoder = quad_encoder_folded;
    s->pulses = quad_pulses_folded;
    s->illegal = quad_illegal_transitions;
    tick_head = (uint8_t)(head + 1u);
  }
}

static uint8_t tick_waiting(void) { return (uint8_t)(tick_head != tick_tail); }

static void tick_start(uint16_t rate_hz) {
  TCCR1B = 0;
  tick_head = 0;
  tick_tail = 0;
  tick_isr = 0;
  tick_next = 0;
  TCCR1A = 0;
  TCNT1 = 0;
  OCR1A = (uint16_t)(2000000UL / rate_hz - 1u); /* F_CPU / 8 = 2 MHz timer clock */
  TIFR1 = (uint8_t)(1u << OCF1A);
  TIMSK1 = (uint8_t)(1u << OCIE1A);
  TCCR1B = (uint8_t)((1u << WGM12) | (1u << CS11)); /* CTC, /8 */
}

static void tick_stop(void) {
  TCCR1B = 0;
  TIMSK1 = 0;
  tick_tail = tick_head;
}

/* ---- frames out ---- */
static uint8_t send_frame(uint8_t type, const uint8_t* payload, uint8_t length, uint8_t droppable) {
  uint8_t out[CS_WIRE_MAX_FRAME];
  const uint8_t size = (uint8_t)cs_frame_encode(out, type, tx_seq, payload, length);
  if (droppable) {
    if (uart_tx_free() < size) return 0;
  } else {
    while (uart_tx_free() < size) {
    }
  }
  uart_write(out, size);
  ++tx_seq;
  return 1;
}

static void send_ack(uint8_t type, uint8_t result, uint16_t detail) {
  uint8_t p[CS_ACK_BYTES];
  p[0] = type;
  p[1] = result;
  cs_put_u16(p + 2, detail);
  send_frame(CS_MSG_ACK, p, CS_ACK_BYTES, 0);
}

/* ---- devices ---- */
static uint8_t gyro_read_z(int16_t* value) {
  uint8_t b[2];
  if (!twi_read_registers(ITG3205_ADDRESS, ITG3205_GYRO_ZOUT_H, b, 2)) return 0;
  *value = (int16_t)(((uint16_t)b[0] << 8) | b[1]);
  return 1;
}

static uint8_t gyro_setup(void) {
  uint8_t v = 0; /* SMPLRT_DIV 0: the output rate is the internal rate (1 kHz, 8 kHz at DLPF 0) */
  if (!twi_write_register(ITG3205_ADDRESS, ITG3205_SMPLRT_DIV, &v, 1)) return 0;
  v = (uint8_t)((cfg.gyro_fs_sel << 3) | cfg.gyro_dlpf_cfg);
  if (!twi_write_register(ITG3205_ADDRESS, ITG3205_DLPF_FS, &v, 1)) return 0;
  v = 0x01u; /* PLL with the X gyro reference (datasheet §8: recommended clock) */
  return twi_write_register(ITG3205_ADDRESS, ITG3205_PWR_MGM, &v, 1);
}

static void servo_set(uint8_t on) {
  servo_on = on;
  if (on) {
    PORTA |= (uint8_t)(1u << BOARD_SERVO_BIT);
  } else {
    PORTA &= (uint8_t)~(1u << BOARD_SERVO_BIT);
  }
}

/* The command's safe value: position stops where it is, speed goes to dac_safe_code. */
static void command_safe(void) {
  if (cfg.mode == CS_MODE_POSITION) {
    quad_stop();
    position_target = quad_pulses_emitted();
  } else {
    dac_code = cfg.dac_safe_code;
    dac_dirty = 1;
  }
}

/* ---- messages in ---- */
static void on_hello(void) {
  uint8_t p[CS_HELLO_ACK_BYTES];
  if (frame.length != CS_HELLO_BYTES) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  cs_put_u16(p + 0, CS_WIRE_VERSION);
  p[2] = FW_MAJOR;
  p[3] = FW_MINOR;
  cs_put_u16(p + 4, FW_PATCH);
  cs_put_u16(p + 6, FW_ENCODER_LINES_HINT);
  cs_put_u32(p + 8, CS_CAP_ENCODER_QUADRATURE | CS_CAP_PULSE_AB | CS_CAP_DAC_MCP4725 |
                        CS_CAP_GYRO_ITG3205 | CS_CAP_SERVO_ON | CS_CAP_WATCHDOG);
  cs_put_u32(p + 12, F_CPU);
  send_frame(CS_MSG_HELLO_ACK, p, CS_HELLO_ACK_BYTES, 0);
}

/* Returns the byte offset of the first bad field, or 0xFFFF when all are in range. */
static uint16_t configure_check(const uint8_t* p) {
  const uint16_t rate = cs_get_u16(p + 4);
  const uint16_t update = cs_get_u16(p + 6);
  const uint32_t pulse = cs_get_u32(p + 8);
  const uint16_t watchdog = cs_get_u16(p + 12);
  if (p[0] > CS_MODE_SPEED) return 0;
  if (p[1] > 3u) return 1;
  if (p[2] > 6u) return 2;
  if (p[3] != 0u) return 3;
  if (rate < 100u || rate > 2000u) return 4;
  if (update < 1u || update > rate) return 6;
  if (pulse < 1u || pulse > CS_MAX_PULSE_RATE_HZ) return 8;
  if (watchdog != 0u && (watchdog < 5u || watchdog > 60000u)) return 12;
  if (cs_get_u16(p + 14) > 4095u) return 14;
  return 0xFFFFu;
}

static void on_configure(void) {
  const uint8_t* p = frame.payload;
  uint16_t bad;
  if (frame.length != CS_CONFIGURE_BYTES) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  if (started) {
    send_ack(frame.type, CS_ERR_STATE, 0);
    return;
  }
  bad = configure_check(p);
  if (bad != 0xFFFFu) {
    send_ack(frame.type, CS_ERR_VALUE, bad);
    return;
  }
  configured = 0;
  cfg.mode = p[0];
  cfg.gyro_fs_sel = p[1];
  cfg.gyro_dlpf_cfg = p[2];
  cfg.sample_rate_hz = cs_get_u16(p + 4);
  cfg.update_rate_hz = cs_get_u16(p + 6);
  cfg.max_pulse_rate_hz = cs_get_u32(p + 8);
  cfg.watchdog_ms = cs_get_u16(p + 12);
  cfg.dac_safe_code = cs_get_u16(p + 14);
  tick_cycles = 8UL * (2000000UL / cfg.sample_rate_hz); /* Timer1 /8, OCR1A + 1 counts */
  max_edges_per_update = (int32_t)(cfg.max_pulse_rate_hz / cfg.update_rate_hz);
  if (max_edges_per_update < 1) max_edges_per_update = 1;
  /* ceil(watchdog_ms * rate / 1000) ticks */
  watchdog_ticks = ((uint32_t)cfg.watchdog_ms * cfg.sample_rate_hz + 999u) / 1000u;
  if (!gyro_setup()) {
    send_ack(frame.type, CS_ERR_DEVICE, ITG3205_ADDRESS);
    return;
  }
  if (cfg.mode == CS_MODE_SPEED && !twi_dac_write(cfg.dac_safe_code)) {
    send_ack(frame.type, CS_ERR_DEVICE, MCP4725_ADDRESS);
    return;
  }
  dac_code = cfg.dac_safe_code;
  configured = 1;
  send_ack(frame.type, CS_OK, 0);
}

static void on_start(void) {
  if (frame.length != 0) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  if (!configured || started) {
    send_ack(frame.type, CS_ERR_STATE, 0);
    return;
  }
  quad_zero();
  position_target = 0;
  target_count = 0;
  target_head = 0;
  dac_code = cfg.dac_safe_code;
  dac_dirty = (uint8_t)(cfg.mode == CS_MODE_SPEED);
  command_seq = 0;
  command_limited = 0;
  /* The first pulse-train update is at tick 0, then every sample_rate/update_rate ticks on
   * average (rig::SimRig's pulse train updates at t = 0, T, 2T, … likewise). */
  update_accumulator = (uint16_t)(cfg.sample_rate_hz - cfg.update_rate_hz);
  ticks_since_command = 0;
  watchdog_active = 0;
  pending_flags = 0;
  rx_rejected_seen = decoder.corrupted + uart_rx_overruns();
  started = 1;
  send_ack(frame.type, CS_OK, 0);
  tick_start(cfg.sample_rate_hz);
}

static void stop_run(void) {
  tick_stop();
  started = 0;
  if (configured) command_safe();
  if (configured && cfg.mode == CS_MODE_SPEED) {
    twi_dac_write(dac_code);
    dac_dirty = 0;
  }
  servo_set(0);
}

static void on_stop(void) {
  if (frame.length != 0) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  stop_run();
  send_ack(frame.type, CS_OK, 0);
}

static void on_command(void) {
  int32_t value;
  if (frame.length != CS_COMMAND_BYTES) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  if (!started) {
    send_ack(frame.type, CS_ERR_STATE, 0);
    return;
  }
  value = cs_get_i32(frame.payload + 4);
  command_seq = frame.seq;
  ticks_since_command = 0;
  watchdog_active = 0;
  if (cfg.mode == CS_MODE_POSITION) {
    uint32_t tick = cs_get_u32(frame.payload);
    uint32_t now;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { now = tick_isr; }
    /* A tick the board has not reached yet cannot be the host's last sample: taken as now. */
    if ((int32_t)(tick - now) >= 0) tick = now - 1u;
    target_value[target_head] = value;
    target_tick[target_head] = tick;
    target_head = (uint8_t)((target_head + 1u) & (TARGET_HISTORY - 1u));
    if (target_count < TARGET_HISTORY) ++target_count;
  } else {
    command_limited = (uint8_t)(value < 0 || value > 4095);
    dac_code = (uint16_t)(value < 0 ? 0 : (value > 4095 ? 4095 : value));
    dac_dirty = 1;
  }
}

static void on_servo(void) {
  if (frame.length != CS_SERVO_BYTES) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  if (frame.payload[0] > 1u) {
    send_ack(frame.type, CS_ERR_VALUE, 0);
    return;
  }
  servo_set(frame.payload[0]);
  send_ack(frame.type, CS_OK, 0);
}

static void on_selftest(void) {
  uint8_t p[CS_SELFTEST_RESULT_BYTES];
  uint8_t who = 0;
  int16_t rest = 0;
  uint8_t gyro_ok;
  if (frame.length != 0) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  if (started) {
    send_ack(frame.type, CS_ERR_STATE, 0);
    return;
  }
  gyro_ok = twi_read_registers(ITG3205_ADDRESS, ITG3205_WHO_AM_I, &who, 1);
  gyro_ok = (uint8_t)(gyro_ok && (who & 0x7Eu) == 0x68u && gyro_read_z(&rest)); /* ID bits 6:1 */
  p[0] = who;
  p[1] = gyro_ok;
  p[2] = twi_probe(MCP4725_ADDRESS);
  p[3] = 0;
  cs_put_i16(p + 4, rest);
  send_frame(CS_MSG_SELFTEST_RESULT, p, CS_SELFTEST_RESULT_BYTES, 0);
}

static void on_get_stats(void) {
  uint8_t p[CS_STATS_BYTES];
  if (frame.length != 0) {
    send_ack(frame.type, CS_ERR_LENGTH, frame.length);
    return;
  }
  cs_put_u32(p + 0, samples_sent);
  cs_put_u32(p + 4, samples_dropped);
  cs_put_u32(p + 8, decoder.corrupted);
  cs_put_u32(p + 12, watchdog_trips);
  cs_put_u32(p + 16, late_ticks);
  send_frame(CS_MSG_STATS, p, CS_STATS_BYTES, 0);
}

static void dispatch(void) {
  switch (frame.type) {
    case CS_MSG_HELLO: on_hello(); break;
    case CS_MSG_CONFIGURE: on_configure(); break;
    case CS_MSG_START: on_start(); break;
    case CS_MSG_STOP: on_stop(); break;
    case CS_MSG_COMMAND: on_command(); break;
    case CS_MSG_SERVO: on_servo(); break;
    case CS_MSG_SELFTEST: on_selftest(); break;
    case CS_MSG_GET_STATS: on_get_stats(); break;
    default: send_ack(frame.type, CS_ERR_UNKNOWN, 0); break;
  }
}

/* ---- the tick's work ---- */
/* The newest COMMAND whose tick is before `tick` becomes the target (none: it stays). */
static void select_target(uint32_t tick) {
  uint8_t i;
  for (i = 0; i < target_count; ++i) {
    const uint8_t k = (uint8_t)((target_head - 1u - i) & (TARGET_HISTORY - 1u));
    if ((int32_t)(target_tick[k] + COMMAND_LATENCY_TICKS - tick) < 0) {
      position_target = target_value[k];
      return;
    }
  }
}

static void plan_pulses(void) {
  /* Spread the edges over the ticks until the next update (33 or 34 at 1 kHz / 30 Hz), so
   * they are all out before it and no edge trails into the next period. */
  const uint16_t ticks =
      (uint16_t)((cfg.sample_rate_hz - update_accumulator + cfg.update_rate_hz - 1u) / cfg.update_rate_hz);
  command_limited = quad_plan_to(position_target, max_edges_per_update, (uint32_t)ticks * tick_cycles,
                                 (F_CPU + cfg.max_pulse_rate_hz - 1u) / cfg.max_pulse_rate_hz);
}

/* Advances the watchdog and the pulse-train update clock by one tick, `tick`. */
static void step_tick_clocks(uint32_t tick) {
  /* Watchdog: ticks since the last COMMAND (which arrived within the tick before the first of
   * them); beyond watchdog_ticks at least watchdog_ms have passed: the command goes safe. */
  if (cfg.watchdog_ms != 0u && !watchdog_active && ++ticks_since_command > watchdog_ticks) {
    watchdog_active = 1;
    ++watchdog_trips;
    command_safe();
  }
  if (cfg.mode == CS_MODE_POSITION && !watchdog_active) {
    update_accumulator = (uint16_t)(update_accumulator + cfg.update_rate_hz);
    if (update_accumulator >= cfg.sample_rate_hz) {
      update_accumulator = (uint16_t)(update_accumulator - cfg.sample_rate_hz);
      select_target(tick);
      plan_pulses();
    }
  }
}

/* The oldest queued tick: its SAMPLE, built from the snapshot taken at the tick instant. */
static void run_tick(void) {
  uint8_t p[CS_SAMPLE_BYTES];
  cs_sample sample;
  uint8_t flags = pending_flags;
  tick_snapshot snap;
  uint32_t missed;
  uint8_t tail;
  int16_t gyro;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    tail = tick_tail;
    snap.tick = tick_queue[tail & (TICK_QUEUE - 1u)].tick;
    snap.encoder = tick_queue[tail & (TICK_QUEUE - 1u)].encoder;
    snap.pulses = tick_queue[tail & (TICK_QUEUE - 1u)].pulses;
    snap.illegal = tick_queue[tail & (TICK_QUEUE - 1u)].illegal;
    tick_tail = (uint8_t)(tail + 1u);
    /* Late: the next tick came before this one's work was done. */
    if (tick_head != tick_tail) flags |= CS_SAMPLE_LATE;
  }
  if (flags & CS_SAMPLE_LATE) ++late_ticks;
  /* Ticks that found the queue full: counted and flagged, their clocks still advance. */
  missed = snap.tick - tick_next;
  tick_next = snap.tick + 1u;
  if (missed != 0u) {
    samples_dropped += missed;
    flags |= CS_SAMPLE_TX_OVERFLOW;
    while (missed != 0u) step_tick_clocks(snap.tick - missed--);
  }
  pending_flags = 0;
  if (gyro_read_z(&gyro)) {
    gyro_last = gyro;
  } else {
    flags |= CS_SAMPLE_TWI_ERROR;
  }
  step_tick_clocks(snap.tick);
  if (gyro_last == 32767 || gyro_last == -32768 || gyro_last == -32767) flags |= CS_SAMPLE_GYRO_SATURATED;
  if (cfg.mode == CS_MODE_SPEED && dac_dirty) {
    if (twi_dac_write(dac_code)) {
      dac_dirty = 0;
    } else {
      flags |= CS_SAMPLE_TWI_ERROR;
    }
  }
  if (watchdog_active) flags |= CS_SAMPLE_WATCHDOG;
  if (command_limited) flags |= CS_SAMPLE_COMMAND_LIMITED;
  if (servo_on) flags |= CS_SAMPLE_SERVO_ON;
  {
    /* Host bytes rejected since the last sample: the host learns at once that a COMMAND may be
     * missing (STATS.rx_corrupted only counts them). */
    const uint32_t rejected = decoder.corrupted + uart_rx_overruns();
    if (rejected != rx_rejected_seen) {
      rx_rejected_seen = rejected;
      flags |= CS_SAMPLE_RX_REJECTED;
    }
  }
  sample.tick = snap.tick;
  sample.encoder_count = snap.encoder;
  sample.gyro_raw = gyro_last;
  sample.flags = flags;
  sample.command_seq = command_seq;
  sample.pulses_emitted = snap.pulses;
  sample.dac_code = dac_code;
  sample.illegal_transitions = snap.illegal;
  cs_sample_encode(p, &sample);
  if (send_frame(CS_MSG_SAMPLE, p, CS_SAMPLE_BYTES, 1)) {
    ++samples_sent;
  } else {
    ++samples_dropped;
    pending_flags |= CS_SAMPLE_TX_OVERFLOW;
  }
}

int main(void) {
  uint8_t byte;
  DDRA |= (uint8_t)(1u << BOARD_SERVO_BIT);
  servo_set(0);
  cs_decoder_reset(&decoder);
  uart_init();
  twi_init();
  quad_init();
  sei();
  for (;;) {
    if (tick_waiting()) run_tick();
    /* Received bytes until the next tick is due: the tick's work always comes first, so a
     * burst of COMMANDs delays it by at most one frame's dispatch. */
    while (!tick_waiting() && uart_read(&byte)) {
      if (cs_decoder_push(&decoder, byte, &frame)) dispatch();
    }
  }
}
