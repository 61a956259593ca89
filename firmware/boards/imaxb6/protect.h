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
    TRIP_WATCHDOG, TRIP_UNCALIBRATED, TRIP_LITHIUM, TRIP_CELL_COUNT, TRIP_OUT_OF_REACH, TRIPS
};
#define PROTECT_DEBOUNCE 4
#define LOST_READINGS 3            /* Vout+ is read every 2.5 ms: a lost or reversed pack is off within 8 ms */
#define LOST_FRACTION 4            /* a pack below 1/4 of its ceiling is lost: its cells at a quarter of
                                    * their maximum, far below any under a discharge's load (1.09 V a
                                    * LiPo cell, 0.45 V a NiMh one); a pack reversed mid-charge pulls the
                                    * output there within a millisecond */
#define REFINE_READINGS 4          /* Vout- readings after a trip (6.25 ms apart) that may still name it
                                    * "battery reversed": the output is off, and a reversed pack shows */

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
#define TIME_LIMIT_MIN (12U * 60U)      /* a run without a longer IF(tm>x)/IF(tf>x): 12 h */
#define TIME_MARGIN_MIN 60U              /* past the macro's longest time condition */
#define TIME_CEILING_MIN (24U * 60U)     /* whatever the macro says */
#define CAPACITY_LIMIT_UAH 10000000UL    /* the charge into a run without a capacity: 10 Ah */
#define CAPACITY_CEILING_UAH 50000000UL  /* 2 x the capacity, at most 50 Ah: the B6's 5 A for 10 h */
#define SINK_AMBIENT_C100 2500     /* the heat-sink estimate: 25 degC + 2 K/W of the stage's losses, 60 s */
#define SINK_MW_PER_C100 5
#define SINK_STEPS 600             /* its time constant in 100 ms steps */
#define PROBE_PRESENT_C100 200     /* a probe reads at least 2 degC; an open input reads 0 */
#define PROBE_OPEN_LOW_C100 100
#define PROBE_OPEN_HIGH_C100 12000
#define CELL_PRESENT_MV 1000       /* a balance tap above this carries a cell */
#define CELL_MARGIN_MV 50          /* a cell trips this far below its chemistry's absolute maximum: a
                                    * tap reading's uncertainty (~1 %), so a cell at the maximum trips */
#define LITHIUM_CELL_MV 2500       /* a cell on the balance lead above this is lithium: Pb's absolute
                                    * maximum, the highest of the lead and nickel chemistries */
#define BOOST_REACH 2              /* the stage reaches at most twice its input (50 % boost, cheali) */
#define REACH_MARGIN_MV 500        /* ... less the charge current's drop in the leads and the stage */
#define STARVED_READINGS 400       /* the regulator's duty at its top with less than a quarter of its current:
                                    * no battery takes it (0.5 s of current readings at ~800/s) */
#define HANG_READINGS 160          /* ADC slots without the main loop: 62 ms on the simulated B6 (6 conversions
                                    * of 52 us a slot, and the interrupts between), ahead of the watchdog */

/* The inputs protect_reading knows (calib.h's order; the cells are computed from the taps). */
typedef struct {
    uint8_t armed;                 /* a run (or a calibration current) is on */
    uint8_t li_cells;              /* a Li macro with a balance lead: its cells (the balancer's); 0 without */
    uint8_t lead_cells;            /* the balance lead's cells at the start, any chemistry: each is checked */
    uint8_t probe;                 /* a probe was there at the start */
    uint16_t pack_max_mv;
    uint16_t cell_max_mv;
} protect_limits_t;

extern protect_limits_t protect_limits;
extern volatile uint8_t protect_trip;  /* the first trip since protect_arm, TRIP_NONE while none */
extern volatile int16_t protect_latest[13];   /* each input's last reading: mV, mA, 0.01 degC */
extern volatile int16_t protect_cell_mv[6];
extern int32_t protect_sink_sum;       /* the heat sink's estimate x SINK_STEPS (the B6 has no sensor) */

/* Absolute maximum per cell of AKK_TYPE `akk_type` (docs/zuml-2.0.md section 5; firmware decisions for LiS,
 * Undef, New), mV. */
