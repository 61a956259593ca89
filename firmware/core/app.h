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

/* For a board's own requests (hal_request) and its front panel. */
void app_tx_begin(uint8_t type, uint8_t seq, uint8_t len);
void app_tx(uint8_t byte);
void app_tx16(uint16_t value);
void app_tx_end(void);
void app_error(uint8_t request_type, uint8_t seq, uint8_t code, const char *message_in_flash);
enum { APP_IDLE, APP_RUNNING, APP_PAUSED, APP_FINISHED };
uint8_t app_state(void);
uint8_t app_running(void);                          /* running or paused */
const zc_run_t *app_run(void);
uint8_t app_end_text(char *out);                    /* the end reason, ZC_TEXT_MAX bytes */
/* Starts slot `number` (0-based) as a charge with the cell count and a current (for INPUT) as its
 * only start values; NULL when it started, else why not (in flash). */
const char *app_start_slot(uint8_t number, uint8_t series, uint16_t current_ma);
void app_stop(void);
/* An LCD line (row 0/1, APP_LCD_COLUMNS characters or fewer, NUL-ended) as an unsolicited LCD frame while
 * no host has spoken since the reset. */
#define APP_LCD_COLUMNS 16
void app_lcd(uint8_t row, const char *text);
/* Ends the run on a board's protection (text in flash): output off, the events and STATUS carry
 * "protection: <text>". */
void app_protect(const char *text);

#endif
