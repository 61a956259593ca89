#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>
#include "stage.h"
#include "pins.h"
#include "protect.h"
#include "calib.h"
#include "duty.h"

/* Timer1 fast PWM mode 14, TOP = ICR1 = 512 as cheali's (generic/50W TIMER1_PERIOD 512, Timer1.cpp
 * ICR1 = TIMER1_PERIOD): 513 counts, 31.19 kHz. The duty is kept in 1/64 of a count and dithered over the
 * periods, so the average current steps finely (one count moves ~0.1 A into a low-resistance pack). */
#define TOP 512U
#define FRAC 6
#define BUCK_FULL ((uint32_t)DUTY_BUCK_FULL)           /* (TOP + 1) << FRAC */
#define DISCHARGE_MAX BUCK_FULL

static volatile uint8_t mode;
static volatile int16_t i_set, i_cap, v_set, v_now, i_now;
static volatile uint32_t duty;
static volatile uint16_t pwm_whole;
static volatile uint8_t pwm_frac, pwm_acc, boosting;
static volatile uint16_t starved, charge_top;   /* starved: protect_starved's readings in a row */

void stage_off(void)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        TCCR1A = _BV(WGM11);                                  /* both compare outputs off the pins */
        PORTD &= (uint8_t)~(_BV(B6_BUCK) | _BV(B6_BOOST));
        PORTD |= _BV(B6_OUTPUT_DISABLE) | _BV(B6_SMPS_DISABLE);
        PORTA |= _BV(B6_DISCHARGE_DISABLE);
        mode = STAGE_OFF;
        duty = 0;
        pwm_whole = 0;
        pwm_frac = 0;
        boosting = 0;
        starved = 0;
    }
}

void stage_init(void)
{
    stage_off();
    DDRD |= _BV(B6_BUCK) | _BV(B6_BOOST) | _BV(B6_OUTPUT_DISABLE) | _BV(B6_SMPS_DISABLE);
    DDRA |= _BV(B6_DISCHARGE_DISABLE);
    ICR1 = TOP;
    OCR1A = OCR1B = 0;
    TCCR1A = _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS10);
    TIMSK |= _BV(TOIE1);
}

uint8_t stage_mode(void) { return mode; }

/* Each period: the next compare value with the dither's carry; a zero duty leaves the pin off the
 * timer (OCR = 0 would still give a one-clock pulse every period in fast PWM). */
ISR(TIMER1_OVF_vect)
{
    uint16_t v = pwm_whole;
    pwm_acc = (uint8_t)(pwm_acc + pwm_frac);
    if (pwm_acc >= (1 << FRAC)) {
        pwm_acc = (uint8_t)(pwm_acc - (1 << FRAC));
        v++;
    }
    if (mode == STAGE_CHARGE && !boosting) {
        OCR1B = v;
        TCCR1A = v ? (uint8_t)(_BV(WGM11) | _BV(COM1B1)) : _BV(WGM11);
    } else if (mode != STAGE_OFF) {
        OCR1A = v;                 /* the boost switch, or the discharge load: both are OC1A */
        TCCR1A = v ? (uint8_t)(_BV(WGM11) | _BV(COM1A1)) : _BV(WGM11);
    }
}

static void apply(void)
{
    uint32_t d = duty;
    if (mode == STAGE_CHARGE && d > BUCK_FULL) {
        boosting = 1;
        PORTD |= _BV(B6_BUCK);     /* the buck switch held on, OC1A boosts */
        d -= BUCK_FULL;
    } else {
        if (boosting)              /* both pins low again: a zero duty leaves them off the timer */
            PORTD &= (uint8_t)~(_BV(B6_BUCK) | _BV(B6_BOOST));
        boosting = 0;
    }
    pwm_whole = (uint16_t)(d >> FRAC);
    pwm_frac = (uint8_t)(d & ((1 << FRAC) - 1));
}

