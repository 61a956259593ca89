#include <stdlib.h>
#include <string.h>
#include "calib.h"
#include "../../core/pgm.h"

/* cheali-charger targets/imaxB6-original/defaultCalibration.cpp, its two points per input turned into
 * a zero and a full scale (docs/firmware.md's table). */
static const cal_pair_t nominal[CAL_INPUTS] PROGMEM = {
    {0, 29902}, {0, 30826}, {26, 1646}, {233, 6042}, {0, 19154},
    {0, 5022}, {0, 4985}, {0, 9761}, {0, 4899}, {0, 5016}, {0, 4993}, {0, 4924}, {0, 25395},
};

/* The window a calibration must fall in (docs/firmware.md, *Calibration*): per input a point of the
 * board's range (its maximum: 27 V out, 5 A charge, 1 A discharge, 18 V in, 4.35 V a cell, 100 degC) and
 * how far a board may read it from the nominal calibration: voltages 3 % (two 1 % divider resistors
 * and a 1 % reference), currents 8 % (shunt, amplifier gain resistors, reference: 4 %, twice; and no
 * more, or a 5 A set point read 8 % low would put more than 5.5 A into the pack), the probe 5 %. The
 * value at the nominal zero must lie within a quarter of that (the amplifiers' offset). */
typedef struct {
    uint16_t point;
    uint8_t pct;
} window_t;
static const window_t window[CAL_INPUTS] PROGMEM = {
    {27000, 3}, {27000, 3}, {1000, 8}, {5000, 8}, {18000, 3},
    {4350, 3}, {4350, 3}, {8700, 3}, {4350, 3}, {4350, 3}, {4350, 3}, {4350, 3}, {10000, 5},
};

static cal_pair_t pairs[CAL_INPUTS];

/* The value `p` gives at ADC16 `a`, rounded half away from zero (unsigned: no overflow for any pair). */
static int32_t value_of(const cal_pair_t *p, uint16_t a)
{
    uint32_t d = a >= p->zero ? (uint32_t)(a - p->zero) : (uint32_t)(p->zero - a);
    int32_t v = (int32_t)((d * p->full + 32768UL) >> 16);
    return a >= p->zero ? v : -v;
}

static uint8_t check_of(const uint8_t *block)
{
    uint8_t k, x = 0;
    for (k = 0; k < CAL_BLOCK - 1; k++)
        x ^= block[k];
    return x;
}

static void pair_of(const uint8_t *block, uint8_t k, cal_pair_t *p)
{
    const uint8_t *b = block + 1 + 4 * k;
    p->zero = (uint16_t)(b[0] | (b[1] << 8));
    p->full = (uint16_t)(b[2] | (b[3] << 8));
}

uint8_t cal_block_check(const uint8_t *block, cal_miss_t *miss)
{
    uint8_t k;
    if (block[0] != CAL_VERSION || check_of(block) != block[CAL_BLOCK - 1])
        return CAL_BAD_FORM;
    for (k = 0; k < CAL_INPUTS; k++) {
        cal_pair_t p, n;
        window_t w;
        uint32_t allowed;       /* x 100 */
        int32_t at_point, at_zero, point;
        pair_of(block, k, &p);
        if (p.full == 0)
            return CAL_BAD_FORM;
        memcpy_P(&n, &nominal[k], sizeof n);
        memcpy_P(&w, &window[k], sizeof w);
        point = w.point;
        allowed = (uint32_t)w.point * w.pct;
        /* what the block reads where the nominal calibration reads the point, and where it reads 0 */
        at_point = value_of(&p, (uint16_t)(n.zero + ((uint32_t)w.point * 65536UL + n.full / 2) / n.full));
        at_zero = value_of(&p, n.zero);
        miss->input = k;
        miss->allowed = (int32_t)(allowed / 100);
        if ((uint32_t)labs(at_point - point) * 100UL > allowed) {
            miss->point = point;
            miss->reads = at_point;
            return CAL_OUT_OF_WINDOW;
        }
        if ((uint32_t)labs(at_zero) * 400UL > allowed) {
            miss->point = 0;
            miss->reads = at_zero;
            miss->allowed = (int32_t)(allowed / 400);
            return CAL_OUT_OF_WINDOW;
        }
    }
    return CAL_OK;
}

uint8_t cal_block_valid(const uint8_t *block)
{
    cal_miss_t miss;
    return cal_block_check(block, &miss) == CAL_OK;
}

uint8_t cal_pack_agrees(int32_t pack_mv, int32_t cells_mv)
{
    /* two truthful calibrations agree within the ADC's steps (29 mV at Vout+, 5 mV a tap) and the
     * nominal scale of a tap the procedure did not reach (within 3 %, on part of the pack) */
    return labs(pack_mv - cells_mv) * 100L <= pack_mv * CAL_AGREE_PCT + CAL_AGREE_MV * 100L;
}

uint8_t cal_use(const uint8_t *block)
{
    uint8_t k;
    if (!cal_block_valid(block)) {
        memcpy_P(pairs, nominal, sizeof pairs);
        return 0;
    }
    for (k = 0; k < CAL_INPUTS; k++)
        pair_of(block, k, &pairs[k]);
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
    /* a reading below the zero is a small negative value */
    return value_of(&pairs[input], adc16);
}

uint16_t cal_adc16(uint8_t input, int32_t value)
{
    /* value * 65536 / full in 32 bits (no 64-bit arithmetic on the AVR): whole scales, then the rest */
    uint32_t v = value < 0 ? 0 : (uint32_t)value, full = pairs[input].full;
    uint32_t a = pairs[input].zero + (v / full) * 65536UL + ((v % full) * 65536UL + full / 2) / full;
    return (uint16_t)(a > 65535UL ? 65535U : a);
}
