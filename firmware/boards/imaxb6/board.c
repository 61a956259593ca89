/* The original iMAX B6 (ATmega32, 16 MHz): hal.h on the board docs/firmware.md describes. The stage
 * is off from the first instructions; the ADC interrupt regulates and checks the protections; the
 * main loop runs the protocol, the macro's ticks, the front panel and the slow limits. */
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/pgmspace.h>
#include <avr/wdt.h>
#include <util/atomic.h>
#include "../../core/app.h"
#include "../../core/protocol.h"
#include "../../core/text.h"
#include "../common/avr_uart.h"
#include "adc.h"
#include "balance.h"
#include "calib.h"
#include "lcd.h"
#include "panel.h"
#include "pins.h"
#include "protect.h"
#include "stage.h"

/* 57600 baud: U2X, UBRR 34 gives 57143 (-0.8 %); 115200 would be +2.1 % off at 16 MHz. */
#define UBRR_57600 34
#define STORE_EEPROM (E2END + 1 - CAL_BLOCK)   /* the macro store's share; the calibration after it */
#define IDLE_LATCH_MS 1000
#define SLOW_MS 100
#define CAL_OUTPUT_MS 60000UL
#define BALANCE_FROM_MV 600                     /* below the chemistry's maximum: the charged part of the curve */
#define BALANCE_BLEED_SLOWS 150                 /* a window of bleeding: at most 15 s of 100 ms (cheali) */
#define BALANCE_SETTLE_SLOWS 40                 /* the loads off this long (4 s) before a decision (cheali) */
#define BALANCE_DROP_READS 4                    /* the first 4 decisions of a window measure each bleed's drop */
#define BALANCE_FILTER 4                        /* the balancer's cells: a filter of 4 decisions (0.4 s) */
#define T_STACK 0x34                            /* after protocol.h's T_CAL_*: the stack never used (tests) */
#define PAINT 0xAA

static volatile uint32_t millis;
static volatile uint8_t beeps;
static hal_output_t out;
static uint8_t calibrated, balancing, bled_before, balance_slows;
static uint16_t run_time_limit_min;
static int16_t bleed_drop_mv[6];                /* each cell's average before its bleed, then what the bleed took
                                                 * off it (cheali's Voff - Von) */
static int16_t cell_filtered[6];                /* x BALANCE_FILTER, mV: cells 1 and 2 are differences of taps to
                                                 * ground read in steps of 5 and 10 mV, one reading a few mV off */
static int16_t hold_ma = B6_CHARGE_MA;                        /* the hold's cap on the charge current, < 0: none */
static uint16_t ceiling_mv;                     /* the run's charge voltage per cell: the hold's ceiling; 0: none */
static uint32_t run_capacity_uah, last_latch_ms, cal_output_end_ms;

ISR(TIMER0_COMP_vect)
{
    /* the buzzer: beeps of 80 ms with 80 ms between them, counted down here (MUSIC never blocks) */
    static uint8_t phase;
    millis++;
    if (beeps) {
        if (++phase == 80)
            PORTB &= (uint8_t)~_BV(B6_BUZZER);
        else if (phase >= 160) {
            phase = 0;
            if (--beeps)
                PORTB |= _BV(B6_BUZZER);
        }
    }
}

uint32_t hal_millis(void)
{
    uint32_t t;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { t = millis; }
    return t;
}

/* The main loop's proof of life for the watchdog and the ADC interrupt's hang check. */
static void alive(void)
{
    wdt_reset();
    adc_main_alive = 1;
}

void hal_uart_write(uint8_t byte)
{
    /* a byte leaves every 174 us: a 240-byte answer takes 43 ms, progress, not a hang */
    while (!(UCSRA & _BV(UDRE)))
        alive();
    UDR = byte;
}

uint16_t hal_eeprom_size(void) { return STORE_EEPROM; }
uint8_t hal_eeprom_read(uint16_t addr) { return eeprom_read_byte((const uint8_t *)addr); }
void hal_eeprom_write(uint16_t addr, uint8_t value)
{
    alive();                         /* 8.5 ms a byte: a long COMMIT (idle only) must not look hung */
    eeprom_write_byte((uint8_t *)addr, value);
}

