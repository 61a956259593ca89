#include <string.h>
#include "protect.h"
#include "calib.h"
#include "stage.h"
#include "../../core/pgm.h"
#include "../../core/record.h"
#include "../../core/text.h"

protect_limits_t protect_limits;
volatile uint8_t protect_trip;
volatile int16_t protect_latest[CAL_INPUTS];
volatile int16_t protect_cell_mv[6];
/* Readings in a row per trip (those below TRIP_TIME), and the discharge current's own: the ADC reads the
 * charge current twice between two of its readings, and a shared count would start again at each of them
 * (the discharge's over-current would never trip). */
#define DISCHARGE_COUNT TRIP_TIME
static uint8_t count[TRIP_TIME + 1];
static uint8_t hang;                 /* ADC slots in a row without the main loop */
static volatile uint8_t refine;      /* Vout- readings left that may name the trip "battery reversed" */
int32_t protect_sink_sum = (int32_t)SINK_AMBIENT_C100 * SINK_STEPS;

uint16_t protect_cell_max_mv(uint8_t akk_type)
{
    /* Undef, Pb, NiCd, NiMh, LiPo, LiIon, LiS, LiFe, New: docs/zuml-2.0.md section 5's absolute maxima; LiS 2.80 V
     * and Undef/New at the highest of any chemistry are the firmware's decisions (docs/firmware.md) */
    static const uint16_t max_mv[9] PROGMEM = {4350, 2500, 1800, 1800, 4350, 4250, 2800, 3700, 4350};
    uint16_t mv = 4350;
    if (akk_type < 9)
        memcpy_P(&mv, &max_mv[akk_type], sizeof mv);
    return mv;
}

uint8_t protect_is_li(uint8_t akk_type) { return akk_type >= 4 && akk_type <= 7; }

uint8_t protect_balance_cells(void)
{
    uint8_t n = 0;
    while (n < 6 && protect_cell_mv[n] > CELL_PRESENT_MV)
        n++;
    return n;
}

/* A cell's voltage at rest, lowest and highest (mV; docs/firmware.md, The check at START, says why), into
 * w; 0 for a chemistry that has none (Undef, New). */
static uint8_t rest_window(uint8_t akk_type, uint16_t w[2])
{
    /* Undef, Pb, NiCd, NiMh, LiPo, LiIon, LiS, LiFe, New */
    static const uint16_t rest_mv[9][2] PROGMEM = {
        {0, 0}, {1800, 2300}, {1000, 1500}, {1000, 1500}, {3000, 4300}, {2500, 4200}, {1700, 2750}, {2500, 3650},
        {0, 0},
    };
    w[1] = 0;
    if (akk_type < 9)   /* a row's first element, not the row: the host build traps on the row past the table */
        memcpy_P(w, &rest_mv[akk_type][0], 2 * sizeof *w);
    return w[1] != 0;
}

int16_t protect_cells_at_rest(uint8_t akk_type, int16_t mv)
{
    uint16_t w[2];
    int16_t n;
    if (mv <= 0 || !rest_window(akk_type, w))
        return 0;
    n = (int16_t)(((uint16_t)mv + w[1] - 1) / w[1]);
    return (int32_t)n * w[0] <= mv && (int32_t)n * protect_cell_max_mv(akk_type) <= B6_MAX_MV ? n : 0;
}

uint16_t protect_time_limit_min(const uint8_t *rec)
{
    uint8_t at, size, has_tm = 0;
    uint32_t run = 0, phases = 0, x;
    for (at = rec[1]; at < rec[0] - 1; at = (uint8_t)(at + size)) {   /* rec[1]: the first instruction */
        /* IF(tm>x) bounds the run, IF(tf>x) its phase: x in tenths of a second (docs/zuml-2.0.md section 3),
         * taken at most up to the ceiling, so the sum of 50 of them still fits */
        if (rec[at] == OP_IF_TM_GT || rec[at] == OP_IF_TF_GT) {
            x = zc_u32(rec + at + 1);
            if (x > TIME_CEILING_MIN * 600UL)
                x = TIME_CEILING_MIN * 600UL;
            if (rec[at] == OP_IF_TF_GT)
                phases += x;
            else if (x > run)
                run = x;
            has_tm |= rec[at] == OP_IF_TM_GT;
        }
        size = zc_op_size(rec[at]);
        if (!size)
            break;
    }
    run = ((has_tm ? run : phases) + 599) / 600 + TIME_MARGIN_MIN;   /* minutes, a started one counted */
    return run < TIME_LIMIT_MIN ? TIME_LIMIT_MIN : (run > TIME_CEILING_MIN ? TIME_CEILING_MIN : (uint16_t)run);
}

