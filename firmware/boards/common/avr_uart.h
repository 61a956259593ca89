/* The ATmega32's USART as both AVR boards use it: 8N1 at double speed, received bytes kept by the
 * receive interrupt in a ring the core empties through hal_uart_read. hal_uart_write stays with
 * each board: the B6 feeds its watchdog while a byte leaves. */
#ifndef ZUML_AVR_UART_H
#define ZUML_AVR_UART_H

#include <stdint.h>

/* UBRR for double speed: F_CPU / (8 * baud) - 1, rounded by the board (its baud error is its own);
 * `receive` 0: transmit only, RXD (PD0) stays a port pin (the B6's cell 4 load) until avr_uart_receive. */
void avr_uart_init(uint8_t ubrr, uint8_t receive);
void avr_uart_receive(void);
uint8_t avr_uart_receiving(void);   /* non-zero once the receiver owns RXD */

#endif
