/* The simulated charger's EEPROM kept in a file, as a real one keeps it over a power cut: both
 * simavr harnesses (the generic ATmega32 and the iMAX B6) write it the same way. */
#ifndef SIM_EEPROM_H
#define SIM_EEPROM_H

#include <stddef.h>
#include <stdint.h>

#include <sim_avr.h>

/* Reads the AVR's EEPROM into `eeprom` and, when it differs from `saved` (what the file holds),
 * writes it to `path` through a temporary file and a rename (a cut never leaves half a file). */
void sim_eeprom_save(avr_t *avr, uint8_t *eeprom, uint8_t *saved, size_t size, const char *path, const char *who);

#endif
