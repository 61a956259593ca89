#include <avr/io.h>
#include <string.h>
#include "../../core/app.h"
#include "../../core/pgm.h"
#include "../../core/store.h"
#include "../../core/text.h"
#include "../common/avr_uart.h"
#include "lcd.h"
#include "panel.h"
#include "pins.h"
#include "protect.h"
#include "calib.h"

#define KEY_MS 10
#define STABLE 3                 /* samples: 30 ms of a steady level is a press or a release */
#define START_HOLD_MS 500        /* START held this long starts a run: a brush does not */
#define SHOW_MS 250
#define SCROLL_MS 500
#define LCD_FRAME_MS 2000        /* both lines go out again this often: a listener that joins late */

static uint8_t keys, raw_last, steady, sel;
static uint32_t key_ms, show_ms, start_down_ms;
static const char *message;      /* a refusal (in flash) shown on line 2 until a key */
static uint8_t dismissed;        /* the finished run's screen was left with a key */
static uint8_t setting;          /* the current for an INPUT macro is being set */
static uint16_t current_ma = 1000;
#define CURRENT_STEP_MA 100
static char shown[2][LCD_COLUMNS + 1];

/* Pressed keys, debounced (pressed = low, external pull-ups); returns the keys pressed just now. */
static uint8_t scan(uint32_t now)
{
    uint8_t raw = (uint8_t)(~PINB & B6_KEYS), was = keys;
    if (now - key_ms < KEY_MS)
        return 0;
    key_ms = now;
    if (raw != raw_last) {
        raw_last = raw;
        steady = 0;
        return 0;
    }
    if (steady < STABLE && ++steady == STABLE)
        keys = raw;
    return (uint8_t)(keys & ~was);
}

/* The record in slot `n` begins at its offset in the store; 0xFFFF when there is no such slot. */
static uint16_t slot_at(uint8_t n)
{
    uint16_t at = 0, size = store_size();
    uint8_t len;
    for (;;) {
        len = store_read(at);
        if (len < 10 || len == 0xFF || at + len > size)
            return 0xFFFF;
        if (!n--)
            return at;
        at = (uint16_t)(at + len);
    }
}

static char *put_text(char *p, const char *s, uint8_t max)
{
    while (max-- && *s)
        *p++ = *s++;
    return p;
}

