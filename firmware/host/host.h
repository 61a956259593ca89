/* The host board's entry points (host.c) that a C caller uses: the simulation engine (engine.c). The
 * differential test in tests/firmware drives the same functions through ctypes. */
#ifndef ZH_HOST_H
#define ZH_HOST_H

#include <stdint.h>
#include "../core/zuml.h"

uint8_t zh_start(const uint8_t *rec, uint16_t len, const zc_start_t *s, const zc_board_t *b);
uint8_t zh_control(int32_t heatsink_uc, int32_t pack_uv, int32_t battery_uc, hal_output_t *out);
uint8_t zh_measure(int32_t pack_uv, int32_t current_ua, int32_t battery_uc, int32_t heatsink_uc, int32_t ocv_uv);
void zh_set_event_sink(void (*sink)(const zc_event_t *e));
void zh_set_ceiling(uint8_t cell, int32_t ceiling_uv);
const zc_run_t *zh_run(void);
uint8_t zh_event_text(const zc_event_t *e, char *out);
void zh_stop(void);

#endif
