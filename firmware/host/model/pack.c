/* battery.py's Pack and cell_pack.py's CellPack, operation for operation (see pack.h). */
#include <math.h>
#include "pack.h"

#define T_REF_C 25.0
#define KELVIN 273.15
#define W_FLOOR 0.05
#define COLLAPSE_V_PER_SOC 20.0
#define SOC_FLOOR (-0.06)
#define CV_TOLERANCE_V 1e-9
#define CV_MAX_STEPS 80

/* bisect.bisect_right: how many of xs[0..n) are <= x */
static int32_t bisect_right(const double *xs, int32_t n, double x)
{
    int32_t lo = 0, hi = n;
    while (lo < hi) {
        int32_t mid = (lo + hi) / 2;
        if (x < xs[mid])
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

double zm_sum(const double *x, int32_t n, int32_t neumaier)
{
    double total = 0.0, c = 0.0;
    int32_t k;
    if (n <= 0)
        return 0.0;
    total = x[0];
    for (k = 1; k < n; k++) {
        if (neumaier) {
            double t = total + x[k];
            if (fabs(total) >= fabs(x[k]))
                c += (total - t) + x[k];
            else
                c += (x[k] - t) + total;
            total = t;
        } else {
            total += x[k];
        }
    }
    if (neumaier && c != 0.0 && isfinite(c))
        total += c;
    return total;
}

/* -- one Pack ----------------------------------------------------------------------------------- */

static double cell_ocv(const zm_constants_t *k, const zm_state_t *st)
{
    double s = st->soc + st->surf, u;
    if (s < 0.0) {
        u = k->ys[0] + s * COLLAPSE_V_PER_SOC;
    } else {
        int32_t j = bisect_right(k->xs, k->last + 1, s);
        if (j > k->last)
            j = k->last;
        u = k->ys[j - 1] + (s - k->xs[j - 1]) * k->slopes[j - 1];
    }
    return u - k->k_t * (st->temp_c - T_REF_C);
}

static double one_ocv(const zm_constants_t *k, const zm_state_t *st)
{
    return (cell_ocv(k, st) + st->v1 + st->v2 + st->vp - k->k_dip * st->oc
            + k->k_over * st->over * st->over - k->half_m * (1.0 - st->h)) * k->series;
}

static double one_step(const zm_constants_t *k, zm_state_t *st, double current_a)
{
    double i = current_a, s = st->soc, t = st->temp_c, f, vp, eta, r, extra, oc, over, v1, v2, e, v, q;
    double t_final, ds, x, su;
    f = exp(k->ea_r / (t + KELVIN) - k->ea_r_ref);
    vp = st->vp * k->a_p;
    if (i > 0.0) {
        double wf = 1.0 + k->w_t * (t - T_REF_C);
        if (wf < W_FLOOR)
            wf = W_FLOOR;
        eta = 1.0 - exp((s - 1.0) * k->inv_w0 / wf);
        r = k->r0 * f;
        vp += i * k->kc / (1.0 - s + k->eps) * (1.0 - k->a_p);
        if (vp > k->vp_max)
            vp = k->vp_max;
        extra = (1.0 - eta) * k->dv_o2;
        oc = st->oc * k->a_o + (1.0 - eta) * i * k->ds_k;
        over = st->over + (1.0 - eta) * i * k->ds_k;
    } else {
        oc = st->oc * k->a_o;
        over = st->over + i * k->ds_k;
        if (over < 0.0)
            over = 0.0;
        eta = 1.0;
        r = k->r0 * f + k->kd / ((s > 0.0 ? s : 0.0) + k->eps);
        extra = 0.0;
    }
    v1 = st->v1 * k->a1 + i * k->r1b * f;
    v2 = st->v2 * k->a2 + i * k->r2b * f;
    ds = eta * i * k->ds_k;
    x = st->surf * k->a_x + ds * k->b_x;
    s += ds;
    if (s > 1.0)
        s = 1.0;
    else if (s < SOC_FLOOR)
        s = SOC_FLOOR;
    su = s + x;                        /* the surface, where the OCV is read */
    if (su < 0.0) {
        if (su < SOC_FLOOR)
            su = SOC_FLOOR;
        e = k->ys[0] + su * COLLAPSE_V_PER_SOC - k->k_t * (t - T_REF_C);
    } else {
        int32_t j = bisect_right(k->xs, k->last + 1, su);
        if (j > k->last)
            j = k->last;
        e = k->ys[j - 1] + (su - k->xs[j - 1]) * k->slopes[j - 1] - k->k_t * (t - T_REF_C);
    }
    v = e - k->k_dip * st->oc * k->a_o + k->k_over * st->over * st->over + extra + i * r + v1 + v2 + vp;
    if (k->half_m != 0.0) {
        double h = st->h;
        v -= k->half_m * (1.0 - h);
        if (i > 0.0)
            st->h = 1.0 + (h - 1.0) * exp(-i * k->h_k);
        else if (i < 0.0)
            st->h = -1.0 + (h + 1.0) * exp(i * k->h_k);
    }
    q = i * (v - eta * e) + eta * i * k->q_rev;
    t_final = k->ambient_c + q * k->inv_ha;
    st->temp_c = t_final + (t - t_final) * k->a_th;
    st->soc = s;
    st->v1 = v1;
    st->v2 = v2;
    st->vp = vp;
    st->oc = oc;
    st->over = over;
    st->surf = x;
    st->current = i;
    st->cell_voltage = v;
    v *= k->series;
    st->voltage = v;
    return v;
}

/* Pack.cv_terms */
typedef struct {
    double rest, r_ohmic, g_charge, extra, vp, r_pol, vp_max, r_dis, g_dis, x0, b_x;
} cv_terms_t;

static void cv_terms(const zm_constants_t *k, const zm_state_t *st, cv_terms_t *c)
{
    double s = st->soc, t = st->temp_c, f, eta, wf;
    f = exp(k->ea_r / (t + KELVIN) - k->ea_r_ref);
    c->vp = st->vp * k->a_p;
    c->rest = (st->v1 * k->a1 + st->v2 * k->a2 - k->k_t * (t - T_REF_C) + c->vp - k->k_dip * st->oc * k->a_o
               + k->k_over * st->over * st->over - k->half_m * (1.0 - st->h));
    c->r_ohmic = (k->r0 + k->r1b + k->r2b) * f;
    wf = 1.0 + k->w_t * (t - T_REF_C);
    eta = 1.0 - exp((s - 1.0) * k->inv_w0 / (wf > W_FLOOR ? wf : W_FLOOR));
    c->r_pol = k->kc / (1.0 - s + k->eps) * (1.0 - k->a_p);
    c->g_charge = eta * k->ds_k;
    c->extra = (1.0 - eta) * k->dv_o2;
    c->vp_max = k->vp_max;
    c->r_dis = c->r_ohmic + k->kd / ((s > 0.0 ? s : 0.0) + k->eps);
    c->g_dis = k->ds_k;
    c->x0 = st->surf * k->a_x;
    c->b_x = k->b_x;
}

/* Pack._solve_ocv: rhs = U(soc + g*i) + r*i on the piecewise-linear table */
static double solve_ocv(const zm_constants_t *k, double s, double rhs, double r, double g)
{
    int32_t last = k->last, j = bisect_right(k->xs, last + 1, s);
    if (j < 1)
        j = 1;
    if (j > last)
        j = last;
    for (;;) {
        double slope = k->slopes[j - 1];
        double i = (rhs - k->ys[j - 1] - (s - k->xs[j - 1]) * slope) / (r + slope * g);
        double s_end = s + g * i;
        if (s_end > k->xs[j] && j < last)
            j++;
        else if (s_end < k->xs[j - 1] && j > 1)
            j--;
        else if (s_end < 0.0) {
            /* past empty the OCV collapses as one_step reads it (Pack._solve_ocv) */
            i = (rhs - k->ys[0] - s * COLLAPSE_V_PER_SOC) / (r + COLLAPSE_V_PER_SOC * g);
            if (s + g * i < SOC_FLOOR)
                i = (rhs - k->ys[0] - SOC_FLOOR * COLLAPSE_V_PER_SOC) / r;
            return i;
        } else
            return i;
    }
}

static double one_current_for_voltage(const zm_constants_t *k, const zm_state_t *st, double v_pack)
{
    cv_terms_t c;
    double target, charge_rhs, i, s, g;
    cv_terms(k, st, &c);
    target = v_pack / k->series;
    charge_rhs = target - c.rest - c.extra;
    s = st->soc + c.x0;
    g = c.g_charge + c.g_charge * c.b_x;
    i = solve_ocv(k, s, charge_rhs, c.r_ohmic + c.r_pol, g);
    if (i > 0.0 && c.vp + i * c.r_pol > c.vp_max)
        i = solve_ocv(k, s, charge_rhs + c.vp - c.vp_max, c.r_ohmic, g);
    if (i > 0.0)
        return i;
    i = solve_ocv(k, s, target - c.rest, c.r_dis, c.g_dis + c.g_dis * c.b_x);
    return i < 0.0 ? i : 0.0;
}

/* -- a CellPack ---------------------------------------------------------------------------------- */

/* cell_pack._cell_voltage: one cell's end-of-step voltage at series current x, and its slope */
static double cell_voltage(const zm_constants_t *k, const cv_terms_t *c, double s, double bleed, double x,
                           double *slope_out)
{
    double i = x - bleed, g, gx, v, dv, pol, slope;
    int32_t j;
    if (i > 0.0) {
        g = c->g_charge;
        v = c->rest + c->extra + c->r_ohmic * i;
        dv = c->r_ohmic;
        pol = c->vp + i * c->r_pol;
        if (pol > c->vp_max) {
            v += c->vp_max - c->vp;
        } else {
            v += i * c->r_pol;
            dv += c->r_pol;
        }
    } else {
        g = c->g_dis;
        v = c->rest + c->r_dis * i;
        dv = c->r_dis;
    }
    gx = g * c->b_x;
    s += g * i;
    if (s > 1.0) {
        s = 1.0;
        g = 0.0;
    }
    s += c->x0 + gx * i;               /* the surface, where the OCV is read */
    g += gx;
    if (s < 0.0) {
        if (s < SOC_FLOOR) {
            *slope_out = dv;
            return v + k->ys[0] + SOC_FLOOR * COLLAPSE_V_PER_SOC;
        }
        *slope_out = dv + g * COLLAPSE_V_PER_SOC;
        return v + k->ys[0] + s * COLLAPSE_V_PER_SOC;
    }
    j = bisect_right(k->xs, k->last + 1, s);
    if (j > k->last)
        j = k->last;
    slope = k->slopes[j - 1];
    *slope_out = dv + g * slope;
    return v + k->ys[j - 1] + (s - k->xs[j - 1]) * slope;
}

/* cell_pack._solve: the series current at which cells [from, to) sum to v_target at the end of the step */
static double solve_cells(const zm_pack_t *p, const cv_terms_t *terms, int32_t from, int32_t to, double v_target,
                          double x)
{
    double lo = -INFINITY, hi = INFINITY;
    int32_t k, step;
    for (step = 0; step < CV_MAX_STEPS; step++) {
        double f = -v_target, df = 0.0, nx;
        for (k = from; k < to; k++) {
            double dv, v = cell_voltage(&p->k[k], &terms[k], p->s[k].soc, p->bleed_a[k], x, &dv);
            f += v;
            df += dv;
        }
        if (fabs(f) <= CV_TOLERANCE_V)
            break;
        if (f < 0.0)
            lo = x;
        else
            hi = x;
        nx = x - f / df;
        if (!(lo < nx && nx < hi))
            nx = 0.5 * (lo + hi);
        if (hi - lo < 1e-12) {
            /* a jump (a cell's O2 overvoltage as its current changes sign): the current just below it */
            x = lo;
            break;
        }
        x = nx;
    }
    return x;
}

static double cells_current_for_voltage(zm_pack_t *p, double v_pack)
{
    cv_terms_t terms[ZM_MAX_CELLS];
    int32_t n = p->cells, k;
    for (k = 0; k < n; k++)
        cv_terms(&p->k[k], &p->s[k], &terms[k]);
    p->cv_guess = solve_cells(p, terms, 0, n, v_pack, p->cv_guess);
    return p->cv_guess;
}

double zm_pack_current_for_ceiling(zm_pack_t *p, double current_a, double ceiling_v)
{
    cv_terms_t terms[ZM_MAX_CELLS];
    int32_t k;
    for (k = 0; k < p->cells; k++) {
        double dv;
        cv_terms(&p->k[k], &p->s[k], &terms[k]);
        if (cell_voltage(&p->k[k], &terms[k], p->s[k].soc, p->bleed_a[k], current_a, &dv) > ceiling_v)
            current_a = solve_cells(p, terms, k, k + 1, ceiling_v, current_a);
    }
    return current_a > 0.0 ? current_a : 0.0;
}

/* -- either ---------------------------------------------------------------------------------------- */

double zm_pack_step(zm_pack_t *p, double current_a)
{
    int32_t k;
    if (!p->cells) {
        p->voltage = one_step(p->k, p->s, current_a);
        p->current = current_a;
        return p->voltage;
    }
    for (k = 0; k < p->cells; k++)
        p->cell_voltages[k] = one_step(&p->k[k], &p->s[k], current_a - p->bleed_a[k]);
    p->current = current_a;
    p->voltage = zm_sum(p->cell_voltages, p->cells, p->neumaier_sum);
    return p->voltage;
}

double zm_pack_current_for_voltage(zm_pack_t *p, double v_pack)
{
    return p->cells ? cells_current_for_voltage(p, v_pack) : one_current_for_voltage(p->k, p->s, v_pack);
}

double zm_pack_open_circuit_voltage(const zm_pack_t *p)
{
    double v[ZM_MAX_CELLS];
    int32_t k;
    if (!p->cells)
        return one_ocv(p->k, p->s);
    for (k = 0; k < p->cells; k++)
        v[k] = one_ocv(&p->k[k], &p->s[k]);
    return zm_sum(v, p->cells, p->neumaier_sum);
}

double zm_pack_temp_c(const zm_pack_t *p)
{
    double t[ZM_MAX_CELLS];
    int32_t k;
    if (!p->cells)
        return p->s->temp_c;
    for (k = 0; k < p->cells; k++)
        t[k] = p->s[k].temp_c;
    return zm_sum(t, p->cells, p->neumaier_sum) / p->cells;
}

double zm_pack_soc(const zm_pack_t *p)
{
    double w[ZM_MAX_CELLS];
    int32_t k;
    if (!p->cells)
        return p->s->soc;
    for (k = 0; k < p->cells; k++)
        w[k] = p->s[k].soc * p->q[k];
    return zm_sum(w, p->cells, p->neumaier_sum) / p->q_total;
}
