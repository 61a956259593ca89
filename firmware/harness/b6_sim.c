/* zuml_b6_sim: the imaxb6 image on simavr, wired as the original iMAX B6 (b6_board.h), its power stage
 * and pack the physics of b6_model.c. The USART on a pty whose path is the first line of stdout; the
 * LCD, the buttons, faults and a trace of the model's truth as options (usage below, docs/firmware.md).
 * Everything is timed in simulated time: --speed 0 runs as fast as the host can, and a slow host only
 * slows the run down, never changes what happens in it. */
#define _DEFAULT_SOURCE
#include <ctype.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_cycle_timers.h"
#include "avr_adc.h"
#include "avr_eeprom.h"
#include "avr_ioport.h"
#include "avr_uart.h"
#include "parts/uart_pty.h"
#include "b6_board.h"
#include "b6_calibration.h"
#include "b6_model.h"
#include "sim_eeprom.h"
#include "sim_timer0.h"

#define F_CPU 16000000UL
#define EEPROM_SIZE 1024
#define STEP_CYCLES 800                 /* 50 us: the model's step, the drive's sampling */
#define STEPS_PER_MS 20
#define MAX_EVENTS 32
#define MAX_RX_BYTES 48                 /* an --rx frame: within simavr's 64-byte receive queue */
#define PRESS_S 0.2                     /* a press held this long unless BUTTON@S:HOLD says otherwise */
#define LCD_SETTLE_MS 3                 /* print the LCD once it has had no write this long */
#define LCD_MAX_WAIT_MS 100             /* ... or at the latest this long after the first change */
#define SLOW_PERIOD_MS 50               /* the slow-loop fault: parked 45 ms of every 50, below the image's 50 ms */
#define SLOW_PARK_MS 45                 /* hang check, so the main loop is slow, not hung */
/* ATmega32 registers in data space */
#define R_TCCR1A 0x4F
#define R_TCCR1B 0x4E
#define R_OCR1A 0x4A
#define R_OCR1B 0x48
#define R_ICR1 0x46
#define R_ADMUX 0x27
#define R_UCSRB 0x2A
#define R_WDTCR 0x41
#define R_MCUCSR 0x54
#define WDRF_BIT 3
#define WDTOE_WDE 0x18
#define RXEN_BIT 4

static const char usage[] =
    "usage: zuml_b6_sim ELF [--eeprom FILE] [--cells N] [--capacity MAH] [--soc F] [--cell-spread MV] [--weak-cell PCT]\n"
    "       [--seed N] [--uncalibrated] [--fault KIND@S]... [--press BUTTON@S[:HOLD]]... [--trace FILE] [--lcd]\n"
    "       [--speed X] [--no-rx] [--rx HEX@S]... [--no-balance-lead] [--end-with-stdin]\n"
    "KIND: disconnect reverse cell-high sensor-open sink-hot input-low input-sag hang slow-loop; BUTTON: start stop inc dec\n";

static const char *const button_names[4] = {"start", "stop", "inc", "dec"};   /* as b6_button[] */

typedef struct {
    double at_s, hold_s;
    int what;                           /* a fault kind, or a button (its index in b6_button) */
    int done;
} timed_t;

/* --rx: bytes that reach the USART's receiver at a simulated time, as if the PC sent them then */
typedef struct {
    double at_s;
    uint8_t bytes[MAX_RX_BYTES];
    int n, done;
} rx_t;

static avr_t *avr;
static uart_pty_t uart;
static b6_model_t model;
static volatile sig_atomic_t stopping;
static const char *eeprom_path;
static uint8_t eeprom[EEPROM_SIZE], saved[EEPROM_SIZE];
static timed_t faults[MAX_EVENTS], presses[MAX_EVENTS];
static rx_t rxs[MAX_EVENTS];
static int n_faults, n_presses, n_rxs, lcd_on, step_count, hang_pending, refs_warned, output_was_on;
/* 1: a USB-serial adapter's TX is wired to PD0 (RXD): the pty's bytes reach the USART and the idle line holds
 * PD0 high; 0 (--no-rx): TX alone, as on the B6's 3-pin port; PD0 is cell 4's load, pulled low when undriven */
static int rx_wire = 1;
/* --end-with-stdin: stdin's end is the host's (a window that started this one and went away): stop then */
static int end_with_stdin;
/* the slow-loop fault: from slow_from_ms on, the main loop is parked SLOW_PARK_MS of every SLOW_PERIOD_MS */
static long slow_from_ms = -1;
static int parked;
static avr_flashaddr_t parked_pc;
static unsigned balancer_was;
static int buzzer_was;                  /* the level last seen on the buzzer's pin (PB4) */
static FILE *trace;
static avr_irq_t *adc_in[8], *button_pin[4], *rxd_pin, *uart_in;   /* looked up once: simavr walks its modules on every lookup */
/* simavr clears its cycle timers at a reset (a watchdog's) and may zero its cycle count: the model's
 * clock goes on across it */
static avr_cycle_count_t cycle_base, cycle_at_reset;
static int reset_seen;
/* the longest stretch with the interrupts off (an ISR or a cli() section) since the image's first sei(): a
 * Timer0 match is lost only past 1 ms; INTERRUPTS|off|MAX_US|AT_S|PC at the end (PC: the first instruction
 * run with them off, a byte address in the flash) */
static avr_cycle_count_t off_since, off_max;
static double off_max_at;
static avr_flashaddr_t off_pc, off_max_pc;
static int sei_seen;
static void (*mcu_reset)(struct avr_t *);

