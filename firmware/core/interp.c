/* The interpreter: the walk through the sections (tasks, CYCLE, commands), a phase's action each
 * tick, its conditions and the charger's defaults (docs/zuml-2.0.md section 3, docs/simulator.md).
 * zuml_studio/sim/interpreter.py is the reference; the differential test in
 * tests/firmware/ runs both on the same battery model and compares every phase. */
#include <stddef.h>
#include <string.h>
#include "zuml.h"
#include "record.h"
#include "pgm.h"

#define DEFAULT_TC_PAUSE 70
#define DEFAULT_TC_CONTINUE 60
#define DEFAULT_T_MAX_UC 60000000L
#define DTDT_RISE_UC 1000000L            /* 1 C per minute over a 60 s window */
#define DTDT_WINDOW_MS 60000UL
#define DTDT_HOLDOFF_MS 120000UL
#define DEFAULT_DISCHARGE_UA 100000L
#define CAPACITY_LIMIT_UAH_PER_MAH 1500UL        /* 1.5 x 1 mAh */

enum { S_BEGIN_REP, S_SECTION_START, S_IN_SECTION, S_AFTER_SECTION, S_CONCLUSION, S_DONE };

/* a x b, both >= 0, saturating at INT32_MAX */
static int32_t mul_sat(uint32_t a, uint32_t b)
{
    return b && a > INT32_MAX / b ? INT32_MAX : (int32_t)(a * b);
}

/* t_ms > tenths x 100 ms, without the product overflowing */
static ZC_NOINLINE uint8_t later_than(uint32_t t_ms, uint32_t tenths)
{
    return t_ms && (t_ms - 1) / 100 >= tenths;
}

static ZC_NOINLINE void charge_add(zc_charge_t *c, const zc_charge_t *d)
{
    c->uah += d->uah;
    c->uams += d->uams;
    if (c->uams >= ZC_UAMS_PER_UAH) {
        c->uams -= ZC_UAMS_PER_UAH;
        c->uah++;
    }
}

/* ua x dt_ms as a charge, exact in 32-bit steps: ua = q x 3.6e6 + r1 x 1000 + r0 */
static void charge_of(zc_charge_t *c, uint32_t ua, uint16_t dt_ms)
{
    uint32_t r = ua % ZC_UAMS_PER_UAH, uas = r / 1000 * dt_ms;
    c->uah = ua / ZC_UAMS_PER_UAH * dt_ms + uas / 3600;
    c->uams = uas % 3600 * 1000 + r % 1000 * dt_ms;
    c->uah += c->uams / ZC_UAMS_PER_UAH;
    c->uams %= ZC_UAMS_PER_UAH;
}

/* A stored current or voltage: INPUT takes the value entered, a relative one (C, S) is raw hundredths
 * of per_unit (0: unknown, ZC_NONE), an absolute one is hundredths of A or V. */
static ZC_NOINLINE int32_t resolve(uint16_t raw, int32_t entered, int32_t per_unit)
{
    if (raw == RAW_INPUT)
        return entered;
    if (raw & RAW_RELATIVE)
        return per_unit > 0 ? mul_sat(raw & 0x7FFF, (uint32_t)per_unit) : ZC_NONE;
    return (int32_t)raw * 10000L;
}

int32_t zc_current_ua(const zc_run_t *r, uint16_t raw)
{
    return resolve(raw, r->start.current_ua, r->capacity_mah * 10L);
}

int32_t zc_voltage_uv(const zc_run_t *r, uint16_t raw)
{
    return resolve(raw, r->start.voltage_uv, r->series * 10000L);
}

int32_t zc_chemistry_end_uv(uint8_t akk_type)
{
    /* docs/zuml-2.0.md section 5, discharge end per cell: Undef, Pb, NiCd, NiMh, LiPo, LiIon, LiS, LiFe, New */
    static const uint16_t end_mv[9] PROGMEM = {0, 1750, 850, 1000, 3000, 2500, 0, 2500, 0};
    uint16_t mv = 0;
    if (akk_type < 9)
        memcpy_P(&mv, &end_mv[akk_type], sizeof mv);
    return (int32_t)mv * 1000L;
}

