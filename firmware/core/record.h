/* Opcodes of ZUML 2.0 (docs/zuml-2.0.md section 1; zuml_studio/lang/opcodes.py is the table they mirror). */
#ifndef ZUML_RECORD_H
#define ZUML_RECORD_H

#include <stdint.h>

enum {
    OP_END_MACRO = 2, OP_DISCHARGE_SECTION = 3, OP_CHARGE_SECTION = 4, OP_END_SECTION = 5,
    OP_CYCLE = 6, OP_END_CYCLE = 7, OP_FAZE = 8, OP_END_FAZE = 9,
    OP_START_SHABLON = 20, OP_AKK_TYPE = 21, OP_SERIES = 22, OP_CAPACITY = 23,
    OP_CONSTANT_I = 60, OP_CONSTANT_V = 61, OP_CHARGE_EX = 62, OP_TRICKLE = 63,
    OP_IF_T_GT = 81, OP_IF_V_LT = 82, OP_IF_V_GT = 83, OP_IF_I_LT = 84, OP_IF_TC_GT = 85,
    OP_IF_TC_LT = 86, OP_IF_TM_GT = 87, OP_IF_TF_GT = 88, OP_IF_DPEAK_GT = 89,
    OP_MUSIC = 100, OP_LIGHT = 101
};

enum { ROLE_STRUCTURE, ROLE_DECLARATION, ROLE_ACTION, ROLE_CONDITION, ROLE_INTRO_CONDITION, ROLE_COMMAND };

#define RAW_INPUT 0xFFFFu
#define RAW_RELATIVE 0x8000u
#define CAPACITY_INPUT 0x0000u
#define CAPACITY_AUTO 0xFFFFu

uint8_t zc_op_role(uint8_t code);
/* The phase at faze_at (its FAZE byte): last[op - OP_CONSTANT_I] the offset of its last instruction
 * op (actions and conditions, OP_CONSTANT_I..OP_IF_DPEAK_GT), 0 for one it does not have. */
#define ZC_PHASE_OPS (OP_IF_DPEAK_GT - OP_CONSTANT_I + 1)
void zc_phase_ops(const uint8_t *rec, uint8_t faze_at, uint8_t last[ZC_PHASE_OPS]);
uint16_t zc_u16(const uint8_t *p);
uint32_t zc_u32(const uint8_t *p);

#endif
