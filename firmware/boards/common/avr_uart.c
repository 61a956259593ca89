#include <avr/interrupt.h>
#include <avr/io.h>
#include "../../core/hal.h"
#include "avr_uart.h"

/* A frame's bytes arrive every 87-174 us while the core may be busy for a millisecond or two. */
#define RX_RING 64

static volatile uint8_t rx_ring[RX_RING];
static volatile uint8_t rx_head, rx_tail;

ISR(USART_RXC_vect)
{
    uint8_t b = UDR, next = (uint8_t)((rx_head + 1) % RX_RING);
    if (next != rx_tail) {
        rx_ring[rx_head] = b;
        rx_head = next;
    }
}

void avr_uart_init(uint8_t ubrr, uint8_t receive)
{
    UCSRA = _BV(U2X);
    UBRRH = 0;
    UBRRL = ubrr;
    UCSRB = _BV(TXEN);
    UCSRC = _BV(URSEL) | _BV(UCSZ1) | _BV(UCSZ0);
    if (receive)
        avr_uart_receive();
}

void avr_uart_receive(void)
{
    UCSRB |= _BV(RXEN) | _BV(RXCIE);
}

uint8_t avr_uart_receiving(void)
{
    return (uint8_t)(UCSRB & _BV(RXEN));
}

int16_t hal_uart_read(void)
{
    uint8_t b;
    if (rx_head == rx_tail)
        return -1;
    b = rx_ring[rx_tail];
    rx_tail = (uint8_t)((rx_tail + 1) % RX_RING);
    return b;
}
