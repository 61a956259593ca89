/* The ATmega32 image (build/atmega32/zuml.elf) on simavr: its USART on a pty, its ADC answered from
 * a simple battery on the power stage its PWM drives, its EEPROM kept in a file. Prints the pty's
 * path alone on the first line of stdout, like `zuml virtual-charger`.
 *
 *   zuml_avr_sim ELF [--eeprom FILE] [--cells N] [--capacity MAH] [--soc F] */
#define _DEFAULT_SOURCE
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "sim_avr.h"
#include "sim_elf.h"
#include "avr_adc.h"
#include "avr_eeprom.h"
#include "parts/uart_pty.h"
#include "sim_battery.h"
#include "sim_eeprom.h"
#include "sim_timer0.h"

#define F_CPU 16000000UL
#define EEPROM_SIZE 1024
/* Timer1's compare registers in data space (ATmega32: OCR1A 0x4A/0x4B, OCR1B 0x48/0x49) */
#define OCR1A_L 0x4A
#define OCR1B_L 0x48
#define PWM_TOP 1023.0

static avr_t *avr;
static uart_pty_t uart;
static volatile sig_atomic_t stopping;
static const char *eeprom_path;
static uint8_t eeprom[EEPROM_SIZE], saved[EEPROM_SIZE];
static double last_s;

static uint16_t reg16(uint16_t low) { return (uint16_t)(avr->data[low] | (avr->data[low + 1] << 8)); }

/* The power stage as the board's calibration assumes it: duty/TOP of 5 A charging, of 1 A
 * discharging; the battery integrates its charge. */
static double pack_voltage(void)
{
    double now = (double)avr->cycle / F_CPU, dt = now - last_s;
    double current = reg16(OCR1A_L) / PWM_TOP * 5.0 - reg16(OCR1B_L) / PWM_TOP * 1.0;
    last_s = now;
    return battery_step(current, dt);
}

static uint32_t scaled_mv(double value, double full_scale)
{
    double mv = value / full_scale * 5000.0;
    return (uint32_t)(mv < 0 ? 0 : (mv > 5000 ? 5000 : mv));
}

/* The ADC asks for channel mux.src: answer in millivolts on the 5 V reference. */
static void adc_trigger(struct avr_irq_t *irq, uint32_t value, void *param)
{
    union { avr_adc_mux_t mux; uint32_t v; } e = {.v = value};
    uint32_t mv = 0;
    double v = pack_voltage();
    (void)irq; (void)param;
    switch (e.mux.src) {
    case 0: mv = scaled_mv(v, 25.6); break;
    case 1: mv = scaled_mv(current_a > 0 ? current_a : 0, 5.0); break;
    case 2: mv = scaled_mv(current_a < 0 ? -current_a : 0, 1.0); break;
    case 3: mv = scaled_mv(100.0 - 25.0, 100.0); break;
    case 4: mv = scaled_mv(100.0 - heatsink_c, 100.0); break;
    default: break;
    }
    avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_ADC0 + e.mux.src), mv);
}

static void save_eeprom(void)
{
    sim_eeprom_save(avr, eeprom, saved, EEPROM_SIZE, eeprom_path, "zuml_avr_sim");
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec / 1e9;
}

static void on_signal(int sig) { (void)sig; stopping = 1; }

int main(int argc, char **argv)
{
    elf_firmware_t fw;
    avr_eeprom_desc_t d = {.ee = eeprom, .offset = 0, .size = EEPROM_SIZE};
    int k, out_fd;
    double start, next_save = 1.0;
    if (argc < 2) {
        fprintf(stderr, "usage: %s ELF " SIM_OPTIONS "\n", argv[0]);
        return 2;
    }
    memset(eeprom, 0xFF, sizeof eeprom);
    for (k = 2; k < argc; k++) {
        if (!sim_option(argc, argv, &k, &eeprom_path, eeprom, EEPROM_SIZE)) {
            fprintf(stderr, "zuml_avr_sim: unknown option %s\n", argv[k]);
            return 2;
        }
    }
    memcpy(saved, eeprom, EEPROM_SIZE);
    /* simavr talks on stdout; the first line of ours is the port alone */
    fflush(stdout);
    out_fd = dup(1);
    dup2(2, 1);
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(argv[1], &fw) != 0) {
        fprintf(stderr, "zuml_avr_sim: cannot read %s\n", argv[1]);
        return 1;
    }
    avr = avr_make_mcu_by_name("atmega32");
    if (!avr) {
        fprintf(stderr, "zuml_avr_sim: simavr has no atmega32\n");
        return 1;
    }
    avr_init(avr);
    sim_timer0_modes(avr);
    avr->frequency = F_CPU;
    avr->vcc = avr->avcc = avr->aref = 5000;
    avr->log = LOG_ERROR;
    avr_load_firmware(avr, &fw);
    avr_ioctl(avr, AVR_IOCTL_EEPROM_SET, &d);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, ADC_IRQ_OUT_TRIGGER), adc_trigger, NULL);
    uart_pty_init(avr, &uart);
    uart_pty_connect(&uart, '0');
    fflush(stdout);
    dup2(out_fd, 1);
    close(out_fd);
    printf("%s\n", uart.pty.slavename);
    fflush(stdout);
    fprintf(stderr, "ZUML firmware on a simulated ATmega32 (simavr): %s, %d-cell battery, EEPROM %s\n", argv[1],
            cells, eeprom_path ? eeprom_path : "in memory");
    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    start = wall_s();
    while (!stopping) {
        int state = avr_run(avr);
        double sim = (double)avr->cycle / F_CPU, ahead;
        if (state == cpu_Done || state == cpu_Crashed) {
            fprintf(stderr, "zuml_avr_sim: the AVR stopped (state %d)\n", state);
            break;
        }
        ahead = sim - (wall_s() - start);
        if (ahead > 0.002)
            usleep((useconds_t)(ahead * 1e6));         /* the AVR's clock keeps to the wall's */
        if (sim >= next_save) {
            next_save = sim + 1.0;
            save_eeprom();
        }
    }
    save_eeprom();
    /* not uart_pty_stop(): it signals its thread and can wait for it forever; exiting ends it */
    return 0;
}
