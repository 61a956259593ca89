/* What docs/firmware.md's calibration procedure finds on this simulated board, in the block the imaxb6 image
 * reads (EEPROM 970..1023: version 1, 13 x (zero u16, full u16) little-endian, XOR check byte). The procedure
 * averages a second of readings, so the block holds the board's true lines, not one noisy sample:
 * - voltages against a meter, zero 0: full = the input's true full scale, for Vout+, Vin, Vb1, Vb2 and the
 *   Vb3..Vb6 the pack's cells reach;
 * - the charge and discharge currents from two points on an ammeter: the true zero and full scale;
 * - what the procedure does not reach (Vout-, Vb0, taps above the pack, T extern) keeps the nominal values. */
#include <math.h>
#include <string.h>
#include "b6_calibration.h"

#define BLOCK_AT 970
#define BLOCK_SIZE 54
#define INPUTS 13

/* The block's input order (docs/firmware.md, "Nominal full scales"): index -> the board's input. */
static const b6_input_t *input_at(int index)
{
    return index < 5 ? &b6_adc_channel[index] : &b6_mux_input[index - 5];
}

/* mV, mA or 0.01 degC per unit of the model's V, A or degC */
static double unit(b6_quantity_t q) { return q == B6_Q_TEXTERN ? 100.0 : 1000.0; }

static int reached(const b6_model_t *m, b6_quantity_t q)
{
    switch (q) {
    case B6_Q_VOUT_PLUS: case B6_Q_VIN: case B6_Q_TAP1: case B6_Q_I_SMPS: case B6_Q_I_DISCHARGE:
        return 1;
    case B6_Q_TAP2:
        return m->cells >= 2;
    case B6_Q_CELL3: case B6_Q_CELL4: case B6_Q_CELL5: case B6_Q_CELL6:
        return m->cells >= 3 + (int)(q - B6_Q_CELL3);
    default:
        return 0;
    }
}

static void put16(uint8_t *at, double v)
{
    long n = lround(v < 0 ? 0 : (v > 65535 ? 65535 : v));
    at[0] = (uint8_t)(n & 0xFF);
    at[1] = (uint8_t)(n >> 8);
}

void b6_calibration_write(const b6_model_t *m, uint8_t *eeprom, size_t size)
{
    uint8_t *block = eeprom + BLOCK_AT, check = 0;
    int k;
    if (size < BLOCK_AT + BLOCK_SIZE)
        return;
    block[0] = 1;
    for (k = 0; k < INPUTS; k++) {
        const b6_input_t *in = input_at(k);
        double zero = in->zero_adc16, full = in->full_scale;
        if (reached(m, in->quantity)) {
            /* the true line: ADC16 at 0 and the value 65536 counts above it */
            zero = b6_model_adc16(m, in, 0);
            full = 1.0 / ((b6_model_adc16(m, in, 1.0) - zero) / 65536);
        }
        put16(block + 1 + 4 * k, zero);
        put16(block + 3 + 4 * k, full * unit(in->quantity));
    }
    for (k = 0; k < BLOCK_SIZE - 1; k++)
        check ^= block[k];
    block[BLOCK_SIZE - 1] = check;
}

int b6_calibration_valid(const uint8_t *eeprom, size_t size)
{
    const uint8_t *block = eeprom + BLOCK_AT;
    uint8_t check = 0;
    int k;
    if (size < BLOCK_AT + BLOCK_SIZE || block[0] != 1)
        return 0;
    for (k = 0; k < BLOCK_SIZE - 1; k++)
        check ^= block[k];
    for (k = 0; k < INPUTS; k++)
        if (!block[3 + 4 * k] && !block[4 + 4 * k])
            return 0;
    return check == block[BLOCK_SIZE - 1];
}

void b6_calibration_erase(uint8_t *eeprom, size_t size)
{
    if (size >= BLOCK_AT + BLOCK_SIZE)
        memset(eeprom + BLOCK_AT, 0xFF, BLOCK_SIZE);
}
