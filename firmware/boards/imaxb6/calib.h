/* The B6's calibration (docs/firmware.md, *Calibration*): per analog input a zero (the ADC16 reading
 * at 0) and a full scale (the value at zero + 65536), in the EEPROM's last 54 bytes with a check
 * byte; the nominal values (cheali's default calibration) while none is valid. Pure C: the host
 * tests build it too. */
#ifndef B6_CALIB_H
#define B6_CALIB_H

#include <stdint.h>

enum {
    CAL_VOUT, CAL_VOUT_MINUS, CAL_IDIS, CAL_ISMPS, CAL_VIN,
    CAL_VB0, CAL_VB1, CAL_VB2, CAL_VB3, CAL_VB4, CAL_VB5, CAL_VB6, CAL_TEXTERN,
    CAL_INPUTS
};
#define CAL_BLOCK (2 + 4 * CAL_INPUTS)   /* version, the pairs, the check byte: 54 */
#define CAL_VERSION 1

typedef struct {
    uint16_t zero;
    uint16_t full;
} cal_pair_t;

enum { CAL_OK, CAL_BAD_FORM, CAL_OUT_OF_WINDOW };
/* Where a block leaves its window: `input` reads `point` (0 or the board's maximum) as `reads`, more
 * than `allowed` off (all in mV, mA or 0.01 degC). */
typedef struct {
    uint8_t input;
    int32_t point, reads, allowed;
} cal_miss_t;

/* CAL_OK when `block` is a calibration a charger may use: version, check byte, and every input within
 * its window around the nominal calibration (calib.c); CAL_BAD_FORM, or CAL_OUT_OF_WINDOW with `miss`. */
uint8_t cal_block_check(const uint8_t *block, cal_miss_t *miss);
/* 1 when cal_block_check says CAL_OK. */
uint8_t cal_block_valid(const uint8_t *block);
/* Uses `block` when valid, else the nominal calibration; returns 1 when the block was used. */
uint8_t cal_use(const uint8_t *block);
/* The calibration in use as a block (the nominal one, sealed, when none is valid). */
void cal_block(uint8_t *block);
/* With the output off the pack at the output and the sum of its cells at the balance lead are one voltage
 * read through two calibrations: 1 when they agree within CAL_AGREE_PCT % + CAL_AGREE_MV. */
#define CAL_AGREE_PCT 2
#define CAL_AGREE_MV 50
uint8_t cal_pack_agrees(int32_t pack_mv, int32_t cells_mv);
/* The value (mV, mA, 0.01 degC) of an ADC16 reading, and the ADC16 reading of a value. */
int32_t cal_value(uint8_t input, uint16_t adc16);
uint16_t cal_adc16(uint8_t input, int32_t value);

#endif
