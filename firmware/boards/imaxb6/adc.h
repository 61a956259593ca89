/* The B6's ADC: every input in a fixed round from the ADC interrupt (AREF, the multiplexer into
 * ADC6), each reading checked by the protections and, for the fast inputs, a step of the regulator;
 * and each input's average over an interval the main loop closes. */
#ifndef B6_ADC_H
#define B6_ADC_H

#include <stdint.h>
#include "calib.h"

void adc_init(void);
/* Closes the averaging interval: adc_average() then gives the interval's averages. */
void adc_latch(void);
uint16_t adc_average(uint8_t input);      /* ADC16 */
int32_t adc_value(uint8_t input);         /* the average through the calibration */
/* Counts up with every ADC reading: the main loop's proof that the interrupt runs. */
extern volatile uint8_t adc_heartbeat;
/* Set by the main loop each pass, cleared by the interrupt: 50 ms without it switches the stage off. */
extern volatile uint8_t adc_main_alive;

#endif
