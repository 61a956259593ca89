/* The lockout follows protocol/passport.py `conflicts`: the battery type; every charge current above
 * A_LIMIT; every voltage above V_LIMIT in a charging phase (the charge section, or any CHARGE_EX or
 * TRICKLE phase); only the sections the task runs; 0 limits mean "not set"; a value that does not
 * resolve is skipped (the start fails on it anyway). CRIT > 0 refuses the start too (spec section 4). */
#include <string.h>
#include "passport.h"
#include "record.h"
#include "text.h"
#include "pgm.h"
#include "../hal.h"

#define MAGIC 0xA7
/* the longest conflict: "the macro lets the voltage rise to 2147.48 V (discharge phase 255); the
 * battery allows 255 V" (92) */
#define LINE_MAX 100

uint8_t zc_passport_read(uint8_t p[PASSPORT_SIZE])
{
    uint8_t request[8] = {MAGIC, 0x00, 0, 0, 0, 0, 0, 0}, k;
    uint16_t check = 0;
    for (k = 0; k < 7; k++)
        request[7] ^= request[k];
    if (!hal_passport_exchange(request, sizeof request, p))
        return PASSPORT_NONE;
    for (k = 0; k < 0x1E; k += 2)
        check ^= zc_u16(p + k);
    /* an error answer (0xEE where the version stands) is no passport */
    return p[0] == MAGIC && p[1] != 0xEE && check == zc_u16(p + 0x1E) ? PASSPORT_OK : PASSPORT_BAD;
}

/* The conflicts, one a line; each is built in `line` and kept only whole. */
typedef struct {
    char *at, *end;
    uint8_t count, full;
    char line[LINE_MAX];
} lines_t;

static void keep(lines_t *l, const char *line_end)
{
    uint8_t n = (uint8_t)(line_end - l->line), sep = l->count != 0;
    l->count++;
    if (l->full || l->at + sep + n > l->end) {
        l->full = 1;                     /* a line that does not fit ends the message */
        return;
    }
    if (sep)
        *l->at++ = '\n';
    memcpy(l->at, l->line, n);
    l->at += n;
}

/* "the macro charges at 3.00 A (charge phase 2); the battery allows 2 A" */
static void conflict(lines_t *l, const char *what, int32_t micro, uint8_t volts, uint8_t section, uint8_t index,
                     uint8_t limit)
{
    char *p = zc_put_2f(zc_put_P(l->line, what), (uint32_t)micro);
    p = zc_put_P(p, volts ? PSTR(" V") : PSTR(" A"));
    p = zc_put_P(p, section ? PSTR(" (charge phase ") : PSTR(" (discharge phase "));
    p = zc_put_uint(p, index);
    p = zc_put_uint(zc_put_P(p, PSTR("); the battery allows ")), limit);
    keep(l, zc_put_P(p, volts ? PSTR(" V") : PSTR(" A")));
}

static void section(lines_t *l, const zc_run_t *r, uint8_t pc, uint8_t section, uint8_t a_lim, uint8_t v_lim)
{
    uint8_t index = 0;
    for (; r->rec[pc] != OP_END_SECTION; pc = (uint8_t)(pc + zc_op_size(r->rec[pc]))) {
        uint8_t at, last[ZC_PHASE_OPS], a_i, a_v, a_ex, a_tr;
        if (r->rec[pc] != OP_FAZE)
            continue;
        index++;
        zc_phase_ops(r->rec, pc, last);
        a_i = last[OP_CONSTANT_I - OP_CONSTANT_I];
        a_v = last[OP_CONSTANT_V - OP_CONSTANT_I];
        a_ex = last[OP_CHARGE_EX - OP_CONSTANT_I];
        a_tr = last[OP_TRICKLE - OP_CONSTANT_I];
        if (!section && !a_ex && !a_tr)
            continue;                        /* a discharge: no charge current, no charge voltage */
        if (a_lim) {
            uint8_t c = a_ex ? (uint8_t)(a_ex + 2) : a_tr ? (uint8_t)(a_tr + 1) : a_i ? (uint8_t)(a_i + 1) : 0;
            int32_t ua = c ? zc_current_ua(r, zc_u16(r->rec + c)) : ZC_NONE;
            if (!c && a_v)
                ua = r->start.current_ua > 0 ? r->start.current_ua : r->board.max_charge_ua;
            if (ua != ZC_NONE && ua > (int32_t)a_lim * 1000000L)
                conflict(l, c ? PSTR("the macro charges at ") : PSTR("the macro charges at up to "), ua, 0,
                         section, index, a_lim);
        }
        for (at = (uint8_t)(pc + 1); v_lim && r->rec[at] != OP_END_FAZE; at = (uint8_t)(at + zc_op_size(r->rec[at]))) {
            uint8_t op = r->rec[at];
            int32_t uv;
            if (op != OP_CONSTANT_V && op != OP_TRICKLE && op != OP_IF_V_GT)
                continue;
            uv = zc_voltage_uv(r, zc_u16(r->rec + at + (op == OP_TRICKLE ? 5 : 1)));
            if (uv != ZC_NONE && uv > (int32_t)v_lim * 1000000L)
                conflict(l, op == OP_CONSTANT_V ? PSTR("the macro holds ") : op == OP_TRICKLE ?
                         PSTR("the macro tops up to ") : PSTR("the macro lets the voltage rise to "), uv, 1,
                         section, index, v_lim);
        }
    }
}

/* The charger's own check at START, as the virtual charger's (docs/safety.md): lint E311, a lithium
 * trickle charge (LiPo, LiIon, LiS, LiFe). */
static void lithium_trickle(lines_t *l, const zc_run_t *r)
{
    uint8_t pc;
    if (r->akk_type < 4 || r->akk_type > 7)
        return;
    for (pc = r->rec[1]; r->rec[pc] != OP_END_MACRO; pc = (uint8_t)(pc + zc_op_size(r->rec[pc])))
        if (r->rec[pc] == OP_TRICKLE)
            keep(l, zc_put_P(zc_put_uint(zc_put_P(l->line, PSTR("E311 (byte ")), pc),
                             PSTR("): Lithium cells must never be trickle-charged")));
}

ZC_NOINLINE uint8_t zc_passport_conflicts(const zc_run_t *r, const uint8_t p[PASSPORT_SIZE], char *out, uint8_t max)
{
    lines_t l;
    uint16_t crit = zc_u16(p + 0x19);
    char *at;
    l.at = out;
    l.end = out + max - 1;
    l.count = l.full = 0;
    lithium_trickle(&l, r);
    if (crit) {
        at = zc_put_uint(zc_put_P(l.line, PSTR("the battery has ")), crit);
        keep(&l, zc_put_P(at, PSTR(" critical error(s) (CRIT): it is not fit for use")));
    }
    if (r->akk_type != p[0x16]) {
        at = zc_put_akk(zc_put_P(l.line, r->akk_type ? PSTR("the macro is for ") :
                               PSTR("the macro sets no battery type (AKK_TYPE ")), r->akk_type);
        keep(&l, zc_put_akk(zc_put_P(at, r->akk_type ? PSTR("; the battery is ") : PSTR("); the battery is ")),
                          p[0x16]));
    }
    if (r->start.task != ZC_CHARGE)
        section(&l, r, r->discharge_at, 0, p[0x1C], p[0x1B]);
    if (r->start.task != ZC_DISCHARGE)
        section(&l, r, r->charge_at, 1, p[0x1C], p[0x1B]);
    *l.at = 0;
    return l.count;
}
