/* TWI master at 400 kHz, polled from the main loop (the tick and encoder ISRs stay
 * deterministic; a gyro read holds the main loop about 0.15 ms), with a bounded wait so a
 * hung bus never stalls the board. Devices: ITG-3205 gyroscope and MCP4725 12-bit DAC. */
#ifndef CLEARSHAPE_FW_TWI_H
#define CLEARSHAPE_FW_TWI_H
#include <stdint.h>

#define ITG3205_ADDRESS 0x68u     /* AD0 low */
#define ITG3205_WHO_AM_I 0x00u
#define ITG3205_SMPLRT_DIV 0x15u
#define ITG3205_DLPF_FS 0x16u     /* FS_SEL bits 4:3, DLPF_CFG bits 2:0 */
#define ITG3205_GYRO_ZOUT_H 0x21u /* _L at 0x22; big-endian two's complement */
#define ITG3205_PWR_MGM 0x3Eu
#define MCP4725_ADDRESS 0x60u     /* A0 low */

void twi_init(void);
/* Writes `length` bytes after the register address. 1 = acknowledged, 0 = failed. */
uint8_t twi_write_register(uint8_t address, uint8_t reg, const uint8_t* data, uint8_t length);
/* Burst read starting at `reg` (repeated start). 1 = ok, 0 = failed. */
uint8_t twi_read_registers(uint8_t address, uint8_t reg, uint8_t* data, uint8_t length);
/* MCP4725 fast write (datasheet Fig. 6-1: 0 0 PD1 PD0 D11..D8, D7..D0), normal power. */
uint8_t twi_dac_write(uint16_t code);
/* Address probe: 1 when the device acknowledges its address. */
uint8_t twi_probe(uint8_t address);

#endif
