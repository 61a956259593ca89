/* The lockout follows device/passport.py `conflicts`: the battery type; every charge current above
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

uint8_t zc_passport_read(uint8_t p[PASSPORT_SIZE])
{
    uint8_t request[8] = {MAGIC, 0x00, 0, 0, 0, 0, 0, 0}, k;
    uint16_t check = 0;
    for (k = 0; k < 7; k++)
        request[7] ^= request[k];
    if (!hal_passport_exchange(request, p))
        return PASSPORT_NONE;
    for (k = 0; k < 0x1E; k += 2)
        check ^= (uint16_t)(p[k] | (p[k + 1] << 8));
    /* an error answer (0xEE where the version stands) is no passport */
    return p[0] == MAGIC && p[1] != 0xEE && check == (uint16_t)(p[0x1E] | (p[0x1F] << 8)) ? PASSPORT_OK : PASSPORT_BAD;
}

typedef struct {
    char *at, *end, *complete;           /* complete: the end of the last whole line */
    uint8_t count;
} lines_t;

static void put(lines_t *l, const char *flash_text)
{
    char c;
    while ((c = (char)pgm_read_byte(flash_text++)) != 0 && l->at < l->end)
        *l->at++ = c;
}

static void put_uint(lines_t *l, uint32_t v)
{
    char digits[10];
    const char *p = digits, *end = zc_put_uint(digits, v);
    while (p < end && l->at < l->end)
        *l->at++ = *p++;
}

/* micro-units with two decimals, as Python's {:.2f} */
static void put_2f(lines_t *l, int32_t micro)
{
    uint32_t c = ((uint32_t)micro + 5000UL) / 10000UL;
    put_uint(l, c / 100);
    if (l->at + 3 <= l->end) {
        *l->at++ = '.';
        *l->at++ = (char)('0' + c % 100 / 10);
        *l->at++ = (char)('0' + c % 10);
    }
}

static void begin_line(lines_t *l)
{
    if (l->at < l->end)
        l->complete = l->at;
    if (l->count && l->at < l->end)
        *l->at++ = '\n';
    l->count++;
}

static void put_type(lines_t *l, uint8_t type)
{
    static const char names[9][6] PROGMEM = {"Undef", "Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiS", "LiFe", "New"};
    if (type < 9)
        put(l, names[type]);
    else
        put_uint(l, type);
}

/* " (charge phase 2); the battery allows 4 A" */
static void where(lines_t *l, uint8_t section, uint8_t index, uint8_t limit, uint8_t volts)
{
    put(l, section ? PSTR(" (charge phase ") : PSTR(" (discharge phase "));
    put_uint(l, index);
    put(l, PSTR("); the battery allows "));
    put_uint(l, limit);
    put(l, volts ? PSTR(" V") : PSTR(" A"));
}

static void section(lines_t *l, const zc_run_t *r, uint8_t pc, uint8_t section, uint8_t a_lim, uint8_t v_lim)
{
    uint8_t index = 0;
    for (; r->rec[pc] != OP_END_SECTION; pc = (uint8_t)(pc + zc_op_size(r->rec[pc]))) {
        uint8_t at, a_i = 0, a_v = 0, a_ex = 0, a_tr = 0;
        if (r->rec[pc] != OP_FAZE)
            continue;
        index++;
        for (at = (uint8_t)(pc + 1); r->rec[at] != OP_END_FAZE; at = (uint8_t)(at + zc_op_size(r->rec[at]))) {
            a_i = r->rec[at] == OP_CONSTANT_I ? at : a_i;
            a_v = r->rec[at] == OP_CONSTANT_V ? at : a_v;
            a_ex = r->rec[at] == OP_CHARGE_EX ? at : a_ex;
            a_tr = r->rec[at] == OP_TRICKLE ? at : a_tr;
        }
        if (!section && !a_ex && !a_tr)
            continue;                        /* a discharge: no charge current, no charge voltage */
        if (a_lim) {
            uint8_t c = a_ex ? (uint8_t)(a_ex + 2) : a_tr ? (uint8_t)(a_tr + 1) : a_i ? (uint8_t)(a_i + 1) : 0;
            int32_t ua = c ? zc_current_ua(r, zc_u16(r->rec + c)) : ZC_NONE;
            if (!c && a_v)
                ua = r->start.current_ua > 0 ? r->start.current_ua : r->board.max_charge_ua;
            if (ua != ZC_NONE && ua > (int32_t)a_lim * 1000000L) {
                begin_line(l);
                put(l, c ? PSTR("the macro charges at ") : PSTR("the macro charges at up to "));
                put_2f(l, ua);
                put(l, PSTR(" A"));
                where(l, section, index, a_lim, 0);
            }
        }
        if (v_lim) {
            for (at = (uint8_t)(pc + 1); r->rec[at] != OP_END_FAZE; at = (uint8_t)(at + zc_op_size(r->rec[at]))) {
                uint8_t op = r->rec[at];
                int32_t uv;
                if (op != OP_CONSTANT_V && op != OP_TRICKLE && op != OP_IF_V_GT)
                    continue;
                uv = zc_voltage_uv(r, zc_u16(r->rec + at + (op == OP_TRICKLE ? 5 : 1)));
                if (uv != ZC_NONE && uv > (int32_t)v_lim * 1000000L) {
                    begin_line(l);
                    put(l, op == OP_CONSTANT_V ? PSTR("the macro holds ") : op == OP_TRICKLE ?
                        PSTR("the macro tops up to ") : PSTR("the macro lets the voltage rise to "));
                    put_2f(l, uv);
                    put(l, PSTR(" V"));
                    where(l, section, index, v_lim, 1);
                }
            }
        }
    }
}

uint8_t zc_passport_conflicts(const zc_run_t *r, const uint8_t p[PASSPORT_SIZE], char *out, uint8_t max)
{
    lines_t l = {out, out + max - 1, out, 0};
    uint16_t crit = (uint16_t)(p[0x19] | (p[0x1A] << 8));
    if (r->akk_type != p[0x16]) {
        begin_line(&l);
        put(&l, r->akk_type ? PSTR("the macro is for ") : PSTR("the macro sets no battery type (AKK_TYPE "));
        put_type(&l, r->akk_type);
        put(&l, r->akk_type ? PSTR("; the battery is ") : PSTR("); the battery is "));
        put_type(&l, p[0x16]);
    }
    if (crit) {
        begin_line(&l);
        put(&l, PSTR("the battery has "));
        put_uint(&l, crit);
        put(&l, PSTR(" critical error(s) (CRIT): it is not fit for use"));
    }
    if (r->start.task != ZC_CHARGE)
        section(&l, r, r->discharge_at, 0, p[0x1C], p[0x1B]);
    if (r->start.task != ZC_DISCHARGE)
        section(&l, r, r->charge_at, 1, p[0x1C], p[0x1B]);
    /* only whole lines: one that did not fit the message is left out */
    if (l.at >= l.end)
        l.at = l.complete;
    else
        l.complete = l.at;
    *l.at = 0;
    return l.count;
}
