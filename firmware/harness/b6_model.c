/* The B6's buck/boost stage, its output, the discharger, the balancer's bleed resistors and a per-cell
 * lithium pack, as averaged circuit equations (the switching ripple at 31 kHz is not modelled; the
 * firmware sees averaged ADC values through the board's filters). */
#include <math.h>
#include <string.h>
#include "b6_model.h"

const char *const b6_fault_names[B6_FAULT_KINDS] = {
    "disconnect", "reverse", "cell-high", "sensor-open", "sink-hot", "input-low", "hang", "slow-loop", "input-sag",
};

/* Component values cheali does not give: assumed, typical of a 50 W buck/boost of this kind. */
#define INDUCTOR_H 47e-6        /* tolerance +-20 % */
#define INDUCTOR_R 0.08         /* inductor, switch and shunt resistance, ohm */
#define OUTPUT_C 470e-6         /* output capacitor, F */
#define OUTPUT_BLEED_R 10e3     /* the output dividers' load on the capacitor, ohm */
#define WIRE_R 0.02             /* leads and connectors, ohm */
#define DIODE_V 0.7             /* the freewheel diode that clamps a reversed output */
#define BLEED_R 14.0            /* a balancer load resistor: 300 mA at 4.2 V, the B6 manual's "balance drain" */
#define DISCHARGE_FULL_A 1.2    /* the discharger's current at 100 % of its PWM reference */
#define VIN_V 12.0              /* the supply (the B6 takes 11..18 V) */
#define VIN_LOW_V 10.5          /* what the input-low fault sags it to */
#define VIN_SAG_V 11.3          /* the input-sag fault's: above the 11 V trip, under half a charged 6S pack */
#define CELL_HIGH_V 4.35        /* what one tap reads under the cell-high fault */
#define SINK_HOT_C 95.0
#define AMBIENT_C 25.0
#define SUBSTEP_S 2e-6

/* A LiPo cell's open-circuit voltage against its state of charge (typical curve; steep past full). */
static const double ocv_soc[] = {0.00, 0.05, 0.10, 0.20, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80, 0.90, 1.00};
static const double ocv_v[] = {3.00, 3.45, 3.60, 3.70, 3.75, 3.79, 3.83, 3.87, 3.92, 4.00, 4.08, 4.20};
#define OCV_POINTS (sizeof ocv_v / sizeof ocv_v[0])

static double ocv(double soc)
{
    unsigned k;
    if (soc <= 0)
        return ocv_v[0] + soc * 3.0;
    if (soc >= 1)
        return ocv_v[OCV_POINTS - 1] + (soc - 1) * 5.0;
    for (k = 1; soc > ocv_soc[k]; k++)
        ;
    return ocv_v[k - 1] + (ocv_v[k] - ocv_v[k - 1]) * (soc - ocv_soc[k - 1]) / (ocv_soc[k] - ocv_soc[k - 1]);
}

static double soc_of(double v)
{
    double lo = -0.2, hi = 1.2;
    int k;
    for (k = 0; k < 60; k++) {
        double mid = (lo + hi) / 2;
        if (ocv(mid) < v)
            lo = mid;
        else
            hi = mid;
    }
    return (lo + hi) / 2;
}