static void emit(zc_run_t *r, uint8_t kind, uint8_t offset)
{
    zc_event_t e;
    memset(&e, 0, sizeof e);
    e.kind = kind;
    e.offset = offset;
    e.time_ms = r->time_ms;
    e.section = r->phase_section;
    e.index = r->phase_index;
    e.repetition = r->phase_rep;
    e.cycle_pass = r->phase_pass;
    e.reason = r->end_reason;
    e.reason_offset = r->end_offset;
    if (kind == ZC_EV_SECTION) {
        e.section = r->section;
        e.repetition = r->rep;
    } else if (kind == ZC_EV_MUSIC || kind == ZC_EV_LIGHT) {
        e.arg = r->rec[offset + 1];
    } else if (kind == ZC_EV_PHASE_END) {
        e.mah_in_x1000 = r->q_in.uah;
        e.mah_out_x1000 = r->q_out.uah;
    }
    zc_event(&e);
}

/* A start refused for an INPUT or a relative value nothing resolves (checked for every phase of
 * the task before the run, as the charger asks for every value at start). */
static uint8_t value_missing(const zc_run_t *r, const uint8_t *operand, uint8_t is_current)
{
    uint16_t raw = zc_u16(operand);
    if ((is_current ? zc_current_ua(r, raw) : zc_voltage_uv(r, raw)) != ZC_NONE)
        return ZC_OK;
    /* ZC_ERR_INPUT_CURRENT, _C_NEEDS_CAPACITY, _INPUT_VOLTAGE, _S_NEEDS_SERIES in that order */
    return (uint8_t)(ZC_ERR_INPUT_CURRENT + (is_current ? 0 : 2) + (raw == RAW_INPUT ? 0 : 1));
}

static uint8_t value_error(const zc_run_t *r, uint8_t at)
{
    const uint8_t *p = r->rec + at;
    uint8_t err;
    switch (p[0]) {
    case OP_CONSTANT_I: case OP_IF_I_LT:
        return value_missing(r, p + 1, 1);
    case OP_CONSTANT_V: case OP_IF_V_LT: case OP_IF_V_GT: case OP_IF_DPEAK_GT:
        return value_missing(r, p + 1, 0);
    case OP_CHARGE_EX:
        return (err = value_missing(r, p + 2, 1)) != ZC_OK ? err : value_missing(r, p + 5, 1);
    case OP_TRICKLE:
        if ((err = value_missing(r, p + 1, 1)) != ZC_OK || (err = value_missing(r, p + 3, 0)) != ZC_OK)
            return err;
        return value_missing(r, p + 5, 0);
    default:
        return ZC_OK;
    }
}

static uint8_t section_values(const zc_run_t *r, uint8_t pc)
{
    uint8_t err;
    while (r->rec[pc] != OP_END_SECTION) {
        if (r->rec[pc] == OP_FAZE) {
            uint8_t pass, at;
            /* actions first, then conditions, as the reference checks them */
            for (pass = 0; pass < 2; pass++)
                for (at = (uint8_t)(pc + 1); r->rec[at] != OP_END_FAZE; at = (uint8_t)(at + zc_op_size(r->rec[at])))
                    if ((zc_op_role(r->rec[at]) == ROLE_ACTION) == (pass == 0) && (err = value_error(r, at)) != ZC_OK)
                        return err;
        }
        pc = (uint8_t)(pc + zc_op_size(r->rec[pc]));
    }
    return ZC_OK;
}

