/* The macro store: the EEPROM holds the PC's image (records back to back, docs/zuml-2.0.md section 2), then the
 * staging copy of a write transaction, then the 16 start templates (each with a check byte); the byte before the last marks
 * the templates as set up, the last is a journal flag, so a COMMIT cut off by a power loss is
 * finished at the next start, never left mixed. */
#ifndef ZUML_STORE_H
#define ZUML_STORE_H

#include <stdint.h>

uint16_t store_size(void);                 /* bytes of the image the PC sees */
#define STORE_TEMPLATES 16
/* Finishes a COMMIT a power loss interrupted; 1 when the templates were blank (first start: none
 * held now; the caller stores the factory ones). */
uint8_t store_init(void);
/* Start template `number` (1..16) into t (ZC_TEMPLATE_SIZE bytes); 0 when there is none. */
uint8_t store_template(uint8_t number, uint8_t *t);
void store_set_template(uint8_t number, const uint8_t *t);
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
