/* Quadrature I/O: the x4 decoder of the drive's encoder output (INT4/INT5, any edge, state
 * table with an illegal-transition counter) and the A/B pulse generator of position mode
 * (Timer3 CTC, one edge per compare match, stops exactly on its goal). */
#ifndef CLEARSHAPE_FW_QUADRATURE_H
#define CLEARSHAPE_FW_QUADRATURE_H
#include <stdint.h>

/* The edge ISRs count into 16-bit deltas (short ISRs); quad_fold_counts(), called from the
 * tick ISR, folds them into the 32-bit counts (at most 32767 edges per tick of either kind). */
extern volatile int16_t quad_encoder_delta;
extern volatile uint16_t quad_illegal_transitions;
extern volatile int16_t quad_pulses_delta;

/* Largest plan: edges per update period (the pulse ISR counts down a 16-bit register). */
#define QUAD_MAX_EDGES_PER_PLAN 65535u

extern volatile int32_t quad_encoder_folded;
extern volatile int32_t quad_pulses_folded;

/* Interrupts off (the tick ISR): folds the deltas into the 32-bit counts. */
static inline __attribute__((always_inline)) void quad_fold_counts(void) {
  quad_encoder_folded += quad_encoder_delta;
  quad_encoder_delta = 0;
  quad_pulses_folded += quad_pulses_delta;
  quad_pulses_delta = 0;
}
/* Pulses emitted so far (any context). */
int32_t quad_pulses_emitted(void);

void quad_init(void);
/* Zeroes the encoder count, the pulse count and stops the generator. */
void quad_zero(void);
/* Plans the pulse train towards the absolute `target`: the edges still missing, at most
 * `max_edges` (then returns 1: limited), spread evenly over `period_cycles` CPU cycles from
 * now, at least `min_interval_cycles` apart (the rate cap). Whatever the previous plan had not emitted is re-planned, so no edge is ever lost and
 * the count ends exactly on the target. */
uint8_t quad_plan_to(int32_t target, int32_t max_edges, uint32_t period_cycles,
                     uint32_t min_interval_cycles);
/* Stops the generator at the current count. */
void quad_stop(void);

#endif
