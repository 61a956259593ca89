/* The B6's balancer and its hold (docs/firmware.md, Balancer), the decisions alone: which cells bleed, how
 * far the charge current may go while the highest cell is at its ceiling, when a held charge ends. Cheali's
 * facts: it decides with the loads off once the cells have settled (Balancer.h balancerStartStableCount
 * 6 x 0.7 s), bleeds every cell above the lowest for at most maxBalanceTime 15 s; the current is the lowest
 * that keeps every cell at the charge voltage per cell (TheveninMethod.cpp calculateI); the charge ends when
 * a cell is there and the current has fallen to minIc = Ic / 10 (ProgramData.cpp). Pure C: the host tests
 * build it. */
#ifndef B6_BALANCE_H
#define B6_BALANCE_H

#include <stdint.h>

#define BALANCE_ON_MV 8            /* a cell this far above the lowest starts bleeding (cheali balancerError) */
#define BALANCE_OFF_MV 3           /* ... one that bled in the last window, this far */
#define BALANCE_MAX_BLEEDERS 3     /* 3 x 4.2 V x 0.3 A = 3.8 W; 4 would be 5.0 W, over the 5 W the board burns
                                    * ([C] MAX_DISCHARGE_P); 0.3 A: the B6 manual's balance drain */
#define HOLD_MA_PER_MV 5           /* the cap moves 5 mA per mV off the ceiling per decision (every 100 ms):
                                    * x ~50 mOhm per cell, a quarter of the way a step: no overshoot */
#define CEILING_AT_MV 5            /* a cell read this close to its ceiling is at it (the hold's own ripple) */
#define HELD_END_SHARE 10          /* a held charge ends at 1/10 of its phase's current (minIc = Ic / 10) */
#define BLEED_OHM 14               /* a load: 300 mA at 4.2 V, the B6 manual's balance drain (the simulated B6's) */

/* The charge voltage per cell the balancer holds the highest cell at, mV, by AKK_TYPE; 0: none. */
uint16_t balance_ceiling_mv(uint8_t akk_type);
/* The cells to bleed (bit k: cell k+1), decided with the loads off: among those of `can` (the cells whose
 * load can switch now: not cell 4 while PD0 is the receive line), each more than BALANCE_ON_MV above the
 * lowest (BALANCE_OFF_MV if it is in `bled_before`), at most BALANCE_MAX_BLEEDERS, the highest first. */
uint8_t balance_bleeders(const volatile int16_t *cell_mv, uint8_t n, uint8_t bled_before, uint8_t can);
/* The cells of `bleeding` that go on: those whose presumed voltage (the reading now plus `drop_mv`, what
 * its own bleed took off its reading when it started: cheali's Voff - Von) is above the lowest cell that
 * does not bleed. */
uint8_t balance_keep(const volatile int16_t *cell_mv, uint8_t n, uint8_t bleeding, const int16_t *drop_mv);
/* The hold's next cap on the charge current (mA), from the last one, the highest cell's room to its ceiling
 * (mV), the current now and the phase's own: below the ceiling it grows from where it was (a phase change
 * restarts the stage, not the cells), above it, it falls from the current now; never above the phase's. */
int16_t balance_cap(int16_t cap_ma, int16_t room_mv, int16_t now_ma, int32_t own_ma);
/* What the loads of `bleeding` draw from their cells now, uA. */
int32_t balance_bled_ua(const volatile int16_t *cell_mv, uint8_t n, uint8_t bleeding);
/* 1 when a held charge ends: the highest cell at its ceiling and the charge the `n` cells keep (the current
 * less the mean of what the loads bleed, `bled_ua` in all) down to a tenth of `own_ua`: a constant-current
 * phase's own current, 0 for a phase that holds a voltage (its own current condition ends it; this, once
 * the bleeds take all the charge). The simulator's B6 the same. */
uint8_t balance_held_end(int32_t top_uv, int32_t ceiling_uv, int32_t current_ua, int32_t bled_ua, uint8_t n,
                         int32_t own_ua);

#endif
