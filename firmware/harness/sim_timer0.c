#include <string.h>
#include <avr_timer.h>
#include "sim_timer0.h"

#define R_TCCR0 0x53                    /* in data space */
#define WGM00_BIT 6
#define WGM01_BIT 3

void sim_timer0_modes(avr_t *avr)
{
    avr_io_t *io;
    for (io = avr->io_port; io; io = io->next) {
        avr_timer_t *t = (avr_timer_t *)io;
        if (strcmp(io->kind, "timer") || t->name != '0' || t->wgm[0].reg)
            continue;
        t->wgm[0] = (avr_regbit_t)AVR_IO_REGBIT(R_TCCR0, WGM00_BIT);
        t->wgm[1] = (avr_regbit_t)AVR_IO_REGBIT(R_TCCR0, WGM01_BIT);
        t->wgm_op[2] = (avr_timer_wgm_t)AVR_TIMER_WGM_CTC();
        t->wgm_op[3] = (avr_timer_wgm_t)AVR_TIMER_WGM_FASTPWM8();
    }
}
