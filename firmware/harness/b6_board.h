/* The original iMAX B6 (ATmega32, TQFP-44) as the simulated board wires it: every pin, ADC channel,
 * multiplexer address and full-scale value the model uses, each with where it comes from, so a reviewer
 * can compare this file line by line with cheali-charger (github.com/stawel/cheali-charger, HEAD):
 *   [P] src/hardware/atmega32/generic/50W/imaxB6-pins.h       pins (TQFP-44 numbers) and mux addresses
 *   [B] src/hardware/atmega32/generic/50W/imaxB6.cpp          button polarity, disable-line polarity
 *   [S] src/hardware/atmega32/generic/50W/SMPS_PID.cpp        buck/boost use, SMPS disable polarity
 *   [A] src/hardware/atmega32/generic/50W/AnalogInputsADC.cpp ADC order, mux on PB5..7, ADC6 discharge
 *   [C] src/hardware/atmega32/targets/imaxB6-original/defaultCalibration.cpp  (ADC16, value) points
 *   [T] src/hardware/atmega32/cpu/Timer1.cpp                  Timer1 mode 14, ICR1 = TIMER1_PERIOD
 *   [G] src/hardware/atmega32/generic/50W/HardwareConfigGeneric.h  TIMER1_PERIOD 512, 6 balance cells
 *   [I] src/hardware/atmega32/cpu/IO.h                        TQFP pin number -> port and bit
 *   [L] src/core/drivers/LiquidCrystal.cpp                    4-bit HD44780, D0..D3 = the LCD's DB4..DB7
 * Nothing here is taken from ZUML's own firmware: the model is the board, the firmware must fit it. */
#ifndef B6_BOARD_H
#define B6_BOARD_H

#include <stdint.h>

/* ATmega32 ports as simavr names them and their data-space addresses (datasheet: I/O + 0x20) */
enum { B6_PA, B6_PB, B6_PC, B6_PD };
#define B6_PORT_LETTER(p) ((char)('A' + (p)))
static const uint8_t b6_port_addr[4] = {0x3B, 0x38, 0x35, 0x32}; /* PORTx; DDRx = -1, PINx = -2 */

typedef struct {
    uint8_t port, bit;
} b6_pin_t;

/* Every digital line the model reads or drives.                     TQFP  [I] port.bit   source */
#define B6_MUX_ADR0        ((b6_pin_t){B6_PB, 5})  /*  1  PB5  [P] MUX_ADR0_PIN 1; [A] (addr&7)<<5 */
#define B6_MUX_ADR1        ((b6_pin_t){B6_PB, 6})  /*  2  PB6  [P] MUX_ADR1_PIN 2 */
#define B6_MUX_ADR2        ((b6_pin_t){B6_PB, 7})  /*  3  PB7  [P] MUX_ADR2_PIN 3 */
#define B6_BAL4_LOAD       ((b6_pin_t){B6_PD, 0})  /*  9  PD0  [P] BALANCER4_LOAD_PIN 9 (also UART RX) */
#define B6_BAL5_LOAD       ((b6_pin_t){B6_PD, 2})  /* 11  PD2  [P] BALANCER5_LOAD_PIN 11 */
#define B6_OUTPUT_DISABLE  ((b6_pin_t){B6_PD, 3})  /* 12  PD3  [P] OUTPUT_DISABLE_PIN 12, high = off [B] */
#define B6_BUCK            ((b6_pin_t){B6_PD, 4})  /* 13  PD4  [P] SMPS_VALUE_BUCK_PIN 13 = OC1B [S][T] */
#define B6_BOOST           ((b6_pin_t){B6_PD, 5})  /* 14  PD5  [P] SMPS_VALUE_BOOST_PIN = DISCHARGE_VALUE_PIN
                                                    *          14 = OC1A [S][T] */
