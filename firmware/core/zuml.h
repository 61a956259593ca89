/* The ZUML 2.0 interpreter core: runs one record's byte code, tick by tick, through hal.h.
 *
 * No malloc, no recursion: all state is in one zc_run_t the caller owns. A tick is two calls:
 * zc_control() sets the power stage for the coming interval, zc_measure() reads what happened in
 * it and checks the phase's conditions. Between them the board lets dt pass.
 */
#ifndef ZUML_CORE_H
#define ZUML_CORE_H

#include <stdint.h>
#include "hal.h"

#define ZC_MAX_RECORD 255
#define ZC_NONE (-1L)              /* a start value not given */

enum zc_task { ZC_CHARGE = 0, ZC_DISCHARGE = 1, ZC_TRAIN = 2 };

/* Why a start is refused (zc_start's result). */
enum zc_start_error {
    ZC_OK = 0,
    ZC_ERR_RECORD = 1,             /* the bytes are not a valid record */
    ZC_ERR_INPUT_CURRENT = 2,      /* INPUT current, none entered */
    ZC_ERR_C_NEEDS_CAPACITY = 3,   /* current in C, no capacity */
    ZC_ERR_INPUT_VOLTAGE = 4,
    ZC_ERR_S_NEEDS_SERIES = 5,
    ZC_ERR_REPETITIONS = 6,
    ZC_ERR_NO_TEMPLATE = 7         /* START_SHABLON=n (or the template chosen at start): no such template */
};

/* How a phase (or the macro) ended. */
enum zc_reason {
    ZC_R_NONE = 0,
    ZC_R_CONDITION = 1,            /* the condition at reason_offset */
    ZC_R_DEFAULT_T = 2,            /* T > 60 */
    ZC_R_DEFAULT_DTDT = 3,         /* dT/dt > 1 C/min */
    ZC_R_DEFAULT_CAPACITY = 4,     /* 1.5 x capacity without a sensor */
    ZC_R_DEFAULT_EMPTY = 5,        /* empty discharge section reached the chemistry's end voltage */
    ZC_R_STOP_MACRO = 6,           /* IF(tm>x) at reason_offset */
    ZC_R_STOPPED = 7,              /* stopped by the user */
    ZC_R_END = 8,                  /* end of macro */
    ZC_R_BALANCER = 9              /* a cell reached the balancer's ceiling; reason_offset: the cell */
};

/* How a phase drives the power stage (zc_run_t.mode); CC-CV is CV with CONSTANT_I as its limit. */
enum zc_mode { M_CC, M_CV, M_PULSE, M_TRICKLE };

enum zc_event_kind {
    ZC_EV_SECTION = 1, ZC_EV_PHASE_START = 2, ZC_EV_PHASE_END = 3, ZC_EV_PAUSE = 4,
    ZC_EV_RESUME = 5, ZC_EV_MUSIC = 6, ZC_EV_LIGHT = 7, ZC_EV_FINISH = 8
};

typedef struct {
    uint8_t kind;                  /* enum zc_event_kind */
    uint8_t section;               /* 0 discharge, 1 charge */
    uint8_t index;                 /* FAZE position in its section, 0 for the default discharge */
    uint8_t repetition;
    uint8_t cycle_pass;
    uint8_t offset;                /* byte offset in the record (FAZE, command, section byte) */
    uint8_t reason;                /* enum zc_reason, for PHASE_END and FINISH */
    uint8_t reason_offset;
    uint8_t arg;                   /* MUSIC/LIGHT operand */
    uint32_t time_ms;
    uint32_t mah_in_x1000;         /* phase coulomb counts at PHASE_END, in uAh */
    uint32_t mah_out_x1000;
} zc_event_t;

/* Supplied by the application: the core reports every event here. */
void zc_event(const zc_event_t *e);

typedef struct {
    uint8_t task;                  /* enum zc_task */
    uint8_t repetitions;
    int32_t capacity_mah;          /* ZC_NONE when not entered */
    int32_t current_ua;            /* ZC_NONE when not entered */
    int32_t voltage_uv;            /* ZC_NONE when not entered */
    int16_t series;                /* 0 when not entered */
    uint8_t sensor;                /* 0: ignore the battery temperature sensor even when one is there */
    uint8_t template_no;           /* start template chosen at start, 0: none (a START_SHABLON=n wins) */
} zc_start_t;

/* Supplied by the application: start template `number`'s values in place of those in *s (task and
 * repetitions always; capacity, current, voltage, series where the template has them); 0 when the
 * charger holds no such template. */
