/* The host board: the HAL backed by variables a test harness sets (through ctypes), so the core
 * runs on a PC against the same battery model as the Python interpreter. Built as libzuml_host.so. */
#include <string.h>
#include "../core/zuml.h"
#include "../core/text.h"
#include "host.h"

#define HOST_EEPROM 1024

static struct {
    hal_output_t out;
    int32_t pack_uv, current_ua, ocv_uv, battery_uc, heatsink_uc;
    uint8_t sensor;
    uint32_t millis;
    uint8_t eeprom[HOST_EEPROM];
    uint8_t music, light;
    uint8_t ceiling_cell;          /* the cell at the balancer's ceiling now, 0: none */
    int32_t ceiling_uv;
} hw;

static zc_run_t run;
/* the charger's start templates, as the harness sets them (index: number; [0] 0 = none) */
static uint8_t templates[256][1 + ZC_TEMPLATE_SIZE];
static void (*event_sink)(const zc_event_t *e);

void hal_output(const hal_output_t *out) { hw.out = *out; }
int32_t hal_pack_uv(void) { return hw.pack_uv; }
int32_t hal_current_ua(void) { return hw.current_ua; }
int32_t hal_open_circuit_uv(void) { return hw.ocv_uv; }
int32_t hal_battery_uc(void) { return hw.battery_uc; }
int32_t hal_heatsink_uc(void) { return hw.heatsink_uc; }
uint8_t hal_battery_sensor(void) { return hw.sensor; }
uint8_t hal_cell_count(void) { return 0; }
int32_t hal_cell_uv(uint8_t cell) { (void)cell; return 0; }
uint8_t hal_balancer_ceiling(int32_t *ceiling_uv)
{
    *ceiling_uv = hw.ceiling_uv;
    return hw.ceiling_cell;
}
uint32_t hal_millis(void) { return hw.millis; }
uint16_t hal_eeprom_size(void) { return HOST_EEPROM; }
uint8_t hal_eeprom_read(uint16_t addr) { return addr < HOST_EEPROM ? hw.eeprom[addr] : 0xFF; }
void hal_eeprom_write(uint16_t addr, uint8_t value) { if (addr < HOST_EEPROM) hw.eeprom[addr] = value; }
int16_t hal_uart_read(void) { return -1; }
void hal_uart_write(uint8_t byte) { (void)byte; }
void hal_buzzer(uint8_t melody) { hw.music = melody; }
void hal_led(uint8_t pattern) { hw.light = pattern; }
uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32])
{
    (void)request; (void)len; (void)answer;
    return 0;
}

void zc_event(const zc_event_t *e)
{
    if (event_sink)
        event_sink(e);
}

uint8_t zc_template(uint8_t number, zc_start_t *s)
{
    if (!templates[number][0])
        return 0;
    zc_template_apply(s, templates[number] + 1);
    return 1;
}

/* -- the harness's entry points ------------------------------------------------------------- */

uint8_t zh_start(const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b)
{
    memset(&hw.out, 0, sizeof hw.out);
    hw.sensor = 1;
    hw.ceiling_cell = 0;
    return zc_start(&run, rec, len, s, b);
}

/* Before the tick: the heat sink and the pack as they are now. Fills *out with the set point;
 * returns 2 when the coming reading needs the open-circuit voltage, 1 while running, 0 once over. */
uint8_t zh_control(int32_t heatsink_uc, int32_t pack_uv, int32_t battery_uc, hal_output_t *out)
{
    hw.heatsink_uc = heatsink_uc;
    hw.pack_uv = pack_uv;
    hw.battery_uc = battery_uc;
    zc_control(&run);
    *out = hw.out;
    if (run.finished)
        return 0;
    return (run.mode == M_PULSE && run.tv == 0) ? 2 : 1;
}

/* After the tick: what was measured. Returns 2 while the phase runs on, 1 when it has just ended
 * and the macro goes on, 0 once the macro is over. */
uint8_t zh_measure(int32_t pack_uv, int32_t current_ua, int32_t battery_uc, int32_t heatsink_uc, int32_t ocv_uv)
{
    hw.pack_uv = pack_uv;
    hw.current_ua = current_ua;
    hw.battery_uc = battery_uc;
    hw.heatsink_uc = heatsink_uc;
    hw.ocv_uv = ocv_uv;
    hw.millis += run.board.tick_ms;
    zc_measure(&run);
    return run.finished ? 0 : (run.active ? 2 : 1);
}

/* The balancer's ceiling and the cell at it (0: none) for the coming zh_measure. */
void zh_set_ceiling(uint8_t cell, int32_t ceiling_uv)
{
    hw.ceiling_cell = cell;
    hw.ceiling_uv = ceiling_uv;
}

/* The run's state, read by the engine (host/engine.c) that drives this board from C. */
const zc_run_t *zh_run(void) { return &run; }

void zh_stop(void) { zc_stop(&run); }

/* Start template `number` := t (ZC_TEMPLATE_SIZE bytes), or none when t is NULL. */
void zh_set_template(uint8_t number, const uint8_t *t)
{
    templates[number][0] = t != 0;
    if (t)
        memcpy(templates[number] + 1, t, ZC_TEMPLATE_SIZE);
}

/* The harness's function that receives every event as it happens. */
void zh_set_event_sink(void (*sink)(const zc_event_t *e)) { event_sink = sink; }

uint16_t zh_validate(const uint8_t *rec, uint16_t len) { return zc_validate(rec, len); }
int32_t zh_chemistry_end_uv(uint8_t akk_type) { return zc_chemistry_end_uv(akk_type); }
void zh_totals(int64_t *in_uams, int64_t *out_uams)
{
    *in_uams = (int64_t)run.total_in.uah * ZC_UAMS_PER_UAH + run.total_in.uams;
    *out_uams = (int64_t)run.total_out.uah * ZC_UAMS_PER_UAH + run.total_out.uams;
}

void zh_phase_counts(int64_t *in_uams, int64_t *out_uams)
{
    *in_uams = (int64_t)run.q_in.uah * ZC_UAMS_PER_UAH + run.q_in.uams;
    *out_uams = (int64_t)run.q_out.uah * ZC_UAMS_PER_UAH + run.q_out.uams;
}

/* The per-cell end voltage an empty discharge section runs to (the reason's text names it). */
int32_t zh_empty_end_uv(void)
{
    int32_t per_cell = zc_chemistry_end_uv(run.akk_type);
    return per_cell ? per_cell : run.board.fallback_end_uv_per_cell;
}

/* The text the device would report for an event (the differential test compares it with Python's). */
uint8_t zh_event_text(const zc_event_t *e, char *out) { return zc_event_text(&run, e, out); }
