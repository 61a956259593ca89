/* GENERIC ATmega32 board: a made-up board, NOT for an iMAX B6 (its pins would short a B6's stage: see
 * boards/imaxb6 for the real one). 16 MHz: Timer0 millisecond clock, USART at 115200 baud
 * (../avr_uart.c), the EEPROM, the ADC (free-running over PORTA, oversampled) and Timer1 PWM for the
 * charge buck and the discharge load, both set through calibration.c. The power stage regulates
 * once per millisecond: current mode steers the measured current to the set point, voltage mode
 * steers the voltage within the current limit.
 *
 * Pins (PORTA ADC0..4): VOUT, I charge, I discharge, T battery (NTC), T heat sink.
 * PD4 (OC1B) discharge PWM, PD5 (OC1A) charge PWM, PB0 buzzer, PB1 LED, PD2 passport line. */
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/pgmspace.h>
#include "../../core/app.h"
#include "../common/avr_uart.h"
#include "calibration.h"

#define BAUD 115200UL
#define ADC_OVERSAMPLE 16

static volatile uint32_t millis;
static volatile uint16_t adc_sum[IN_COUNT], adc_value[IN_COUNT];
static volatile uint8_t adc_channel, adc_count;
static hal_output_t out;
static uint16_t duty_charge, duty_discharge;

ISR(TIMER0_COMP_vect) { millis++; }

ISR(ADC_vect)
{
    adc_sum[adc_channel] += ADC;
    if (++adc_count == ADC_OVERSAMPLE) {
        adc_value[adc_channel] = adc_sum[adc_channel];
        adc_sum[adc_channel] = 0;
        adc_count = 0;
        adc_channel = (uint8_t)((adc_channel + 1) % IN_COUNT);
        ADMUX = (uint8_t)((ADMUX & 0xE0) | adc_channel);
    }
    ADCSRA |= _BV(ADSC);
}

static uint16_t adc(uint8_t input)
{
    uint16_t v;
    cli();
    v = adc_value[input];
    sei();
    return v;
}

uint32_t hal_millis(void)
{
    uint32_t t;
    cli();
    t = millis;
    sei();
    return t;
}

void hal_uart_write(uint8_t byte)
{
    while (!(UCSRA & _BV(UDRE)))
        ;
    UDR = byte;
}

uint16_t hal_eeprom_size(void) { return E2END + 1; }
uint8_t hal_eeprom_read(uint16_t addr) { return eeprom_read_byte((const uint8_t *)addr); }
void hal_eeprom_write(uint16_t addr, uint8_t value) { eeprom_write_byte((uint8_t *)addr, value); }

int32_t hal_pack_uv(void) { return cal_input(IN_VOUT, adc(IN_VOUT)); }
int32_t hal_current_ua(void) { return cal_input(IN_ICHARGE, adc(IN_ICHARGE)) - cal_input(IN_IDISCHARGE, adc(IN_IDISCHARGE)); }
int32_t hal_battery_uc(void) { return cal_input(IN_T_EXTERN, adc(IN_T_EXTERN)); }
int32_t hal_heatsink_uc(void) { return cal_input(IN_T_INTERN, adc(IN_T_INTERN)); }
/* An open NTC input reads at the top of the range. */
uint8_t hal_battery_sensor(void) { return adc(IN_T_EXTERN) < 16000; }
uint8_t hal_cell_count(void) { return 0; }
int32_t hal_cell_uv(uint8_t cell) { (void)cell; return 0; }

int32_t hal_open_circuit_uv(void)
{
    /* the output off for a moment: the measurement after the stage has settled */
    uint16_t c = duty_charge, d = duty_discharge;
    uint32_t t0;
    OCR1A = 0;
    OCR1B = 0;
    t0 = hal_millis();
    while (hal_millis() - t0 < 20)
        ;
    {
        int32_t v = hal_pack_uv();
        OCR1A = c;
        OCR1B = d;
        return v;
    }
}