uint8_t zc_start(zc_run_t *r, const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b)
{
    uint8_t pc, err, template_no, declared = 0;
    uint16_t capacity_raw = CAPACITY_INPUT;
    zc_start_t entered = *s;
    /* rec may be r->rec itself (the device reads the slot straight into the run) */
    memset((uint8_t *)r + sizeof r->rec, 0, sizeof *r - sizeof r->rec);
    r->finished = 1;
    if (zc_validate(rec, len))
        return ZC_ERR_RECORD;
    memmove(r->rec, rec, len);
    r->end = (uint8_t)(len - 1);
    r->charge_at = rec[2];
    r->conclusion_at = rec[3];
    r->board = *b;
    r->tc_pause = DEFAULT_TC_PAUSE;
    r->tc_continue = DEFAULT_TC_CONTINUE;
    template_no = s->template_no;
    for (pc = rec[1]; rec[pc] != OP_DISCHARGE_SECTION; pc = (uint8_t)(pc + zc_op_size(rec[pc]))) {
        switch (rec[pc]) {
        case OP_AKK_TYPE: r->akk_type = rec[pc + 1]; break;
        case OP_SERIES: r->series = rec[pc + 1]; break;
        case OP_CAPACITY: capacity_raw = zc_u16(rec + pc + 1); break;
        case OP_IF_TC_GT: r->tc_pause = (int8_t)rec[pc + 1]; break;
        case OP_IF_TC_LT: r->tc_continue = (int8_t)rec[pc + 1]; break;
        case OP_IF_TM_GT: r->tm_stop_at = pc; break;
        case OP_START_SHABLON: template_no = rec[pc + 1]; declared = 1; break;
        default: break;
        }
    }
    r->discharge_at = (uint8_t)(pc + 1);
    /* the start template: the macro's START_SHABLON=n wins over the one chosen at start */
    if ((declared || template_no) && !zc_template(template_no, &entered))
        return ZC_ERR_NO_TEMPLATE;
    s = &entered;
    r->start = entered;
    /* a declared CAPACITY or SERIES wins over the values entered at start */
    if (capacity_raw != CAPACITY_INPUT && capacity_raw != CAPACITY_AUTO)
        r->capacity_mah = capacity_raw;
    else
        r->capacity_mah = s->capacity_mah > 0 ? s->capacity_mah : 0;
    if (!r->series)
        r->series = s->series > 0 ? s->series : 0;
    if (s->repetitions < 1)
        return ZC_ERR_REPETITIONS;
    if (s->task != ZC_CHARGE && (err = section_values(r, r->discharge_at)) != ZC_OK)
        return err;
    if (s->task != ZC_DISCHARGE && (err = section_values(r, r->charge_at)) != ZC_OK)
        return err;
    r->reps = s->task == ZC_TRAIN ? s->repetitions : 1;
    r->rep = 1;
    r->stage = S_BEGIN_REP;
    r->finished = 0;
    return ZC_OK;
}

void zc_template_apply(zc_start_t *s, const uint8_t *t)
{
    s->task = t[0] <= ZC_TRAIN ? t[0] : ZC_CHARGE;
    s->repetitions = t[1];
    if (zc_u16(t + 2))
        s->capacity_mah = zc_u16(t + 2);
    if (zc_u16(t + 4))
        s->current_ua = (int32_t)zc_u16(t + 4) * 1000L;
    if (zc_u16(t + 6))
        s->voltage_uv = (int32_t)zc_u16(t + 6) * 1000L;
    if (t[8])
        s->series = t[8];
}

static void finish(zc_run_t *r, uint8_t reason, uint8_t offset)
{
    if (r->finished)
        return;
    r->finished = 1;
    r->stage = S_DONE;
    r->end_reason = reason;
    r->end_offset = offset;
    emit(r, ZC_EV_FINISH, 0);
}

static ZC_NOINLINE void end_phase(zc_run_t *r, uint8_t reason, uint8_t offset)
{
    r->end_reason = reason;
    r->end_offset = offset;
    r->active = 0;
    emit(r, ZC_EV_PHASE_END, r->phase_at);
}

static void command(zc_run_t *r, uint8_t at)
{
    if (r->rec[at] == OP_MUSIC) {
        hal_buzzer(r->rec[at + 1]);
        emit(r, ZC_EV_MUSIC, at);
    } else {
        hal_led(r->rec[at + 1]);
        emit(r, ZC_EV_LIGHT, at);
    }
}