int32_t hal_pack_uv(void) { return adc_value(CAL_VOUT) * 1000L; }
int32_t hal_current_ua(void)
{
    int32_t in = adc_value(CAL_ISMPS), away = adc_value(CAL_IDIS);
    return ((in > 0 ? in : 0) - (away > 0 ? away : 0)) * 1000L;
}
int32_t hal_battery_uc(void) { return adc_value(CAL_TEXTERN) * 10000L; }
int32_t hal_heatsink_uc(void) { return protect_sink_c100() * 10000L; }
uint8_t hal_battery_sensor(void)
{
    int16_t t = protect_latest[CAL_TEXTERN];
    return t >= PROBE_PRESENT_C100 && t <= PROBE_OPEN_HIGH_C100;
}
uint8_t hal_cell_count(void) { return protect_balance_cells(); }
int32_t hal_cell_uv(uint8_t cell)
{
    int32_t mv = cell == 0 ? adc_value(CAL_VB1) - adc_value(CAL_VB0)
               : cell == 1 ? adc_value(CAL_VB2) - adc_value(CAL_VB1) : adc_value((uint8_t)(CAL_VB1 + cell));
    return mv * 1000L;
}

/* Whether the stage charges now (a charge current or voltage set). */
static uint8_t charging(void)
{
    return out.kind == HAL_VOLTAGE_CHARGE || (out.kind == HAL_CURRENT && out.current_ua > 0);
}

/* The held charge's end (cheali's): the highest cell at its ceiling and the current down to a tenth of
 * the phase's own. */
uint8_t hal_balancer_ceiling(int32_t *ceiling_uv)
{
    uint8_t k, at = 0;
    int32_t top = 0, v;
    *ceiling_uv = (int32_t)ceiling_mv * 1000L;
    if (!charging())
        return 0;
    for (k = 0; k < protect_limits.li_cells; k++) {
        v = hal_cell_uv(k);
        if (v > top) {
            top = v;
            at = (uint8_t)(k + 1);
        }
    }
    v = balance_bled_ua(protect_cell_mv, protect_limits.li_cells, balancing);
    return balance_held_end(top, *ceiling_uv, hal_current_ua(), v, protect_limits.li_cells,
                            out.kind == HAL_VOLTAGE_CHARGE ? 0 : out.current_ua) ? at : 0;
}

void hal_measure_latch(void)
{
    adc_latch();
    last_latch_ms = hal_millis();
}

int32_t hal_open_circuit_uv(void)
{
    /* the stage off for 20 ms; the latest burst (not the tick's average) is the open-circuit voltage */
    hal_output_t was = out;
    uint32_t t0 = hal_millis();
    int32_t v;
    stage_off();
    while (hal_millis() - t0 < 20)
        alive();
    v = protect_latest[CAL_VOUT] * 1000L;
    hal_output(&was);
    return v;
}

void hal_output(const hal_output_t *o)
{
    out = *o;
    switch (protect_trip ? HAL_OFF : o->kind) {     /* a trip waiting for its reason stays off */
    case HAL_CURRENT:
        if (o->current_ua > 0)
            stage_set(STAGE_CHARGE, o->current_ua / 1000, 0);   /* over its ceiling the pack trips */
        else
            stage_set(STAGE_DISCHARGE, -o->current_ua / 1000, 0);
        break;
    case HAL_VOLTAGE_CHARGE: stage_set(STAGE_CHARGE, o->current_ua / 1000, o->voltage_uv / 1000); break;
    case HAL_VOLTAGE_DISCHARGE: stage_set(STAGE_DISCHARGE, o->current_ua / 1000, o->voltage_uv / 1000); break;
    default: stage_off();
    }
}

void hal_buzzer(uint8_t melody)
{
    /* a beep per melody number, up to 4, played by the timer */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        beeps = melody > 4 ? 4 : (melody ? melody : 1);
        PORTB |= _BV(B6_BUZZER);
    }
}

void hal_led(uint8_t pattern) { (void)pattern; }   /* the B6 has no LED */

uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32])
{
    /* the B6 has no passport line: nothing answers */
    (void)request;
    (void)len;
    (void)answer;
    return 0;
}

/* The balance port's cells added up (0 without a lead: then nothing to compare). */
static int32_t balance_sum_mv(void)
{
    uint8_t n = protect_balance_cells(), k;
    int32_t sum = 0;
    if (!n)
        return protect_latest[CAL_VOUT];
    for (k = 0; k < n; k++)
        sum += protect_cell_mv[k];
    return sum;
}

