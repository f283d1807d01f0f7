/* Pin map and clock of the rig board (Arduino Mega 2560, ATmega2560 at 16 MHz).
 * docs/hardware.md shows the wiring to the servo drive's X5 terminal.
 *
 *   encoder A (drive AO via AM26LS32)  Mega pin 2  = PE4 / INT4, any edge
 *   encoder B (drive BO via AM26LS32)  Mega pin 3  = PE5 / INT5, any edge
 *   pulse A   (drive PF via AM26LS31)  Mega pin 22 = PA0
 *   pulse B   (drive PR via AM26LS31)  Mega pin 23 = PA1
 *   servo on  (drive SVON via NPN)     Mega pin 24 = PA2 (high = servo on)
 *   TWI SDA / SCL (ITG-3205, MCP4725)  Mega pins 20 / 21 = PD1 / PD0
 *   UART0 RX / TX (USB bridge)         Mega pins 0 / 1
 *
 * Quadrature convention (encoder input and pulse output alike): the state is (A, B); forward
 * is 00 -> 10 -> 11 -> 01 -> 00 (A leads B), one count per edge (x4). */
#ifndef CLEARSHAPE_FW_BOARD_H
#define CLEARSHAPE_FW_BOARD_H

#define BOARD_ENCODER_A_BIT 4 /* PINE */
#define BOARD_ENCODER_B_BIT 5 /* PINE */
#define BOARD_PULSE_A_BIT 0   /* PORTA */
#define BOARD_PULSE_B_BIT 1   /* PORTA */
#define BOARD_SERVO_BIT 2     /* PORTA */

#define FW_MAJOR 0u
#define FW_MINOR 1u
#define FW_PATCH 0u
#define FW_ENCODER_LINES_HINT 3000u

#endif
