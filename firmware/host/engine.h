/* The simulation engine: the core on the host board (host.c) driven tick by tick from C on the battery and
 * charger models of firmware/host/model/, the loop of zuml_studio/sim/interpreter.py's _ticks (which stays the
 * reference; tests/sim/test_engine.py holds the two together). Built as libzuml_engine.so and run through
 * ctypes by zuml_studio/sim/engine.py, which builds the models from Python's and reads the buffers back. */
#ifndef ZE_ENGINE_H
#define ZE_ENGINE_H

#include <stdint.h>
#include "../core/zuml.h"
#include "model/pack.h"
#include "model/charger.h"

#define ZE_TEXT 80
#define ZE_LIMIT 100               /* an event kind of the engine's own: the simulation's limit cut the phase */
#define ZE_ERR_CELLS 100           /* ze_start: more cells than the models hold (ZM_MAX_CELLS) */

typedef struct {
    uint8_t kind, section, index, repetition, cycle_pass, offset, reason, reason_offset;
    int32_t text_len;
    char text[ZE_TEXT];            /* the device's text for it (zc_event_text) */
    double time_s;
    /* a phase's end (PHASE_END, ZE_LIMIT): what PhaseResult holds besides the event */
    double mah_in, mah_out, v_end, temp_end, soc_end, pack_v;
    double clip_asked_a, clip_given_a, clip_pack_v, clipped_s;
    int32_t cells_at;              /* into phase_cells: the cells' end voltages, then their bled ticks; -1: none */
} ze_event_t;

typedef struct {
    /* the models and the run's settings */
    zm_pack_t *pack;
    zm_charger_t *charger;
    const zm_balancer_t *balancer;
    int32_t per_cell;              /* the interpreter's _per_cell: the cells differ and there are several */
    double dt, limit_s, lsb_v;
    /* the samples of one ze_run, from row 0 (cells, balance_mask: per_cell only, pack->cells a row) */
    double *time_s;
    int8_t *section;
    int64_t *phase;
    float *voltage_v, *current_a, *temp_c, *heatsink_c, *mah_in, *mah_out, *cells;
    uint32_t *balance_mask;
    /* the events of one ze_run */
    ze_event_t *events;
    int32_t events_cap, n_events;
    double *phase_cells;
    int32_t phase_cells_cap, n_phase_cells;
    /* the run, across ze_run calls */
    double time, q_in, q_out;      /* s; A*s */
    int64_t ticks;
    int32_t finished, paused;
} ze_run_t;

/* Starts the run (enum zc_start_error, or ZE_ERR_CELLS); the models in *e must be at their start state. */
uint8_t ze_start(ze_run_t *e, const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b);
/* Runs at most max_ticks ticks (fewer when the event buffers fill); returns the samples written. */
int32_t ze_run(ze_run_t *e, int32_t max_ticks);
/* Stops the run between ticks, as the user's stop does (the phase's end and the finish as events). */
void ze_stop(ze_run_t *e);

#endif