static avr_cycle_count_t now_cycles(void) { return cycle_base + avr->cycle; }
static double now_s(void) { return (double)now_cycles() / F_CPU; }
static long now_ms(void) { return (long)(now_cycles() / (F_CPU / 1000)); }

/* ---- pins ---- */

static uint8_t port_reg(int port, int offset) { return avr->data[b6_port_addr[port] - offset]; }
static int driven(b6_pin_t p) { return port_reg(p.port, 1) >> p.bit & 1; }
static int latch(b6_pin_t p) { return port_reg(p.port, 0) >> p.bit & 1; }
static int driven_high(b6_pin_t p) { return driven(p) && latch(p); }
static uint16_t reg16(uint16_t low) { return (uint16_t)(avr->data[low] | (avr->data[low + 1] << 8)); }

/* The on-time of an OC1x switch: its PWM when Timer1 drives the pin, its level when the port does;
 * an undriven gate is off (its driver pulls it down: an assumption, cheali does not say). */
static double switch_duty(b6_pin_t pin, int com_shift, uint16_t ocr_reg)
{
    uint8_t a = avr->data[R_TCCR1A], b = avr->data[R_TCCR1B];
    int com = a >> com_shift & 3, mode = (b >> 1 & 0x0C) | (a & 3), fast;
    double top, ocr, duty;
    if (!driven(pin))
        return 0;
    if (com < 2 || (b & 7) == 0 || mode == 0 || mode == 4 || mode == 12)
        return driven_high(pin);
    switch (mode) {
    case 1: case 5: top = 0xFF; break;
    case 2: case 6: top = 0x1FF; break;
    case 3: case 7: top = 0x3FF; break;
    case 9: case 11: case 15: top = reg16(R_OCR1A); break;
    default: top = reg16(R_ICR1); break;
    }
    fast = mode == 5 || mode == 6 || mode == 7 || mode == 14 || mode == 15;
    ocr = reg16(ocr_reg);
    if (top <= 0)
        return 0;
    /* fast PWM sets the pin at BOTTOM and clears it one clock after the match: OCR = 0 is a spike */
    duty = fast ? (ocr >= top ? 1 : (ocr + 1) / (top + 1)) : (ocr >= top ? 1 : ocr / top);
    return com == 3 ? 1 - duty : duty;
}

static void sample_drive(void)
{
    b6_drive_t *d = &model.drive;
    double oc1a = switch_duty(B6_BOOST, 6, R_OCR1A);
    int k;
    d->buck_duty = switch_duty(B6_BUCK, 4, R_OCR1B);
    d->boost_duty = oc1a;
    d->discharge_duty = oc1a;
    /* the disable lines are active high ([B], [S]); an undriven one is taken as not disabling: cheali does
     * not say which way the board pulls it, and the model takes the way that finds the firmware's bug */
    d->smps_on = !driven_high(B6_SMPS_DISABLE);
    d->output_on = !driven_high(B6_OUTPUT_DISABLE);
    d->discharge_on = !driven_high(B6_DISCHARGE_DISABLE);
    d->balancer = 0;
    for (k = 0; k < 6; k++) {
        b6_pin_t p = b6_balancer_load[k];
        if (p.port == B6_PD && p.bit == 0 && (avr->data[R_UCSRB] >> RXEN_BIT & 1))
            continue;                   /* PD0 is the USART's RX while the receiver is on */
        if (driven_high(p))
            d->balancer |= 1u << k;
    }
}

/* ---- ADC ---- */

/* The multiplexer's output (PA6) holds a charge, its own and the ADC's sample capacitance: it follows an input
 * within MUX_SETTLE_S, but falls no faster than MUX_FALL_V_PER_S, as behind the B6's simplified Vb0..Vb2
 * circuit, a follower that sources current and sinks only a small bias current: a small ripple is followed, a
 * step down from another input's volts takes milliseconds. Assumed values: cheali empties the node (PA6 driven
 * low) before each reading behind the mux and gives none. A reading that skips the emptying, or that lets the
 * node charge from a wrong address first, reads a lower input too high. */
#define MUX_SETTLE_S 10e-6
#define MUX_FALL_V_PER_S 400.0          /* 2 V in 5 ms */
#define MUX_WATCH_CYCLES 256            /* 16 us: the firmware drives PA6 for a conversion (52 us) */
static double mux_node_v;
static avr_cycle_count_t mux_node_at;
static int mux_node_address, mux_node_driven = -1;      /* the pins since mux_node_at; driven: -1 no, 0 low, 1 high */

static int mux_address(void)
{
    return driven_high(B6_MUX_ADR0) | driven_high(B6_MUX_ADR1) << 1 | driven_high(B6_MUX_ADR2) << 2;
}

/* The input's true pin voltage (no noise) */
static double mux_input_v(int address)
{
    const b6_input_t *in = &b6_mux_input[address];
    double v = b6_model_adc16(&model, in, b6_model_quantity(&model, in->quantity)) / 65536 * model.aref_v;
    return v < 0 ? 0 : v;
}

/* The node since its last update under the pins as they were, then the pins as they are now: called at every
 * write to PORTB (the address), within MUX_WATCH_CYCLES of a change of PA6's direction (simavr reports no DDR
 * write), every model step and every conversion */