const char *hal_run_start(const uint8_t *rec, uint8_t akk_type, int16_t series, int32_t capacity_mah,
                          uint8_t *code, char *sentence)
{
    uint8_t trip;
    const char *why;
    *code = E_UNCALIBRATED;
    if (!calibrated)
        return PSTR("the charger is not calibrated: run zuml calibrate");
    *code = E_PROTECTION;
    cal_output_end_ms = 0;
    if (!cal_pack_agrees(protect_latest[CAL_VOUT], balance_sum_mv()))
        why = PSTR("pack and balance lead read over 2% apart: calibrate or check the leads");
    else
        why = protect_arm(akk_type, series, &trip, sentence);
    if (why) {
        panel_say(why);                      /* a PC's start too: the LCD says why */
        return why;
    }
    run_time_limit_min = protect_time_limit_min(rec);
    ceiling_mv = protect_limits.li_cells ? balance_ceiling_mv(akk_type) : 0;
    run_capacity_uah = protect_capacity_limit_uah(capacity_mah);
    return 0;
}

/* PD0 is cell 4's load or, when a USB-serial adapter's TX is wired to it, the PC's receive line
 * (docs/firmware.md, Line). While cell 4 does not bleed PD0 is an input; an adapter's TX idles high, so
 * PD0 high while undriven since the last round is that wire: the receiver takes PD0 until the reset
 * and cell 4 is not balanced (its load follows the adapter's line, which no firmware can stop). */
static void find_receive_wire(void)
{
    if (!avr_uart_receiving() && !(DDRD & _BV(B6_BAL4)) && (PIND & _BV(B6_BAL4)))
        avr_uart_receive();
}

/* One balance load switch: driven high to bleed, an input (and its latch low) while it does not (as
 * cheali's setBalancerOutput). Driven low before it turns into an input, so its gate never sees the
 * pull-up. */
static void bleed_pin(volatile uint8_t *ddr, volatile uint8_t *port, uint8_t bit, uint8_t on)
{
    if (on) {
        *ddr |= bit;
        *port |= bit;
    } else {
        *port &= (uint8_t)~bit;
        *ddr &= (uint8_t)~bit;
    }
}

static void bleed(uint8_t mask)
{
    uint8_t pd0_free = !avr_uart_receiving();    /* PD0: cell 4's load unless it is the receive line */
    balancing = (uint8_t)(mask & (pd0_free ? 0xFF : ~8));
    /* atomic: the ADC interrupt drives the disable lines on the same ports (a trip must not be undone) */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        bleed_pin(&DDRC, &PORTC, _BV(B6_BAL1), balancing & 1);
        bleed_pin(&DDRC, &PORTC, _BV(B6_BAL2), balancing & 2);
        bleed_pin(&DDRA, &PORTA, _BV(B6_BAL3), balancing & 4);
        if (pd0_free)
            bleed_pin(&DDRD, &PORTD, _BV(B6_BAL4), balancing & 8);
        bleed_pin(&DDRD, &PORTD, _BV(B6_BAL5), balancing & 16);
        bleed_pin(&DDRD, &PORTD, _BV(B6_BAL6), balancing & 32);
    }
}

/* Every 100 ms. The hold: while a Li charge runs with its balance lead, the charge current is capped so
 * that the highest cell stays at its ceiling (balance_cap: the cells decide the current, as cheali's). The
 * balancer: in that charge, once its cells are on the charged part of their curve
 * (the highest within 600 mV of the chemistry's maximum) or the pack holds its voltage, windows of at most
 * 15 s bleeding, then 4 s off: at most 2 + BALANCE_MAX_BLEEDERS switch changes in 19 s, whatever the noise.
 * Cell 4 bleeds too unless PD0 is the receive line (find_receive_wire). */
