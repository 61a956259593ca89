/* A probe image for the simulated iMAX B6 (tests/firmware/test_fw_b6_sim.py), written from the B6's wiring as
 * cheali-charger documents it, independently of the harness's table: it answers one-letter requests on the
 * USART (38400 8N1) and shows the buttons on the LCD, so a test can check what the harness wires where.
 *   aN   ADC channel N (0..7) against AREF, the sum of 64 conversions    -> "aN=SUM\n"
 *   mN   multiplexer address N (PB7..PB5) into ADC6, the same             -> "mN=SUM\n"
 *   bNNN the buck switch (OC1B, PD4) at NNN/512, the output and the SMPS enabled  -> "ok\n"
 *   lHH  the balancer's load switches, bit n-1 = cell n                   -> "ok\n"
 *   x    everything off: the disable lines high, no PWM                   -> "ok\n"
 *   t0   Timer0 in CTC at 16 MHz / 64 / (OCR0 249 + 1) = 1 kHz: cell 1's load on for 1000 compare matches
 *        (the firmware's millisecond clock)                               -> "ok\n"
 * Line 1 of the LCD reads "PROBE" (or "PROBE WDT" after a watchdog reset), line 2 "KEYS sdiS" with each button
 * pressed shown by its letter; START switches the buck on at 500/512 as b500 does. The watchdog (30 ms) is fed
 * by the main loop only. */
#include <avr/io.h>
#include <avr/wdt.h>
#include <util/delay.h>

#define LCD_E 4
#define LCD_RS 5

static void off(void)
{
    TCCR1A = 0;
    PORTD = (uint8_t)((PORTD & ~(_BV(4) | _BV(5))) | _BV(3) | _BV(6));  /* OUTPUT_DISABLE, SMPS_DISABLE high */
    PORTA |= _BV(7);                                                    /* DISCHARGE_DISABLE high */
}

static void lcd_nibble(uint8_t rs, uint8_t n)
{
    /* DB4..DB7 = PC3..PC0 */
    uint8_t c = (uint8_t)((PORTC & 0xC0) | (n & 1 ? 8 : 0) | (n & 2 ? 4 : 0) | (n & 4 ? 2 : 0) | (n & 8 ? 1 : 0));
    PORTC = (uint8_t)(c | (rs ? _BV(LCD_RS) : 0));
    PORTC |= _BV(LCD_E);
    _delay_us(1);
    PORTC &= (uint8_t)~_BV(LCD_E);
    _delay_us(50);
}

static void lcd_byte(uint8_t rs, uint8_t v)
{
    lcd_nibble(rs, v >> 4);
    lcd_nibble(rs, v & 15);
}

static void lcd_text(uint8_t address, const char *s)
{
    lcd_byte(0, (uint8_t)(0x80 | address));
    while (*s)
        lcd_byte(1, (uint8_t)*s++);
}

static void put(char c)
{
    while (!(UCSRA & _BV(UDRE)))
        ;
    UDR = (uint8_t)c;
}

