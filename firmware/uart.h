/* UART0 at 1 Mbaud (U2X, UBRR = 1: exactly 16 MHz / 16), interrupt-driven RX and TX rings. */
#ifndef CLEARSHAPE_FW_UART_H
#define CLEARSHAPE_FW_UART_H
#include <stdint.h>

/* RX: a power of two up to 32768 (16-bit indices, read and written atomically). 1024 bytes hold
 * 73 COMMAND frames, 73 ms of a 1 kHz host's commands; RAM budget in docs/hardware.md. */
#define UART_RX_RING 1024u
#define UART_TX_RING 256u /* 256: the 8-bit indices wrap by themselves */

void uart_init(void);
/* Next received byte in *byte: 1, or 0 when none is waiting. */
uint8_t uart_read(uint8_t* byte);
/* Free bytes in the TX ring. */
uint16_t uart_tx_free(void);
/* Queues `length` bytes; the caller checked uart_tx_free() (returns 0 and queues nothing
 * when they do not fit). */
uint8_t uart_write(const uint8_t* data, uint8_t length);
/* Count of RX bytes lost because the ring was full. */
uint16_t uart_rx_overruns(void);

#endif
