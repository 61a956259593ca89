/* Constant text and tables in flash on the AVR (its RAM is 2 KB), plain memory elsewhere. */
#ifndef ZUML_PGM_H
#define ZUML_PGM_H

#ifdef __AVR__
#include <avr/pgmspace.h>
#else
#include <string.h>
#define PROGMEM
#define PSTR(s) (s)
#define pgm_read_byte(p) (*(const uint8_t *)(p))
#define memcpy_P memcpy
#define strlen_P strlen
#define strcpy_P strcpy
#endif

/* A helper called from several places stays one copy (LTO would inline it at each). */
#ifdef __GNUC__
#define ZC_NOINLINE __attribute__((noinline))
#else
#define ZC_NOINLINE
#endif

#endif
