/* A pack driven along a logged curve: sim/fit.py's simulate_curve, operation for operation, so a fit's
 * objective runs at C speed (issue 35 section 4) and bit for bit as the Python loop (tests/sim/test_drive.py).
 * Host only, like pack.c: the fit calls it through sim/engine.py's drive(). */
#include "drive.h"

int32_t zm_drive(zm_pack_t *p, const zm_constants_t *const *ks, const int32_t *which, const double *current,
                 const double *voltage, const uint8_t *cv, int32_t n, double stop_v, double *v_out, double *i_out,
                 double *temp_out)
{
    int32_t k;
    for (k = 0; k < n; k++) {
        double cur = current[k], v;
        p->k = ks[which[k]];
        if (cv[k]) {
            /* Held at a voltage, the model's current keeps the log's direction (a discharge's hold never charges). */
            double held = zm_pack_current_for_voltage(p, voltage[k]);
            cur = cur >= 0.0 ? (held > 0.0 ? held : 0.0) : (held < 0.0 ? held : 0.0);
        }
        v = zm_pack_step(p, cur);
        v_out[k] = v;
        i_out[k] = cur;
        temp_out[k] = zm_pack_temp_c(p);
        if (v <= stop_v)
            return k + 1;
    }
    return n;
}
