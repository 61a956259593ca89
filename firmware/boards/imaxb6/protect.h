/* The protections no macro can lift (docs/firmware.md): each reading the ADC interrupt takes is
 * checked against the board's and the chemistry's limits; a limit that holds for PROTECT_DEBOUNCE
 * readings in a row trips, and a trip stays until the run ends. Pure C: the host tests build it. */
#ifndef B6_PROTECT_H
#define B6_PROTECT_H

#include <stdint.h>

enum {
    TRIP_NONE, TRIP_OVER_CURRENT, TRIP_PACK_MAX, TRIP_CELL1_MAX, TRIP_CELL6_MAX = TRIP_CELL1_MAX + 5,
    TRIP_NO_BATTERY, TRIP_REVERSED, TRIP_DISCONNECTED, TRIP_LEAD0, TRIP_LEAD6 = TRIP_LEAD0 + 6,
    TRIP_INPUT_LOW, TRIP_PROBE_HOT, TRIP_SINK_HOT, TRIP_PROBE_OPEN, TRIP_TIME, TRIP_CAPACITY, TRIP_HANG,
    TRIP_WATCHDOG, TRIP_UNCALIBRATED, TRIPS
};
#define PROTECT_DEBOUNCE 4
#define DISCONNECT_READINGS 16     /* Vout+ is read every 2.5 ms: 40 ms */

/* Board limits: cheali targets/imaxB6-original/HardwareConfig.h (5 A, 50 W, 27 V charge; 1 A, 5 W
 * discharge), trips 5 % above the limits the set points are clamped to. */
#define B6_CHARGE_MA 5000
#define B6_CHARGE_MW 50000L
#define B6_DISCHARGE_MA 1000
#define B6_DISCHARGE_MW 5000L
#define B6_MAX_MV 27000
#define TRIP_CHARGE_MA 5250
#define TRIP_DISCHARGE_MA 1050
#define TRIP_INPUT_MV 11000
#define TRIP_PRESENT_MV 500        /* below: no battery (start), disconnected (run) */
#define TRIP_REVERSED_MV 500       /* Vout- above: reversed */
#define TRIP_LEAD_MV 1000          /* Li: the pack and its cells' sum apart by more */
#define TRIP_PROBE_C100 6000
#define TRIP_SINK_C100 8000
#define SINK_AMBIENT_C100 2500     /* the heat-sink estimate: 25 degC + 2 K/W of the stage's losses, 60 s */
#define SINK_MW_PER_C100 5
#define SINK_STEPS 600             /* its time constant in 100 ms steps */
#define PROBE_PRESENT_C100 200     /* a probe reads at least 2 degC; an open input reads 0 */
#define PROBE_OPEN_LOW_C100 100
#define PROBE_OPEN_HIGH_C100 12000
#define CELL_PRESENT_MV 1000       /* a balance tap above this carries a cell */
#define CELL_MARGIN_MV 50          /* a cell trips this far below its chemistry's absolute maximum: a
                                    * tap reading's uncertainty (~1 %), so a cell at the maximum trips */

/* The inputs protect_reading knows (calib.h's order; the cells are computed from the taps). */
typedef struct {
    uint8_t armed;                 /* a run (or a calibration current) is on */
    uint8_t li_cells;              /* a Li macro with a balance lead: its cells; 0 without */
    uint8_t probe;                 /* a probe was there at the start */
    uint16_t pack_max_mv;
    uint16_t cell_max_mv;
} protect_limits_t;

extern protect_limits_t protect_limits;
extern volatile uint8_t protect_trip;  /* the first trip since protect_arm, TRIP_NONE while none */
extern volatile int16_t protect_latest[13];   /* each input's last reading: mV, mA, 0.01 degC */
extern volatile int16_t protect_cell_mv[6];
extern int32_t protect_sink_sum;       /* the heat sink's estimate x SINK_STEPS (the B6 has no sensor) */

/* Absolute maximum per cell of AKK_TYPE `akk_type` (spec section 5; firmware decisions for LiS,
 * Undef, New), mV. */
uint16_t protect_cell_max_mv(uint8_t akk_type);
uint8_t protect_is_li(uint8_t akk_type);
/* The balance port's cells: how many in a row from cell 1 carry a cell. */
uint8_t protect_balance_cells(void);
/* Why a run may not start on what the inputs read now (text in flash), NULL when it may; then the
 * limits are armed for `akk_type` and `cells` (0: unknown). */
const char *protect_arm(uint8_t akk_type, int16_t cells, uint8_t *trip);
void protect_disarm(void);
/* One reading of input `input` (calib.h); returns the trip it caused, TRIP_NONE else. */
uint8_t protect_reading(uint8_t input, int16_t value);
/* A trip found elsewhere (the stage, the main loop); the first one stays. */
void protect_raise(uint8_t trip);
/* Whether protect_trip is its final name: an over-current or a lost pack waits for one reading of Vout-,
 * which renames it `battery reversed` when that is what it was (the output is off meanwhile). */
uint8_t protect_named(void);
const char *protect_text(uint8_t trip);
/* One 100 ms step of the heat-sink estimate towards what `loss_mw` of the stage's losses hold it at; over
 * TRIP_SINK_C100 it trips (armed only). */
void protect_sink_step(int32_t loss_mw);
int32_t protect_sink_c100(void);      /* the estimate, 0.01 degC */

#endif