static void mux_node_follow(void)
{
    double dt = avr->cycle > mux_node_at ? (double)(avr->cycle - mux_node_at) / F_CPU : 0, target;
    mux_node_at = avr->cycle;
    if (mux_node_driven >= 0) {
        mux_node_v = mux_node_driven ? B6_AVCC_V : 0;
    } else {
        double slewed = mux_node_v - MUX_FALL_V_PER_S * dt;
        target = mux_input_v(mux_node_address);
        mux_node_v += (target - mux_node_v) * (1 - exp(-dt / MUX_SETTLE_S));
        if (mux_node_v < slewed)
            mux_node_v = slewed;
    }
    mux_node_address = mux_address();
    mux_node_driven = driven(B6_MUX_Z) ? driven_high(B6_MUX_Z) : -1;
    if (mux_node_driven >= 0)
        mux_node_v = mux_node_driven ? B6_AVCC_V : 0;
}

static void mux_pins_written(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq; (void)value; (void)param;
    mux_node_follow();
}

static avr_cycle_count_t mux_watch(struct avr_t *a, avr_cycle_count_t when, void *param)
{
    (void)a; (void)param;
    if ((driven(B6_MUX_Z) ? driven_high(B6_MUX_Z) : -1) != mux_node_driven)
        mux_node_follow();
    return when + MUX_WATCH_CYCLES;
}

static double input_pin_v(int channel)
{
    if (channel == B6_MUX_ADC_CHANNEL) {
        int address = mux_address();
        mux_node_follow();
        if (driven(B6_MUX_Z))
            return mux_node_v;
        /* the input's noise as before, on the node's charge */
        return b6_model_pin_v(&model, &b6_mux_input[address]) - mux_input_v(address) + mux_node_v;
    }
    if (channel < 8 && b6_adc_channel[channel].quantity != B6_Q_NONE)
        return b6_model_pin_v(&model, &b6_adc_channel[channel]);
    return channel < 8 && driven_high((b6_pin_t){B6_PA, (uint8_t)channel}) ? B6_AVCC_V : 0;
}

/* The code the ATmega32's ADC makes (datasheet: ADC = Vin * 1024 / Vref, the first step at half an LSB),
 * handed to simavr as the middle of that code's step: simavr converts value * 1023 / reference, truncated,
 * which read directly would be 0.1 % and half an LSB low. */
static void adc_trigger(struct avr_irq_t *irq, uint32_t value, void *param)
{
    union { avr_adc_mux_t mux; uint32_t v; } e = {.v = value};
    int refs = avr->data[R_ADMUX] >> 6;
    double ref_v = model.aref_v, units = avr->aref, v;
    (void)irq; (void)param;
    if (refs != 0 && !refs_warned) {
        refs_warned = 1;
        fprintf(stderr, "zuml_b6_sim: the firmware selects %s as the ADC reference: on a B6 the external AREF is "
                "driven and this shorts it (ATmega32 datasheet, ADMUX)\n", refs == 3 ? "the internal 2.56 V" : "AVCC");
    }
    if (refs == 1) {
        ref_v = B6_AVCC_V;
        units = avr->avcc;
    } else if (refs == 3) {
        ref_v = 2.56;
        units = 2560;
    }
    if (e.mux.kind != ADC_MUX_SINGLE)
        return;
    v = floor(input_pin_v(e.mux.src) / ref_v * 1024 + 0.5);
    v = v < 0 ? 0 : (v > 1023 ? 1023 : v);
    if (e.mux.src < 8)
        avr_raise_irq(adc_in[e.mux.src], (uint32_t)floor((v + 0.5) * units / 1023));
}

/* ---- the HD44780 in 4-bit mode, RW tied low ---- */

static struct {
    uint8_t ddram[128], addr, mode4, have_high, high, increment, display_on, cgram, prev_e;
    char shown[2][17];
    long last_write_ms, first_change_ms;
    int changed;
} lcd = {.increment = 1, .display_on = 0, .last_write_ms = -1, .first_change_ms = -1};


static void lcd_byte(int rs, uint8_t v)
{
    if (rs) {
        if (!lcd.cgram) {
            lcd.ddram[lcd.addr] = v;
            lcd.addr = (uint8_t)((lcd.addr + (lcd.increment ? 1 : -1)) & 0x7F);
        }
    } else if (v & 0x80) {
        lcd.addr = v & 0x7F;
        lcd.cgram = 0;
    } else if (v & 0x40) {
        lcd.cgram = 1;
    } else if (v & 0x20) {
        lcd.mode4 = !(v & 0x10);
    } else if (v & 0x10) {
        if (!(v & 0x08))
            lcd.addr = (uint8_t)((lcd.addr + (v & 0x04 ? 1 : -1)) & 0x7F);
    } else if (v & 0x08) {
        lcd.display_on = (v & 0x04) != 0;
    } else if (v & 0x04) {
        lcd.increment = (v & 0x02) != 0;
    } else if (v & 0x02) {
        lcd.addr = 0;
    } else if (v & 0x01) {
        memset(lcd.ddram, ' ', sizeof lcd.ddram);
        lcd.addr = 0;
        lcd.increment = 1;
    }
    lcd.last_write_ms = now_ms();
    if (!lcd.changed)
        lcd.first_change_ms = lcd.last_write_ms;
    lcd.changed = 1;
}

/* E falls: the controller latches DB7..DB4 and RS */
static void lcd_enable(struct avr_irq_t *irq, uint32_t value, void *param)
{
    int rs = latch(B6_LCD_RS);
    uint8_t nibble = (uint8_t)(latch(B6_LCD_DB4) | latch(B6_LCD_DB5) << 1 | latch(B6_LCD_DB6) << 2 |
                               latch(B6_LCD_DB7) << 3);
    (void)irq; (void)param;
    if (lcd.prev_e && !value) {
        if (!lcd.mode4) {
            lcd.have_high = 0;
            lcd_byte(rs, (uint8_t)(nibble << 4));   /* 8-bit mode: DB3..DB0 are not wired, they read 0 */
        } else if (!lcd.have_high) {
            lcd.high = nibble;
            lcd.have_high = 1;
        } else {
            lcd.have_high = 0;
            lcd_byte(rs, (uint8_t)(lcd.high << 4 | nibble));
        }
    }
    lcd.prev_e = value != 0;
}

