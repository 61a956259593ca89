#include <avr/io.h>
#include <util/delay.h>
#include "lcd.h"
#include "pins.h"

/* DB7..DB4 are PC0..PC3: the nibble's bits in reverse order ([P] LCD_D3_PIN 19 .. LCD_D0_PIN 22). */
static void nibble(uint8_t n)
{
    uint8_t bits = (uint8_t)(((n & 8) >> 3) | ((n & 4) >> 1) | ((n & 2) << 1) | ((n & 1) << 3));
    PORTC = (uint8_t)((PORTC & 0xF0) | bits);
    PORTC |= _BV(B6_LCD_E);
    _delay_us(1);
    PORTC &= (uint8_t)~_BV(B6_LCD_E);
    _delay_us(1);
}

static void write(uint8_t rs, uint8_t byte)
{
    if (rs)
        PORTC |= _BV(B6_LCD_RS);
    else
        PORTC &= (uint8_t)~_BV(B6_LCD_RS);
    nibble(byte >> 4);
    nibble(byte & 15);
    _delay_us(50);                   /* the slowest instruction but clear/home takes 37 us */
}

void lcd_init(void)
{
    DDRC |= 0x0F | _BV(B6_LCD_E) | _BV(B6_LCD_RS);
    _delay_ms(50);
    /* into 4-bit mode from any state (HD44780 datasheet, initialisation by instruction) */
    nibble(3);
    _delay_ms(5);
    nibble(3);
    _delay_us(150);
    nibble(3);
    _delay_us(150);
    nibble(2);
    _delay_us(50);
    write(0, 0x28);                  /* 4 bits, 2 lines, 5x8 */
    write(0, 0x0C);                  /* display on, no cursor */
    write(0, 0x06);                  /* left to right */
    write(0, 0x01);                  /* clear */
    _delay_ms(2);
}

void lcd_line(uint8_t row, const char *text)
{
    uint8_t k;
    write(0, (uint8_t)(0x80 | (row ? 0x40 : 0)));
    for (k = 0; k < LCD_COLUMNS; k++)
        write(1, *text ? (uint8_t)*text++ : ' ');
}
