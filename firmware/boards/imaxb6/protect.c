#include <string.h>
#include "protect.h"
#include "calib.h"
#include "../../core/pgm.h"

protect_limits_t protect_limits;
volatile uint8_t protect_trip;
volatile int16_t protect_latest[CAL_INPUTS];
volatile int16_t protect_cell_mv[6];
int32_t protect_sink_sum = (int32_t)SINK_AMBIENT_C100 * SINK_STEPS;
/* Readings in a row per trip, and the discharge current's own: the ADC reads the charge current twice between
 * two of its readings, and a shared count would start again at each of them (the discharge's over-current
 * would never trip). */
#define DISCHARGE_COUNT TRIPS
#define NAMED TRIP_NONE              /* count[NAMED]: Vout- has been read since the trip */
static uint8_t count[TRIPS + 1];

uint16_t protect_cell_max_mv(uint8_t akk_type)
{
    /* Undef, Pb, NiCd, NiMh, LiPo, LiIon, LiS, LiFe, New: spec section 5's absolute maxima; LiS 2.80 V
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

const char *protect_arm(uint8_t akk_type, int16_t cells, uint8_t *trip)
{
    uint8_t balance = protect_balance_cells(), li = protect_is_li(akk_type), k;
    uint16_t cell_max = protect_cell_max_mv(akk_type);
    int32_t pack_max = B6_MAX_MV;
    if (li && balance && cells <= 0)
        cells = balance;
    if (cells > 0 && (int32_t)cells * cell_max < pack_max)
        pack_max = (int32_t)cells * cell_max;
    *trip = TRIP_NONE;
    if (protect_latest[CAL_VOUT_MINUS] > TRIP_REVERSED_MV)
        *trip = TRIP_REVERSED;
    else if (protect_latest[CAL_VOUT] < TRIP_PRESENT_MV)
        *trip = TRIP_NO_BATTERY;
    else if (protect_latest[CAL_VIN] < TRIP_INPUT_MV)
        *trip = TRIP_INPUT_LOW;
    else if (li && balance && cells != balance)
        *trip = (uint8_t)(TRIP_LEAD0 + balance);
    else if (protect_latest[CAL_VOUT] > pack_max)
        *trip = TRIP_PACK_MAX;
    for (k = 0; !*trip && li && k < balance; k++)
        if (protect_cell_mv[k] > (int16_t)(cell_max - CELL_MARGIN_MV))
            *trip = (uint8_t)(TRIP_CELL1_MAX + k);
    if (*trip)
        return protect_text(*trip);
    protect_disarm();
    protect_limits.li_cells = li ? balance : 0;
    protect_limits.probe = protect_latest[CAL_TEXTERN] >= PROBE_PRESENT_C100 &&
                           protect_latest[CAL_TEXTERN] <= PROBE_OPEN_HIGH_C100;
    protect_limits.pack_max_mv = (uint16_t)pack_max;
    protect_limits.cell_max_mv = (uint16_t)(cell_max - CELL_MARGIN_MV);
    protect_limits.armed = 1;
    return 0;
}

void protect_disarm(void)
{
    protect_limits.armed = 0;
    protect_trip = TRIP_NONE;
    memset(count, 0, sizeof count);
}

void protect_raise(uint8_t trip)
{
    if (protect_limits.armed && !protect_trip)
        protect_trip = trip;
}

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
    if (k < protect_limits.li_cells)
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
    if (input == CAL_VB6 && protect_limits.li_cells) {
        uint8_t n = protect_balance_cells();
        condition((uint8_t)(TRIP_LEAD0 + n), n != protect_limits.li_cells);
    }
}

uint8_t protect_reading(uint8_t input, int16_t value)
{
    const protect_limits_t *l = &protect_limits;
    protect_latest[input] = value;
    if (protect_trip && input == CAL_VOUT_MINUS) {
        /* a reversed pack trips first on its current (or its lost voltage), before Vout- is read: the
         * output is off at once, the name follows from this reading */
        if (value > TRIP_REVERSED_MV && (protect_trip == TRIP_OVER_CURRENT || protect_trip == TRIP_DISCONNECTED))
            protect_trip = TRIP_REVERSED;
        count[NAMED] = 1;
    }
    if (!l->armed || protect_trip) {
        if (input >= CAL_VB0 && input <= CAL_VB6)
            cells(input, value);      /* kept up to date for the start's checks and the readout */
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
        for (k = 0; k < l->li_cells; k++)
            sum = (int16_t)(sum + protect_cell_mv[k]);
        d = (int16_t)(value - sum);
        /* a reversed pack also reads no voltage at Vout+: Vout- (read 2.5 x less often) names it first,
         * so no voltage trips only after DISCONNECT_READINGS */
        condition_after(TRIP_DISCONNECTED, protect_latest[CAL_VOUT_MINUS] <= TRIP_REVERSED_MV &&
                        (value < TRIP_PRESENT_MV || (l->li_cells && (d > TRIP_LEAD_MV || d < -TRIP_LEAD_MV))),
                        DISCONNECT_READINGS);
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

uint8_t protect_named(void)
{
    return count[NAMED] || (protect_trip != TRIP_OVER_CURRENT && protect_trip != TRIP_DISCONNECTED);
}

const char *protect_text(uint8_t trip)
{
    static const char texts[TRIPS][21] PROGMEM = {
        "", "over current", "pack over max", "cell 1 over max", "cell 2 over max", "cell 3 over max",
        "cell 4 over max", "cell 5 over max", "cell 6 over max", "no battery", "battery reversed",
        "battery disconnected", "balance lead 0 cells", "balance lead 1 cells", "balance lead 2 cells",
        "balance lead 3 cells", "balance lead 4 cells", "balance lead 5 cells", "balance lead 6 cells",
        "input below 11V", "probe over 60C", "heat sink over 80C", "probe open", "time limit",
        "capacity limit", "main loop hang", "watchdog reset", "not calibrated",
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
