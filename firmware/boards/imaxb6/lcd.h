/* The B6's 16x2 HD44780, 4-bit, written blind (no RW line: fixed waits instead of the busy flag). */
#ifndef B6_LCD_H
#define B6_LCD_H

#include <stdint.h>

#define LCD_COLUMNS 16
void lcd_init(void);
/* Line 0 or 1: `text` (RAM), cut or padded with spaces to the 16 columns. */
void lcd_line(uint8_t row, const char *text);

#endif