static void put_number(const char *prefix, uint32_t v)
{
    char digits[11];
    int n = 0;
    while (*prefix)
        put(*prefix++);
    do {
        digits[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        put(digits[--n]);
    put('\n');
}

static void buck(uint16_t top_fraction)
{
    OCR1B = top_fraction;
    TCCR1A = _BV(COM1B1) | _BV(WGM11);
    PORTD &= (uint8_t)~(_BV(3) | _BV(6));
}

static int get(void)
{
    uint16_t waited = 0;
    while (!(UCSRA & _BV(RXC))) {
        _delay_us(100);
        wdt_reset();
        if (++waited > 2000)
            return -1;
    }
    return UDR;
}

static uint32_t adc_sum(uint8_t channel)
{
    uint32_t sum = 0;
    uint8_t k;
    ADMUX = channel;                                    /* REFS = 00: the external AREF */
    _delay_us(50);
    for (k = 0; k < 64; k++) {
        ADCSRA |= _BV(ADSC);
        while (ADCSRA & _BV(ADSC))
            ;
        sum += ADC;
    }
    return sum;
}

/* 1000 Timer0 compare matches, polled (never an interrupt to be late), between cell 1's load going on and off:
 * the harness's BALANCER lines time them */
static void timer0_second(void)
{
    uint16_t matches = 0;
    TCCR0 = 0;
    TCNT0 = 0;
    OCR0 = 249;
    TIFR = _BV(OCF0);
    TCCR0 = _BV(WGM01) | _BV(CS01) | _BV(CS00);
    PORTC |= 0x40;
    while (matches < 1000) {
        wdt_reset();
        if (TIFR & _BV(OCF0)) {
            TIFR = _BV(OCF0);
            matches++;
        }
    }
    PORTC &= (uint8_t)~0x40;
    TCCR0 = 0;
}

static int hex(int c) { return c >= '0' && c <= '9' ? c - '0' : (c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1); }

int main(void)
{
    uint8_t by_watchdog = MCUCSR & _BV(WDRF);
    char keys[10] = "KEYS     ";
    MCUCSR = 0;
    DDRD = _BV(3) | _BV(4) | _BV(5) | _BV(6);
    DDRA = _BV(7);
    off();
    wdt_enable(WDTO_30MS);
    DDRC = 0xFF;
    DDRB = 0xE0;
    UBRRH = 0;                                          /* first: simavr takes the rate at the UBRRL write */
    UBRRL = 25;                                         /* 38400 at 16 MHz: 0.2 % */
    UCSRB = _BV(RXEN) | _BV(TXEN);
    ADCSRA = _BV(ADEN) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
    ICR1 = 512;
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS10);
    _delay_ms(20);
    wdt_reset();
    lcd_nibble(0, 3);
    _delay_ms(5);
    lcd_nibble(0, 3);
    lcd_nibble(0, 3);
    lcd_nibble(0, 2);
    lcd_byte(0, 0x28);
    lcd_byte(0, 0x0C);
    lcd_byte(0, 0x06);
    lcd_byte(0, 0x01);
    _delay_ms(2);
    lcd_text(0, by_watchdog ? "PROBE WDT" : "PROBE");
    for (;;) {
        uint8_t pins = PINB;
        wdt_reset();
        keys[5] = pins & _BV(0) ? ' ' : 's';
        keys[6] = pins & _BV(1) ? ' ' : 'd';
        keys[7] = pins & _BV(2) ? ' ' : 'i';
        keys[8] = pins & _BV(3) ? ' ' : 'S';
        lcd_text(0x40, keys);
        if (!(pins & _BV(3)))
            buck(500);
        if (UCSRA & _BV(RXC)) {
            int c = UDR, n = get(), a, b;
            if (c == 'a' && n >= '0' && n <= '7') {
                char prefix[4] = {'a', (char)n, '=', 0};
                put_number(prefix, adc_sum((uint8_t)(n - '0')));
            } else if (c == 'm' && n >= '0' && n <= '7') {
                char prefix[4] = {'m', (char)n, '=', 0};
                /* the mux's output holds the last input's charge: emptied first (PA6 driven low), as the firmware does */
                DDRA |= _BV(6);
                _delay_us(50);
                PORTB = (uint8_t)((PORTB & 0x1F) | (n - '0') << 5);
                DDRA &= (uint8_t)~_BV(6);
                put_number(prefix, adc_sum(6));
            } else if (c == 'b' && (a = get()) >= '0' && (b = get()) >= '0') {
                buck((uint16_t)((n - '0') * 100 + (a - '0') * 10 + (b - '0')));
                put('o'); put('k'); put('\n');
            } else if (c == 'l' && hex(n) >= 0 && (a = hex(get())) >= 0) {
                uint8_t mask = (uint8_t)(hex(n) << 4 | a);
                /* cells 1..6: PC6, PC7, PA5, PD0, PD2, PD7 */
                PORTC = (uint8_t)((PORTC & 0x3F) | (mask & 1 ? 0x40 : 0) | (mask & 2 ? 0x80 : 0));
                DDRA |= _BV(5);
                PORTA = (uint8_t)((PORTA & ~_BV(5)) | (mask & 4 ? _BV(5) : 0));
                DDRD |= _BV(2) | _BV(7);
                PORTD = (uint8_t)((PORTD & ~(_BV(2) | _BV(7))) | (mask & 16 ? _BV(2) : 0) | (mask & 32 ? _BV(7) : 0));
                put('o'); put('k'); put('\n');
            } else if (c == 't' && n == '0') {
                timer0_second();
                put('o'); put('k'); put('\n');
            } else if (c == 'x') {
                off();
                put('o'); put('k'); put('\n');
            }
        }
        _delay_ms(2);
    }
}