uint16_t protect_cell_max_mv(uint8_t akk_type);
uint8_t protect_is_li(uint8_t akk_type);
/* The cells of `akk_type` a pack resting at `mv` holds when nobody gave the count: the fewest whose
 * rest voltages (docs/firmware.md, The check at START) add up to it, for the tightest ceiling; 0 when
 * no whole number fits, or more than the board can hold at their maximum. */
int16_t protect_cells_at_rest(uint8_t akk_type, int16_t mv);
/* The balance port's cells: how many in a row from cell 1 carry a cell. */
uint8_t protect_balance_cells(void);
/* The run's time limit (minutes): TIME_LIMIT_MIN, or the macro's own bound and TIME_MARGIN_MIN more when
 * that is longer: the record's IF(tm>x) (the whole run), else the sum of its IF(tf>x) (each phase once);
 * never past TIME_CEILING_MIN. */
uint16_t protect_time_limit_min(const uint8_t *rec);
/* The charge a run may put in (uAh): 2 x `capacity_mah` (declared or entered), CAPACITY_LIMIT_UAH without
 * one (<= 0), never past CAPACITY_CEILING_UAH. */
uint32_t protect_capacity_limit_uah(int32_t capacity_mah);
/* The trip a running run's time (ms) and charge put in (uAh) are past their limits by (the time's first), or
 * TRIP_NONE: at a limit exactly the run goes on. The main loop asks every 100 ms. */
uint8_t protect_run_limits(uint32_t time_ms, uint16_t time_limit_min, uint32_t in_uah, uint32_t capacity_limit_uah);
/* Why a run may not start on what the inputs read now (text in flash), NULL when it may; then the
 * limits are armed for `akk_type` and `cells` (0: not given: the balance lead's, else counted from the
 * rest voltage). The sentence the PC gets, with its volts, goes to `sentence` (HAL_SENTENCE_MAX bytes;
 * NULL: none wanted) when the refusal has one. */
const char *protect_arm(uint8_t akk_type, int16_t cells, uint8_t *trip, char *sentence);
void protect_disarm(void);
/* One reading of input `input` (calib.h); returns the trip it caused, TRIP_NONE else. */
uint8_t protect_reading(uint8_t input, int16_t value);
/* A trip found elsewhere (the stage, the main loop); the first one stays (but for a reversed pack, which
 * names it once the output is off). */
void protect_raise(uint8_t trip);
/* The trip's reason is final: a reversed pack had its REFINE_READINGS to show since the output went off. */
uint8_t protect_settled(void);
const char *protect_text(uint8_t trip);
/* One 100 ms step of the heat-sink estimate towards what `loss_mw` of the stage's losses hold it at; over
 * TRIP_SINK_C100 it trips (armed only). */
void protect_sink_step(int32_t loss_mw);
int32_t protect_sink_c100(void);      /* the estimate, 0.01 degC */
/* The stage's losses (mW) for the estimate at `v_mv` and `i_ma` in `mode` (stage.h's STAGE_*): a tenth of a
 * charge's power (the converter's), all of a discharge's (the load burns it), none when off. */
int32_t protect_loss_mw(uint8_t mode, int16_t v_mv, int16_t i_ma);
/* One current reading `i_ma` of a regulator at its top duty, set to `set_ma`: under a quarter of it the
 * reading is starved, one more in *run (else *run starts again); the STARVED_READINGS-th in a row returns
 * its trip (TRIP_NONE before): the pack out of the boost's reach when `boosting` and `v_mv` is above what
 * `vin_mv` reaches, else a lost pack. */
uint8_t protect_starved(volatile uint16_t *run, int16_t i_ma, int16_t set_ma, uint8_t boosting, int16_t v_mv,
                        int16_t vin_mv);
/* One ADC slot: `loop_ran` when the main loop showed life since the last one. After HANG_READINGS slots in a
 * row without it TRIP_HANG is raised and 1 returned (the caller switches the stage off); 0 else. */
uint8_t protect_loop_slot(uint8_t loop_ran);

#endif
