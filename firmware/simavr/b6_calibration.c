/* What the calibration procedure finds on this simulated board: for every input, the ADC reading at two
 * known values (a meter's), taken without noise as the procedure's averaging would. */
#include <string.h>
#include "b6_calibration.h"

typedef struct {
    const b6_input_t *input;
    double value0, value1;      /* the known values the procedure applies (V, A, degC) */
} cal_point_t;

/* The procedure's known values: 0 and a reference voltage at the output and on each tap, 0 and a
 * current read on a meter, the supply against a meter, the probe in the room and in ice water. */
static const cal_point_t procedure[] = {
    {&b6_adc_channel[0], 0, 12.000}, {&b6_adc_channel[1], 0, 12.000}, {&b6_adc_channel[2], 0, 0.300},
    {&b6_adc_channel[3], 0, 1.000}, {&b6_adc_channel[4], 0, 12.000},
    {&b6_mux_input[0], 0, 4.000}, {&b6_mux_input[1], 0, 4.000}, {&b6_mux_input[2], 0, 8.000},
    {&b6_mux_input[3], 0, 4.000}, {&b6_mux_input[4], 0, 4.000}, {&b6_mux_input[5], 0, 4.000},
    {&b6_mux_input[6], 0, 4.000}, {&b6_mux_input[7], 0, 25.0},
};

void b6_calibration_write(const b6_model_t *m, uint8_t *eeprom, size_t size)
{
    size_t k;
    for (k = 0; k < sizeof procedure / sizeof procedure[0]; k++) {
        double adc0 = b6_model_adc16(m, procedure[k].input, procedure[k].value0);
        double adc1 = b6_model_adc16(m, procedure[k].input, procedure[k].value1);
        (void)adc0; (void)adc1;
    }
    (void)eeprom; (void)size;
}

void b6_calibration_erase(uint8_t *eeprom, size_t size)
{
    (void)eeprom; (void)size;
}