/* Turns the phase's byte code into set points once, at its start. */
static ZC_NOINLINE void compile_phase(zc_run_t *r, uint8_t at)
{
    uint8_t last[ZC_PHASE_OPS], a_i, a_v, a_ex, a_tr;
    int32_t sign = r->charging ? 1 : -1;
    zc_phase_ops(r->rec, at, last);
    a_i = last[OP_CONSTANT_I - OP_CONSTANT_I];
    a_v = last[OP_CONSTANT_V - OP_CONSTANT_I];
    a_ex = last[OP_CHARGE_EX - OP_CONSTANT_I];
    a_tr = last[OP_TRICKLE - OP_CONSTANT_I];
    r->own_t = last[OP_IF_T_GT - OP_CONSTANT_I] != 0;
    r->dpeak_at = last[OP_IF_DPEAK_GT - OP_CONSTANT_I];
    if (a_ex) {
        const uint8_t *p = r->rec + a_ex;
        r->mode = M_PULSE;
        r->tch_ms = (uint32_t)p[1] * 1000UL;
        r->i_set = zc_current_ua(r, zc_u16(p + 2));
        r->period_ms = r->tch_ms + (uint32_t)p[4] * 1000UL;
        r->i2 = zc_current_ua(r, zc_u16(p + 5));
        r->tv = p[7];
    } else if (a_tr) {
        const uint8_t *p = r->rec + a_tr;
        r->mode = M_TRICKLE;
        r->i_set = zc_current_ua(r, zc_u16(p + 1));
        r->v_low = zc_voltage_uv(r, zc_u16(p + 3));
        r->v_set = zc_voltage_uv(r, zc_u16(p + 5));
    } else if (a_i && a_v) {
        /* CC-CV: the voltage held with the current limited to CONSTANT_I, in either section */
        r->mode = M_CV;
        r->i_max = zc_current_ua(r, zc_u16(r->rec + a_i + 1));
        r->v_set = zc_voltage_uv(r, zc_u16(r->rec + a_v + 1));
    } else if (a_v) {
        r->mode = M_CV;
        r->v_set = zc_voltage_uv(r, zc_u16(r->rec + a_v + 1));
        if (r->start.current_ua > 0)
            r->i_max = r->start.current_ua;
        else
            r->i_max = r->charging ? r->board.max_charge_ua : r->board.max_discharge_ua;
    } else {
        r->mode = M_CC;
        r->i_set = sign * zc_current_ua(r, zc_u16(r->rec + a_i + 1));
    }
}

static ZC_NOINLINE void begin_phase(zc_run_t *r, uint8_t at, uint8_t is_default)
{
    r->active = 1;
    r->run_no++;
    r->is_default = is_default;
    r->phase_at = at;
    r->phase_section = r->section;
    r->phase_index = is_default ? 0 : r->faze_index;
    r->phase_pass = is_default ? 0 : r->loop_pass;
    r->phase_rep = r->rep;
    r->charging = r->section;
    r->check_defaults = r->section;
    r->trickle_on = 1;
    r->dtdt_next = DTDT_WINDOW_MS;
    memset(&r->own_t, 0, sizeof *r - offsetof(zc_run_t, own_t));
    r->dp_peak_count = 1;          /* the held peak starts at 0 V */
    if (is_default) {
        int32_t per_cell = zc_chemistry_end_uv(r->akk_type);
        if (!per_cell)
            per_cell = r->board.fallback_end_uv_per_cell;
        r->i_set = -DEFAULT_DISCHARGE_UA;
        r->v_low = mul_sat((uint32_t)per_cell, r->series > 0 ? (uint32_t)r->series : 1);
    } else {
        compile_phase(r, at);
    }
    r->measured_v = hal_pack_uv();
    r->dtdt_t0 = hal_battery_uc();
    emit(r, ZC_EV_PHASE_START, at);
}

