#include "sim_eeprom.h"

#include <stdio.h>
#include <string.h>

#include <avr_eeprom.h>

void sim_eeprom_save(avr_t *avr, uint8_t *eeprom, uint8_t *saved, size_t size, const char *path, const char *who)
{
    avr_eeprom_desc_t d = {.ee = eeprom, .offset = 0, .size = (uint32_t)size};
    char tmp[4096];
    FILE *f;
    if (!path)
        return;
    avr_ioctl(avr, AVR_IOCTL_EEPROM_GET, &d);
    if (d.ee != eeprom)
        memcpy(eeprom, d.ee, size);
    if (!memcmp(eeprom, saved, size))
        return;
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    f = fopen(tmp, "wb");
    if (f && fwrite(eeprom, 1, size, f) == size && fclose(f) == 0 && rename(tmp, path) == 0)
        memcpy(saved, eeprom, size);
    else
        fprintf(stderr, "%s: cannot write %s\n", who, path);
}