uint32_t protect_capacity_limit_uah(int32_t capacity_mah)
{
    uint32_t uah = capacity_mah > 0 ? (uint32_t)capacity_mah * 2000UL : CAPACITY_LIMIT_UAH;
    return uah > CAPACITY_CEILING_UAH ? CAPACITY_CEILING_UAH : uah;
}

uint8_t protect_run_limits(uint32_t time_ms, uint16_t time_limit_min, uint32_t in_uah, uint32_t capacity_limit_uah)
{
    if (time_ms > time_limit_min * 60000UL)
        return TRIP_TIME;
    return in_uah > capacity_limit_uah ? TRIP_CAPACITY : TRIP_NONE;
}

static char *put_mv(char *p, int16_t mv) { return zc_put_P(zc_put_2f(p, (uint32_t)mv * 1000UL), PSTR(" V")); }

const char *protect_arm(uint8_t akk_type, int16_t cells, uint8_t *trip, char *sentence)
{
    uint8_t balance = protect_balance_cells(), li = protect_is_li(akk_type), k, high = 0;
    uint16_t cell_max = protect_cell_max_mv(akk_type), cell_trip = (uint16_t)(cell_max - CELL_MARGIN_MV);
    int16_t vout = protect_latest[CAL_VOUT], vin = protect_latest[CAL_VIN];
    int32_t pack_max = B6_MAX_MV;
    char *p = sentence;
    for (k = 1; k < balance; k++)
        if (protect_cell_mv[k] > protect_cell_mv[high])
            high = k;
    /* the count given (SERIES, the PC, the panel, a template), else the balance lead's, else the rest
     * voltage's: no run without one */
    if (cells <= 0)
        cells = balance ? balance : protect_cells_at_rest(akk_type, vout);
    if ((int32_t)cells * cell_max < pack_max)
        pack_max = (int32_t)cells * cell_max;
    *trip = TRIP_NONE;
    if (protect_latest[CAL_VOUT_MINUS] > TRIP_REVERSED_MV)
        *trip = TRIP_REVERSED;
    else if (vout < TRIP_PRESENT_MV)
        *trip = TRIP_NO_BATTERY;
    else if (vin < TRIP_INPUT_MV)
        *trip = TRIP_INPUT_LOW;
    else if (balance && protect_cell_mv[high] > (int16_t)cell_trip)
        /* the balance lead is evidence for every chemistry: lithium cells refuse a nickel or lead macro */
        *trip = (uint8_t)(!li && protect_cell_mv[high] > LITHIUM_CELL_MV ? TRIP_LITHIUM : TRIP_CELL1_MAX + high);
    else if (balance && cells != balance)
        *trip = (uint8_t)(TRIP_LEAD0 + balance);
    else if (cells <= 0)
        *trip = TRIP_CELL_COUNT;
    else if (vout > pack_max)
        *trip = TRIP_PACK_MAX;
    else if ((int32_t)vout > (int32_t)vin * BOOST_REACH - REACH_MARGIN_MV)
        *trip = TRIP_OUT_OF_REACH;
    if (*trip) {
        if (p && (*trip == TRIP_LITHIUM || (*trip >= TRIP_CELL1_MAX && *trip <= TRIP_CELL6_MAX))) {
            /* "the balance lead shows 3 cells up to 4.14 V: a lithium pack; this macro is for NiMh" */
            p = put_mv(zc_put_P(zc_put_uint(zc_put_P(p, PSTR("the balance lead shows ")), balance),
                                PSTR(" cells up to ")), protect_cell_mv[high]);
            if (*trip == TRIP_LITHIUM)
                p = zc_put_akk(zc_put_P(p, PSTR(": a lithium pack; this macro is for ")), akk_type);
            else
                p = zc_put_P(put_mv(zc_put_P(zc_put_akk(zc_put_P(p, PSTR(": over ")), akk_type), PSTR("'s ")),
                                    (int16_t)cell_trip), PSTR(" a cell"));
            *p = 0;
        } else if (p && *trip == TRIP_CELL_COUNT) {
            /* "no cell count: 1.70 V fits no whole number of NiMh cells (1.00..1.50 V each at rest)" */
            uint16_t w[2];
            p = zc_put_P(p, PSTR("no cell count: "));
            if (rest_window(akk_type, w)) {
                p = zc_put_akk(zc_put_P(put_mv(p, vout), PSTR(" fits no whole number of ")), akk_type);
                p = zc_put_P(zc_put_2f(zc_put_P(p, PSTR(" cells (")), w[0] * 1000UL), PSTR(".."));
                p = zc_put_P(put_mv(p, (int16_t)w[1]), PSTR(" each at rest)"));
            } else {
                p = zc_put_P(zc_put_akk(p, akk_type), PSTR(" cells cannot be counted from the voltage"));
            }
            *p = 0;
        } else if (p && *trip == TRIP_PACK_MAX) {
            /* "the pack reads 12.42 V: over 5.40 V, the ceiling of 3 NiMh cells" */
            p = put_mv(zc_put_P(put_mv(zc_put_P(p, PSTR("the pack reads ")), vout), PSTR(": over ")),
                       (int16_t)pack_max);
            p = zc_put_akk(zc_put_P(zc_put_uint(zc_put_P(p, PSTR(", the ceiling of ")), (uint32_t)cells), PSTR(" ")),
                           akk_type);
            *zc_put_P(p, PSTR(" cells")) = 0;
        } else if (p && *trip == TRIP_OUT_OF_REACH) {
            /* "the stage cannot reach the pack's 24.60 V from 12.00 V in: at most twice the input" */
            p = put_mv(zc_put_P(put_mv(zc_put_P(p, PSTR("the stage cannot reach the pack's ")), vout),
                                PSTR(" from ")), vin);
            *zc_put_P(p, PSTR(" in: at most twice the input")) = 0;
        }
        return protect_text(*trip);
    }
    protect_disarm();
    protect_limits.li_cells = li ? balance : 0;
    protect_limits.lead_cells = balance;
    protect_limits.probe = protect_latest[CAL_TEXTERN] >= PROBE_PRESENT_C100 &&
                           protect_latest[CAL_TEXTERN] <= PROBE_OPEN_HIGH_C100;
    protect_limits.pack_max_mv = (uint16_t)pack_max;
    protect_limits.cell_max_mv = cell_trip;
    protect_limits.armed = 1;
    return 0;
}

