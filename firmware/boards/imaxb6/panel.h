/* The B6's front panel without a PC (docs/firmware.md, *Front panel*): pick a slot by its name,
 * start and stop it with the buttons, read the run and its end on the LCD. */
#ifndef B6_PANEL_H
#define B6_PANEL_H

#include <stdint.h>

void panel_poll(uint32_t now_ms, uint8_t calibrated);

/* A refusal (text in flash) on line 2 until a key: the START the PC sent too. */
void panel_say(const char *message);

#endif
