/* The macro store: the EEPROM holds the PC's image (records back to back, spec section 2) in its
 * first half and the staging copy of a write transaction in its second half; the last byte is a
 * journal flag, so a COMMIT cut off by a power loss is finished at the next start, never left mixed. */
#ifndef ZUML_STORE_H
#define ZUML_STORE_H

#include <stdint.h>

uint16_t store_size(void);                 /* bytes of the image the PC sees */
void store_init(void);                     /* finishes a COMMIT a power loss interrupted */
uint8_t store_read(uint16_t at);
void store_stage_begin(void);              /* staging := the image */
void store_stage_write(uint16_t at, uint8_t value);
uint16_t store_stage_crc(void);            /* CRC-16/MODBUS of the whole staged image */
uint16_t store_commit(void);               /* copies the staged bytes that differ; returns how many */
/* The record in slot `slot` (0-based, EEPROM order) into rec; its length, 0 when there is no such
 * slot, 0xFFFF when the record list is broken before it. */
uint16_t store_record(uint8_t slot, uint8_t *rec);
uint16_t zc_crc16(uint16_t crc, uint8_t byte);

#endif