static void lcd_line(int row, char *out)
{
    int k;
    for (k = 0; k < 16; k++) {
        uint8_t ch = lcd.display_on ? lcd.ddram[row * 0x40 + k] : ' ';
        out[k] = ch >= 0x20 && ch < 0x7F && ch != '|' ? (char)ch : (ch < 8 ? '#' : '?');
    }
    out[16] = 0;
    for (k = 15; k >= 0 && out[k] == ' '; k--)
        out[k] = 0;
}

static void lcd_print_if_settled(void)
{
    long now = now_ms();
    char l1[17], l2[17];
    if (!lcd.changed || (now - lcd.last_write_ms < LCD_SETTLE_MS && now - lcd.first_change_ms < LCD_MAX_WAIT_MS))
        return;
    lcd.changed = 0;
    lcd_line(0, l1);
    lcd_line(1, l2);
    if (!strcmp(l1, lcd.shown[0]) && !strcmp(l2, lcd.shown[1]))
        return;
    strcpy(lcd.shown[0], l1);
    strcpy(lcd.shown[1], l2);
    fprintf(stderr, "LCD|%s|%s\n", l1, l2);
    fflush(stderr);
}

/* ---- buttons, faults, the hang ---- */

/* `again`: after a reset, which clears the PIN registers under simavr's unchanged pin values */
static void set_buttons(double now_s, int again)
{
    int k, button;
    for (button = 0; button < 4; button++) {
        int pressed = 0;
        avr_irq_t *pin = button_pin[button];
        for (k = 0; k < n_presses; k++)
            if (presses[k].what == button && now_s >= presses[k].at_s
                && now_s < presses[k].at_s + presses[k].hold_s)
                pressed = 1;
        if (again)
            avr_raise_irq(pin, pressed);
        /* external pull-ups ([B]): released reads high, pressed pulls the line low */
        avr_raise_irq(pin, pressed ? 0 : 1);
    }
}

/* PD0 as the wire outside holds it while the AVR does not drive it (also after a reset, as the buttons) */
static void set_rxd(int again)
{
    if (driven(B6_BAL4_LOAD))
        return;
    if (again)
        avr_raise_irq(rxd_pin, !rx_wire);
    avr_raise_irq(rxd_pin, rx_wire);
}

/* The rjmp . at the top of the flash, where a stopped main loop is sent. */
static avr_flashaddr_t park_loop(void)
{
    uint32_t end = avr->flashend - 1;
    if (avr->flash[end] != 0xFF || (avr->flash[end + 1] != 0xFF && avr->flash[end + 1] != 0xCF))
        fprintf(stderr, "zuml_b6_sim: the image reaches the last flash word; hang overwrites it\n");
    avr->flash[end] = 0xFF;             /* rjmp . = 0xCFFF, little endian */
    avr->flash[end + 1] = 0xCF;
    return end;
}

/* The slow-loop fault's state for now: 1 while the main loop should be parked. */
static int park_wanted(void)
{
    return slow_from_ms >= 0 && now_ms() >= slow_from_ms && (now_ms() - slow_from_ms) % SLOW_PERIOD_MS < SLOW_PARK_MS;
}

/* Parks the main loop or lets it go on where it was (between two avr_run()s, outside any ISR: an ISR's
 * return address must be the main loop's own). */
static void park_now(void)
{
    if (avr->interrupts.running_ptr || parked == park_wanted())
        return;
    if (!parked) {
        parked_pc = avr->pc;
        avr->pc = park_loop();
    } else {
        avr->pc = parked_pc;
    }
    parked = !parked;
}

/* The main loop stops: the CPU is sent to an endless loop at the top of the flash while the interrupts stay
 * on, so an ISR that still runs cannot hide the hang from a watchdog fed only by the main loop. Called
 * between two avr_run()s: simavr sets the PC after its cycle timers, so a timer cannot move it. */
static void hang_now(void)
{
    if (avr->interrupts.running_ptr)
        return;                         /* inside an ISR: wait for the main loop */
    avr->pc = park_loop();
    parked = 0;                         /* for good: the slow-loop fault ends */
    slow_from_ms = -1;
    hang_pending = 0;
    fprintf(stderr, "FAULT|hang|%.3f\n", now_s());
}

static void apply_faults(double now_s)
{
    int k;
    for (k = 0; k < n_faults; k++) {
        if (faults[k].done || now_s < faults[k].at_s)
            continue;
        faults[k].done = 1;
        if (faults[k].what == B6_FAULT_HANG) {
            hang_pending = 1;
            continue;
        }
        if (faults[k].what == B6_FAULT_SLOW_LOOP)
            slow_from_ms = (long)(faults[k].at_s * 1000 + 0.5);
        model.fault[faults[k].what] = 1;
        fprintf(stderr, "FAULT|%s|%.3f\n", b6_fault_names[faults[k].what], now_s);
    }
}

/* RX|T|N when an --rx frame's N bytes enter the receiver (at the USART's own rate from there) */
static void apply_rxs(double now_s)
{
    int k, b;
    for (k = 0; k < n_rxs; k++) {
        if (rxs[k].done || now_s < rxs[k].at_s)
            continue;
        rxs[k].done = 1;
        for (b = 0; b < rxs[k].n; b++)
            avr_raise_irq(uart_in, rxs[k].bytes[b]);
        fprintf(stderr, "RX|%.3f|%d\n", now_s, rxs[k].n);
    }
}