void protect_disarm(void)
{
    protect_limits.armed = 0;
    protect_trip = TRIP_NONE;
    refine = 0;
    memset(count, 0, sizeof count);
}

void protect_raise(uint8_t trip)
{
    if (protect_limits.armed && !protect_trip) {
        protect_trip = trip;
        refine = REFINE_READINGS;
    }
}

uint8_t protect_settled(void) { return !refine; }

/* `holds` for this reading: one more in count[at] (a trip after `readings` in a row), or the row starts again. */
static void counted(uint8_t at, uint8_t trip, uint8_t holds, uint8_t readings)
{
    if (!holds) {
        count[at] = 0;
    } else if (++count[at] >= readings) {
        /* limits that follow from another one name it: a reversed or lost pack also breaks the pack's,
         * the lead's and the cells' limits, and the more specific reason is the one a user can act on */
        if (count[TRIP_REVERSED])
            trip = TRIP_REVERSED;
        else if (count[TRIP_DISCONNECTED] && trip != TRIP_OVER_CURRENT && trip != TRIP_INPUT_LOW &&
                 trip < TRIP_PROBE_HOT)
            trip = TRIP_DISCONNECTED;
        protect_raise(trip);
    }
}

static void condition_after(uint8_t trip, uint8_t holds, uint8_t readings) { counted(trip, trip, holds, readings); }
static void condition(uint8_t trip, uint8_t holds) { condition_after(trip, holds, PROTECT_DEBOUNCE); }

static void cell(uint8_t k, int16_t mv)
{
    protect_cell_mv[k] = mv;
    if (k < protect_limits.lead_cells)
        condition((uint8_t)(TRIP_CELL1_MAX + k), mv > (int16_t)protect_limits.cell_max_mv);
}

static void cells(uint8_t input, int16_t value)
{
    /* cell 1 = Vb1 - Vb0, cell 2 = Vb2 - Vb1 (taps to ground), cells 3..6 measured alone; a cell is
     * checked when a reading of its own changes it */
    if (input <= CAL_VB1)
        cell(0, (int16_t)(protect_latest[CAL_VB1] - protect_latest[CAL_VB0]));
    if (input == CAL_VB1 || input == CAL_VB2)
        cell(1, (int16_t)(protect_latest[CAL_VB2] - protect_latest[CAL_VB1]));
    if (input >= CAL_VB3)
        cell((uint8_t)(input - CAL_VB1), value);
    if (input == CAL_VB6 && protect_limits.lead_cells) {
        uint8_t n = protect_balance_cells();
        condition((uint8_t)(TRIP_LEAD0 + n), n != protect_limits.lead_cells);
    }
}

