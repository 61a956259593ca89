/* The battery passport (docs/zuml-2.0.md section 4, seed 003) and the lockout: a macro whose chemistry or
 * limits do not match the battery must not start. */
#ifndef ZUML_PASSPORT_H
#define ZUML_PASSPORT_H

#include <stdint.h>
#include "zuml.h"

#define PASSPORT_SIZE 32
enum { PASSPORT_NONE = 0, PASSPORT_OK = 1, PASSPORT_BAD = 2 };

/* Reads the whole passport over hal_passport_exchange; PASSPORT_NONE when nothing answers. */
uint8_t zc_passport_read(uint8_t passport[PASSPORT_SIZE]);
/* Why the started run `r` must not run on this battery: one conflict per line into out (at most
 * max bytes with its 0); returns the number of conflicts. */
uint8_t zc_passport_conflicts(const zc_run_t *r, const uint8_t passport[PASSPORT_SIZE], char *out, uint8_t max);

#endif
