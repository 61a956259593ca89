/* Canonical texts, byte for byte those of zuml_studio/lang/formatter.py + opcodes.canonical_text
 * (the differential test compares every end reason). No printf: it costs kilobytes on the AVR. */
#include <string.h>
#include "text.h"
#include "record.h"
#include "pgm.h"

#define put zc_put_P

char *zc_put_P(char *p, const char *s)
{
    char c;
    while ((c = (char)pgm_read_byte(s++)) != 0)
        *p++ = c;
    return p;
}

char *zc_put_uint(char *p, uint32_t v)
{
    char digits[10];
    uint8_t n = 0;
    do {
        digits[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        *p++ = digits[--n];
    return p;
}

static char *put_int(char *p, int32_t v)
{
    if (v < 0) {
        *p++ = '-';
        return zc_put_uint(p, (uint32_t)(-(v + 1)) + 1);
    }
    return zc_put_uint(p, (uint32_t)v);
}

/* value/100 in its shortest decimal form (410 -> 4.1, 5 -> 0.05), or with both decimals (fixed) */
static ZC_NOINLINE char *put_hundredths(char *p, uint32_t v, uint8_t fixed)
{
    uint8_t cents;
    p = zc_put_uint(p, v / 100);
    cents = (uint8_t)(v % 100);
    if (cents || fixed) {
        *p++ = '.';
        *p++ = (char)('0' + cents / 10);
        if (cents % 10 || fixed)
            *p++ = (char)('0' + cents % 10);
    }
    return p;
}

ZC_NOINLINE char *zc_put_akk(char *p, uint8_t type)
{
    static const char names[9][6] PROGMEM = {"Undef", "Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiS", "LiFe", "New"};
    return type < 9 ? zc_put_P(p, names[type]) : zc_put_uint(p, type);
}

ZC_NOINLINE char *zc_put_2f(char *p, uint32_t micro)
{
    return put_hundredths(p, (micro + 5000UL) / 10000UL, 1);
}

/* A current (absolute 'A', relative 'C') or a voltage ('V'/'S'). */
static char *put_scaled(char *p, uint16_t raw, char abs_unit, char rel_unit)
{
    if (raw == RAW_INPUT)
        return put(p, PSTR("INPUT"));
    p = put_hundredths(p, raw & 0x7FFF, 0);
    *p++ = (raw & RAW_RELATIVE) ? rel_unit : abs_unit;
    return p;
}

/* Tenths of a second in the largest unit that states them exactly. */
static char *put_time(char *p, uint32_t raw)
{
    if (raw) {
        if (raw % 36000UL == 0)
            return put(zc_put_uint(p, raw / 36000UL), PSTR("h"));
        if (raw % 600UL == 0)
            return put(zc_put_uint(p, raw / 600UL), PSTR("min"));
        if (raw % 10UL == 0)
            return put(zc_put_uint(p, raw / 10UL), PSTR("s"));
    }
    return zc_put_uint(p, raw);
}

uint8_t zc_instruction_text(const uint8_t *ins, char *out)
{
    /* names of MUSIC 1..4 and LIGHT 100..103, 10 bytes apart */
    static const char names[8][10] PROGMEM = {"START", "STOP", "ERROR", "ATTENTION", "SLOW", "FAST", "ON", "FAZE"};
    char *p = out;
    uint8_t op = ins[0];
    if (op == OP_MUSIC || op == OP_LIGHT) {
        p = put(p, op == OP_MUSIC ? PSTR("MUSIC(") : PSTR("LIGHT("));
        if (op == OP_MUSIC && ins[1] >= 1 && ins[1] <= 4)
            p = put(p, names[ins[1] - 1]);
        else if (op == OP_LIGHT && ins[1] >= 100 && ins[1] <= 103)
            p = put(p, names[ins[1] - 96]);
        else
            p = zc_put_uint(p, ins[1]);
        *p++ = ')';
    } else {
        const char *outcome = PSTR("STOP_FAZE");
        p = put(p, PSTR("IF("));
        switch (op) {
        case OP_IF_T_GT: p = put_int(put(p, PSTR("T>")), (int8_t)ins[1]); break;
        case OP_IF_V_LT: p = put_scaled(put(p, PSTR("V<")), zc_u16(ins + 1), 'V', 'S'); break;
        case OP_IF_V_GT: p = put_scaled(put(p, PSTR("V>")), zc_u16(ins + 1), 'V', 'S'); break;
        case OP_IF_I_LT: p = put_scaled(put(p, PSTR("I<")), zc_u16(ins + 1), 'A', 'C'); break;
        case OP_IF_TC_GT: p = put_int(put(p, PSTR("Tc>")), (int8_t)ins[1]); outcome = PSTR("PAUSE_MACRO"); break;
        case OP_IF_TC_LT: p = put_int(put(p, PSTR("Tc<")), (int8_t)ins[1]); outcome = PSTR("CONTINUE_MACRO"); break;
        case OP_IF_TM_GT: p = put_time(put(p, PSTR("tm>")), zc_u32(ins + 1)); outcome = PSTR("STOP_MACRO"); break;
        case OP_IF_TF_GT: p = put_time(put(p, PSTR("tf>")), zc_u32(ins + 1)); break;
        default: p = put_scaled(put(p, PSTR("DELTA_PEAK>")), zc_u16(ins + 1), 'V', 'S'); break;
        }
        *p++ = ')';
        *p++ = ' ';
        p = put(p, outcome);
    }
    *p = 0;
    return (uint8_t)(p - out);
}

uint8_t zc_reason_text(const zc_run_t *r, uint8_t reason, uint8_t offset, char *out)
{
    char *p = out;
    switch (reason) {
    case ZC_R_CONDITION: case ZC_R_STOP_MACRO:
        return zc_instruction_text(r->rec + offset, out);
    case ZC_R_DEFAULT_T: p = put(p, PSTR("default: T>60")); break;
    case ZC_R_DEFAULT_DTDT: p = put(p, PSTR("default: dT/dt>1C/min")); break;
    case ZC_R_DEFAULT_CAPACITY: p = put(p, PSTR("default: capacity 1.5x")); break;
    case ZC_R_DEFAULT_EMPTY: {
        /* the per-cell end voltage to 10 mV, as Python's {:.2f} */
        int32_t per_cell = zc_chemistry_end_uv(r->akk_type);
        if (!per_cell)
            per_cell = r->board.fallback_end_uv_per_cell;
        p = put(zc_put_2f(put(p, PSTR("default: empty discharge section, V<")), (uint32_t)per_cell), PSTR("V/cell"));
        break;
    }
    case ZC_R_BALANCER: {
        int32_t ceiling_uv;
        hal_balancer_ceiling(&ceiling_uv);
        p = put(zc_put_uint(put(p, PSTR("balancer: cell ")), offset), PSTR(" reached "));
        p = put(zc_put_2f(p, (uint32_t)ceiling_uv), PSTR("V (ceiling)"));
        break;
    }
    case ZC_R_STOPPED: p = put(p, PSTR("stopped")); break;
    case ZC_R_END: p = put(p, PSTR("end of macro")); break;
    default: break;
    }
    *p = 0;
    return (uint8_t)(p - out);
}

uint8_t zc_event_text(const zc_run_t *r, const zc_event_t *e, char *out)
{
    char *p = out;
    switch (e->kind) {
    case ZC_EV_PHASE_END: case ZC_EV_FINISH:
        return zc_reason_text(r, e->reason, e->reason_offset, out);
    case ZC_EV_MUSIC: case ZC_EV_LIGHT:
        return zc_instruction_text(r->rec + e->offset, out);
    case ZC_EV_PAUSE: p = put_int(put(p, PSTR("Tc>")), r->tc_pause); break;
    case ZC_EV_RESUME: p = put_int(put(p, PSTR("Tc<")), r->tc_continue); break;
    default: break;
    }
    *p = 0;
    return (uint8_t)(p - out);
}