static double uniform(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return ((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
}

static double gauss(uint64_t *s)
{
    double u = uniform(s) + 1e-12, v = uniform(s);
    return sqrt(-2 * log(u)) * cos(6.283185307179586 * v);
}

/* a tolerance band: +-tol, uniform */
static double within(uint64_t *s, double tol) { return 1 + tol * (2 * uniform(s) - 1); }

void b6_model_init(b6_model_t *m, uint64_t seed, int cells, double capacity_mah, double soc, double spread_mv)
{
    int k;
    double v0 = ocv(soc);
    memset(m, 0, sizeof *m);
    m->rng = seed * 0x2545F4914F6CDD1DULL + 1;
    m->aref_v = B6_AREF_V * within(&m->rng, 0.01);      /* a 1 % reference */
    for (k = 0; k < B6_Q_NONE; k++)
        m->gain[k] = within(&m->rng, 0.01);             /* 1 % divider resistors */
    m->gain[B6_Q_I_SMPS] = within(&m->rng, 0.03);       /* shunt and amplifier */
    m->gain[B6_Q_I_DISCHARGE] = within(&m->rng, 0.03);
    m->gain[B6_Q_TEXTERN] = within(&m->rng, 0.02);
    /* the current amplifiers' offsets: half to one and a half times cheali's (never below 0 V) */
    m->ismps_zero_adc16 = b6_adc_channel[3].zero_adc16 * (0.5 + uniform(&m->rng));
    m->idis_zero_adc16 = b6_adc_channel[2].zero_adc16 * (0.5 + uniform(&m->rng));
    m->inductor_h = INDUCTOR_H * within(&m->rng, 0.2);
    m->vin_v = VIN_V * within(&m->rng, 0.01);
    m->cells = cells;
    for (k = 0; k < cells; k++) {
        double offset = cells > 1 ? spread_mv / 1000.0 * ((double)k / (cells - 1) - 0.5) : 0;
        m->soc[k] = soc_of(v0 + offset);
        m->capacity_as[k] = capacity_mah * 3.6 * within(&m->rng, 0.05);
        m->r_cell[k] = 0.03 * within(&m->rng, 0.2);
    }
    m->t_sink_c = m->t_pack_c = AMBIENT_C;
    m->vc_v = 0;
}

double b6_model_cell_v(const b6_model_t *m, int k)
{
    double bleed = m->drive.balancer >> k & 1 ? ocv(m->soc[k]) / BLEED_R : 0;
    return ocv(m->soc[k]) + (m->i_batt_a - bleed) * m->r_cell[k];
}

int b6_model_output_enabled(const b6_model_t *m)
{
    return m->drive.output_on && (m->drive.smps_on || m->drive.discharge_on);
}

/* The supply now, faults applied. */
static double supply_v(const b6_model_t *m)
{
    return m->fault[B6_FAULT_INPUT_LOW] ? VIN_LOW_V : m->fault[B6_FAULT_INPUT_SAG] ? VIN_SAG_V : m->vin_v;
}

void b6_model_step(b6_model_t *m, double dt)
{
    const b6_drive_t *d = &m->drive;
    int connected = d->output_on && !m->fault[B6_FAULT_DISCONNECT];
    int reversed = m->fault[B6_FAULT_REVERSE];
    double vin = supply_v(m);
    double d1 = d->smps_on ? d->buck_duty : 0, d2 = d->smps_on ? d->boost_duty : 0;
    double e = 0, r = WIRE_R, bleed[B6_MAX_CELLS] = {0}, t;
    int k;
    for (k = 0; k < m->cells; k++) {
        bleed[k] = d->balancer >> k & 1 ? ocv(m->soc[k]) / BLEED_R : 0;
        e += ocv(m->soc[k]) - bleed[k] * m->r_cell[k];
        r += m->r_cell[k];
    }
    if (reversed)
        e = -e;
    m->i_dis_a = connected && !reversed && d->discharge_on && !d->smps_on ? d->discharge_duty * DISCHARGE_FULL_A : 0;
    for (t = 0; t < dt; t += SUBSTEP_S) {
        double h = dt - t < SUBSTEP_S ? dt - t : SUBSTEP_S;
        double drive = d1 * vin - (1 - d2) * m->vc_v, il_inf = drive / INDUCTOR_R;
        double g = (connected ? 1 / r : 0) + 1 / OUTPUT_BLEED_R;
        double v_inf = ((1 - d2) * m->il_a - m->i_dis_a + (connected ? e / r : 0)) / g;
        m->il_a = il_inf + (m->il_a - il_inf) * exp(-h * INDUCTOR_R / m->inductor_h);
        if (m->il_a < 0)
            m->il_a = 0;                                 /* the diodes carry no reverse current */
        m->vc_v = v_inf + (m->vc_v - v_inf) * exp(-h * g / OUTPUT_C);
        if (m->vc_v < -DIODE_V)
            m->vc_v = -DIODE_V;
    }
    if (connected) {
        double into_terminal = (m->vc_v - e) / r;
        m->i_batt_a = reversed ? -into_terminal : into_terminal;
        m->v_term_v = m->vc_v;
    } else {
        /* the output dividers sit on the terminals: they see the pack behind an open switch */
        m->i_batt_a = 0;
        m->v_term_v = m->fault[B6_FAULT_DISCONNECT] ? (d->output_on ? m->vc_v : 0) : e;
    }
    for (k = 0; k < m->cells; k++)
        m->soc[k] += (m->i_batt_a - bleed[k]) * dt / m->capacity_as[k];
    /* the heat sink: 10 % of the stage's power and all the discharger's, 2 K/W, 60 s */
    {
        double loss = 0.1 * fabs(m->vc_v * (1 - d2) * m->il_a) + m->i_dis_a * fabs(m->v_term_v);
        double k_s = dt / 60.0 > 1 ? 1 : dt / 60.0;
        m->t_sink_c += (AMBIENT_C + 2.0 * loss - m->t_sink_c) * k_s;
        if (m->fault[B6_FAULT_SINK_HOT])
            m->t_sink_c = SINK_HOT_C;
    }
}

/* What the balance lead's taps carry: the true cells, one replaced by the cell-high fault (the last); nothing
 * when the lead is unplugged. */
static double tap_cell(const b6_model_t *m, int k)
{
    if (k >= m->cells || m->no_lead)
        return 0;
    if (m->fault[B6_FAULT_CELL_HIGH] && k == m->cells - 1)
        return CELL_HIGH_V;
    return b6_model_cell_v(m, k);
}

double b6_model_quantity(const b6_model_t *m, b6_quantity_t q)
{
    switch (q) {
    case B6_Q_VOUT_PLUS:
        return m->v_term_v > 0 ? m->v_term_v : 0;
    case B6_Q_VOUT_MINUS:
        return m->v_term_v < 0 ? -m->v_term_v : 0;   /* a reversed pack lifts the minus terminal */
    case B6_Q_I_DISCHARGE:
        return m->i_dis_a;
    case B6_Q_I_SMPS:
        return m->il_a;
    case B6_Q_VIN:
        return supply_v(m);
    case B6_Q_TAP0:
        return 0;
    case B6_Q_TAP1:
        return tap_cell(m, 0);
    case B6_Q_TAP2:
        return m->cells >= 2 ? tap_cell(m, 0) + tap_cell(m, 1) : 0;
    case B6_Q_CELL3: case B6_Q_CELL4: case B6_Q_CELL5: case B6_Q_CELL6:
        return tap_cell(m, 2 + (q - B6_Q_CELL3));
    case B6_Q_TEXTERN:
        /* an unplugged probe reads 0: the stock firmware reports 0 with no sensor (docs/formats/imaxb6_serial.md) */
        return m->fault[B6_FAULT_SENSOR_OPEN] ? 0 : m->t_pack_c;
    default:
        return 0;
    }
}

double b6_model_adc16(const b6_model_t *m, const b6_input_t *in, double value)
{
    double zero = in->quantity == B6_Q_I_SMPS ? m->ismps_zero_adc16
                  : in->quantity == B6_Q_I_DISCHARGE ? m->idis_zero_adc16 : in->zero_adc16;
    /* the pin: zero offset plus value over the divider (its tolerance), converted against the true AREF */
    return (zero * B6_AREF_V / 65536 + value / (in->full_scale * m->gain[in->quantity]) * B6_AREF_V)
           / m->aref_v * 65536;
}

double b6_model_pin_v(b6_model_t *m, const b6_input_t *in)
{
    double adc16 = b6_model_adc16(m, in, b6_model_quantity(m, in->quantity));
    double v = adc16 / 65536 * m->aref_v + gauss(&m->rng) * 0.4 * m->aref_v / 1024;   /* 0.4 LSB rms */
    return v < 0 ? 0 : v;
}
