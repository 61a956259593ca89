#include "store.h"
#include "pgm.h"
#include "zuml.h"
#include "hal.h"

#define JOURNAL_COMMITTING 0xA5
#define TEMPLATES_READY 0x5A
/* a template and its check byte (XOR of its bytes): a write a power cut tore reads as no template */
#define TEMPLATE_STORED (ZC_TEMPLATE_SIZE + 1)
#define TEMPLATE_AREA (STORE_TEMPLATES * TEMPLATE_STORED)

uint16_t zc_crc16(uint16_t crc, uint8_t byte)
{
    uint8_t k;
    crc ^= byte;
    for (k = 0; k < 8; k++)
        crc = (crc & 1) ? (uint16_t)((crc >> 1) ^ 0xA001) : (uint16_t)(crc >> 1);
    return crc;
}

uint16_t store_size(void) { return (uint16_t)((hal_eeprom_size() - 2 - TEMPLATE_AREA) / 2); }

static ZC_NOINLINE uint16_t journal(void) { return (uint16_t)(hal_eeprom_size() - 1); }
static ZC_NOINLINE uint16_t templates_mark(void) { return (uint16_t)(hal_eeprom_size() - 2); }
static uint16_t template_at(uint8_t number)
{
    return (uint16_t)(2 * store_size() + (uint16_t)(number - 1) * TEMPLATE_STORED);
}

static ZC_NOINLINE void update(uint16_t addr, uint8_t value)
{
    /* an EEPROM byte wears with every write: write only what changes */
    if (hal_eeprom_read(addr) != value)
        hal_eeprom_write(addr, value);
}

uint16_t store_commit(void)
{
    uint16_t at, size = store_size(), changed = 0;
    update(journal(), JOURNAL_COMMITTING);
    for (at = 0; at < size; at++) {
        uint8_t v = hal_eeprom_read((uint16_t)(size + at));
        if (hal_eeprom_read(at) != v) {
            hal_eeprom_write(at, v);
            changed++;
        }
    }
    update(journal(), 0xFF);
    return changed;
}

uint8_t store_init(void)
{
    uint8_t k;
    if (hal_eeprom_read(journal()) == JOURNAL_COMMITTING)
        store_commit();
    if (hal_eeprom_read(templates_mark()) == TEMPLATES_READY)
        return 0;
    for (k = 1; k <= STORE_TEMPLATES; k++)
        update(template_at(k), 0xFF);
    update(templates_mark(), TEMPLATES_READY);
    return 1;
}

uint8_t store_template(uint8_t number, uint8_t *t)
{
    uint8_t k, check = 0;
    if (number < 1 || number > STORE_TEMPLATES || hal_eeprom_read(template_at(number)) > ZC_TRAIN)
        return 0;
    for (k = 0; k < ZC_TEMPLATE_SIZE; k++)
        check ^= t[k] = hal_eeprom_read((uint16_t)(template_at(number) + k));
    return check == hal_eeprom_read((uint16_t)(template_at(number) + ZC_TEMPLATE_SIZE));
}

void store_set_template(uint8_t number, const uint8_t *t)
{
    /* the task byte (0xFF: none) goes last: a cut leaves no template or the new one, never a mix */
    uint16_t at = template_at(number);
    uint8_t k, check = t[0];
    update(at, 0xFF);
    for (k = 1; k < ZC_TEMPLATE_SIZE; k++) {
        update((uint16_t)(at + k), t[k]);
        check ^= t[k];
    }
    update((uint16_t)(at + ZC_TEMPLATE_SIZE), check);
    update(at, t[0]);
}

uint8_t store_read(uint16_t at) { return hal_eeprom_read(at); }

void store_stage_begin(void)
{
    uint16_t at, size = store_size();
    for (at = 0; at < size; at++)
        update((uint16_t)(size + at), hal_eeprom_read(at));
}

void store_stage_write(uint16_t at, uint8_t value) { update((uint16_t)(store_size() + at), value); }

uint16_t store_stage_crc(void)
{
    uint16_t at, size = store_size(), crc = 0xFFFF;
    for (at = 0; at < size; at++)
        crc = zc_crc16(crc, hal_eeprom_read((uint16_t)(size + at)));
    return crc;
}

uint16_t store_record(uint8_t slot, uint8_t *rec)
{
    uint16_t at = 0, size = store_size(), k;
    uint8_t index = 0;
    while (at < size) {
        uint8_t len = hal_eeprom_read(at);
        if (len == 0x00 || len == 0xFF)
            return 0;
        if (len < 10 || at + len > size)
            return 0xFFFF;
        if (index == slot) {
            for (k = 0; k < len; k++)
                rec[k] = hal_eeprom_read((uint16_t)(at + k));
            return len;
        }
        at = (uint16_t)(at + len);
        index++;
    }
    return 0;
}