static void balance(void)
{
    uint8_t n = protect_limits.li_cells, k, ref = 0xFF;   /* ref: the lowest cell that does not bleed */
    int16_t high = 0, mv[6];
    uint8_t on = app_running() && charging();
    find_receive_wire();
    for (k = 0; k < n; k++) {
        if (protect_cell_mv[k] > high)
            high = protect_cell_mv[k];
        cell_filtered[k] = (int16_t)(cell_filtered[k] + protect_cell_mv[k] - cell_filtered[k] / BALANCE_FILTER);
        mv[k] = (int16_t)(cell_filtered[k] / BALANCE_FILTER);
        if (!(balancing & (1 << k)) && (ref == 0xFF || mv[k] < mv[ref]))
            ref = k;
    }
    hold_ma = on && n && ceiling_mv ? balance_cap(hold_ma, (int16_t)(ceiling_mv - high),
                                                  stage_battery_ma(protect_latest[CAL_ISMPS]),
                                                  out.current_ua / 1000) : B6_CHARGE_MA;
    stage_cap(hold_ma);
    if (!on || n < 2 || (high < (int16_t)protect_limits.cell_max_mv + CELL_MARGIN_MV - BALANCE_FROM_MV &&
                         !(out.kind == HAL_VOLTAGE_CHARGE && adc_value(CAL_VOUT) >= out.voltage_uv / 1000 - 50))) {
        if (balancing)
            bleed(0);
        bled_before = 0;
        balance_slows = 0;
        return;
    }
    if (balancing) {
        /* a cell leaves its window early once its presumed voltage is at most the lowest cell that does
         * not bleed (`ref`); only leaving, so a window makes at most 1 + BALANCE_MAX_BLEEDERS changes. On the
         * filtered cells (cell_filtered): on single readings a cell left its window seconds early. */
        uint8_t keep = balancing;
        if (ref != 0xFF && ++balance_slows <= BALANCE_DROP_READS) {
            /* what each bleed takes off its cell (cheali's Voff - Von): its gap to `ref` before (filtered, with
             * the loads off) less the gap in the first readings after, their mean. Against `ref`, as the
             * charge moves every cell when the loads go on (a CV phase lifts them all), the bleed only its own. */
            int16_t base = bleed_drop_mv[ref];
            for (k = 0; k < n; k++) {
                if (balance_slows == 1)
                    bleed_drop_mv[k] = (int16_t)((bleed_drop_mv[k] - base) * BALANCE_DROP_READS);
                bleed_drop_mv[k] = (int16_t)(bleed_drop_mv[k] - (protect_cell_mv[k] - protect_cell_mv[ref]));
            }
            if (balance_slows == BALANCE_DROP_READS)
                for (k = 0; k < n; k++)
                    bleed_drop_mv[k] = balancing & (1 << k) ? (int16_t)(bleed_drop_mv[k] / BALANCE_DROP_READS) : 0;
        } else {
            keep = balance_keep(mv, n, balancing, bleed_drop_mv);
        }
        if (balance_slows >= BALANCE_BLEED_SLOWS || !keep) {
            bled_before = balancing;
            keep = 0;
            balance_slows = 0;
        }
        if (keep != balancing)
            bleed(keep);
    } else if (++balance_slows >= BALANCE_SETTLE_SLOWS) {
        for (k = 0; k < n; k++)
            bleed_drop_mv[k] = mv[k];
        bleed(balance_bleeders(mv, n, bled_before, avr_uart_receiving() ? (uint8_t)~8 : 0xFF));
        balance_slows = 0;
    }
}

/* The stack's high-water mark, measured (docs/firmware.md, *Budgets*): the RAM between the variables
 * and the stack is painted before main() runs; STACK counts what was never written since. */
extern uint8_t __bss_end;
void paint_stack(void) __attribute__((naked, used, section(".init3")));
void paint_stack(void)
{
    uint8_t *p = &__bss_end;
    while (p < (uint8_t *)SP)
        *p++ = PAINT;
}

static uint16_t stack_never_used(void)
{
    const uint8_t *p = &__bss_end;
    uint16_t n = 0;
    while (p + n < (const uint8_t *)RAMEND && p[n] == PAINT)
        n++;
    return n;
}

/* CAL_WRITE's refusal (1) of a block that is not one or lies outside its window, in the input's unit:
 * "Vout+ reads 27.00V as 21.60V: more than 0.81V off" (docs/firmware.md, *Calibration*). */