void stage_set(uint8_t m, int32_t current_ma, int32_t voltage_mv)
{
    int32_t v = protect_latest[CAL_VOUT], limit_ma = m == STAGE_CHARGE ? B6_CHARGE_MA : B6_DISCHARGE_MA;
    int32_t limit_mw = m == STAGE_CHARGE ? B6_CHARGE_MW : B6_DISCHARGE_MW;
    if (m == STAGE_OFF || current_ma <= 0) {
        stage_off();
        return;
    }
    if (v > 1000 && limit_mw * 1000L / v < limit_ma)
        limit_ma = limit_mw * 1000L / v;
    if (current_ma > limit_ma)
        current_ma = limit_ma;
    /* the charge duty's ceiling from Vin and the pack's ceiling, renewed with every set point (each tick):
     * a current reading that is low cannot open the stage wider */
    v = duty_top(protect_latest[CAL_VIN], protect_limits.armed ? protect_limits.pack_max_mv : B6_MAX_MV);
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        charge_top = (uint16_t)v;
        if (m != mode) {
            stage_off();
            if (m == STAGE_CHARGE) {
                /* from off, the duty starts where the current is about to flow (cheali SMPS_PID::init: the
                 * buck full when the pack is above the input): 95 % of Vout / Vin, so a phase change does
                 * not spend a second of its first tick ramping up from zero */
                int32_t vin = protect_latest[CAL_VIN], vout = (int32_t)protect_latest[CAL_VOUT] * 95 / 100;
                if (vin > 0 && vout > 0)
                    duty = vout >= vin ? BUCK_FULL : BUCK_FULL * (uint32_t)vout / (uint32_t)vin;
                apply();
                PORTD &= (uint8_t)~(_BV(B6_SMPS_DISABLE) | _BV(B6_OUTPUT_DISABLE));
            } else {
                PORTD &= (uint8_t)~_BV(B6_OUTPUT_DISABLE);
                PORTA &= (uint8_t)~_BV(B6_DISCHARGE_DISABLE);
            }
            mode = m;
        }
        i_set = (int16_t)current_ma;
        v_set = (int16_t)(voltage_mv > 0 ? (voltage_mv > B6_MAX_MV ? B6_MAX_MV : voltage_mv) : 0);
    }
}

void stage_cap(int16_t ma)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { i_cap = ma; }
}

/* One integral step towards the set point: the current's error, or the voltage's when that one asks
 * for less (CV within the current limit). A charge's current is also under the balancer's cap. The duty
 * carries over from tick to tick. */
static void step(void)
{
    int16_t set = mode == STAGE_CHARGE && i_cap >= 0 && i_cap < i_set ? i_cap : i_set;
    int32_t e = ((int32_t)set - i_now) / 4, ev, d = (int32_t)duty;
    uint32_t top = mode == STAGE_CHARGE ? charge_top : DISCHARGE_MAX;
    if (v_set) {
        ev = mode == STAGE_CHARGE ? (int32_t)v_set - v_now : (int32_t)v_now - v_set;
        if (ev < e)
            e = ev;
    }
    d += e;
    if (d < 0)
        d = 0;
    if ((uint32_t)d > top)
        d = (int32_t)top;
    duty = (uint32_t)d;
    apply();
    if ((uint32_t)d == top) {
        uint8_t trip = protect_starved(&starved, i_now, set, boosting, v_now, protect_latest[CAL_VIN]);
        if (trip)
            protect_raise(trip);
    } else {
        starved = 0;
    }
}

void stage_current(int16_t ma)
{
    i_now = ma;
    if (mode != STAGE_OFF)
        step();
}

void stage_voltage(int16_t mv) { v_now = mv; }

int16_t stage_battery_ma(int16_t inductor_ma)
{
    /* the boost switch closed (a share d of the period) shorts the inductor to ground; the battery gets
     * its current only the rest of the period: I_battery = I_inductor x (1 - d), d = duty - BUCK_FULL */
    if (!boosting || inductor_ma <= 0)
        return inductor_ma;
    return (int16_t)((int32_t)inductor_ma * (int32_t)(2 * BUCK_FULL - duty) / (int32_t)BUCK_FULL);
}

int32_t stage_loss_mw(void)
{
    return protect_loss_mw(mode, v_now, i_now);
}
