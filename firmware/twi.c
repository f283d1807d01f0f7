/* TWI master (ATmega2560 datasheet §24.7, status codes Table 24-3 and 24-4). Each bus step
 * is started from the main loop; the TWI interrupt only latches the status and masks itself,
 * and the main loop waits for that flag. (Waiting on TWINT itself would also work on silicon,
 * but a set-by-software TWINT bit reads back as set in simavr; the flag works on both.) */
#include "twi.h"

#include <avr/interrupt.h>
#include <avr/io.h>

#define TWI_WAIT_LIMIT 4000u /* polls; one byte at 400 kHz is ~23 µs = ~370 cycles */

static volatile uint8_t twi_done;
static volatile uint8_t twi_sr;

ISR(TWI_vect) {
  twi_sr = (uint8_t)(TWSR & 0xF8u);
  twi_done = 1;
  TWCR = (uint8_t)(1u << TWEN); /* TWIE off; TWINT written 0 leaves the bus waiting */
}

/* Starts one bus step: TWINT written 1 (clears it), the given control bits, TWIE on. */
static void twi_go(uint8_t control) {
  twi_done = 0;
  TWCR = (uint8_t)((1u << TWINT) | (1u << TWEN) | (1u << TWIE) | control);
}

void twi_init(void) {
  TWSR = 0;   /* prescaler 1 */
  TWBR = 12u; /* SCL = F_CPU / (16 + 2 TWBR) = 400 kHz (datasheet §24.5.2) */
  TWCR = (uint8_t)(1u << TWEN);
}

static uint8_t twi_wait(void) {
  uint16_t n = 0;
  while (!twi_done) {
    if (++n >= TWI_WAIT_LIMIT) return 0;
  }
  return 1;
}

static uint8_t twi_status(void) { return twi_sr; }

static uint8_t twi_start(uint8_t address_rw) {
  twi_go((uint8_t)(1u << TWSTA));
  if (!twi_wait()) return 0;
  if (twi_status() != 0x08u && twi_status() != 0x10u) return 0; /* START, REPEATED START */
  TWDR = address_rw;
  twi_go(0);
  if (!twi_wait()) return 0;
  if (address_rw & 1u) return (uint8_t)(twi_status() == 0x40u); /* SLA+R ACK */
  /* SLA+W ACK is 0x18; simavr 1.6 reports it as 0x28 (data ACK), which silicon never gives
   * after an address, so accepting both costs nothing on the board. */
  return (uint8_t)(twi_status() == 0x18u || twi_status() == 0x28u);
}

static uint8_t twi_send(uint8_t byte) {
  TWDR = byte;
  twi_go(0);
  if (!twi_wait()) return 0;
  return (uint8_t)(twi_status() == 0x28u); /* data ACK */
}

static void twi_stop(void) {
  TWCR = (uint8_t)((1u << TWINT) | (1u << TWSTO) | (1u << TWEN));
}

uint8_t twi_write_register(uint8_t address, uint8_t reg, const uint8_t* data, uint8_t length) {
  uint8_t ok = twi_start((uint8_t)(address << 1)) && twi_send(reg);
  uint8_t i;
  for (i = 0; ok && i < length; ++i) ok = twi_send(data[i]);
  twi_stop();
  return ok;
}

uint8_t twi_read_registers(uint8_t address, uint8_t reg, uint8_t* data, uint8_t length) {
  uint8_t i;
  uint8_t ok = twi_start((uint8_t)(address << 1)) && twi_send(reg) &&
               twi_start((uint8_t)((address << 1) | 1u));
  for (i = 0; ok && i < length; ++i) {
    const uint8_t last = (uint8_t)(i + 1u == length);
    twi_go(last ? 0u : (uint8_t)(1u << TWEA));
    ok = twi_wait() && twi_status() == (last ? 0x58u : 0x50u);
    data[i] = TWDR;
  }
  twi_stop();
  return ok;
}

uint8_t twi_dac_write(uint16_t code) {
  uint8_t ok = twi_start((uint8_t)(MCP4725_ADDRESS << 1)) &&
               twi_send((uint8_t)((code >> 8) & 0x0Fu)) && twi_send((uint8_t)(code & 0xFFu));
  twi_stop();
  return ok;
}

uint8_t twi_probe(uint8_t address) {
  const uint8_t ok = twi_start((uint8_t)(address << 1));
  twi_stop();
  return ok;
}
