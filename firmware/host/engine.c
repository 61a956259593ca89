/* The simulation engine (engine.h): one tick is interpreter.py's _ticks body, with the core deciding what
 * the macro does (zc_control, zc_measure through host.c) and the models of firmware/host/model/ doing what the
 * Python's Pack, CellPack and Charger do, in the same order. What PhaseResult holds that the core does not
 * report (the charge counts in A*s, the clip, the balancer's time per cell, the state at the end) is tracked
 * here, as the reference tracks it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "engine.h"
#include "host.h"

#define HOLDING_V 0.05             /* a CV phase within this of its voltage holds it: the B6 balances there */
#define EVENT_ROOM 300             /* the most events one tick can make: a phase end, ~128 commands, a start */

static ze_run_t *cur;              /* the run the event sink writes to (one run at a time: host.c is one board) */
/* the running phase's own, cleared at its start */
static struct {
    double phase_q_in, phase_q_out, measured_v, clip_asked, clip_given, clip_v, clipped_s;
    int32_t clip_set, bleeder, ceiling;
    zm_window_t win;
    int64_t bled[ZM_MAX_CELLS];
} ph;

static int32_t fixed(double x)
{
    double r = nearbyint(x * 1e6);
    return r < -2147483648.0 ? INT32_MIN : r > 2147483647.0 ? INT32_MAX : (int32_t)r;
}

/* Python's round(v, 6): the nearest double to v rounded to 1 uV, ties to even on v's exact value. The product
 * v * 1e6 is rounded itself, which can only matter right at a half: there the exact decimal expansion decides. */
static double round6(double v)
{
    double y = v * 1e6, r = nearbyint(y);
    if (fabs(fabs(y - floor(y)) - 0.5) <= ldexp(fabs(y) + 1.0, -50)) {
        char text[400];
        snprintf(text, sizeof text, "%.6f", v);
        return strtod(text, 0);
    }
    return r / 1e6;
}

static void set_bleed(zm_pack_t *p, uint32_t mask, const zm_balancer_t *b)
{
    int32_t k;
    if (mask) {
        for (k = 0; k < p->cells; k++)
            p->bleed_a[k] = mask >> k & 1 ? zm_bleed(b, p->cell_voltages[k]) : 0.0;
    } else {
        for (k = 0; k < p->cells; k++)
            p->bleed_a[k] = 0.0;
    }
}

static void phase_end_values(ze_run_t *e, ze_event_t *ev)
{
    zm_pack_t *p = e->pack;
    int32_t k;
    ev->mah_in = ph.phase_q_in / 3.6;
    ev->mah_out = ph.phase_q_out / 3.6;
    ev->v_end = ph.measured_v;
    ev->temp_end = zm_pack_temp_c(p);
    ev->soc_end = zm_pack_soc(p);
    ev->pack_v = p->voltage;
    ev->clip_asked_a = ph.clip_asked;
    ev->clip_given_a = ph.clip_given;
    ev->clip_pack_v = ph.clip_v;
    ev->clipped_s = ph.clip_set ? ph.clipped_s : 0.0;
    ev->cells_at = -1;
    if (e->per_cell) {
        ev->cells_at = e->n_phase_cells;
        for (k = 0; k < p->cells; k++) {
            e->phase_cells[e->n_phase_cells + k] = p->cell_voltages[k];
            e->phase_cells[e->n_phase_cells + p->cells + k] = (double)ph.bled[k];
        }
        e->n_phase_cells += 2 * p->cells;
        set_bleed(p, 0, e->balancer);      /* the balancer stops with the phase */
    }
}

static ze_event_t *new_event(ze_run_t *e, uint8_t kind)
{
    ze_event_t *ev = &e->events[e->n_events++];
    memset(ev, 0, sizeof *ev);
    ev->kind = kind;
    ev->time_s = e->time;
    return ev;
}

static void sink(const zc_event_t *z)
{
    ze_run_t *e = cur;
    ze_event_t *ev = new_event(e, z->kind);
    const zc_run_t *run = zh_run();
    ev->section = z->section;
    ev->index = z->index;
    ev->repetition = z->repetition;
    ev->cycle_pass = z->cycle_pass;
    ev->offset = z->offset;
    ev->reason = z->reason;
    ev->reason_offset = z->reason_offset;
    ev->text_len = zh_event_text(z, ev->text);
    if (z->kind == ZC_EV_PHASE_START) {
        const zm_balancer_t *b = e->balancer;
        memset(&ph, 0, sizeof ph);
        ph.measured_v = e->pack->voltage;
        ph.ceiling = e->per_cell && b->on && z->section;
        ph.bleeder = ph.ceiling && (!b->cv_only || run->mode == M_CV);
    } else if (z->kind == ZC_EV_PHASE_END) {
        phase_end_values(e, ev);
    }
}

uint8_t ze_start(ze_run_t *e, const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b)
{
    cur = e;
    e->n_events = e->n_phase_cells = 0;
    e->time = e->q_in = e->q_out = 0.0;
    e->ticks = 0;
    e->finished = e->paused = 0;
    memset(&ph, 0, sizeof ph);
    zh_set_event_sink(sink);
    zm_charger_start(e->charger, e->dt);
    if (e->pack->cells > ZM_MAX_CELLS)
        return ZE_ERR_CELLS;
    return zh_start(rec, len, s, b);
}