/* ---- the model's clock ---- */

/* OUTPUT|on|T and OUTPUT|off|T|CELL1|CELL2|... (the cells' true voltages, V) when the stage switches;
 * BALANCER|T|MASK when the load switches change (bit n-1: cell n bleeds) */
static void report_output(double t)
{
    int on = b6_model_output_enabled(&model), k;
    if (model.drive.balancer != balancer_was) {
        balancer_was = model.drive.balancer;
        fprintf(stderr, "BALANCER|%.3f|%u\n", t, balancer_was);
    }
    if (on == output_was_on)
        return;
    output_was_on = on;
    fprintf(stderr, "OUTPUT|%s|%.3f", on ? "on" : "off", t);
    for (k = 0; !on && k < model.cells; k++)
        fprintf(stderr, "|%.4f", b6_model_cell_v(&model, k));
    fputc('\n', stderr);
    fflush(stderr);
}

/* BEEP|T when the buzzer's pin (PB4) rises: a beep begins (the image times its length and the pause with Timer0) */
static void buzzer_pin(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq; (void)param;
    if (value && !buzzer_was) {
        fprintf(stderr, "BEEP|%.3f\n", now_s());
        fflush(stderr);
    }
    buzzer_was = value != 0;
}

static avr_cycle_count_t step(struct avr_t *a, avr_cycle_count_t when, void *param)
{
    double t = now_s();
    (void)a; (void)param;
    sample_drive();
    mux_node_follow();
    b6_model_step(&model, (double)STEP_CYCLES / F_CPU);
    apply_faults(t);
    apply_rxs(t);
    set_buttons(t, 0);
    set_rxd(0);
    report_output(t);
    if (++step_count % STEPS_PER_MS == 0) {
        if (trace) {
            double top = 0;
            int k;
            for (k = 0; k < model.cells; k++)
                if (b6_model_cell_v(&model, k) > top)
                    top = b6_model_cell_v(&model, k);
            fprintf(trace, "%ld,%.4f,%.4f,%d,%.4f,%.4f,%.4f\n", now_ms(), model.drive.buck_duty,
                    model.drive.boost_duty, b6_model_output_enabled(&model), model.i_batt_a, model.v_term_v, top);
        }
        if (lcd_on)
            lcd_print_if_settled();
    }
    return when + STEP_CYCLES;
}

/* After each instruction: the interrupts' state (simavr runs one instruction per avr_run) */
static void watch_interrupts(void)
{
    if (avr->sreg[S_I]) {
        if (off_since && now_cycles() - off_since > off_max) {
            off_max = now_cycles() - off_since;
            off_max_at = (double)off_since / F_CPU;
            off_max_pc = off_pc;
        }
        off_since = 0;
        sei_seen = 1;
    } else if (sei_seen && !off_since) {
        off_since = now_cycles();
        off_pc = avr->pc;
    }
}

/* ---- EEPROM ---- */

static void save_eeprom(void)
{
    sim_eeprom_save(avr, eeprom, saved, EEPROM_SIZE, eeprom_path, "zuml_b6_sim");
}

/* ---- options ---- */

static int fail(const char *what, const char *value)
{
    fprintf(stderr, "zuml_b6_sim: %s: %s\n", what, value);
    return 0;
}

static int number(const char *text, double lo, double hi, double *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v) || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

/* "NAME@SECONDS[:HOLD]" against `names`; the index of the name, -1 when it is not one of them */
static int timed(const char *text, const char *const *names, int n, int hold_allowed, timed_t *out)
{
    const char *at = strchr(text, '@');
    char when[64], *colon;
    int k;
    if (!at || (size_t)(at - text) >= 32 || strlen(at + 1) >= sizeof when)
        return -1;
    for (k = 0; k < n; k++)
        if ((size_t)(at - text) == strlen(names[k]) && !strncmp(text, names[k], (size_t)(at - text)))
            break;
    if (k == n)
        return -1;
    strcpy(when, at + 1);
    out->hold_s = PRESS_S;
    colon = strchr(when, ':');
    if (colon) {
        *colon = 0;
        if (!hold_allowed || !number(colon + 1, 0.001, 1e6, &out->hold_s))
            return -1;
    }
    if (!number(when, 0, 1e7, &out->at_s))
        return -1;
    out->what = k;
    out->done = 0;
    return k;
}

/* "HEX@SECONDS": up to MAX_RX_BYTES bytes in hex digits */
static int rx_at(const char *text, rx_t *out)
{
    const char *at = strchr(text, '@');
    unsigned byte;
    int k;
    if (!at || (at - text) % 2 || at == text || (at - text) / 2 > MAX_RX_BYTES || !number(at + 1, 0, 1e7, &out->at_s))
        return 0;
    for (k = 0; k < (at - text) / 2; k++) {
        if (!isxdigit((unsigned char)text[2 * k]) || !isxdigit((unsigned char)text[2 * k + 1]) ||
            sscanf(text + 2 * k, "%2x", &byte) != 1)
            return 0;
        out->bytes[k] = (uint8_t)byte;
    }
    out->n = k;
    out->done = 0;
    return 1;
}

typedef struct {
    int cells, calibrated, no_lead;
    double capacity_mah, soc, spread_mv, weak_pct, speed;
    uint64_t seed;
} options_t;

