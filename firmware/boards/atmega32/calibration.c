#include <avr/pgmspace.h>
#include "calibration.h"

/* ADC channel of each input on PORTA: see board.c. Nominal points: VOUT through a 1:10 divider
 * (0..25.6 V on a 2.56 V reference), currents through 0.01 Ohm shunts and x10 amplifiers (0..5 A,
 * 0..1 A), temperatures through the NTC curve's linear part (0..100 C). */
static const cal_input_t inputs[IN_COUNT] PROGMEM = {
    {{0, 16368}, {0L, 25600000L}},
    {{0, 16368}, {0L, 5000000L}},
    {{0, 16368}, {0L, 1000000L}},
    {{16368, 0}, {0L, 100000000L}},
    {{16368, 0}, {0L, 100000000L}},
};

static const cal_output_t outputs[OUT_COUNT] PROGMEM = {
    {{0L, 5000000L}, {0, PWM_TOP}},
    {{0L, 1000000L}, {0, PWM_TOP}},
};

static int32_t interpolate(int32_t x, int32_t x0, int32_t x1, int32_t y0, int32_t y1)
{
    if (x1 == x0)
        return y0;
    return y0 + (int32_t)(((int64_t)(x - x0) * (y1 - y0)) / (x1 - x0));
}

int32_t cal_input(uint8_t input, uint16_t adc)
{
    cal_input_t c;
    memcpy_P(&c, &inputs[input], sizeof c);
    return interpolate(adc, c.adc[0], c.adc[1], c.value[0], c.value[1]);
}

uint16_t cal_output(uint8_t output, int32_t value)
{
    cal_output_t c;
    int32_t duty;
    memcpy_P(&c, &outputs[output], sizeof c);
    duty = interpolate(value, c.value[0], c.value[1], c.duty[0], c.duty[1]);
    return (uint16_t)(duty < 0 ? 0 : (duty > (int32_t)PWM_TOP ? PWM_TOP : duty));
}
