/* The battery models of zuml_studio/sim/battery.py (Pack) and sim/cell_pack.py (CellPack) in C, for the
 * simulation engine (host/engine.c). Host only: never linked into an AVR image.
 *
 * Every function does the Python's double-precision operations in the Python's order (build with
 * -ffp-contract=off, no fast-math), so a run is bit for bit the reference's; the names are the Python's,
 * so a change to battery.py can be carried over line by line. The constants are the ones Python computes
 * (Pack.step_constants), handed in by sim/engine.py: no chemistry data lives here. */
#ifndef ZM_PACK_H
#define ZM_PACK_H

#include <stdint.h>

#define ZM_MAX_CELLS 32            /* a CellPack's most cells (the balance mask is 32 bits) */

/* Pack._k for the run's tick, in its order, and the OCV table it points into. */
typedef struct {
    double r0, r1b, a1, r2b, a2, ea_r, ea_r_ref, kc, kd, eps, inv_w0, w_t, dv_o2, k_t, q_rev, ds_k, a_th, inv_ha;
    double a_p, vp_max, k_dip, a_o, k_over, half_m, h_k, a_x, b_x;
    double ambient_c;
    const double *xs, *ys, *slopes;    /* last + 1 points, last segments */
    int32_t last, series;
} zm_constants_t;

/* What Pack.step carries from tick to tick (Pack.STATE's order). */
typedef struct {
    double soc, temp_c, current, cell_voltage, voltage, v1, v2, vp, oc, over, h, surf;
} zm_state_t;

/* One Pack (cells == 0: `series` identical cells, one state) or a CellPack of `cells` one-cell Packs. */
typedef struct {
    int32_t cells;
    int32_t neumaier_sum;              /* Python >= 3.12's sum() of floats is compensated */
    const zm_constants_t *k;           /* per cell (one for a Pack) */
    zm_state_t *s;
    const double *q;                   /* CellPack: each cell's capacity, mAh */
    double q_total;
    double *bleed_a;                   /* CellPack: the balancer's current out of each cell */
    double *cell_voltages;
    double voltage, current, cv_guess;
} zm_pack_t;

double zm_pack_step(zm_pack_t *p, double current_a);
double zm_pack_current_for_voltage(zm_pack_t *p, double v_pack);
/* CellPack.current_for_ceiling: the lower of current_a and each cell's current to ceiling_v (>= 0); cells only. */
double zm_pack_current_for_ceiling(zm_pack_t *p, double current_a, double ceiling_v);
double zm_pack_open_circuit_voltage(const zm_pack_t *p);
double zm_pack_temp_c(const zm_pack_t *p);
double zm_pack_soc(const zm_pack_t *p);
/* Python's sum() of n floats, as the interpreter running the reference does it. */
double zm_sum(const double *x, int32_t n, int32_t neumaier);

#endif
