/* The record as stored (docs/zuml-2.0.md section 2): instruction sizes, operand ranges and the structural check
 * a record passes before it runs. The PC's checker does the rest (lint, units); the firmware only
 * makes sure that the walk through the bytes can never leave the record or meet a phase with no
 * action. */
#include <string.h>
#include "zuml.h"
#include "pgm.h"
#include "record.h"

uint8_t zc_op_size(uint8_t code)
{
    switch (code) {
    case OP_END_MACRO: case OP_DISCHARGE_SECTION: case OP_CHARGE_SECTION: case OP_END_SECTION:
    case OP_END_CYCLE: case OP_FAZE: case OP_END_FAZE:
        return 1;
    case OP_CYCLE: case OP_START_SHABLON: case OP_AKK_TYPE: case OP_SERIES: case OP_IF_T_GT:
    case OP_IF_TC_GT: case OP_IF_TC_LT: case OP_MUSIC: case OP_LIGHT:
        return 2;
    case OP_CAPACITY: case OP_CONSTANT_I: case OP_CONSTANT_V: case OP_IF_V_LT: case OP_IF_V_GT:
    case OP_IF_I_LT: case OP_IF_DPEAK_GT:
        return 3;
    case OP_IF_TM_GT: case OP_IF_TF_GT:
        return 5;
    case OP_TRICKLE:
        return 7;
    case OP_CHARGE_EX:
        return 8;
    default:
        return 0;
    }
}

uint8_t zc_op_role(uint8_t code)
{
    if (code <= OP_END_FAZE)
        return ROLE_STRUCTURE;
    if (code <= OP_CAPACITY)
        return ROLE_DECLARATION;
    if (code <= OP_TRICKLE)
        return ROLE_ACTION;
    if (code <= OP_IF_DPEAK_GT)
        return (code >= OP_IF_TC_GT && code <= OP_IF_TM_GT) ? ROLE_INTRO_CONDITION : ROLE_CONDITION;
    return ROLE_COMMAND;
}

void zc_phase_ops(const uint8_t *rec, uint8_t faze_at, uint8_t last[ZC_PHASE_OPS])
{
    uint8_t pc;
    memset(last, 0, ZC_PHASE_OPS);
    for (pc = (uint8_t)(faze_at + 1); rec[pc] != OP_END_FAZE; pc = (uint8_t)(pc + zc_op_size(rec[pc])))
        if (rec[pc] >= OP_CONSTANT_I && rec[pc] <= OP_IF_DPEAK_GT)
            last[rec[pc] - OP_CONSTANT_I] = pc;
}

uint16_t zc_u16(const uint8_t *p) { return (uint16_t)(p[0] | ((uint16_t)p[1] << 8)); }

uint32_t zc_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/* Operands with a narrower range than their width (opcodes.py lo/hi). */
static uint8_t operands_ok(const uint8_t *p)
{
    switch (p[0]) {
    case OP_CYCLE: case OP_SERIES: case OP_MUSIC: return p[1] >= 1;
    case OP_AKK_TYPE: return p[1] <= 8;
    case OP_CAPACITY: return zc_u16(p + 1) != 1;
    case OP_LIGHT: return p[1] >= 1 && p[1] <= 103;
    case OP_CHARGE_EX: return p[1] >= 1 && p[7] <= 2;
    default: return 1;
    }
}

/* Reads the instruction at pc; 0 when it is not one or runs past `end`. */
static ZC_NOINLINE uint8_t take(const uint8_t *rec, uint8_t pc, uint8_t end)
{
    uint8_t size;
    if (pc >= end)
        return 0;
    size = zc_op_size(rec[pc]);
    if (size == 0 || (uint16_t)pc + size > end || !operands_ok(rec + pc))
        return 0;
    return size;
}

#define FAIL(at) return (uint16_t)((at) + 1)

/* One section from pc (after its opening byte) to its END_SECTION; returns the offset after it in
 * *pc, or a failure. */