void hal_output(const hal_output_t *o)
{
    out = *o;
    if (out.kind == HAL_OFF) {
        duty_charge = duty_discharge = 0;
    } else if (out.kind == HAL_CURRENT) {
        /* feed-forward from the calibration; regulate() trims it every millisecond */
        duty_charge = out.current_ua > 0 ? cal_output(OUT_CHARGE, out.current_ua) : 0;
        duty_discharge = out.current_ua < 0 ? cal_output(OUT_DISCHARGE, -out.current_ua) : 0;
    }
    OCR1A = duty_charge;
    OCR1B = duty_discharge;
}

/* One step of the power stage's regulation (called every millisecond from the main loop). */
static void regulate(void)
{
    int32_t i = hal_current_ua(), v;
    if (out.kind == HAL_CURRENT) {
        if (out.current_ua > 0) {
            if (i < out.current_ua && duty_charge < PWM_TOP) duty_charge++;
            else if (i > out.current_ua && duty_charge > 0) duty_charge--;
        } else if (out.current_ua < 0) {
            if (-i < -out.current_ua && duty_discharge < PWM_TOP) duty_discharge++;
            else if (-i > -out.current_ua && duty_discharge > 0) duty_discharge--;
        }
    } else if (out.kind == HAL_VOLTAGE_CHARGE) {
        v = hal_pack_uv();
        if (v < out.voltage_uv && i < out.current_ua && duty_charge < PWM_TOP) duty_charge++;
        else if ((v > out.voltage_uv || i > out.current_ua) && duty_charge > 0) duty_charge--;
    } else if (out.kind == HAL_VOLTAGE_DISCHARGE) {
        v = hal_pack_uv();
        if (v > out.voltage_uv && -i < out.current_ua && duty_discharge < PWM_TOP) duty_discharge++;
        else if ((v < out.voltage_uv || -i > out.current_ua) && duty_discharge > 0) duty_discharge--;
    }
    OCR1A = duty_charge;
    OCR1B = duty_discharge;
}

void hal_buzzer(uint8_t melody)
{
    /* a beep per melody number, up to 4 (the melodies are the board's; this one only counts) */
    uint8_t n = melody > 4 ? 4 : melody;
    while (n--) {
        uint32_t t0 = hal_millis();
        PORTB |= _BV(PB0);
        while (hal_millis() - t0 < 80)
            ;
        PORTB &= (uint8_t)~_BV(PB0);
        while (hal_millis() - t0 < 160)
            ;
    }
}

void hal_led(uint8_t pattern)
{
    if (pattern)
        PORTB |= _BV(PB1);
    else
        PORTB &= (uint8_t)~_BV(PB1);
}

uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32])
{
    /* the B6 has no passport line wired: nothing answers */
    (void)request;
    (void)len;
    (void)answer;
    return 0;
}


int main(void)
{
    static const char model[] PROGMEM = "generic ATmega32 (not a B6)";
    static const char firmware[] PROGMEM = "zuml-fw 0.1";
    static const app_board_t board = {
        model, firmware, 5000, 500, 1000, 50, 26000, 8500,
        {5000000L, 1000000L, 3000000L, 1000, 30, 300}
    };
    uint32_t last_ms = 0;
    /* Timer0: CTC, /64, 250 counts = 1 ms at 16 MHz */
    TCCR0 = _BV(WGM01) | _BV(CS01) | _BV(CS00);
    OCR0 = 249;
    TIMSK |= _BV(OCIE0);
    /* USART: 115200 8N1, double speed */
    avr_uart_init((uint8_t)(F_CPU / (8UL * BAUD) - 1), 1);
    /* Timer1: fast PWM, 10 bit, OC1A and OC1B */
    DDRD |= _BV(PD4) | _BV(PD5);
    TCCR1A = _BV(COM1A1) | _BV(COM1B1) | _BV(WGM11) | _BV(WGM10);
    TCCR1B = _BV(WGM12) | _BV(CS10);
    DDRB |= _BV(PB0) | _BV(PB1);
    /* ADC: AVcc reference, /128, interrupt-driven round robin */
    ADMUX = _BV(REFS0);
    ADCSRA = _BV(ADEN) | _BV(ADIE) | _BV(ADSC) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);
    sei();
    app_init(&board);
    for (;;) {
        uint32_t now = hal_millis();
        if (now != last_ms) {
            last_ms = now;
            regulate();
        }
        app_poll();
    }
}