static int parse(int argc, char **argv, options_t *o)
{
    int k;
    static const char *const known[] = {"--eeprom", "--cells", "--capacity", "--soc", "--cell-spread", "--seed",
                                        "--speed", "--fault", "--press", "--trace", "--weak-cell", "--rx"};
    for (k = 2; k < argc; k++) {
        const char *name = argv[k], *value = k + 1 < argc ? argv[k + 1] : NULL;
        double v;
        size_t n;
        if (!strcmp(name, "--uncalibrated")) {
            o->calibrated = 0;
            continue;
        }
        if (!strcmp(name, "--lcd")) {
            lcd_on = 1;
            continue;
        }
        if (!strcmp(name, "--no-rx")) {
            rx_wire = 0;
            continue;
        }
        if (!strcmp(name, "--no-balance-lead")) {
            o->no_lead = 1;
            continue;
        }
        if (!strcmp(name, "--end-with-stdin")) {
            end_with_stdin = 1;
            continue;
        }
        for (n = 0; n < sizeof known / sizeof known[0] && strcmp(name, known[n]); n++)
            ;
        if (n == sizeof known / sizeof known[0])
            return fail("unknown option", name);
        if (!value)
            return fail("missing value after", name);
        k++;
        if (!strcmp(name, "--eeprom")) {
            FILE *f = fopen(value, "rb");
            eeprom_path = value;
            if (f) {
                size_t n = fread(eeprom, 1, EEPROM_SIZE, f);
                (void)n;
                fclose(f);
            }
        } else if (!strcmp(name, "--cells")) {
            if (!number(value, 1, B6_MAX_CELLS, &v) || v != floor(v))
                return fail("--cells is 1..6 (the B6's balance port)", value);
            o->cells = (int)v;
        } else if (!strcmp(name, "--capacity")) {
            if (!number(value, 1e-3, 1e6, &o->capacity_mah) || o->capacity_mah <= 0)
                return fail("--capacity is above 0 and at most 1000000 mAh", value);
        } else if (!strcmp(name, "--soc")) {
            if (!number(value, 0, 1, &o->soc))
                return fail("--soc is 0..1", value);
        } else if (!strcmp(name, "--cell-spread")) {
            if (!number(value, 0, 1000, &o->spread_mv))
                return fail("--cell-spread is 0..1000 mV", value);
        } else if (!strcmp(name, "--weak-cell")) {
            if (!number(value, 0, 90, &o->weak_pct))
                return fail("--weak-cell is 0..90 % less capacity in the last cell", value);
        } else if (!strcmp(name, "--seed")) {
            if (!number(value, 0, 4294967295.0, &v) || v != floor(v))
                return fail("--seed is a whole number 0..4294967295", value);
            o->seed = (uint64_t)v;
        } else if (!strcmp(name, "--speed")) {
            if (!number(value, 0, 1e6, &o->speed))
                return fail("--speed is 0 (as fast as the host can) or the simulated seconds per second", value);
        } else if (!strcmp(name, "--fault")) {
            if (n_faults == MAX_EVENTS || timed(value, b6_fault_names, B6_FAULT_KINDS, 0, &faults[n_faults]) < 0)
                return fail("--fault is KIND@SECONDS, KIND one of disconnect reverse cell-high sensor-open sink-hot "
                            "input-low input-sag hang slow-loop (at most 32)", value);
            n_faults++;
        } else if (!strcmp(name, "--press")) {
            if (n_presses == MAX_EVENTS || timed(value, button_names, 4, 1, &presses[n_presses]) < 0)
                return fail("--press is BUTTON@SECONDS[:HOLD], BUTTON one of start stop inc dec (at most 32)", value);
            n_presses++;
        } else if (!strcmp(name, "--rx")) {
            if (n_rxs == MAX_EVENTS || !rx_at(value, &rxs[n_rxs]))
                return fail("--rx is HEX@SECONDS, 1..48 bytes in hex digits (at most 32)", value);
            n_rxs++;
        } else if (!strcmp(name, "--trace")) {
            trace = fopen(value, "w");
            if (!trace)
                return fail("cannot write the trace", value);
            fputs("t_ms,buck_duty,boost_duty,output_enabled,current_a,voltage_v,cell_max_v\n", trace);
        }
    }
    return 1;
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec / 1e9;
}

static void on_signal(int sig) { (void)sig; stopping = 1; }

static void on_reset(struct avr_t *a)
{
    if (mcu_reset)
        mcu_reset(a);
    cycle_at_reset = a->cycle;
    reset_seen = 1;
}

/* The ATmega32 comes out of any reset with its watchdog off (datasheet, WDTCR: WDE reads 0 after a reset
 * unless the WDTON fuse is programmed); simavr restarts it at 16 ms after a watchdog reset as the newer AVRs
 * do, which would reset a B6 image again before its LCD is up. The timed sequence turns it off, WDRF kept. */
static void watchdog_off(void)
{
    int io = AVR_DATA_TO_IO(R_WDTCR);
    uint8_t mcucsr = avr->data[R_MCUCSR];
    if (!avr->io[io].w.c)
        return;
    avr->data[R_MCUCSR] = mcucsr & (uint8_t)~(1u << WDRF_BIT);
    avr->io[io].w.c(avr, R_WDTCR, WDTOE_WDE, avr->io[io].w.param);
    avr->io[io].w.c(avr, R_WDTCR, 0, avr->io[io].w.param);
    avr->data[R_MCUCSR] = mcucsr;
}

