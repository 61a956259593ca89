/* zuml_studio/sim/charger_model.py's Charger (the power stage's limits, the heat sink) and BalancerSpec
 * in C for the simulation engine, operation for operation (see pack.h). Host only. */
#ifndef ZM_CHARGER_H
#define ZM_CHARGER_H

#include <stdint.h>
#include "pack.h"

typedef struct {
    double max_charge_a, max_charge_w, max_discharge_a, max_discharge_w;
    double loss_per_w, r, tau, ambient_c;      /* Charger._loss_per_w, _r, _tau */
    double heatsink_c, a;                      /* state; a: exp(-dt / tau), set by zm_charger_start */
} zm_charger_t;

/* The balancer as the run's interpreter uses it (on: the pack's cells differ and the chemistry has a
 * ceiling on this charger). */
typedef struct {
    int32_t on;
    int32_t cv_only;                           /* during = "cv" */
    double bleed_r_ohm;                        /* 0: a regulated bleed_a */
    double bleed_a;
    double spread_v;
    double ceiling_v;
    /* windows as the B6's firmware (window_s 0: the cells of zm_balance_mask bleed every tick) */
    double window_s, settle_s;                 /* a window's longest bleed; the loads off this long before one */
    double spread_off_v;                       /* a cell that bled in the last window bleeds again from this */
    double from_v;                             /* no window while every cell is below this (0: any) */
    int32_t max_bleeders;                      /* at most this many cells bleed at once */
} zm_balancer_t;

/* A balancer's windows (BalanceWindow in charger_model.py), cleared at a phase's start. */
typedef struct {
    uint32_t mask, bled;                       /* bleeding now; bled in the last window */
    int32_t first;                             /* 1: the window's first tick, its drops not measured yet */
    double t;                                  /* seconds in the window, or with the loads off */
    double before[ZM_MAX_CELLS], drop[ZM_MAX_CELLS];
} zm_window_t;

void zm_charger_start(zm_charger_t *c, double dt);
double zm_limit_current(const zm_charger_t *c, double requested_a, double pack_v);
double zm_charger_step(zm_charger_t *c, double current_a, double pack_v);

double zm_bleed(const zm_balancer_t *b, double cell_v);
uint32_t zm_balance_mask(const zm_balancer_t *b, const double *cell_v, int32_t n, uint32_t bleeding);
/* The cells that bleed over the next tick of dt s (charger_model.py's BalancerSpec.window); `holding`: the phase
 * holds its voltage (then the windows run below from_v too). */
uint32_t zm_balance_window(const zm_balancer_t *b, zm_window_t *w, const double *cell_v, int32_t n, double dt,
                           int32_t holding);
/* The cell (from 1) whose voltage read to 1 mV has reached the ceiling, the first of the highest, once the charge the
 * cells keep (current_a less the mean of bleed_a) has fallen to a tenth of own_a (charger_model.py's
 * ceiling_reason: 0 for a CV phase, < 0 when no current is asked); 0: none. */
uint8_t zm_ceiling_cell(const zm_balancer_t *b, const double *cell_v, int32_t n, double current_a, double own_a,
                        const double *bleed_a);

#endif
