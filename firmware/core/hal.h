/* The board under the ZUML core: everything the interpreter needs from the hardware.
 *
 * Units are fixed point and the same on every board: microvolts, microamperes (+ charges the
 * pack, - discharges it), micro-degrees Celsius (the same scale as the voltages, so no reading loses a decision to rounding), milliseconds. A board converts its ADC counts
 * and PWM duties through its own calibration (see boards/atmega32/calibration.c).
 */
#ifndef ZUML_HAL_H
#define ZUML_HAL_H

#include <stdint.h>

/* What the power stage is asked to hold for the next tick. */
enum hal_output_kind {
    HAL_OFF = 0,
    HAL_CURRENT = 1,          /* hold current_ua (signed) */
    HAL_VOLTAGE_CHARGE = 2,   /* hold voltage_uv, charging with at most current_ua */
    HAL_VOLTAGE_DISCHARGE = 3 /* hold voltage_uv, discharging with at most current_ua */
};

typedef struct {
    uint8_t kind;             /* enum hal_output_kind */
    int32_t current_ua;
    int32_t voltage_uv;
} hal_output_t;

void hal_output(const hal_output_t *out);

/* Measurements. Pack voltage and current are the last tick's readings under the output set. */
int32_t hal_pack_uv(void);
int32_t hal_current_ua(void);
/* The pack voltage with the power stage switched off (CHARGE_EX measuring point 0). */
int32_t hal_open_circuit_uv(void);
int32_t hal_battery_uc(void);
int32_t hal_heatsink_uc(void);
uint8_t hal_battery_sensor(void);                 /* 1 when a battery temperature sensor is connected */
uint8_t hal_cell_count(void);                     /* balance-port cells measured, 0 without a balancer */
int32_t hal_cell_uv(uint8_t cell);
/* The balancer's ceiling, which ends a charge phase (checked after the phase's own conditions and -dV,
 * before the defaults): the cell (from 1) at it now, 0 when none is; *ceiling_uv the ceiling. A board
 * whose balancer ends no charge answers 0. */
uint8_t hal_balancer_ceiling(int32_t *ceiling_uv);

/* Closes the interval the readings above average over: called once per tick, just before they are
 * read (a board that has no averages does nothing). */
void hal_measure_latch(void);

/* The board's say at START, after the core accepted the macro (its record, chemistry, cells,
 * capacity as resolved): NULL to start, else why not (text in flash, a line for a display) and the
 * error code *code (protocol.h's E_UNCALIBRATED, E_PROTECTION); the board may write the whole sentence, with
 * its volts, to `sentence` (HAL_SENTENCE_MAX bytes with the NUL; "" as given otherwise): the PC gets it.
 * The board arms its run's protections here. */
#define HAL_SENTENCE_MAX 100
const char *hal_run_start(const uint8_t *rec, uint8_t akk_type, int16_t series, int32_t capacity_mah,
                          uint8_t *code, char *sentence);
/* A board's own request, types 0x30..0x3F (docs/protocol.md): answers it through app_tx_* or
 * app_error (E_UNKNOWN_TYPE for one it lacks); `running`: a macro runs. */
void hal_request(uint8_t type, uint8_t seq, const uint8_t *payload, uint8_t len, uint8_t running);

/* Time. */
uint32_t hal_millis(void);

/* EEPROM holding the macro records (the PC's image layout). */
uint16_t hal_eeprom_size(void);
uint8_t hal_eeprom_read(uint16_t addr);
void hal_eeprom_write(uint16_t addr, uint8_t value);

/* Serial link to the PC. */
int16_t hal_uart_read(void);                      /* next byte, -1 when none is waiting */
void hal_uart_write(uint8_t byte);

/* Signals. */
void hal_buzzer(uint8_t melody);                  /* MUSIC(n): play melody n once */
void hal_led(uint8_t pattern);                    /* LIGHT(n) */

/* The battery passport line (seed 003): send the request (len bytes, 8 when well formed: the battery
 * answers any other length with an error answer), receive 32; 0 when nothing answers. */
uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32]);

#endif
