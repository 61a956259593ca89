/* charger_model.py's Charger and BalancerSpec, operation for operation (see charger.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "charger.h"

void zm_charger_start(zm_charger_t *c, double dt) { c->a = exp(-dt / c->tau); }

double zm_limit_current(const zm_charger_t *c, double requested_a, double pack_v)
{
    double i;
    if (requested_a > 0.0) {
        i = c->max_charge_a < requested_a ? c->max_charge_a : requested_a;
        if (pack_v > 0.0 && c->max_charge_w / pack_v < i)
            i = c->max_charge_w / pack_v;
        return i;
    }
    if (requested_a < 0.0) {
        i = c->max_discharge_a < -requested_a ? c->max_discharge_a : -requested_a;
        if (pack_v > 0.0 && c->max_discharge_w / pack_v < i)
            i = c->max_discharge_w / pack_v;
        return -i;
    }
    return 0.0;
}

double zm_charger_step(zm_charger_t *c, double current_a, double pack_v)
{
    double power = fabs(current_a * pack_v);
    double loss = current_a > 0.0 ? power * c->loss_per_w : power;
    double t_final = c->ambient_c + loss * c->r;
    /* exact first-order response for a loss held constant over the step */
    c->heatsink_c = t_final + (c->heatsink_c - t_final) * c->a;
    return c->heatsink_c;
}

double zm_bleed(const zm_balancer_t *b, double cell_v)
{
    if (!(b->bleed_r_ohm > 0.0))
        return b->bleed_a;
    return (cell_v > 0.0 ? cell_v : 0.0) / b->bleed_r_ohm;
}

uint32_t zm_balance_mask(const zm_balancer_t *b, const double *cell_v, int32_t n, uint32_t bleeding)
{
    double low = cell_v[0], start;
    uint32_t mask = 0;
    int32_t k;
    for (k = 1; k < n; k++)
        if (cell_v[k] < low)
            low = cell_v[k];
    start = low + b->spread_v;
    for (k = 0; k < n; k++)
        if (cell_v[k] > start || ((bleeding >> k & 1) && cell_v[k] > low))
            mask |= 1UL << k;
    return mask;
}

/* The cells to bleed at a window's start, the highest first: more than spread_v above the lowest (spread_off_v
 * for one that bled in the last window), at most max_bleeders; a tie goes to the first cell. */
static uint32_t bleeders(const zm_balancer_t *b, const double *v, int32_t n, uint32_t bled)
{
    double low = v[0];
    uint32_t mask = 0;
    int32_t k, pick;
    for (k = 1; k < n; k++)
        if (v[k] < low)
            low = v[k];
    for (pick = 0; pick < b->max_bleeders; pick++) {
        double best = 0.0;
        int32_t at = -1;
        for (k = 0; k < n; k++) {
            double over = v[k] - low;
            if (!(mask >> k & 1) && over > best && (over > b->spread_v || ((bled >> k & 1) && over > b->spread_off_v))) {
                best = over;
                at = k;
            }
        }
        if (at < 0)
            break;
        mask |= 1UL << at;
    }
    return mask;
}

uint32_t zm_balance_window(const zm_balancer_t *b, zm_window_t *w, const double *v, int32_t n, double dt,
                           int32_t holding)
{
    double top = v[0], low = 0.0;
    uint32_t keep;
    int32_t k, ref = -1;
    if (!(b->window_s > 0.0))
        return w->mask = zm_balance_mask(b, v, n, w->mask);
    for (k = 1; k < n; k++)
        if (v[k] > top)
            top = v[k];
    if (top < b->from_v && !holding) {
        w->mask = w->bled = 0;
        w->t = 0.0;
        return 0;
    }
    w->t += dt;
    if (!w->mask) {
        if (w->t >= b->settle_s) {
            for (k = 0; k < n; k++)
                w->before[k] = v[k];
            w->mask = bleeders(b, v, n, w->bled);
            w->first = 1;
            w->t = 0.0;
        }
        return w->mask;
    }
    for (k = 0; k < n; k++)
        if (!(w->mask >> k & 1) && (ref < 0 || v[k] < v[ref]))
            ref = k;
    keep = w->mask;
    if (w->first) {
        /* what each bleed took off its cell, against the lowest cell that does not bleed (the charge moves them
         * all as the loads go on) */
        for (k = 0; k < n; k++)
            w->drop[k] = w->mask >> k & 1 ? (w->before[k] - w->before[ref]) - (v[k] - v[ref]) : 0.0;
        w->first = 0;
    } else {
        low = v[ref];
        for (k = 0; k < n; k++)
            if ((keep >> k & 1) && v[k] + w->drop[k] <= low)
                keep &= ~(1UL << k);
    }
    if (w->t >= b->window_s || !keep) {
        w->bled = w->mask;
        keep = 0;
        w->t = 0.0;
    }
    return w->mask = keep;
}

/* Python's round(x, 3): correctly rounded, ties to even on the exact binary value (as printf's %.3f) */
static double round3(double x)
{
    char text[64];
    snprintf(text, sizeof text, "%.3f", x);
    return strtod(text, 0);
}

uint8_t zm_ceiling_cell(const zm_balancer_t *b, const double *cell_v, int32_t n, double current_a, double own_a,
                        const double *bleed_a)
{
    double top = cell_v[0], bled = 0.0;
    int32_t k, at = 0;
    for (k = 1; k < n; k++)
        if (cell_v[k] > top) {
            top = cell_v[k];
            at = k;
        }
    for (k = 0; k < n; k++)
        bled += bleed_a[k];
    if (own_a < 0.0 || (current_a - bled / n) * 10.0 > own_a)
        return 0;
    /* far from the ceiling the rounding to 1 mV cannot decide: no text conversion every tick */
    if (top < b->ceiling_v - 0.001)
        return 0;
    if (top < b->ceiling_v + 0.001 && round3(top) < b->ceiling_v)
        return 0;
    return (uint8_t)(at + 1);
}