/* Walks the byte code to the next phase, running commands on the way; 0 once the macro is over. */
static uint8_t next_phase(zc_run_t *r)
{
    for (;;) {
        switch (r->stage) {
        case S_BEGIN_REP:
            if (r->rep > r->reps) {
                r->stage = S_CONCLUSION;
                r->pc = r->conclusion_at;
            } else {
                r->section = r->start.task == ZC_CHARGE ? 1 : 0;
                r->stage = S_SECTION_START;
            }
            break;
        case S_SECTION_START:
            r->pc = r->section ? r->charge_at : r->discharge_at;
            r->faze_index = 0;
            r->ran = 0;
            r->loop_left = 0;
            r->loop_pass = 0;
            r->stage = S_IN_SECTION;
            emit(r, ZC_EV_SECTION, (uint8_t)(r->pc - 1));
            break;
        case S_IN_SECTION: {
            uint8_t at = r->pc, op = r->rec[at];
            r->pc = (uint8_t)(at + zc_op_size(op));
            switch (op) {
            case OP_END_SECTION:
                r->stage = S_AFTER_SECTION;
                if (!r->section && !r->ran) {
                    begin_phase(r, (uint8_t)(r->discharge_at - 1), 1);
                    return 1;
                }
                break;
            case OP_CYCLE:
                r->loop_left = r->rec[at + 1];
                r->loop_pc = r->pc;
                r->loop_pass = 1;
                r->loop_faze = r->faze_index;
                break;
            case OP_END_CYCLE:
                if (--r->loop_left > 0) {
                    r->pc = r->loop_pc;
                    r->loop_pass++;
                    r->faze_index = r->loop_faze;
                } else {
                    r->loop_pass = 0;
                }
                break;
            case OP_FAZE:
                r->faze_index++;
                r->ran = 1;
                while (r->rec[r->pc] != OP_END_FAZE)
                    r->pc = (uint8_t)(r->pc + zc_op_size(r->rec[r->pc]));
                r->pc++;
                begin_phase(r, at, 0);
                return 1;
            default:
                command(r, at);
            }
            break;
        }
        case S_AFTER_SECTION:
            if (!r->section && r->rec[r->pc] != OP_CHARGE_SECTION) {
                /* the commands between the sections, read on from the discharge section */
                command(r, r->pc);
                r->pc = (uint8_t)(r->pc + zc_op_size(r->rec[r->pc]));
            } else if (!r->section && r->start.task != ZC_DISCHARGE) {
                r->section = 1;
                r->stage = S_SECTION_START;
            } else {
                r->rep++;
                r->stage = S_BEGIN_REP;
            }
            break;
        case S_CONCLUSION:
            if (r->rec[r->pc] == OP_END_MACRO) {
                if (r->stop_macro)
                    finish(r, ZC_R_STOP_MACRO, r->tm_stop_at);
                else
                    finish(r, ZC_R_END, 0);
                return 0;
            }
            command(r, r->pc);
            r->pc = (uint8_t)(r->pc + zc_op_size(r->rec[r->pc]));
            break;
        default:
            return 0;
        }
    }
}

void zc_control(zc_run_t *r)
{
    hal_output_t out = {HAL_OFF, 0, 0};
    int32_t hs;
    if (r->finished || (!r->active && !next_phase(r))) {
        hal_output(&out);
        return;
    }
    hs = hal_heatsink_uc();
    if (r->paused) {
        if (hs < (int32_t)r->tc_continue * 1000000L) {
            r->paused = 0;
            emit(r, ZC_EV_RESUME, r->phase_at);
        }
    } else if (hs > (int32_t)r->tc_pause * 1000000L) {
        r->paused = 1;
        emit(r, ZC_EV_PAUSE, r->phase_at);
    } else {
        switch (r->mode) {
        case M_CC:
            out.kind = HAL_CURRENT;
            out.current_ua = r->i_set;
            break;
        case M_CV:
            out.kind = r->charging ? HAL_VOLTAGE_CHARGE : HAL_VOLTAGE_DISCHARGE;
            out.current_ua = r->i_max;
            out.voltage_uv = r->v_set;
            break;
        case M_TRICKLE:
            if (r->trickle_on && r->measured_v >= r->v_set)
                r->trickle_on = 0;
            else if (!r->trickle_on && r->measured_v <= r->v_low)
                r->trickle_on = 1;
            if (r->trickle_on) {
                out.kind = HAL_CURRENT;
                out.current_ua = r->i_set;
            }
            break;
        default:
            out.kind = HAL_CURRENT;
            out.current_ua = r->t_phase % r->period_ms < r->tch_ms ? r->i_set : -r->i2;
        }
    }
    hal_output(&out);
}

