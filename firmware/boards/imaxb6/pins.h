/* The original iMAX B6's wiring, as docs/firmware.md's pin table gives it with its cheali-charger
 * sources ([P] imaxB6-pins.h, [B] imaxB6.cpp, [S] SMPS_PID.cpp, [A] AnalogInputsADC.cpp). */
#ifndef B6_PINS_H
#define B6_PINS_H

#include <avr/io.h>

/* PORTD */
#define B6_BAL4 PD0                /* TQFP 9: cell 4's load, also the USART's RXD */
#define B6_BAL5 PD2                /* 11 */
#define B6_OUTPUT_DISABLE PD3      /* 12: high = off [B] setBatteryOutput */
#define B6_BUCK PD4                /* 13: OC1B [S] */
#define B6_BOOST PD5               /* 14: OC1A, the boost switch and the discharge load [P] */
#define B6_SMPS_DISABLE PD6        /* 15: high = off [S] setChargerOutput */
#define B6_BAL6 PD7                /* 16 */
/* PORTC: the LCD's DB7..DB4 on PC0..PC3 (a nibble reversed), E, RS; cells 1, 2's loads */
#define B6_LCD_E PC4               /* 23 */
#define B6_LCD_RS PC5              /* 24 */
#define B6_BAL1 PC6                /* 25 */
#define B6_BAL2 PC7                /* 26 */
/* PORTA: ADC0..ADC4, the multiplexer's output on ADC6; cell 3's load, the discharger's disable */
#define B6_ADC_VOUT 0              /* 37 */
#define B6_ADC_VOUT_MINUS 1        /* 36 */
#define B6_ADC_IDIS 2              /* 35 */
#define B6_ADC_ISMPS 3             /* 34 */
#define B6_ADC_VIN 4               /* 33 */
#define B6_BAL3 PA5                /* 32 */
#define B6_ADC_MUX 6               /* 31 */
#define B6_DISCHARGE_DISABLE PA7   /* 30: high = off [S] setDischargerOutput */
/* PORTB: buttons (inputs, external pull-ups, pressed = low [B]), buzzer, multiplexer address */
#define B6_KEY_STOP PB0            /* 40 */
#define B6_KEY_DEC PB1             /* 41 */
#define B6_KEY_INC PB2             /* 42 */
#define B6_KEY_START PB3           /* 43 */
#define B6_KEYS (_BV(PB0) | _BV(PB1) | _BV(PB2) | _BV(PB3))
#define B6_BUZZER PB4              /* 44 */
#define B6_MUX_SHIFT 5             /* PB5..PB7: address 0..7 [A] */
#define B6_MUX_MASK 0xE0

#endif
