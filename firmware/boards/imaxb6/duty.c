#include "duty.h"

#define VIN_KNOWN_MV 1000

uint16_t duty_top(int32_t vin_mv, int32_t ceiling_mv)
{
    uint32_t target = (uint32_t)(ceiling_mv > 0 ? ceiling_mv : 0) + DUTY_MARGIN_MV, vin, boost;
    if (vin_mv < VIN_KNOWN_MV)
        return 0;
    vin = (uint32_t)vin_mv;
    if (target <= vin)             /* buck: Vout = d x Vin */
        return (uint16_t)(target * DUTY_BUCK_FULL / vin);
    boost = DUTY_BUCK_FULL - vin * DUTY_BUCK_FULL / target;    /* boost: Vout = Vin / (1 - b) */
    return (uint16_t)(DUTY_BUCK_FULL + (boost < DUTY_BOOST_MAX ? boost : DUTY_BOOST_MAX));
}