static uint8_t refused_calibration(uint8_t type, uint8_t seq, const uint8_t *block)
{
    static const char names[CAL_INPUTS][12] PROGMEM = {
        "Vout+", "Vout-", "I discharge", "I charge", "Vin", "Vb0", "Vb1", "Vb2", "Vb3", "Vb4", "Vb5", "Vb6",
        "T extern",
    };
    cal_miss_t miss, *m = &miss;
    uint8_t k, verdict = cal_block_check(block, m);
    char text[64], *p = text, unit = 'V';
    int32_t reads, scale = 1000L;   /* micro-units per unit */
    if (verdict == CAL_OK)
        return 0;
    if (verdict == CAL_BAD_FORM) {
        app_error(type, seq, E_BAD_RANGE, PSTR("not a calibration block (version 1, check byte, no zero full scale)"));
        return 1;
    }
    if (m->input == CAL_IDIS || m->input == CAL_ISMPS)
        unit = 'A';
    if (m->input == CAL_TEXTERN) {
        unit = 'C';
        scale = 10000L;
    }
    p = zc_put_P(p, names[m->input]);
    p = zc_put_P(p, PSTR(" reads "));
    p = zc_put_2f(p, (uint32_t)(m->point * scale));
    *p++ = unit;
    p = zc_put_P(p, PSTR(" as "));
    reads = m->reads;
    if (reads < 0) {
        *p++ = '-';
        reads = -reads;
    }
    p = zc_put_2f(p, (uint32_t)(reads * scale));
    *p++ = unit;
    p = zc_put_P(p, PSTR(": more than "));
    p = zc_put_2f(p, (uint32_t)(m->allowed * scale));
    *p++ = unit;
    p = zc_put_P(p, PSTR(" off"));
    app_tx_begin(T_ERROR, seq, (uint8_t)(2 + (p - text)));
    app_tx(type);
    app_tx(E_BAD_RANGE);
    for (k = 0; text + k < p; k++)
        app_tx((uint8_t)text[k]);
    app_tx_end();
    return 1;
}

static void send_calibration(uint8_t type, uint8_t seq)
{
    uint8_t block[CAL_BLOCK], k;
    cal_block(block);
    app_tx_begin((uint8_t)(type | RESPONSE), seq, 1 + CAL_BLOCK);
    app_tx(calibrated);
    for (k = 0; k < CAL_BLOCK; k++)
        app_tx(block[k]);
    app_tx_end();
}

void hal_request(uint8_t type, uint8_t seq, const uint8_t *p, uint8_t len, uint8_t running)
{
    static const uint8_t lengths[5] PROGMEM = {0, CAL_BLOCK, 0, 3, 0};
    uint8_t k;
    if (type > T_STACK) {
        app_error(type, seq, E_UNKNOWN_TYPE, PSTR("unknown request type"));
        return;
    }
    if (len != pgm_read_byte(&lengths[type - T_CAL_READ])) {
        app_error(type, seq, E_BAD_REQUEST, PSTR("the payload does not fit the request's layout"));
        return;
    }
    if (running && (type == T_CAL_WRITE || type == T_CAL_OUTPUT)) {
        app_error(type, seq, E_BUSY, PSTR("a macro runs: stop it first"));
        return;
    }
    switch (type) {
    case T_CAL_WRITE:
        if (refused_calibration(type, seq, p))
            return;
        for (k = 0; k < CAL_BLOCK; k++) {
            alive();
            eeprom_update_byte((uint8_t *)(STORE_EEPROM + k), p[k]);
        }
        calibrated = cal_use(p);
        /* fall through */
    case T_CAL_READ:
        send_calibration(type, seq);
        return;
    case T_STACK:
        app_tx_begin(T_STACK | RESPONSE, seq, 4);
        app_tx16(stack_never_used());
        app_tx16((uint16_t)(RAMEND + 1 - (uint16_t)&__bss_end));
        app_tx_end();
        return;
    case T_CAL_MEASURE:
        app_tx_begin(T_CAL_MEASURE | RESPONSE, seq, 6 * CAL_INPUTS);
        for (k = 0; k < CAL_INPUTS; k++) {
            int32_t v = adc_value(k);
            app_tx16(adc_average(k));
            app_tx16((uint16_t)v);
            app_tx16((uint16_t)(v >> 16));
        }
        app_tx_end();
        return;
    default: {
        uint16_t ma = (uint16_t)(p[1] | (p[2] << 8));
        uint8_t trip;
        const char *why;
        stage_off();
        protect_disarm();
        cal_output_end_ms = 0;
        if (p[0] > 2 || (p[0] == 1 && ma > 2000) || (p[0] == 2 && ma > 500)) {
            app_error(type, seq, E_BAD_RANGE, PSTR("mode 0..2, at most 2000 mA charging, 500 mA discharging"));
            return;
        }
        if (p[0] && ma) {
            why = protect_arm(4, 0, &trip, 0);  /* as a LiPo pack of the balance port's cells */
            if (why) {
                app_error(type, seq, E_PROTECTION, why);
                return;
            }
            stage_set(p[0] == 1 ? STAGE_CHARGE : STAGE_DISCHARGE, ma, p[0] == 1 ? protect_limits.pack_max_mv : 0);
            cal_output_end_ms = hal_millis() + CAL_OUTPUT_MS;
        }
        app_tx_begin(T_CAL_OUTPUT | RESPONSE, seq, 3);
        app_tx(p[0]);
        app_tx16(ma);
        app_tx_end();
    }
    }
}