/* CHARGE_EX measures once a period, at the point tV chooses; in between the last reading holds. */
static int32_t pulse_reading(const zc_run_t *r, int32_t v)
{
    uint32_t at = r->t_phase % r->period_ms;
    if (r->tv == 1 && at == r->tch_ms % r->period_ms)
        return v;
    if (r->tv == 2 && at == 0)
        return v;
    if (r->tv == 0 && at == 0)
        return hal_open_circuit_uv();
    return r->measured_v;
}

/* The window's average, exact: whole uV into *uv, the remainder over dp_count returned (long
 * division of the 64-bit sum by 16-bit digits). */
static uint16_t window_average(const zc_run_t *r, uint32_t *uv)
{
    uint32_t rem = 0, q = 0;
    uint8_t k;
    for (k = 0; k < 4; k++) {
        uint32_t x = rem << 16 | r->dp_sum[k];
        q = q << 16 | x / r->dp_count;
        rem = x % r->dp_count;
    }
    *uv = q;
    return (uint16_t)rem;
}

/* -dV on window averages with a held peak (delta_peak.py); averages compared exactly as whole uV
 * and remainder fractions. Returns whether the drop below the peak exceeds the threshold. */
static uint8_t minus_dv(zc_run_t *r, int32_t v, int32_t threshold)
{
    /* a pack voltage below 0 V (a reading's noise on a shorted pack) counts as 0 V */
    uint32_t window_ms = r->board.dp_window_s * 1000UL, avg, carry = v > 0 ? (uint32_t)v : 0;
    uint16_t rem;
    uint8_t k;
    if (!r->dp_window_open) {
        r->dp_window_open = 1;
        r->dp_window_end = (r->t_phase / window_ms + 1) * window_ms;
    }
    for (k = 4; k--; carry >>= 16) {       /* v < 2^31: the carry never overflows */
        carry += r->dp_sum[k];
        r->dp_sum[k] = (uint16_t)carry;
    }
    r->dp_count++;
    if (r->t_phase >= r->dp_window_end) {
        r->dp_window_end = (r->t_phase / window_ms + 1) * window_ms;
        rem = window_average(r, &avg);
        /* avg + rem/count against peak + peak_rem/peak_count; fractions below 1, products < 2^32 */
        if (r->t_phase <= r->board.dp_holdoff_s * 1000UL || avg > r->dp_peak_uv || (avg == r->dp_peak_uv &&
            (uint32_t)rem * r->dp_peak_count >= (uint32_t)r->dp_peak_rem * r->dp_count)) {
            r->dp_peak_uv = avg;
            r->dp_peak_rem = rem;
            r->dp_peak_count = r->dp_count;
            r->dp_hit = threshold < 0;
        } else {
            /* drop = (peak - avg) + (peak_rem/peak_count - rem/count), the fraction within (-1, 1) */
            uint32_t whole = r->dp_peak_uv - avg;
            r->dp_hit = threshold < 0 || whole > (uint32_t)threshold || (whole == (uint32_t)threshold &&
                        (uint32_t)r->dp_peak_rem * r->dp_count > (uint32_t)rem * r->dp_peak_count);
        }
        memset(r->dp_sum, 0, sizeof r->dp_sum);
        r->dp_count = 0;
    }
    return r->dp_hit;
}

