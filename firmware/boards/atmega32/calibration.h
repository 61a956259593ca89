/* ADC and PWM through two-point calibration, as cheali-charger calibrates a B6: each analog input
 * has two points (ADC reading, true value) and is interpolated linearly between them; each output
 * likewise maps a set value to a PWM duty. The points below are nominal for an iMAX B6 class board
 * (resistor dividers and shunts of the common layout); a real board is calibrated against a meter
 * and its points replace these. */
#ifndef ZUML_CALIBRATION_H
#define ZUML_CALIBRATION_H

#include <stdint.h>

typedef struct {
    uint16_t adc[2];      /* ADC readings, 10 bit, oversampled x16 (0..16368) */
    int32_t value[2];     /* the true value at each reading: uV, uA or uC */
} cal_input_t;

typedef struct {
    int32_t value[2];     /* set values: uA */
    uint16_t duty[2];     /* Timer1 duty, 0..PWM_TOP */
} cal_output_t;

enum { IN_VOUT, IN_ICHARGE, IN_IDISCHARGE, IN_T_EXTERN, IN_T_INTERN, IN_COUNT };
enum { OUT_CHARGE, OUT_DISCHARGE, OUT_COUNT };

#define PWM_TOP 1023u

int32_t cal_input(uint8_t input, uint16_t adc);
uint16_t cal_output(uint8_t output, int32_t value);

#endif