/* The limits the main loop keeps (every 100 ms): the heat-sink estimate, time, capacity, the end of
 * a calibration current; and the trips, which end the run. */
static void slow_limits(void)
{
    const zc_run_t *r = app_run();
    protect_sink_step(stage_loss_mw());
    if (app_running()) {
        uint8_t trip = protect_run_limits(r->time_ms, run_time_limit_min, r->total_in.uah, run_capacity_uah);
        if (trip)
            protect_raise(trip);
    }
    if (cal_output_end_ms && (int32_t)(hal_millis() - cal_output_end_ms) >= 0) {
        cal_output_end_ms = 0;
        stage_off();
        protect_disarm();
    }
}

static void watch(void)
{
    uint8_t trip = protect_trip;
    if (trip && protect_settled()) {
        stage_off();
        trip = protect_trip;        /* as the Vout- readings after the switch-off named it (protect_settled) */
        if (app_running())
            app_protect(protect_text(trip));
        cal_output_end_ms = 0;
        protect_disarm();
        hal_buzzer(3);
    } else if (protect_limits.armed && !app_running() && !cal_output_end_ms) {
        protect_disarm();
    }
}

int main(void)
{
    static const char model[] PROGMEM = "iMAX B6 (ZUML firmware)";
    /* only a host on the receive wire asks (find_receive_wire), so this always holds when it is read */
    static const char firmware[] PROGMEM = "zuml-fw 0.2 imaxb6 (RX on PD0: cell 4 not balanced)";
    static const app_board_t board = {
        model, firmware, B6_CHARGE_MA, (uint16_t)(B6_CHARGE_MW / 100), B6_DISCHARGE_MA,
        (uint16_t)(B6_DISCHARGE_MW / 100), B6_MAX_MV, 8500,
        {(int32_t)B6_CHARGE_MA * 1000L, (int32_t)B6_DISCHARGE_MA * 1000L, 3000000L, 1000, 30, 300}
    };
    uint8_t was_watchdog = MCUCSR & _BV(WDRF), block[CAL_BLOCK], k;
    uint32_t last_slow = 0;
    MCUCSR = 0;
    stage_init();                    /* first: every disable line high, both switches low */
    DDRB |= _BV(B6_BUZZER);          /* PB0..PB3 stay inputs: the buttons */
    /* Timer0: CTC, /64, 250 counts = 1 ms */
    TCCR0 = _BV(WGM01) | _BV(CS01) | _BV(CS00);
    OCR0 = 249;
    TIMSK |= _BV(OCIE0);
    avr_uart_init(UBRR_57600, PIND & _BV(B6_BAL4));   /* PD0 an input since the reset: find_receive_wire */
    for (k = 0; k < CAL_BLOCK; k++)
        block[k] = eeprom_read_byte((const uint8_t *)(STORE_EEPROM + k));
    calibrated = cal_use(block);
    adc_init();
    sei();
    lcd_init();
    wdt_enable(WDTO_60MS);           /* after the LCD's 60 ms of start-up waits */
    alive();
    app_init(&board);
    if (was_watchdog)
        app_protect(protect_text(TRIP_WATCHDOG));
    for (;;) {
        uint32_t now = hal_millis();
        alive();
        app_poll();
        watch();
        if (!app_running() && now - last_latch_ms >= IDLE_LATCH_MS)
            hal_measure_latch();
        if (now - last_slow >= SLOW_MS) {
            last_slow = now;
            slow_limits();
            balance();
        }
        panel_poll(now, calibrated);
    }
}