/* What CHARGE_EX's reading is after this tick (interp.c's pulse_reading, on the doubles the reference logs). */
static double pulse_reading(const zc_run_t *r, double v, double ocv)
{
    uint32_t at = (r->t_phase + (r->paused ? 0U : r->board.tick_ms)) % r->period_ms;
    if (r->tv == 1 && at == r->tch_ms % r->period_ms)
        return v;
    if (r->tv == 2 && at == 0)
        return v;
    if (r->tv == 0 && at == 0)
        return ocv;
    return ph.measured_v;
}

int32_t ze_run(ze_run_t *e, int32_t max_ticks)
{
    zm_pack_t *p = e->pack;
    zm_charger_t *ch = e->charger;
    const zm_balancer_t *bal = e->balancer;
    const zc_run_t *run = zh_run();
    int32_t n = 0, cells = p->cells, ceiling_uv = fixed(bal->ceiling_v);
    double dt = e->dt;
    cur = e;
    e->n_events = e->n_phase_cells = 0;
    while (n < max_ticks && !e->finished && e->n_events <= e->events_cap - EVENT_ROOM &&
           e->n_phase_cells + 4 * cells <= e->phase_cells_cap) {
        hal_output_t out;
        uint8_t state, running, was_paused = run->paused;
        double i, own, v, hs, ocv, temp;
        state = zh_control(fixed(ch->heatsink_c), fixed(p->voltage), fixed(zm_pack_temp_c(p)), &out);
        if (state == 0) {
            e->finished = 1;
            break;
        }
        if (e->per_cell) {
            /* decided on the cells' last readings, bleeding over this tick */
            if (ph.bleeder && !was_paused)
                zm_balance_window(bal, &ph.win, p->cell_voltages, cells, dt,
                                  out.kind == HAL_VOLTAGE_CHARGE && p->voltage >= out.voltage_uv / 1e6 - HOLDING_V);
            else
                ph.win.mask = 0;
            set_bleed(p, ph.win.mask, bal);
        }
        if (out.kind == HAL_CURRENT) {
            i = out.current_ua / 1e6;
        } else if (out.kind == HAL_OFF) {
            i = 0.0;
        } else {
            double i_max = out.current_ua / 1e6;
            i = zm_pack_current_for_voltage(p, out.voltage_uv / 1e6);
            if (out.kind == HAL_VOLTAGE_CHARGE)
                i = i > i_max ? i_max : (i < 0.0 ? 0.0 : i);
            else
                i = i < -i_max ? -i_max : (i > 0.0 ? 0.0 : i);
        }
        own = i > 0.0 ? (out.kind == HAL_VOLTAGE_CHARGE ? 0.0 : i) : -1.0;
        if (ph.ceiling && i > 0.0)
            i = zm_pack_current_for_ceiling(p, i, bal->ceiling_v);
        if (i != 0.0) {
            double asked = i;
            i = zm_limit_current(ch, i, p->voltage);
            if (i != asked) {
                if (!ph.clip_set) {
                    ph.clip_set = 1;
                    ph.clip_asked = asked;
                    ph.clip_given = i;
                    ph.clip_v = p->voltage;
                }
                ph.clipped_s += dt;
            }
        }
        v = zm_pack_step(p, i);
        hs = zm_charger_step(ch, i, v);
        e->time += dt;
        if (i > 0.0) {
            ph.phase_q_in += i * dt;
            e->q_in += i * dt;
        } else {
            ph.phase_q_out -= i * dt;
            e->q_out -= i * dt;
        }
        if (e->lsb_v != 0.0)
            v = nearbyint(v / e->lsb_v) * e->lsb_v;
        v = round6(v);
        ocv = state == 2 ? zm_pack_open_circuit_voltage(p) : 0.0;
        ph.measured_v = run->mode == M_PULSE ? pulse_reading(run, v, ocv) : v;
        temp = zm_pack_temp_c(p);
        e->time_s[n] = e->time;
        e->section[n] = (int8_t)run->phase_section;
        e->phase[n] = run->run_no;
        e->voltage_v[n] = (float)ph.measured_v;
        e->current_a[n] = (float)i;
        e->temp_c[n] = (float)temp;
        e->heatsink_c[n] = (float)hs;
        e->mah_in[n] = (float)(e->q_in / 3.6);
        e->mah_out[n] = (float)(e->q_out / 3.6);
        if (e->per_cell) {
            int32_t k;
            for (k = 0; k < cells; k++) {
                e->cells[(int64_t)n * cells + k] = (float)p->cell_voltages[k];
                if (ph.win.mask >> k & 1)
                    ph.bled[k]++;
            }
            e->balance_mask[n] = ph.win.mask;
        }
        zh_set_ceiling(ph.ceiling ? zm_ceiling_cell(bal, p->cell_voltages, cells, i, own, p->bleed_a) : 0, ceiling_uv);
        running = zh_measure(fixed(v), fixed(i), fixed(temp), fixed(hs), fixed(ocv));
        n++;
        e->ticks++;
        if (running == 0) {
            e->finished = 1;
        } else if (running == 2 && e->time >= e->limit_s) {
            phase_end_values(e, new_event(e, ZE_LIMIT));
            e->finished = 1;
        }
    }
    e->paused = run->paused;
    return n;
}

void ze_stop(ze_run_t *e)
{
    cur = e;
    e->n_events = e->n_phase_cells = 0;
    zh_stop();
    e->finished = 1;
}
