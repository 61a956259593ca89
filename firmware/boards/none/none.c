/* A board with no hardware behind the HAL: the firmware core alone, linked for the ATmega32 to
 * measure what the core takes (`make size`); every driver a real board adds comes on top. */
#include "../../core/app.h"
#include "../../core/pgm.h"

/* Readings from volatile memory, so the compiler keeps every path of the core. */
static volatile int32_t v32;
static volatile uint8_t v8;

void hal_output(const hal_output_t *out) { v32 = out->current_ua; }
int32_t hal_pack_uv(void) { return v32; }
int32_t hal_current_ua(void) { return v32; }
int32_t hal_open_circuit_uv(void) { return v32; }
int32_t hal_battery_uc(void) { return v32; }
int32_t hal_heatsink_uc(void) { return v32; }
uint8_t hal_battery_sensor(void) { return v8; }
uint8_t hal_cell_count(void) { return v8; }
int32_t hal_cell_uv(uint8_t cell) { (void)cell; return 0; }
uint32_t hal_millis(void) { return (uint32_t)v32; }
uint16_t hal_eeprom_size(void) { return (uint16_t)v32; }
uint8_t hal_eeprom_read(uint16_t addr) { (void)addr; return v8; }
void hal_eeprom_write(uint16_t addr, uint8_t value) { (void)addr; v8 = value; }
int16_t hal_uart_read(void) { return (int16_t)v32; }
void hal_uart_write(uint8_t byte) { v8 = byte; }
void hal_buzzer(uint8_t melody) { (void)melody; }
void hal_led(uint8_t pattern) { (void)pattern; }
uint8_t hal_passport_exchange(const uint8_t *request, uint8_t len, uint8_t answer[32])
{
    answer[0] = len ? request[0] : 0;
    return v8;
}


int main(void)
{
    static const char model[] PROGMEM = "none", firmware[] PROGMEM = "zuml-fw";
    static const app_board_t board = {model, firmware, 0, 0, 0, 0, 0, 0, {0, 0, 0, 1000, 30, 300}};
    app_init(&board);
    for (;;)
        app_poll();
}
