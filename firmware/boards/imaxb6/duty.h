/* The stage's duty bound that no current reading can lift (docs/firmware.md, *Protections no macro can
 * lift*): the buck/boost duty that would put the pack's ceiling plus a margin on the output at this
 * input voltage. Pure C: the host tests build it. */
#ifndef B6_DUTY_H
#define B6_DUTY_H

#include <stdint.h>

/* The duty in 1/64 of a Timer1 count (stage.c): DUTY_BUCK_FULL is the buck switch on for the whole
 * period; above it the buck is held on and the rest is the boost switch's, at most DUTY_BOOST_MAX. */
#define DUTY_BUCK_FULL 32768U
#define DUTY_BOOST_MAX 16384U      /* 50 % boost (cheali caps it so) */
#define DUTY_MARGIN_MV 1500        /* above the ceiling: the stage's drops at 5 A (switch, inductor, shunt,
                                    * diode ~1 V) with room to hold the ceiling while the pack takes current */

/* The highest charge duty for an input of `vin_mv` and a pack ceiling of `ceiling_mv` (0 when the
 * input reads under 1 V: no duty is known to be safe). */
uint16_t duty_top(int32_t vin_mv, int32_t ceiling_mv);

#endif
