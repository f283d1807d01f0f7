/* UART0 rings (see uart.h). ISRs touch only the ring indices they own. The RX indices are 16
 * bits wide: the main loop reads rx_head and writes rx_tail with interrupts off, so the ISR never
 * sees half of an update (and the main loop never half of the ISR's). */
#include "uart.h"

#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

typedef char uart_rx_ring_is_a_power_of_two_up_to_32768
    [((UART_RX_RING & (UART_RX_RING - 1u)) == 0u && UART_RX_RING <= 32768u) ? 1 : -1];

static volatile uint8_t rx_ring[UART_RX_RING];
static volatile uint16_t rx_head; /* written by the ISR */
static volatile uint16_t rx_tail; /* written by the main loop */
static volatile uint16_t rx_overruns;
static volatile uint8_t tx_ring[UART_TX_RING];
static volatile uint8_t tx_head; /* written by the main loop (UART_TX_RING = 256: wraps as u8) */
static volatile uint8_t tx_tail; /* written by the ISR */

void uart_init(void) {
  UCSR0A = (uint8_t)(1u << U2X0);
  UBRR0 = 1u; /* ATmega2560 datasheet Table 22-1: f = F_CPU / (8 (UBRR + 1)) with U2X = 1 MHz */
  UCSR0C = (uint8_t)((1u << UCSZ01) | (1u << UCSZ00)); /* 8N1 */
  UCSR0B = (uint8_t)((1u << RXEN0) | (1u << TXEN0) | (1u << RXCIE0));
}

ISR(USART0_RX_vect) {
  const uint8_t byte = UDR0;
  const uint16_t next = (uint16_t)((rx_head + 1u) & (UART_RX_RING - 1u));
  if (next == rx_tail) {
    ++rx_overruns;
    return;
  }
  rx_ring[rx_head] = byte;
  rx_head = next;
}

ISR(USART0_UDRE_vect) {
  if (tx_tail == tx_head) {
    UCSR0B &= (uint8_t)~(1u << UDRIE0);
    return;
  }
  UDR0 = tx_ring[tx_tail];
  tx_tail = (uint8_t)(tx_tail + 1u);
}

uint8_t uart_read(uint8_t* byte) {
  const uint16_t tail = rx_tail; /* only this function writes it */
  uint16_t head;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { head = rx_head; }
  if (tail == head) return 0;
  *byte = rx_ring[tail];
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { rx_tail = (uint16_t)((tail + 1u) & (UART_RX_RING - 1u)); }
  return 1;
}

uint16_t uart_tx_free(void) {
  /* One slot stays empty to tell full from empty. */
  return (uint16_t)(UART_TX_RING - 1u - (uint8_t)(tx_head - tx_tail));
}

uint8_t uart_write(const uint8_t* data, uint8_t length) {
  uint8_t i;
  if (uart_tx_free() < length) return 0;
  for (i = 0; i < length; ++i) {
    tx_ring[tx_head] = data[i];
    tx_head = (uint8_t)(tx_head + 1u);
  }
  UCSR0B |= (uint8_t)(1u << UDRIE0);
  return 1;
}

uint16_t uart_rx_overruns(void) {
  uint16_t n;
  ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { n = rx_overruns; }
  return n;
}
