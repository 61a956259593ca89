/* The calibration a B6 owner's procedure finds for this board's components, written where the imaxb6 image
 * keeps it in the EEPROM (the layout of docs/firmware.md, "Calibration"). */
#ifndef B6_CALIBRATION_H
#define B6_CALIBRATION_H

#include <stddef.h>
#include <stdint.h>
#include "b6_model.h"

/* The calibration block for model `m`'s tolerances, in `eeprom` (size bytes). */
void b6_calibration_write(const b6_model_t *m, uint8_t *eeprom, size_t size);
/* 1 when `eeprom` holds a block the image accepts (version 1, check byte, no zero full scale). */
int b6_calibration_valid(const uint8_t *eeprom, size_t size);
/* The calibration block erased, as on a charger never calibrated. */
void b6_calibration_erase(uint8_t *eeprom, size_t size);

#endif
