#include "balance.h"
#include "../../core/pgm.h"

uint16_t balance_ceiling_mv(uint8_t akk_type)
{
    /* LiPo, LiIon, LiS, LiFe: cheali ProgramData.cpp Vc (LiPo 4.200, LiFe 3.600); LiIon 4.20, docs/zuml-2.0.md section
     * 5's end voltage of our LiIon; LiS none (the protections' limit only); the simulator's B6 the same */
    static const uint16_t charge_mv[4] PROGMEM = {4200, 4200, 0, 3600};
    uint16_t mv = 0;
    if (akk_type >= 4 && akk_type <= 7)
        memcpy_P(&mv, &charge_mv[akk_type - 4], sizeof mv);
    return mv;
}

uint8_t balance_bleeders(const volatile int16_t *cell_mv, uint8_t n, uint8_t bled_before, uint8_t can)
{
    uint8_t mask = 0, pick, k, at;
    int16_t low = 0x7FFF;
    for (k = 0; k < n; k++)
        if (cell_mv[k] < low)
            low = cell_mv[k];
    for (pick = 0; pick < BALANCE_MAX_BLEEDERS; pick++) {
        int16_t best = 0;
        at = 0xFF;
        for (k = 0; k < n; k++) {
            uint8_t bit = (uint8_t)(1 << k);
            int16_t over = (int16_t)(cell_mv[k] - low);
            if (!(mask & bit) && (can & bit) && over > best &&
                (over > BALANCE_ON_MV || (over > BALANCE_OFF_MV && (bled_before & bit)))) {
                best = over;
                at = k;
            }
        }
        if (at == 0xFF)
            break;
        mask |= (uint8_t)(1 << at);
    }
    return mask;
}

uint8_t balance_keep(const volatile int16_t *cell_mv, uint8_t n, uint8_t bleeding, const int16_t *drop_mv)
{
    uint8_t k, keep = bleeding;
    int16_t low = 0x7FFF;
    for (k = 0; k < n; k++)
        if (!(bleeding & (1 << k)) && cell_mv[k] < low)
            low = cell_mv[k];
    for (k = 0; k < n; k++)
        if ((bleeding & (1 << k)) && cell_mv[k] + drop_mv[k] <= low)
            keep &= (uint8_t)~(1 << k);
    return keep;
}

int16_t balance_cap(int16_t cap_ma, int16_t room_mv, int16_t now_ma, int32_t own_ma)
{
    int32_t cap = cap_ma;
    if (room_mv < 0 && now_ma < cap)
        cap = now_ma;
    cap += (int32_t)room_mv * HOLD_MA_PER_MV;
    if (cap > own_ma)
        cap = own_ma;
    return (int16_t)(cap < 0 ? 0 : cap);
}

int32_t balance_bled_ua(const volatile int16_t *cell_mv, uint8_t n, uint8_t bleeding)
{
    int32_t ua = 0;
    uint8_t k;
    for (k = 0; k < n; k++)
        if (bleeding & (1 << k))
            ua += (int32_t)cell_mv[k] * 1000L / BLEED_OHM;
    return ua;
}

uint8_t balance_held_end(int32_t top_uv, int32_t ceiling_uv, int32_t current_ua, int32_t bled_ua, uint8_t n,
                         int32_t own_ua)
{
    return ceiling_uv > 0 && own_ua >= 0 && n && top_uv >= ceiling_uv - CEILING_AT_MV * 1000L &&
           current_ua - bled_ua / n <= own_ua / HELD_END_SHARE;
}