#define B6_SMPS_DISABLE    ((b6_pin_t){B6_PD, 6})  /* 15  PD6  [P] SMPS_DISABLE_PIN 15, high = off [S] */
#define B6_BAL6_LOAD       ((b6_pin_t){B6_PD, 7})  /* 16  PD7  [P] BALANCER6_LOAD_PIN 16 */
#define B6_LCD_DB7         ((b6_pin_t){B6_PC, 0})  /* 19  PC0  [P] LCD_D3_PIN 19 [L] bit 3 of a nibble */
#define B6_LCD_DB6         ((b6_pin_t){B6_PC, 1})  /* 20  PC1  [P] LCD_D2_PIN 20 */
#define B6_LCD_DB5         ((b6_pin_t){B6_PC, 2})  /* 21  PC2  [P] LCD_D1_PIN 21 */
#define B6_LCD_DB4         ((b6_pin_t){B6_PC, 3})  /* 22  PC3  [P] LCD_D0_PIN 22 [L] bit 0 of a nibble */
#define B6_LCD_E           ((b6_pin_t){B6_PC, 4})  /* 23  PC4  [P] LCD_ENABLE_PIN 23 (no RW pin: tied low) */
#define B6_LCD_RS          ((b6_pin_t){B6_PC, 5})  /* 24  PC5  [P] LCD_RS_PIN 24 */
#define B6_BAL1_LOAD       ((b6_pin_t){B6_PC, 6})  /* 25  PC6  [P] BALANCER1_LOAD_PIN 25 */
#define B6_BAL2_LOAD       ((b6_pin_t){B6_PC, 7})  /* 26  PC7  [P] BALANCER2_LOAD_PIN 26 */
#define B6_DISCHARGE_DISABLE ((b6_pin_t){B6_PA, 7}) /* 30 PA7  [P] DISCHARGE_DISABLE_PIN 30, high = off [S] */
#define B6_MUX_Z           ((b6_pin_t){B6_PA, 6})  /* 31  PA6  [P] MUX0_Z_A_PIN A6 / MUX0_Z_D_PIN 31 */
#define B6_BAL3_LOAD       ((b6_pin_t){B6_PA, 5})  /* 32  PA5  [P] BALANCER3_LOAD_PIN 32 */
#define B6_BUTTON_STOP     ((b6_pin_t){B6_PB, 0})  /* 40  PB0  [P] BUTTON_STOP_PIN 40, pressed = low [B] */
#define B6_BUTTON_DEC      ((b6_pin_t){B6_PB, 1})  /* 41  PB1  [P] BUTTON_DEC_PIN 41 */
#define B6_BUTTON_INC      ((b6_pin_t){B6_PB, 2})  /* 42  PB2  [P] BUTTON_INC_PIN 42 */
#define B6_BUTTON_START    ((b6_pin_t){B6_PB, 3})  /* 43  PB3  [P] BUTTON_START_PIN 43 */
#define B6_BUZZER          ((b6_pin_t){B6_PB, 4})  /* 44  PB4  [P] BUZZER_PIN 44 */
/* The buttons have external pull-ups ([B]: "all encountered chargers have external pull-up resistors"),
 * in the order the harness's --press names them */
static const b6_pin_t b6_button[4] = {
    {B6_PB, 3}, {B6_PB, 0}, {B6_PB, 2}, {B6_PB, 1},                /* start, stop, inc, dec */
};

/* Balancer load switches, cell 1..6 ([P] BALANCERn_LOAD_PIN; [B] setBalancer: bit n-1 of the mask) */
static const b6_pin_t b6_balancer_load[6] = {
    {B6_PC, 6}, {B6_PC, 7}, {B6_PA, 5}, {B6_PD, 0}, {B6_PD, 2}, {B6_PD, 7},
};

/* What an analog input measures, at the board's terminals. */
typedef enum {
    B6_Q_VOUT_PLUS,     /* output + terminal to board ground, V */
    B6_Q_VOUT_MINUS,    /* output - terminal to board ground, V (a reversed battery lifts it) */
    B6_Q_I_DISCHARGE,   /* discharge load current, A */
    B6_Q_I_SMPS,        /* buck/boost inductor current, A */
    B6_Q_VIN,           /* supply input, V */
    B6_Q_TAP0,          /* balance port: pack minus to ground, V */
    B6_Q_TAP1,          /* balance port: tap 1 to ground (cell 1), V */
    B6_Q_TAP2,          /* balance port: tap 2 to ground (cells 1+2), V */
    B6_Q_CELL3, B6_Q_CELL4, B6_Q_CELL5, B6_Q_CELL6, /* cell n alone (the board's differential stages) */
    B6_Q_TEXTERN,       /* external probe, degC */
    B6_Q_NONE,
} b6_quantity_t;

/* The ADC16 (cheali's left-adjusted, 65536 = AREF) two points of [C] give each input's full scale (the
 * value at AREF) and offset (ADC16 at zero). full_scale = (v1 - v0) * 65536 / (adc1 - adc0). */
typedef struct {
    b6_quantity_t quantity;
    double full_scale;      /* value at AREF: V, A or degC */
    double zero_adc16;      /* ADC16 reading at 0 */
    const char *source;
} b6_input_t;