static char *put_uint(char *p, uint32_t v, uint8_t digits)
{
    /* right-aligned in `digits` columns (leading spaces), or more when the number needs them */
    char buf[10];
    uint8_t n = 0;
    do {
        buf[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (digits > n) {
        *p++ = ' ';
        digits--;
    }
    while (n)
        *p++ = buf[--n];
    return p;
}

/* milli-units as "12.345" (decimals 3) or "1.23" (2), the whole part right-aligned */
static char *put_milli(char *p, int32_t milli, uint8_t whole_digits, uint8_t decimals)
{
    uint32_t v = (uint32_t)(milli < 0 ? -milli : milli), frac = v % 1000;
    uint8_t k;
    p = put_uint(p, v / 1000, whole_digits);
    *p++ = '.';
    if (decimals == 2)
        frac /= 10;
    for (k = decimals; k--;) {
        p[k] = (char)('0' + frac % 10);
        frac /= 10;
    }
    return p + decimals;
}

static void show(uint8_t row, const char *text)
{
    if (strncmp(shown[row], text, LCD_COLUMNS) != 0) {
        strncpy(shown[row], text, LCD_COLUMNS);
        lcd_line(row, text);
        app_lcd(row, shown[row]);
    }
}

/* `text` on a row, scrolled when longer than the LCD. */
static void show_long(uint8_t row, const char *text, uint32_t now)
{
    uint8_t n = (uint8_t)strlen(text), at = 0;
    if (n > LCD_COLUMNS)
        at = (uint8_t)((now / SCROLL_MS) % (n - LCD_COLUMNS + 1));
    show(row, text + at);
}

static void idle_screen(uint32_t now, uint8_t calibrated)
{
    char line[ZC_TEXT_MAX], *p = line;
    uint16_t at = slot_at(sel);
    if (at == 0xFFFF) {
        sel = 0;
        at = slot_at(0);
    }
    if (at == 0xFFFF) {
        strcpy_P(line, PSTR("no macros"));
    } else {
        uint8_t k;
        p = put_uint(p, sel + 1u, 0);
        *p++ = ' ';
        for (k = 0; k < 16 && store_read((uint16_t)(at + 4 + k)); k++)
            *p++ = (char)store_read((uint16_t)(at + 4 + k));
        *p = 0;
    }
    show(0, line);
    if (setting) {
        p = put_text(line, "charge at ", 10);
        p = put_milli(p, current_ma, 1, 2);
        *p++ = 'A';
        *p = 0;
    } else if (message) {
        strcpy_P(line, message);
    } else if (!calibrated) {
        strcpy_P(line, protect_text(TRIP_UNCALIBRATED));
    } else {
        p = line;
        p = put_text(p, "ready Vin ", 10);
        p = put_milli(p, protect_latest[CAL_VIN], 2, 2);
        *p++ = 'V';
        *p = 0;
        if (avr_uart_receiving())        /* PD0 is the PC's receive line (docs/firmware.md, Line) */
            strcpy_P(p, PSTR(" cell 4 not balanced"));
    }
    show_long(1, line, now);
}

static void run_screen(void)
{
    const zc_run_t *r = app_run();
    char line[LCD_COLUMNS + 8], *p = line;
    int32_t ma = hal_current_ua() / 1000;    /* the battery's (in boost not the inductor's), as counted */
    *p++ = r->paused ? 'P' : (r->phase_section ? 'C' : 'D');
    *p++ = (char)('0' + r->phase_index % 10);
    *p++ = ' ';
    p = put_milli(p, protect_latest[CAL_VOUT], 2, 3);
    *p++ = 'V';
    p = put_milli(p, ma, 2, 2);
    *p++ = 'A';
    *p = 0;
    show(0, line);
    p = put_uint(line, (r->phase_section ? r->total_in.uah : r->total_out.uah) / 1000, 5);
    p = put_text(p, "mAh ", 4);
    if (protect_limits.probe)
        p = put_uint(p, (uint32_t)(protect_latest[CAL_TEXTERN] > 0 ? protect_latest[CAL_TEXTERN] : 0) / 100, 2);
    else
        p = put_text(p, "--", 2);
    p = put_text(p, "C ", 2);
    p = put_uint(p, r->time_ms / 60000UL, 2);
    *p++ = 'm';
    *p = 0;
    show(1, line);
}

static void end_screen(uint32_t now)
{
    char line[ZC_TEXT_MAX];
    const char *name = (const char *)app_run()->rec + 4;
    char *p = put_text(line, "end ", 4);
    p = put_text(p, name, 12);
    *p = 0;
    show(0, line);
    app_end_text(line);
    /* a protection's text alone: the LCD has no room for the prefix */
    show_long(1, strncmp_P(line, PSTR("protection: "), 12) ? line : line + 12, now);
}

void panel_say(const char *text) { message = text; }

void panel_poll(uint32_t now, uint8_t calibrated)
{
    uint8_t pressed = scan(now), state = app_state();
    if (pressed)
        message = 0;
    if (state == APP_RUNNING || state == APP_PAUSED) {
        dismissed = 0;
        if (pressed & _BV(B6_KEY_STOP))
            app_stop();
    } else if (state == APP_FINISHED && !dismissed) {
        if (pressed)
            dismissed = 1;
    } else {
        /* idle: INC/DEC pick the slot; START shows the current (INC/DEC set it, STOP goes back); START
         * held starts the slot */
        if (setting) {
            if ((pressed & _BV(B6_KEY_INC)) && current_ma < B6_CHARGE_MA)
                current_ma += CURRENT_STEP_MA;
            if ((pressed & _BV(B6_KEY_DEC)) && current_ma > CURRENT_STEP_MA)
                current_ma -= CURRENT_STEP_MA;
            if (pressed & _BV(B6_KEY_STOP))
                setting = 0;
        } else {
            if (pressed & _BV(B6_KEY_INC))
                sel++;
            if ((pressed & _BV(B6_KEY_DEC)) && sel)
                sel--;
        }
        if (pressed & _BV(B6_KEY_START)) {
            start_down_ms = now;
            setting = 1;
        }
        if ((keys & _BV(B6_KEY_START)) && start_down_ms && now - start_down_ms >= START_HOLD_MS) {
            start_down_ms = 0;
            setting = 0;
            message = app_start_slot(sel, protect_balance_cells(), current_ma);
        }
        if (!(keys & _BV(B6_KEY_START)))
            start_down_ms = 0;
    }
    if (now - show_ms < SHOW_MS && !pressed)
        return;
    if (now / LCD_FRAME_MS != show_ms / LCD_FRAME_MS) {
        app_lcd(0, shown[0]);
        app_lcd(1, shown[1]);
    }
    show_ms = now;
    state = app_state();
    if (state == APP_RUNNING || state == APP_PAUSED)
        run_screen();
    else if (state == APP_FINISHED && !dismissed)
        end_screen(now);
    else
        idle_screen(now, calibrated);
}
