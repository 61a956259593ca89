/* simavr 1.6's ATmega32 Timer0 corrected to the datasheet: both simavr harnesses (the generic ATmega32 and
 * the iMAX B6) run images whose millisecond clock is Timer0 in CTC. */
#ifndef SIM_TIMER0_H
#define SIM_TIMER0_H

#include <sim_avr.h>

/* simavr 1.6 gives the ATmega32's Timer0 no WGM bits (its megax core is shared with the ATmega8, whose Timer0
 * has none): TCCR0's CTC is ignored and the compare matches every 256 counts, so a 1 kHz CTC clock (OCR0 249)
 * ran 2.3 % slow. Gives Timer0 its WGM00/WGM01 bits and modes as the datasheet has them (simavr's own fix
 * after 1.6, commit 8d8e833, issue #538); a simavr that already has them is left alone. Call after avr_init. */
void sim_timer0_modes(avr_t *avr);

#endif