uint8_t protect_reading(uint8_t input, int16_t value)
{
    const protect_limits_t *l = &protect_limits;
    protect_latest[input] = value;
    if (!l->armed || protect_trip) {
        if (input >= CAL_VB0 && input <= CAL_VB6)
            cells(input, value);      /* kept up to date for the start's checks and the readout */
        if (input == CAL_VOUT_MINUS && refine) {
            /* the output went off on the first trip; behind the open switch a reversed pack shows, and
             * that is the reason a user can act on */
            refine--;
            if (value > TRIP_REVERSED_MV) {
                protect_trip = TRIP_REVERSED;
                refine = 0;
            }
        }
        return protect_trip;
    }
    if (input >= CAL_VB0 && input <= CAL_VB6)
        cells(input, value);
    switch (input) {
    case CAL_ISMPS: condition(TRIP_OVER_CURRENT, value > TRIP_CHARGE_MA); break;
    case CAL_IDIS: counted(DISCHARGE_COUNT, TRIP_OVER_CURRENT, value > TRIP_DISCHARGE_MA, PROTECT_DEBOUNCE); break;
    case CAL_VOUT_MINUS: condition(TRIP_REVERSED, value > TRIP_REVERSED_MV); break;
    case CAL_VIN: condition(TRIP_INPUT_LOW, value < TRIP_INPUT_MV); break;
    case CAL_VOUT: {
        int16_t sum = 0, d;
        uint8_t k;
        condition(TRIP_PACK_MAX, value > (int16_t)l->pack_max_mv);
        for (k = 0; k < l->lead_cells; k++)
            sum = (int16_t)(sum + protect_cell_mv[k]);
        d = (int16_t)(value - sum);
        /* a reversed pack also pulls Vout+ down: it trips here, and the Vout- readings after the output
         * is off name it (refine) */
        condition_after(TRIP_DISCONNECTED, protect_latest[CAL_VOUT_MINUS] <= TRIP_REVERSED_MV &&
                        (value < TRIP_PRESENT_MV || value < (int16_t)(l->pack_max_mv / LOST_FRACTION) ||
                         (l->lead_cells && (d > TRIP_LEAD_MV || d < -TRIP_LEAD_MV))), LOST_READINGS);
        break;
    }
    case CAL_TEXTERN:
        if (l->probe) {
            uint8_t open = value < PROBE_OPEN_LOW_C100 || value > PROBE_OPEN_HIGH_C100;
            condition(TRIP_PROBE_OPEN, open);
            condition(TRIP_PROBE_HOT, !open && value > TRIP_PROBE_C100);
        }
        break;
    }
    return protect_trip;
}

const char *protect_text(uint8_t trip)
{
    static const char texts[TRIPS][27] PROGMEM = {
        "", "over current", "pack over max", "cell 1 over max", "cell 2 over max", "cell 3 over max",
        "cell 4 over max", "cell 5 over max", "cell 6 over max", "no battery", "battery reversed",
        "battery disconnected", "balance lead 0 cells", "balance lead 1 cells", "balance lead 2 cells",
        "balance lead 3 cells", "balance lead 4 cells", "balance lead 5 cells", "balance lead 6 cells",
        "input below 11V", "probe over 60C", "heat sink over 80C", "probe open", "time limit",
        "capacity limit", "main loop hang", "watchdog reset", "not calibrated", "lithium pack", "no cell count",
        "pack above twice the input",
    };
    return texts[trip < TRIPS ? trip : 0];
}

/* The estimate kept as its sum over the time constant: a step of (target - estimate) / SINK_STEPS in 0.01 degC
 * would stop up to 6 K short of its target. */
void protect_sink_step(int32_t loss_mw)
{
    protect_sink_sum += SINK_AMBIENT_C100 + loss_mw / SINK_MW_PER_C100 - protect_sink_sum / SINK_STEPS;
    if (protect_sink_c100() > TRIP_SINK_C100)
        protect_raise(TRIP_SINK_HOT);
}

int32_t protect_sink_c100(void) { return protect_sink_sum / SINK_STEPS; }

int32_t protect_loss_mw(uint8_t mode, int16_t v_mv, int16_t i_ma)
{
    int32_t p = (int32_t)v_mv * i_ma / 1000;
    return mode == STAGE_CHARGE ? p / 10 : (mode == STAGE_DISCHARGE ? p : 0);
}

uint8_t protect_starved(volatile uint16_t *run, int16_t i_ma, int16_t set_ma, uint8_t boosting, int16_t v_mv,
                        int16_t vin_mv)
{
    if (i_ma < set_ma / 4) {
        if (++*run >= STARVED_READINGS)   /* a pack the boost cannot reach takes nothing either */
            return boosting && (int32_t)v_mv > (int32_t)vin_mv * BOOST_REACH - REACH_MARGIN_MV ? TRIP_OUT_OF_REACH
                                                                                               : TRIP_DISCONNECTED;
    } else {
        *run = 0;
    }
    return TRIP_NONE;
}

uint8_t protect_loop_slot(uint8_t loop_ran)
{
    if (loop_ran) {
        hang = 0;
    } else if (++hang >= HANG_READINGS) {
        hang = HANG_READINGS;             /* held there: the count cannot wrap round to a live loop */
        protect_raise(TRIP_HANG);
        return 1;
    }
    return 0;
}