/* After a reset: the clock carried on, the model's step timer registered again. */
static void after_reset(void)
{
    int by_watchdog = avr->data[R_MCUCSR] >> WDRF_BIT & 1;
    reset_seen = 0;
    parked = 0;                         /* the reset moved the PC */
    sei_seen = 0;                       /* the image starts again with its interrupts off */
    off_since = 0;
    buzzer_was = 0;                     /* the reset made PB4 an input again: the next beep is an edge */
    if (avr->cycle < cycle_at_reset)
        cycle_base += cycle_at_reset;
    if (by_watchdog)
        watchdog_off();
    avr_cycle_timer_register(avr, STEP_CYCLES, step, NULL);
    avr_cycle_timer_register(avr, MUX_WATCH_CYCLES, mux_watch, NULL);
    set_buttons(now_s(), 1);
    set_rxd(1);
    fprintf(stderr, "RESET|%s|%.3f\n", by_watchdog ? "watchdog" : "other", now_s());
}

/* Presses typed on stdin while the B6 runs, one a line (the window's front panel sends them): `BUTTON [HOLD]`
 * pressed now for HOLD seconds (default 0.2); `BUTTON down`, pressed until `BUTTON up [HELD]`, which lets
 * it go now, or once it has been held HELD simulated seconds (a host slower than the wall still sees the
 * hold the user made). One finger, as the window's one mouse: a press while any button is still down (a
 * click faster than the simulation) follows it after RELEASE_S up (a finger's pause), so the firmware sees
 * each alone. (INC clicked while START was still down in simulated time, under a loaded host, changed the
 * keys twice within INC's press: the firmware's 30 ms debounce never saw INC steady, and the click was
 * lost.) BUTTON: start stop inc dec. A press that ended frees its place. */
#define RELEASE_S 0.1
static void press_line(char *line)
{
    char *arg = strchr(line, ' '), text[64];
    timed_t press;
    double now = now_s(), held = 0, free_at = now;
    int k, up, down, last = -1;
    if (arg)
        *arg++ = 0;
    up = arg && !strncmp(arg, "up", 2) && (!arg[2] || arg[2] == ' ');
    down = arg && !strcmp(arg, "down");
    snprintf(text, sizeof text, "%s@0%s%s", line, arg && !up && !down ? ":" : "", arg && !up && !down ? arg : "");
    if (timed(text, button_names, 4, 1, &press) < 0 || (up && arg[2] && !number(arg + 3, 0, 1e6, &held))) {
        fprintf(stderr, "zuml_b6_sim: not a press (BUTTON [HOLD|down|up [HELD]], BUTTON one of start stop inc "
                        "dec): %s%s%s\n", line, arg ? " " : "", arg ? arg : "");
        return;
    }
    for (k = 0; k < n_presses; k++)     /* this button's latest press that has not ended */
        if (presses[k].what == press.what && now < presses[k].at_s + presses[k].hold_s &&
            (last < 0 || presses[k].at_s > presses[last].at_s))
            last = k;
    for (k = 0; k < n_presses; k++)     /* the finger free: after every press down by then (a later one: anew) */
        if (presses[k].at_s <= free_at && free_at < presses[k].at_s + presses[k].hold_s + RELEASE_S) {
            free_at = presses[k].at_s + presses[k].hold_s + RELEASE_S;
            k = -1;
        }
    if (up) {
        if (last >= 0)
            presses[last].hold_s = fmax(now - presses[last].at_s, held);
        fprintf(stderr, "PRESS|%s|up|%.3f\n", button_names[press.what], now);
        return;
    }
    if (down)
        press.hold_s = 1e6;
    press.at_s = free_at;
    for (k = 0; k < n_presses && presses[k].at_s + presses[k].hold_s >= now; k++)
        ;
    if (k == MAX_EVENTS)
        return;
    presses[k] = press;
    if (k == n_presses)
        n_presses++;
    fprintf(stderr, "PRESS|%s|%.3f|%.3f\n", button_names[press.what], press.at_s, press.hold_s);
}

static void read_presses(void)
{
    static char line[48];
    static size_t n;
    struct pollfd in = {0, POLLIN, 0};
    char c;
    ssize_t got;
    while (poll(&in, 1, 0) == 1 && (in.revents & (POLLIN | POLLHUP))) {
        if ((got = read(0, &c, 1)) != 1) {
            if (got == 0 && end_with_stdin)
                stopping = 1;
            return;
        }
        if (c != '\n') {
            if (n < sizeof line - 1)
                line[n++] = c;
            continue;
        }
        line[n] = 0;
        n = 0;
        press_line(line);
    }
}

