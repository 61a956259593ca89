#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>
#include "adc.h"
#include "pins.h"
#include "protect.h"
#include "stage.h"
#include "../../core/pgm.h"

/* A slot reads one input: 2 conversions after the switch are dropped (the channel and the
 * multiplexer settle, as cheali's ADC does), 4 are summed (x16 = ADC16). A round alternates the fast
 * inputs (the regulator's) with the slow ones. */
#define DROP 2
#define TAKE 4
#define FAST 4
#define SLOW 10
#define MUX 0x80                 /* an input behind the multiplexer: address in the low bits */
#define EMPTY_ADDRESS 6          /* cheali's ADC_CAPACITOR_DISCHARGE_ADDRESS: MADDR_V_BALANSER6 */

static const uint8_t fast[FAST][2] PROGMEM = {
    {B6_ADC_ISMPS, CAL_ISMPS}, {B6_ADC_VOUT, CAL_VOUT}, {B6_ADC_ISMPS, CAL_ISMPS}, {B6_ADC_IDIS, CAL_IDIS},
};
static const uint8_t slow[SLOW][2] PROGMEM = {
    {B6_ADC_VOUT_MINUS, CAL_VOUT_MINUS}, {B6_ADC_VIN, CAL_VIN}, {MUX | 0, CAL_VB0}, {MUX | 1, CAL_VB1},
    {MUX | 2, CAL_VB2}, {MUX | 3, CAL_VB3}, {MUX | 4, CAL_VB4}, {MUX | 5, CAL_VB5}, {MUX | 6, CAL_VB6},
    {MUX | 7, CAL_TEXTERN},
};

volatile uint8_t adc_heartbeat, adc_main_alive;
static uint8_t conversion, slot, next_fast, next_slow, input;
static uint16_t burst;
static uint32_t sum[CAL_INPUTS];
static uint16_t count[CAL_INPUTS];
static uint16_t average[CAL_INPUTS];

/* Points the ADC (and the multiplexer) at the next slot's input. */
static void select(void)
{
    const uint8_t *s;
    uint8_t channel;
    if (slot & 1) {
        s = slow[next_slow];
        next_slow = (uint8_t)((next_slow + 1) % SLOW);
    } else {
        s = fast[next_fast];
        next_fast = (uint8_t)((next_fast + 1) % FAST);
    }
    channel = pgm_read_byte(&s[0]);
    input = pgm_read_byte(&s[1]);
    if (channel & MUX) {
        PORTB = (uint8_t)((PORTB & ~B6_MUX_MASK) | ((channel & 7) << B6_MUX_SHIFT));
        channel = B6_ADC_MUX;
    }
    ADMUX = channel;                 /* REFS = 0: the external AREF (AVCC would short it) */
    slot++;
}

static void reading(uint8_t input, uint16_t adc16)
{
    int16_t value = (int16_t)cal_value(input, adc16);
    if (protect_reading(input, value))     /* the inductor's current: the stage's own limit */
        stage_off();
    if (input == CAL_ISMPS && stage_battery_ma(value) != value) {
        /* in boost the battery's current is regulated, shown and counted, not the inductor's */
        value = stage_battery_ma(value);
        adc16 = cal_adc16(CAL_ISMPS, value);
    }
    sum[input] += adc16;
    count[input]++;
    if (input == CAL_VOUT)
        stage_voltage(value);
    else if ((input == CAL_ISMPS && stage_mode() == STAGE_CHARGE) ||
             (input == CAL_IDIS && stage_mode() == STAGE_DISCHARGE))
        stage_current(value);
    adc_heartbeat++;
    if (protect_loop_slot(adc_main_alive))
        stage_off();
    adc_main_alive = 0;
}

/* Before each reading behind the multiplexer (during the fast slot before it), as cheali does for the
 * B6's simplified Vb0..Vb2 circuit (generic/50W AnalogInputsADC.cpp, ENABLE_ADC_MUX_CAPACITOR_DISCHARGE):
 * after the slot's first conversion the mux's output (PA6) is driven low on Vb6's address, emptying the
 * capacitor the last tap charged; after the second it is an input again on the next input's address. */
static void empty_mux(void)
{
    uint8_t channel = pgm_read_byte(&slow[next_slow][0]);
    if (!(slot & 1) || !(channel & MUX) || conversion > 2)
        return;                      /* the next slot is a fast one, or not behind the mux */
    if (conversion == 1) {
        PORTB = (uint8_t)((PORTB & ~B6_MUX_MASK) | (EMPTY_ADDRESS << B6_MUX_SHIFT));
        DDRA |= _BV(B6_ADC_MUX);     /* PORTA's bit stays 0: driven low */
    } else {                         /* the address first: released on Vb6, the node would take its charge */
        PORTB = (uint8_t)((PORTB & ~B6_MUX_MASK) | ((channel & 7) << B6_MUX_SHIFT));
        DDRA &= (uint8_t)~_BV(B6_ADC_MUX);
    }
}

ISR(ADC_vect)
{
    uint16_t v = ADC;
    if (conversion >= DROP)
        burst += v;
    ++conversion;
    empty_mux();
    if (conversion == DROP + TAKE) {
        uint16_t adc16 = (uint16_t)(burst << 4);
        uint8_t done = input;
        conversion = 0;
        burst = 0;
        select();                    /* the next input settles while this one is processed */
        ADCSRA |= _BV(ADSC);
        reading(done, adc16);
        return;
    }
    ADCSRA |= _BV(ADSC);
}

void adc_init(void)
{
    DDRB |= B6_MUX_MASK;
    select();
    /* 16 MHz / 64 = 250 kHz, as cheali; one conversion at a time, started here and by the interrupt */
    ADCSRA = _BV(ADEN) | _BV(ADIE) | _BV(ADPS2) | _BV(ADPS1);
    ADCSRA |= _BV(ADSC);
}

void adc_latch(void)
{
    /* one input at a time, the division outside: the 11 divisions under one lock held the interrupts off
     * for 515 us, half of Timer0's millisecond */
    uint8_t k;
    uint32_t s;
    uint16_t n;
    for (k = 0; k < CAL_INPUTS; k++) {
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
            s = sum[k];
            n = count[k];
            sum[k] = 0;
            count[k] = 0;
        }
        if (n)
            average[k] = (uint16_t)(s / n);
    }
}

uint16_t adc_average(uint8_t input_no) { return average[input_no]; }
int32_t adc_value(uint8_t input_no) { return cal_value(input_no, average[input_no]); }
