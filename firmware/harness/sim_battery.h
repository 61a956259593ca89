/* The battery both PC-side harnesses put on the firmware's output (the host pty device,
 * harness/pty_main.c, and the ATmega32 on simavr, harness/avr_sim.c): a linear OCV, a
 * series resistance, coulomb counting and a heat sink that warms with |I|. A plain load for
 * protocol and end-to-end tests; the differential test drives the core with the simulator's
 * own battery model instead (zuml_studio/sim/battery.py). Header-only: each harness is one
 * program, and neither is built for the charger. */
#ifndef ZUML_SIM_BATTERY_H
#define ZUML_SIM_BATTERY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIM_R_PER_CELL 0.05
#define SIM_OPTIONS "[--eeprom FILE] [--cells N] [--capacity MAH] [--soc F]"

static double soc = 0.2, capacity_as = 2.0 * 3600, current_a, heatsink_c = 25.0;
static int cells = 3;

static double ocv(void) { return cells * (3.3 + 0.9 * soc); }

/* `current` (A, + charge) flows for dt seconds; returns the pack voltage it makes. */
static double battery_step(double current, double dt)
{
    double k = dt / 60.0 > 1 ? 1 : dt / 60.0;
    current_a = current;
    soc += current * dt / capacity_as;
    soc = soc < 0 ? 0 : (soc > 1 ? 1 : soc);
    heatsink_c += (25.0 + 4.0 * (current < 0 ? -current : current) - heatsink_c) * k;
    return ocv() + current * SIM_R_PER_CELL * cells;
}

/* argv[*k] as one of SIM_OPTIONS: its value read (--eeprom loads the file into `eeprom`, a
 * missing file leaving it erased), *k moved past it, 1; 0 for any other argument. */
static int sim_option(int argc, char **argv, int *k, const char **eeprom_path, uint8_t *eeprom, size_t size)
{
    const char *name = argv[*k];
    if (*k + 1 >= argc)
        return 0;
    if (!strcmp(name, "--eeprom")) {
        FILE *f;
        *eeprom_path = argv[++*k];
        if ((f = fopen(*eeprom_path, "rb")) != NULL) {
            size_t n = fread(eeprom, 1, size, f);
            (void)n;
            fclose(f);
        }
    } else if (!strcmp(name, "--cells")) {
        cells = atoi(argv[++*k]);
    } else if (!strcmp(name, "--capacity")) {
        capacity_as = atof(argv[++*k]) * 3.6;
    } else if (!strcmp(name, "--soc")) {
        soc = atof(argv[++*k]);
    } else {
        return 0;
    }
    return 1;
}

#endif
