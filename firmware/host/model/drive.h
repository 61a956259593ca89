/* A pack driven along a curve (drive.c). Host only. */
#ifndef ZM_DRIVE_H
#define ZM_DRIVE_H

#include "pack.h"

/* Steps the pack through n samples: sample k with the constants ks[which[k]] (one per tick length, each the
 * pack's per-cell array), at current[k], or where cv[k] at the current that puts it at voltage[k] (kept to
 * current[k]'s direction). Writes the pack's voltage, its current and its temperature per sample; stops after
 * the first sample whose voltage is at or below stop_v. Returns the samples done. */
int32_t zm_drive(zm_pack_t *p, const zm_constants_t *const *ks, const int32_t *which, const double *current,
                 const double *voltage, const uint8_t *cv, int32_t n, double stop_v, double *v_out, double *i_out,
                 double *temp_out);

#endif
