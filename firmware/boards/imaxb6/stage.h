/* The B6's power stage: the buck/boost (charge) and the discharge load on Timer1, their disable lines,
 * and the regulator the ADC interrupt steps on every fast reading. */
#ifndef B6_STAGE_H
#define B6_STAGE_H

#include <stdint.h>

enum { STAGE_OFF, STAGE_CHARGE, STAGE_DISCHARGE };

void stage_init(void);
/* Off at once: compare outputs disconnected, both switch pins low, all three disable lines high. */
void stage_off(void);
/* Hold current_ma (clamped to the board's current and power limits at the present voltage), and
 * when voltage_mv > 0 that voltage too (charge: at most it; discharge: at least it). The regulator's
 * duty carries over from the last set point: only a start from off begins at zero. */
void stage_set(uint8_t mode, int32_t current_ma, int32_t voltage_mv);
uint8_t stage_mode(void);
/* The balancer's hold (docs/firmware.md, Balancer): a charge's current is at most `ma` too (< 0: no cap),
 * so it falls as the highest cell reaches its ceiling. */
void stage_cap(int16_t ma);
/* The battery's share of a charge current reading (mA): in boost the inductor's current reaches the
 * battery only while the boost switch is open; in buck all of it does. */
int16_t stage_battery_ma(int16_t inductor_ma);
/* From the ADC interrupt: a new reading of the charge current, discharge current or output voltage. */
void stage_current(int16_t ma);
void stage_voltage(int16_t mv);
/* The charger's losses now (mW), for the heat-sink estimate: protect_loss_mw of its mode, V and I. */
int32_t stage_loss_mw(void);

#endif
