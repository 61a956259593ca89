/* The HAL hooks of a board with no requests, averaging or protections of its own (the PC's device on
 * a pty, the generic ATmega32, the core measured alone): nothing refuses a start, and every request
 * the core does not know is unknown. The iMAX B6 has its own (boards/imaxb6). */
#include "../../core/app.h"
#include "../../core/pgm.h"
#include "../../core/protocol.h"

void hal_measure_latch(void) {}

uint8_t hal_balancer_ceiling(int32_t *ceiling_uv)
{
    *ceiling_uv = 0;
    return 0;
}

const char *hal_run_start(const uint8_t *rec, uint8_t akk_type, int16_t series, int32_t capacity_mah, uint8_t *code,
                          char *sentence)
{
    (void)rec; (void)akk_type; (void)series; (void)capacity_mah; (void)code; (void)sentence;
    return 0;
}

void hal_request(uint8_t type, uint8_t seq, const uint8_t *payload, uint8_t len, uint8_t running)
{
    (void)payload; (void)len; (void)running;
    app_error(type, seq, E_UNKNOWN_TYPE, PSTR("unknown request type"));
}