/* Direct ADC channels 0..7 ([P] *_PIN A0..A4, A6; PA5 and PA7 are digital lines) */
static const b6_input_t b6_adc_channel[8] = {
    {B6_Q_VOUT_PLUS, 25.141 * 65536 / 55102, 0, "[P] OUTPUT_VOLTAGE_PLUS_PIN A0; [C] Vout {55102, 25141 mV}"},
    {B6_Q_VOUT_MINUS, 12.518 * 65536 / 26613, 0, "[P] OUTPUT_VOLTAGE_MINUS_PIN A1; [C] VreversePolarity "
                                                 "{26613, 12518 mV}"},
    {B6_Q_I_DISCHARGE, (0.300 - 0.050) * 65536 / (11971 - 2017), 2017 - 0.050 * (11971 - 2017) / 0.250,
     "[P] DISCHARGE_CURRENT_PIN A2; [C] Idischarge {2017, 50 mA} {11971, 300 mA}"},
    {B6_Q_I_SMPS, (1.000 - 0.050) * 65536 / (11080 - 775), 775 - 0.050 * (11080 - 775) / 0.950,
     "[P] SMPS_CURRENT_PIN A3; [C] Ismps {775, 50 mA} {11080, 1000 mA}"},
    {B6_Q_VIN, 14.047 * 65536 / 48061, 0, "[P] V_IN_PIN A4; [C] Vin {48061, 14047 mV}"},
    {B6_Q_NONE, 1, 0, "[P] PA5 is BALANCER3_LOAD_PIN (digital)"},
    {B6_Q_NONE, 1, 0, "[P] MUX0_Z_A_PIN A6: the multiplexer's output (below)"},
    {B6_Q_NONE, 1, 0, "[P] PA7 is DISCHARGE_DISABLE_PIN (digital)"},
};
#define B6_MUX_ADC_CHANNEL 6

/* The 8-way multiplexer into ADC6, address = PB7..PB5 ([P] MADDR_*; [A] getPortBAddress) */
static const b6_input_t b6_mux_input[8] = {
    {B6_Q_TAP0, 3.752 * 65536 / 48963, 0, "[P] MADDR_V_BALANSER_BATT_MINUS 0; [C] Vb0_pin {48963, 3752 mV}"},
    {B6_Q_TAP1, 4.187 * 65536 / 55048, 0, "[P] MADDR_V_BALANSER1 1; [C] Vb1_pin {55048, 4187 mV}"},
    {B6_Q_TAP2, 8.378 * 65536 / 56248, 0, "[P] MADDR_V_BALANSER2 2; [C] Vb2_pin {56248, 8378 mV} (tap 2 "
                                          "to ground: twice the divider)"},
    {B6_Q_CELL3, 4.191 * 65536 / 56067, 0, "[P] MADDR_V_BALANSER3 3; [C] Vb3_pin {56067, 4191 mV}"},
    {B6_Q_CELL4, 4.193 * 65536 / 54784, 0, "[P] MADDR_V_BALANSER4 4; [C] Vb4_pin {54784, 4193 mV}"},
    {B6_Q_CELL5, 4.196 * 65536 / 55070, 0, "[P] MADDR_V_BALANSER5 5; [C] Vb5_pin {55070, 4196 mV}"},
    {B6_Q_CELL6, 4.193 * 65536 / 55808, 0, "[P] MADDR_V_BALANSER6 6; [C] Vb6_pin {55808, 4193 mV}"},
    {B6_Q_TEXTERN, 22.80 * 65536 / 5884, 0, "[P] MADDR_T_EXTERN 7; [C] Textern {5884, 22.80 C} {0, 0}: "
                                            "a linear probe, 0 V at 0 C"},
};

/* The external reference. cheali selects it ([A] setADC: REFS = EXTERNAL = 0; [B] analogReference) but
 * does not state its voltage; [C]'s Textern point (0 V at 0 C, 22.8 C at ADC16 5884) is an LM35-type
 * 10 mV/C probe on an undivided input when AREF is 2.54 V. The model takes 2.50 V: only the full scales
 * above reach the firmware, AREF sets the pin voltages simavr converts. */
#define B6_AREF_V 2.50
#define B6_AVCC_V 5.00

/* Timer1: fast PWM mode 14, TOP = ICR1 = 512, no prescaler: 31.2 kHz ([T], [G] TIMER1_PERIOD 512).
 * The buck switch is OC1B, the boost switch OC1A; with the boost off the buck PWM sets the output, above
 * 100 % buck the buck pin is held high and OC1A boosts ([S] setPID_MV). Averaged: Vout = Vin*d_buck/(1-d_boost);
 * cheali caps the boost duty at 0.5 ([S] MAX_PID_MV_FACTOR 1.5: "Vout <= Vin/(1-D)"). */

#endif