/* The phase's own conditions in byte order; the offset of the first that holds, else 0. */
static uint8_t own_condition(zc_run_t *r, int32_t v, int32_t i, int32_t temp, uint8_t sensor)
{
    uint8_t pc;
    for (pc = (uint8_t)(r->phase_at + 1); r->rec[pc] != OP_END_FAZE; pc = (uint8_t)(pc + zc_op_size(r->rec[pc]))) {
        const uint8_t *p = r->rec + pc;
        uint8_t hit = 0;
        switch (p[0]) {
        case OP_IF_V_GT: hit = v > zc_voltage_uv(r, zc_u16(p + 1)); break;
        case OP_IF_V_LT: hit = v < zc_voltage_uv(r, zc_u16(p + 1)); break;
        case OP_IF_TF_GT: hit = later_than(r->t_phase, zc_u32(p + 1)); break;
        case OP_IF_I_LT: {
            int32_t limit = zc_current_ua(r, zc_u16(p + 1));
            hit = !r->paused && limit > 0 && (i < 0 ? 0U - (uint32_t)i : (uint32_t)i) < (uint32_t)limit;
            break;
        }
        case OP_IF_T_GT: hit = sensor && temp > (int32_t)(int8_t)p[1] * 1000000L; break;
        default: break;
        }
        if (hit)
            return pc;
    }
    return 0;
}

void zc_measure(zc_run_t *r)
{
    int32_t v, i, temp;
    uint8_t sensor, reason = ZC_R_NONE, at = 0;
    uint16_t dt;
    zc_charge_t dq;
    if (!r->active)
        return;
    dt = r->board.tick_ms;
    i = hal_current_ua();
    v = hal_pack_uv();
    temp = hal_battery_uc();
    sensor = r->start.sensor && hal_battery_sensor();
    r->time_ms += dt;
    if (!r->paused)
        r->t_phase += dt;
    charge_of(&dq, i < 0 ? 0U - (uint32_t)i : (uint32_t)i, dt);
    charge_add(i > 0 ? &r->q_in : &r->q_out, &dq);
    charge_add(i > 0 ? &r->total_in : &r->total_out, &dq);
    if (r->mode == M_PULSE)
        v = pulse_reading(r, v);
    r->measured_v = v;
    if (r->is_default) {
        if (v < r->v_low)
            reason = ZC_R_DEFAULT_EMPTY;
    } else if ((at = own_condition(r, v, i, temp, sensor)) != 0) {
        reason = ZC_R_CONDITION;
    }
    if (!reason && r->dpeak_at && !r->paused &&
        minus_dv(r, v, zc_voltage_uv(r, zc_u16(r->rec + r->dpeak_at + 1)))) {
        reason = ZC_R_CONDITION;
        at = r->dpeak_at;
    }
    if (!reason && r->charging) {
        int32_t ceiling_uv;
        if ((at = hal_balancer_ceiling(&ceiling_uv)) != 0)
            reason = ZC_R_BALANCER;
    }
    if (!reason) {
        if (sensor) {
            if (!r->own_t && temp > DEFAULT_T_MAX_UC) {
                reason = ZC_R_DEFAULT_T;
            } else if (r->check_defaults && r->t_phase >= r->dtdt_next) {
                int32_t rise = temp - r->dtdt_t0;
                r->dtdt_t0 = temp;
                r->dtdt_next += DTDT_WINDOW_MS;
                if (r->t_phase > DTDT_HOLDOFF_MS && rise > DTDT_RISE_UC)
                    reason = ZC_R_DEFAULT_DTDT;
            }
        } else if (r->check_defaults && r->capacity_mah > 0) {
            uint32_t limit = (uint32_t)r->capacity_mah * CAPACITY_LIMIT_UAH_PER_MAH;
            if (r->q_in.uah > limit || (r->q_in.uah == limit && r->q_in.uams))
                reason = ZC_R_DEFAULT_CAPACITY;
        }
    }
    if (!reason && r->tm_stop_at && later_than(r->time_ms, zc_u32(r->rec + r->tm_stop_at + 1))) {
        /* STOP_MACRO: the remaining phases and sections are skipped; the conclusion still runs */
        end_phase(r, ZC_R_STOP_MACRO, r->tm_stop_at);
        r->stop_macro = 1;
        r->stage = S_CONCLUSION;
        r->pc = r->conclusion_at;
        return;
    }
    if (reason)
        end_phase(r, reason, at);
}

void zc_stop(zc_run_t *r)
{
    hal_output_t off = {HAL_OFF, 0, 0};
    if (r->active)
        end_phase(r, ZC_R_STOPPED, 0);
    finish(r, ZC_R_STOPPED, 0);
    hal_output(&off);
}
