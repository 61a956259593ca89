/* The device: the protocol of docs/protocol.md over hal_uart, the macro store, and the runs of the
 * interpreter at the board's tick. A board's main() calls app_init once and app_poll forever. */
#ifndef ZUML_APP_H
#define ZUML_APP_H

#include <stdint.h>
#include "zuml.h"

typedef struct {
    const char *model;             /* both in flash on the AVR (PROGMEM) */
    const char *firmware;
    uint32_t max_charge_ma;
    uint16_t max_charge_dw;
    uint32_t max_discharge_ma;
    uint16_t max_discharge_dw;
    uint32_t max_mv;
    uint32_t write_us_per_byte;
    zc_board_t core;
} app_board_t;

void app_init(const app_board_t *board);
void app_poll(void);

#endif
