/* Canonical texts the device reports (end reasons, commands), as the PC's formatter writes them. */
#ifndef ZUML_TEXT_H
#define ZUML_TEXT_H

#include <stdint.h>
#include "zuml.h"

#define ZC_TEXT_MAX 64

/* The instruction at rec+at as canonical text (conditions and MUSIC/LIGHT); returns its length. */
uint8_t zc_instruction_text(const uint8_t *ins, char *out);
/* The reason of a phase end or of the macro's finish; returns its length. */
uint8_t zc_reason_text(const zc_run_t *r, uint8_t reason, uint8_t offset, char *out);
/* What an event says in its detail field (reason, command, Tc>70 ...); returns its length. */
uint8_t zc_event_text(const zc_run_t *r, const zc_event_t *e, char *out);

/* v in decimal at p (at most 10 characters, no terminator); returns the end. */
char *zc_put_uint(char *p, uint32_t v);
/* micro-units with two decimals, rounded half up as Python's {:.2f} of the value; returns the end. */
char *zc_put_2f(char *p, uint32_t micro);
/* AKK_TYPE's name ("NiMh"), or its number when it has none; returns the end. */
char *zc_put_akk(char *p, uint8_t type);
/* The flash string s at p (no terminator); returns the end. */
char *zc_put_P(char *p, const char *s);

#endif