static uint16_t section(const uint8_t *rec, uint8_t *pc, uint8_t end)
{
    uint8_t in_cycle = 0, in_phase = 0, actions = 0, has_i = 0, has_v = 0;
    for (;;) {
        uint8_t at = *pc, size = take(rec, at, end), op;
        if (!size)
            FAIL(at);
        op = rec[at];
        *pc = (uint8_t)(at + size);
        if (in_phase) {
            uint8_t role = zc_op_role(op);
            if (op == OP_END_FAZE) {
                /* exactly one action, or CONSTANT_I with CONSTANT_V (CC-CV) */
                if (actions == 0 || (actions > 1 && !(actions == 2 && has_i && has_v)))
                    FAIL(at);
                in_phase = 0;
            } else if (role == ROLE_ACTION) {
                actions++;
                has_i |= op == OP_CONSTANT_I;
                has_v |= op == OP_CONSTANT_V;
            } else if (role != ROLE_CONDITION) {
                FAIL(at);
            }
            continue;
        }
        switch (op) {
        case OP_END_SECTION:
            if (in_cycle)
                FAIL(at);
            return 0;
        case OP_FAZE:
            in_phase = 1; actions = has_i = has_v = 0;
            break;
        case OP_CYCLE:
            if (in_cycle)
                FAIL(at);
            in_cycle = 1;
            break;
        case OP_END_CYCLE:
            if (!in_cycle)
                FAIL(at);
            in_cycle = 0;
            break;
        default:
            if (zc_op_role(op) != ROLE_COMMAND)
                FAIL(at);
        }
    }
}

uint16_t zc_validate(const uint8_t *rec, uint16_t len)
{
    uint8_t end, pc, check = 0, i;
    uint16_t bad;
    if (len < 10 || len > ZC_MAX_RECORD || rec[0] != len)
        FAIL(0);
    end = (uint8_t)(len - 1);
    for (i = 0; i < end; i++)
        check ^= rec[i];
    if (check != rec[end])
        FAIL(end);
    /* the name: 1..16 printable characters, then 0 */
    for (pc = 4; pc < end && rec[pc] != 0; pc++)
        if (rec[pc] < ' ' || rec[pc] > '~' || pc - 4 >= 16)
            FAIL(pc);
    if (pc == 4 || pc >= end || rec[1] != pc + 1)
        FAIL(1);
    pc++;
    while (pc < end && rec[pc] != OP_DISCHARGE_SECTION) {
        uint8_t size = take(rec, pc, end), role = zc_op_role(rec[pc]);
        if (!size || (role != ROLE_DECLARATION && role != ROLE_INTRO_CONDITION))
            FAIL(pc);
        pc = (uint8_t)(pc + size);
    }
    if (pc >= end)
        FAIL(pc);
    pc++;
    if ((bad = section(rec, &pc, end)) != 0)
        return bad;
    /* commands between the sections (seed 000, byte layout item 8) */
    while (pc < end && zc_op_role(rec[pc]) == ROLE_COMMAND) {
        uint8_t size = take(rec, pc, end);
        if (!size)
            FAIL(pc);
        pc = (uint8_t)(pc + size);
    }
    if (pc >= end || rec[pc] != OP_CHARGE_SECTION)
        FAIL(pc);
    pc++;
    if (rec[2] != pc)
        FAIL(2);
    if ((bad = section(rec, &pc, end)) != 0)
        return bad;
    if (rec[3] != pc)
        FAIL(3);
    for (;;) {
        uint8_t size = take(rec, pc, end);
        if (!size)
            FAIL(pc);
        if (rec[pc] == OP_END_MACRO)
            break;
        if (zc_op_role(rec[pc]) != ROLE_COMMAND)
            FAIL(pc);
        pc = (uint8_t)(pc + size);
    }
    if (pc + 1 != end)
        FAIL(pc);
    return 0;
}