int main(int argc, char **argv)
{
    options_t o = {.cells = 3, .calibrated = 1, .capacity_mah = 2000, .soc = 0.2, .spread_mv = 0, .speed = 1};
    elf_firmware_t fw;
    avr_eeprom_desc_t d = {.ee = eeprom, .offset = 0, .size = EEPROM_SIZE};
    int out_fd, k;
    double start, next_save = 1.0;
    if (argc < 2 || argv[1][0] == '-') {
        fputs(usage, stderr);
        return 2;
    }
    memset(eeprom, 0xFF, sizeof eeprom);
    memset(lcd.ddram, ' ', sizeof lcd.ddram);
    if (!parse(argc, argv, &o))
        return 2;
    if (n_rxs && !rx_wire) {
        fail("--rx needs the receive wire", "--no-rx");
        return 2;
    }
    b6_model_init(&model, o.seed, o.cells, o.capacity_mah, o.soc, o.spread_mv);
    model.capacity_as[o.cells - 1] *= 1.0 - o.weak_pct / 100.0;     /* --weak-cell: the last cell */
    memcpy(saved, eeprom, EEPROM_SIZE);     /* as read: a calibration written below goes to the file too */
    /* a block already in the EEPROM file (a `zuml calibrate` of an earlier run) is the charger's own */
    if (!o.calibrated)
        b6_calibration_erase(eeprom, EEPROM_SIZE);
    else if (!b6_calibration_valid(eeprom, EEPROM_SIZE))
        b6_calibration_write(&model, eeprom, EEPROM_SIZE);
    model.no_lead = o.no_lead;              /* after the calibration: the board was calibrated with its lead */
    /* simavr talks on stdout; the first line of ours is the port alone */
    fflush(stdout);
    out_fd = dup(1);
    dup2(2, 1);
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(argv[1], &fw) != 0) {
        fprintf(stderr, "zuml_b6_sim: cannot read %s\n", argv[1]);
        return 1;
    }
    avr = avr_make_mcu_by_name("atmega32");
    if (!avr) {
        fprintf(stderr, "zuml_b6_sim: simavr has no atmega32\n");
        return 1;
    }
    avr_init(avr);
    sim_timer0_modes(avr);
    mcu_reset = avr->reset;
    avr->reset = on_reset;
    avr->frequency = F_CPU;
    /* simavr's references and inputs in units of 100 uV: finer than the pins' LSB, and 5 V still fits the
     * 16 bits simavr keeps an input in */
    avr->vcc = avr->avcc = (uint32_t)(B6_AVCC_V * 1e4);
    avr->aref = (uint32_t)floor(model.aref_v * 1e4 + 0.5);
    avr->log = LOG_ERROR;
    avr_load_firmware(avr, &fw);
    avr_ioctl(avr, AVR_IOCTL_EEPROM_SET, &d);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_OUT_TRIGGER), adc_trigger, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(B6_MUX_ADR0.port)),
                                          IOPORT_IRQ_REG_PORT), mux_pins_written, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(B6_MUX_Z.port)),
                                          IOPORT_IRQ_DIRECTION_ALL), mux_pins_written, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(B6_LCD_E.port)),
                                          B6_LCD_E.bit), lcd_enable, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(B6_BUZZER.port)),
                                          B6_BUZZER.bit), buzzer_pin, NULL);
    for (k = 0; k < 8; k++)
        adc_in[k] = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + k);
    for (k = 0; k < 4; k++)
        button_pin[k] = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(b6_button[k].port)),
                                      b6_button[k].bit);
    uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    rxd_pin = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(B6_PORT_LETTER(B6_BAL4_LOAD.port)), B6_BAL4_LOAD.bit);
    avr_cycle_timer_register(avr, STEP_CYCLES, step, NULL);
    avr_cycle_timer_register(avr, MUX_WATCH_CYCLES, mux_watch, NULL);
    set_buttons(0, 1);
    set_rxd(1);
    uart_pty_init(avr, &uart);
    uart_pty_connect(&uart, '0');
    if (!rx_wire)                       /* no wire from the PC: what it sends reaches nothing */
        avr_unconnect_irq(uart.irq + IRQ_UART_PTY_BYTE_OUT,
                          avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT));
    {
        /* simavr sleeps the host at every poll of an empty receiver: that would tie simulated time to the wall's */
        uint32_t flags = 0;
        avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
        flags &= ~(uint32_t)AVR_UART_FLAG_POLL_SLEEP;
        avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    }
    fflush(stdout);
    dup2(out_fd, 1);
    close(out_fd);
    /* before the port is out: a client that stops us at once still gets the EEPROM and the trace saved */
    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    printf("%s\n", uart.pty.slavename);
    fflush(stdout);
    fprintf(stderr, "ZUML firmware on a simulated iMAX B6 (simavr): %s, %d-cell LiPo, seed %llu, %s, EEPROM %s, %s\n",
            argv[1], o.cells, (unsigned long long)o.seed, o.calibrated ? "calibrated" : "uncalibrated",
            eeprom_path ? eeprom_path : "in memory", rx_wire ? "receive wire on PD0" : "TX only (no receive wire)");
    start = wall_s();
    while (!stopping) {
        /* a simulated millisecond at a time: the wall's clock is read once per ms, not per instruction */
        avr_cycle_count_t until = avr->cycle + F_CPU / 1000;
        int state;
        double sim;
        do {                            /* one instruction at a time while a hang waits for the main loop */
            state = avr_run(avr);
            watch_interrupts();
        } while (avr->cycle < until && !reset_seen && !hang_pending && parked == park_wanted() && state != cpu_Done &&
               state != cpu_Crashed);
        if (state == cpu_Done || state == cpu_Crashed) {
            fprintf(stderr, "zuml_b6_sim: the AVR stopped (state %d)\n", state);
            break;
        }
        if (reset_seen)
            after_reset();
        read_presses();
        if (hang_pending)
            hang_now();
        park_now();
        sim = now_s();
        if (o.speed > 0) {
            double ahead = sim / o.speed - (wall_s() - start);
            if (ahead > 0.002)
                usleep((useconds_t)(ahead * 1e6));
        }
        if (sim >= next_save) {
            next_save = sim + 1.0;
            save_eeprom();
            if (trace)
                fflush(trace);
        }
    }
    save_eeprom();
    fprintf(stderr, "INTERRUPTS|off|%.1f|%.3f|0x%x\n", off_max * 1e6 / F_CPU, off_max_at, (unsigned)off_max_pc);
    if (trace)
        fclose(trace);
    /* not uart_pty_stop(): it signals its thread and can wait for it forever; exiting ends it */
    return 0;
}
