#include <string.h>
#include "calib.h"
#include "../../core/pgm.h"

/* cheali-charger targets/imaxB6-original/defaultCalibration.cpp, its two points per input turned into
 * a zero and a full scale (docs/firmware.md's table). */
static const cal_pair_t nominal[CAL_INPUTS] PROGMEM = {
    {0, 29902}, {0, 30826}, {26, 1646}, {233, 6042}, {0, 19154},
    {0, 5022}, {0, 4985}, {0, 9761}, {0, 4899}, {0, 5016}, {0, 4993}, {0, 4924}, {0, 25395},
};

static cal_pair_t pairs[CAL_INPUTS];

static uint8_t check_of(const uint8_t *block)
{
    uint8_t k, x = 0;
    for (k = 0; k < CAL_BLOCK - 1; k++)
        x ^= block[k];
    return x;
}

uint8_t cal_block_valid(const uint8_t *block)
{
    uint8_t k;
    if (block[0] != CAL_VERSION || check_of(block) != block[CAL_BLOCK - 1])
        return 0;
    for (k = 0; k < CAL_INPUTS; k++)
        if (block[1 + 4 * k + 2] == 0 && block[1 + 4 * k + 3] == 0)
            return 0;
    return 1;
}

uint8_t cal_use(const uint8_t *block)
{
    uint8_t k;
    if (!cal_block_valid(block)) {
        memcpy_P(pairs, nominal, sizeof pairs);
        return 0;
    }
    for (k = 0; k < CAL_INPUTS; k++) {
        const uint8_t *p = block + 1 + 4 * k;
        pairs[k].zero = (uint16_t)(p[0] | (p[1] << 8));
        pairs[k].full = (uint16_t)(p[2] | (p[3] << 8));
    }
    return 1;
}

void cal_block(uint8_t *block)
{
    uint8_t k;
    block[0] = CAL_VERSION;
    for (k = 0; k < CAL_INPUTS; k++) {
        uint8_t *p = block + 1 + 4 * k;
        p[0] = (uint8_t)pairs[k].zero;
        p[1] = (uint8_t)(pairs[k].zero >> 8);
        p[2] = (uint8_t)pairs[k].full;
        p[3] = (uint8_t)(pairs[k].full >> 8);
    }
    block[CAL_BLOCK - 1] = check_of(block);
}

int32_t cal_value(uint8_t input, uint16_t adc16)
{
    int32_t d = (int32_t)adc16 - pairs[input].zero;
    /* rounded to the nearest unit: a reading below the zero is a small negative value */
    return (d * (int32_t)pairs[input].full + (d < 0 ? -32768L : 32768L)) / 65536L;
}

uint16_t cal_adc16(uint8_t input, int32_t value)
{
    /* value * 65536 / full in 32 bits (no 64-bit arithmetic on the AVR): whole scales, then the rest */
    uint32_t v = value < 0 ? 0 : (uint32_t)value, full = pairs[input].full;
    uint32_t a = pairs[input].zero + (v / full) * 65536UL + ((v % full) * 65536UL + full / 2) / full;
    return (uint16_t)(a > 65535UL ? 65535U : a);
}
