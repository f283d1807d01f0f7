#include "quadrature.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#include "board.h"

volatile int16_t quad_encoder_delta;
volatile uint16_t quad_illegal_transitions;
volatile int16_t quad_pulses_delta;

static volatile uint8_t encoder_state; /* (A << 1) | B */
static volatile uint16_t pulse_remaining; /* edges left in the current plan */
static volatile int8_t pulse_direction;
static volatile uint8_t pulse_phase; /* 0..3 along 00, 10, 11, 01 */
volatile int32_t quad_pulses_folded;
volatile int32_t quad_encoder_folded;

/* x4 decoding, index (previous << 2) | current with state (A << 1) | B; forward is
 * 0 -> 2 -> 3 -> 1 -> 0. 2 marks an illegal transition (both channels changed). */
static const int8_t kQuadTable[16] = {0, -1, 1, 2, 1, 0, 2, -1, -1, 2, 0, 1, 2, 1, -1, 0};
/* PORTA bits (A = bit 0, B = bit 1) of phases 0..3: (A, B) = 00, 10, 11, 01. */
static const uint8_t kPhaseBits[4] = {0u, 1u, 3u, 2u};

static inline __attribute__((always_inline)) uint8_t encoder_read(void) {
  const uint8_t pins = PINE;
  return (uint8_t)((((pins >> BOARD_ENCODER_A_BIT) & 1u) << 1) | ((pins >> BOARD_ENCODER_B_BIT) & 1u));
}

/* Both channels share one handler: whichever edge fired, the table sees the new state. */
static inline __attribute__((always_inline)) void encoder_edge(void) {
  const uint8_t now = encoder_read();
  const int8_t step = kQuadTable[(uint8_t)(encoder_state << 2) | now];
  encoder_state = now;
  if (step == 2) {
    ++quad_illegal_transitions;
  } else {
    quad_encoder_delta += step;
  }
}

ISR(INT4_vect) { encoder_edge(); }
ISR(INT5_vect, ISR_ALIASOF(INT4_vect));

ISR(TIMER3_COMPA_vect) {
  uint8_t phase;
  if (pulse_remaining == 0u) {
    TCCR3B = (uint8_t)(1u << WGM32); /* clock off */
    return;
  }
  --pulse_remaining;
  phase = (uint8_t)((pulse_phase + (uint8_t)pulse_direction) & 3u);
  pulse_phase = phase;
  quad_pulses_delta += pulse_direction;
  /* Writing a 1 to PINx toggles the pin (datasheet §13.2.2): exactly one channel changes. */
  PINA = (uint8_t)((PORTA ^ kPhaseBits[phase]) & ((1u << BOARD_PULSE_A_BIT) | (1u << BOARD_PULSE_B_BIT)));
}

void quad_init(void) {
  DDRA |= (uint8_t)((1u << BOARD_PULSE_A_BIT) | (1u << BOARD_PULSE_B_BIT));
  PORTA &= (uint8_t)~((1u << BOARD_PULSE_A_BIT) | (1u << BOARD_PULSE_B_BIT));
  DDRE &= (uint8_t)~((1u << BOARD_ENCODER_A_BIT) | (1u << BOARD_ENCODER_B_BIT));
  PORTE |= (uint8_t)((1u << BOARD_ENCODER_A_BIT) | (1u << BOARD_ENCODER_B_BIT)); /* pull-ups */
  encoder_state = encoder_read();
  EICRB = (uint8_t)((1u << ISC40) | (1u << ISC50)); /* any logical change */
  EIFR = (uint8_t)((1u << INTF4) | (1u << INTF5));
  EIMSK |= (uint8_t)((1u << INT4) | (1u << INT5));
  TCCR3A = 0;
  TCCR3B = (uint8_t)(1u << WGM32); /* CTC on OCR3A, stopped */
  TIMSK3 = (uint8_t)(1u << OCIE3A);
}

int32_t quad_pulses_emitted(void) {
  int32_t pulses;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { pulses = quad_pulses_folded + quad_pulses_delta; }
  return pulses;
}

void quad_stop(void) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    TCCR3B = (uint8_t)(1u << WGM32);
    pulse_remaining = 0;
  }
}

void quad_zero(void) {
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    TCCR3B = (uint8_t)(1u << WGM32);
    pulse_remaining = 0;
    quad_pulses_delta = 0;
    quad_encoder_delta = 0;
    quad_pulses_folded = 0;
    quad_encoder_folded = 0;
    encoder_state = encoder_read();
  }
}

uint8_t quad_plan_to(int32_t target, int32_t max_edges, uint32_t period_cycles,
                     uint32_t min_interval_cycles) {
  static const uint8_t kClockSelect[5] = {1u, 2u, 3u, 4u, 5u}; /* /1 /8 /64 /256 /1024 */
  static const uint8_t kShift[5] = {0u, 3u, 6u, 8u, 10u};
  int32_t edges;
  uint32_t magnitude;
  uint32_t interval;
  uint8_t limited = 0;
  uint8_t i;
  /* Stop first, then count: no edge of the old plan can slip in between the count and the new
   * plan (the generator pauses for the ~0.1 ms of this function). */
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    TCCR3B = (uint8_t)(1u << WGM32);
    pulse_remaining = 0;
    edges = target - (quad_pulses_folded + quad_pulses_delta);
  }
  if (max_edges > (int32_t)QUAD_MAX_EDGES_PER_PLAN) max_edges = (int32_t)QUAD_MAX_EDGES_PER_PLAN;
  if (edges > max_edges) {
    edges = max_edges;
    limited = 1;
  } else if (edges < -max_edges) {
    edges = -max_edges;
    limited = 1;
  }
  if (edges == 0) return limited;
  magnitude = (uint32_t)(edges < 0 ? -edges : edges);
  /* n edges evenly in the period, the last one at n/(n+1) of it: well before the next update
   * (an edge due exactly at the update would be re-planned there, again and again), and never
   * faster than the rate cap. */
  interval = period_cycles / (magnitude + 1u);
  if (interval < min_interval_cycles) interval = min_interval_cycles;
  if (interval < 1u) interval = 1u;
  for (i = 0; i < 4u && (interval >> kShift[i]) > 65536u; ++i) {
  }
  interval >>= kShift[i];
  if (interval < 1u) interval = 1u;
  if (interval > 65536u) interval = 65536u;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
    pulse_remaining = (uint16_t)magnitude;
    pulse_direction = (int8_t)(edges > 0 ? 1 : -1);
    OCR3A = (uint16_t)(interval - 1u);
    TCNT3 = 0;
    TIFR3 = (uint8_t)(1u << OCF3A);
    TCCR3B = (uint8_t)((1u << WGM32) | kClockSelect[i]);
  }
  return limited;
}