uint8_t zc_template(uint8_t number, zc_start_t *s);
/* A template as stored and sent (docs/protocol.md, GET_TEMPLATE): task, repetitions, capacity_mah
 * u16, current_ma u16, voltage_mv u16, series; 0 = not in the template. Applies it over *s. */
#define ZC_TEMPLATE_SIZE 9
void zc_template_apply(zc_start_t *s, const uint8_t *t);

/* A charge, exact: whole uAh and the uA*ms below one (the AVR has no cheap 64-bit arithmetic). */
#define ZC_UAMS_PER_UAH 3600000UL
typedef struct {
    uint32_t uah;
    uint32_t uams;                 /* < ZC_UAMS_PER_UAH */
} zc_charge_t;

typedef struct {
    int32_t max_charge_ua;         /* a CONSTANT_V alone holds at most this without an entered current */
    int32_t max_discharge_ua;
    int32_t fallback_end_uv_per_cell; /* empty discharge section on Undef/LiS/New */
    uint16_t tick_ms;
    uint16_t dp_window_s;          /* -dV: window the voltage is averaged over (the charger model's) */
    uint16_t dp_holdoff_s;         /* -dV: ignored this long after a phase starts (seed 001: 5-10 min) */
} zc_board_t;

typedef struct {
    /* the record and what its introduction decided */
    uint8_t rec[ZC_MAX_RECORD];
    uint8_t end;                   /* offset of the check byte */
    uint8_t discharge_at, charge_at, conclusion_at;
    uint8_t akk_type;
    int16_t series;                /* 0: unknown */
    int32_t capacity_mah;          /* <= 0: unknown */
    int8_t tc_pause, tc_continue;
    uint8_t tm_stop_at;            /* offset of IF(tm>x), 0 when none */
    uint8_t stop_macro;            /* IF(tm>x) STOP_MACRO fired: the conclusion runs, then the run ends on it */
    zc_start_t start;
    zc_board_t board;
    /* the walk through the sections */
    uint8_t stage, section, rep, reps, pc, faze_index, ran;
    uint8_t loop_left, loop_pc, loop_pass, loop_faze;
    /* the running phase */
    uint8_t active, charging, check_defaults, trickle_on, paused, finished;
    uint8_t phase_at, phase_index, phase_pass, phase_rep, phase_section, is_default;
    uint8_t end_reason, end_offset;        /* of the last phase end, or of the macro once finished */
    uint16_t run_no;                       /* phases started in this run */
    int32_t measured_v, dtdt_t0;
    uint32_t dtdt_next, time_ms;
    zc_charge_t total_in, total_out;       /* run */
    /* From own_t to the end: cleared at every phase start. */
    uint8_t own_t, dpeak_at, mode, tv;
    int32_t i_set, v_set, i_max, v_low;    /* v_low: TRICKLE V1, or the default discharge end */
    int32_t i2;                            /* CHARGE_EX discharge current */
    uint32_t tch_ms, period_ms, t_phase;
    zc_charge_t q_in, q_out;               /* phase */
    /* -dV: the window's sum (64 bits as 16-bit digits, the most significant first), the held peak
     * as an exact average: whole uV and the remainder over its window's count */
    uint16_t dp_sum[4];
    uint32_t dp_peak_uv;
    uint16_t dp_count, dp_peak_rem, dp_peak_count;
    uint32_t dp_window_end;
    uint8_t dp_window_open, dp_hit;
} zc_run_t;

/* Validates a record (structure, operand ranges, check byte): 0 when it may run, else the offset+1
 * of the first bad byte. */
uint16_t zc_validate(const uint8_t *rec, uint16_t len);
/* Loads the record, resolves start values; enum zc_start_error. */
uint8_t zc_start(zc_run_t *r, const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b);
/* Sets the power stage for the coming tick (runs commands and starts phases as they are reached). */
void zc_control(zc_run_t *r);
/* Reads the tick's measurements (after tick_ms) and checks the conditions. */
void zc_measure(zc_run_t *r);
void zc_stop(zc_run_t *r);
/* Size of an instruction from its opcode, 0 for a byte that is not one. */
uint8_t zc_op_size(uint8_t code);
int32_t zc_current_ua(const zc_run_t *r, uint16_t raw);
int32_t zc_voltage_uv(const zc_run_t *r, uint16_t raw);
int32_t zc_chemistry_end_uv(uint8_t akk_type);   /* per cell, 0 when the chemistry has none */

#endif
