/* The firmware on a PC: the whole device (protocol, store, interpreter) behind a pty, with a
 * simple battery on its output, so `zuml slots/flash/run/monitor` can talk to the C code as to a
 * charger. Prints the pty's path alone on the first line of stdout.
 *
 *   zuml_host [--eeprom FILE] [--cells N] [--capacity MAH] [--soc F] [--passport TYPE:V_LIMIT:A_LIMIT[:CRIT]]
 * (TYPE as the AKK_TYPE code; without --passport the battery has none). */
#define _XOPEN_SOURCE 600
#define _DEFAULT_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "../../core/app.h"
#include "../../core/pgm.h"
#include "../../sim_battery.h"

#define EEPROM_SIZE 1024

static int master = -1;
static uint8_t eeprom[EEPROM_SIZE];
static const char *eeprom_path;
static int eeprom_dirty;
static volatile sig_atomic_t stopping;
static hal_output_t out;
/* the battery: `cells` cells of a linear OCV 3.3..4.2 V over the state of charge, 50 mOhm each */
static double pack_v;
static uint8_t passport[32], has_passport;

static void seal(uint8_t *p)
{
    uint16_t check = 0;
    int k;
    for (k = 0; k < 0x1E; k += 2)
        check ^= (uint16_t)(p[k] | (p[k + 1] << 8));
    p[0x1E] = (uint8_t)check;
    p[0x1F] = (uint8_t)(check >> 8);
}

/* spec section 4: MAGIC, version, SERIAL, VENDOR, TYPE, ERR, CRIT, V_LIMIT, A_LIMIT, TEMP, check */
static void make_passport(int type, int v_limit, int a_limit, int crit)
{
    memset(passport, 0, sizeof passport);
    passport[0] = 0xA7;
    passport[1] = 0x01;
    memcpy(passport + 0x02, "ZUML-HOST-0001", 14);
    memcpy(passport + 0x12, "ZUML", 4);
    passport[0x16] = (uint8_t)type;
    passport[0x19] = (uint8_t)crit;
    passport[0x1A] = (uint8_t)(crit >> 8);
    passport[0x1B] = (uint8_t)v_limit;
    passport[0x1C] = (uint8_t)a_limit;
    passport[0x1D] = 25;
    seal(passport);
    has_passport = 1;
}

static void plant(double dt)
{
    double r = SIM_R_PER_CELL * cells, i;
    switch (out.kind) {
    case HAL_CURRENT: i = out.current_ua / 1e6; break;
    case HAL_VOLTAGE_CHARGE:
        i = (out.voltage_uv / 1e6 - ocv()) / r;
        i = i < 0 ? 0 : (i > out.current_ua / 1e6 ? out.current_ua / 1e6 : i);
        break;
    case HAL_VOLTAGE_DISCHARGE:
        i = (out.voltage_uv / 1e6 - ocv()) / r;
        i = i > 0 ? 0 : (i < -out.current_ua / 1e6 ? -out.current_ua / 1e6 : i);
        break;
    default: i = 0;
    }
    if (i > 5.0) i = 5.0;
    if (i < -1.0) i = -1.0;
    pack_v = battery_step(i, dt);
}

static unsigned long long boot_ms;

static uint32_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint32_t)(ts.tv_sec * 1000ULL + ts.tv_nsec / 1000000ULL - boot_ms);
}

void hal_output(const hal_output_t *o) { out = *o; }
int32_t hal_pack_uv(void) { return (int32_t)(pack_v * 1e6); }
int32_t hal_current_ua(void) { return (int32_t)(current_a * 1e6); }
int32_t hal_open_circuit_uv(void) { return (int32_t)(ocv() * 1e6); }
int32_t hal_battery_uc(void) { return 25000000L; }
int32_t hal_heatsink_uc(void) { return (int32_t)(heatsink_c * 1e6); }
uint8_t hal_battery_sensor(void) { return 1; }
uint8_t hal_cell_count(void) { return 0; }
int32_t hal_cell_uv(uint8_t cell) { (void)cell; return 0; }
uint32_t hal_millis(void) { return now_ms(); }
uint16_t hal_eeprom_size(void) { return EEPROM_SIZE; }
uint8_t hal_eeprom_read(uint16_t addr) { return addr < EEPROM_SIZE ? eeprom[addr] : 0xFF; }
void hal_eeprom_write(uint16_t addr, uint8_t value)
{
    if (addr < EEPROM_SIZE) {
        eeprom[addr] = value;
        eeprom_dirty = 1;
    }
}
void hal_buzzer(uint8_t melody) { (void)melody; }
void hal_led(uint8_t pattern) { (void)pattern; }
/* The battery's passport chip as protocol/passport.py's PassportChip (production, seed 003): 32 bytes
 * to every request, the passport or an error answer (MAGIC, 0xEE, code, RW_INDEX, PAGE, zeros,
 * check); pages 0..6; the charger may change only ERR and CRIT (0x17..0x1A). */
uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32])
{
    uint8_t x = 0, k, rw = len > 1 ? request[1] : 0, page = len > 2 ? request[2] : 0, code = 0;
    if (!has_passport)
        return 0;
    for (k = 0; k < 7 && k < len; k++)
        x ^= request[k];
    if (len != 8)
        code = 1;                       /* BAD_LENGTH */
    else if (request[0] != 0xA7)
        code = 2;                       /* BAD_MAGIC */
    else if (x != request[7])
        code = 3;                       /* BAD_XOR */
    else if (rw != 0 && (rw & 0xF0) != 0x10 && (rw & 0xF0) != 0x20)
        code = 4;                       /* BAD_COMMAND */
    else if (rw != 0 && ((rw & 0x0F) != page || page > 6))
        code = 5;                       /* BAD_PAGE */
    else if ((rw & 0xF0) == 0x20)
        for (k = 0; k < 4; k++) {
            uint8_t at = (uint8_t)(4 * page + k);
            int own = at <= 0x01 || at >= 0x1D, error_section = at >= 0x17 && at <= 0x1A;
            if (!own && passport[at] != request[3 + k] && !error_section)
                code = 6;               /* READ_ONLY: nothing is written */
        }
    if (code) {
        memset(answer, 0, 32);
        answer[0] = 0xA7;
        answer[1] = 0xEE;
        answer[2] = code;
        answer[3] = rw;
        answer[4] = page;
        seal(answer);
        return 1;
    }
    if ((rw & 0xF0) == 0x20) {
        for (k = 0; k < 4; k++)
            if (4 * page + k >= 0x17 && 4 * page + k <= 0x1A)
                passport[4 * page + k] = request[3 + k];
        seal(passport);
    }
    memcpy(answer, passport, 32);
    return 1;
}

int16_t hal_uart_read(void)
{
    uint8_t b;
    return read(master, &b, 1) == 1 ? b : -1;
}

void hal_uart_write(uint8_t byte)
{
    while (write(master, &byte, 1) != 1 && (errno == EAGAIN || errno == EINTR) && !stopping)
        usleep(100);
}

static void flush_eeprom(void)
{
    char tmp[4096];
    FILE *f;
    if (!eeprom_dirty || !eeprom_path)
        return;
    snprintf(tmp, sizeof tmp, "%s.tmp", eeprom_path);
    f = fopen(tmp, "wb");
    if (f && fwrite(eeprom, 1, EEPROM_SIZE, f) == EEPROM_SIZE && fclose(f) == 0 && rename(tmp, eeprom_path) == 0)
        eeprom_dirty = 0;
    else
        fprintf(stderr, "zuml_host: cannot write %s\n", eeprom_path);
}

static void on_signal(int sig) { (void)sig; stopping = 1; }


int main(int argc, char **argv)
{
    static const app_board_t board = {
        "ZUML firmware (host)", "zuml-fw 0.1", 5000, 500, 1000, 50, 26000, 0,
        {5000000L, 1000000L, 3000000L, 1000, 30, 300}
    };
    struct termios raw;
    int k, slave;
    uint32_t last;
    memset(eeprom, 0xFF, sizeof eeprom);
    boot_ms = now_ms();
    for (k = 1; k < argc; k++) {
        if (sim_option(argc, argv, &k, &eeprom_path, eeprom, EEPROM_SIZE)) {
            continue;
        } else if (!strcmp(argv[k], "--passport") && k + 1 < argc) {
            int type = 0, v = 0, a = 0, crit = 0;
            if (sscanf(argv[++k], "%d:%d:%d:%d", &type, &v, &a, &crit) < 3) {
                fprintf(stderr, "--passport TYPE:V_LIMIT:A_LIMIT[:CRIT]\n");
                return 2;
            }
            make_passport(type, v, a, crit);
        } else {
            fprintf(stderr, "usage: %s " SIM_OPTIONS " [--passport TYPE:V:A[:CRIT]]\n", argv[0]);
            return 2;
        }
    }
    master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) || unlockpt(master)) {
        perror("zuml_host: pty");
        return 1;
    }
    slave = open(ptsname(master), O_RDWR | O_NOCTTY);   /* kept open: hosts may come and go */
    tcgetattr(slave, &raw);
    cfmakeraw(&raw);
    tcsetattr(slave, TCSANOW, &raw);
    fcntl(master, F_SETFL, O_NONBLOCK);
    printf("%s\n", ptsname(master));
    fflush(stdout);
    fprintf(stderr, "ZUML firmware on the host: %d-cell battery, EEPROM %s\n", cells,
            eeprom_path ? eeprom_path : "in memory");
    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    pack_v = ocv();
    app_init(&board);
    last = now_ms();
    while (!stopping) {
        uint32_t t = now_ms();
        plant((t - last) / 1000.0);
        last = t;
        app_poll();
        flush_eeprom();
        usleep(500);
    }
    flush_eeprom();
    close(slave);
    return 0;
}
