/* See cosim_io.h.  Formats with its own hex writer (no printf %lx, whose
 * argument type `long` the project does not use). */
#include <stdio.h>

#include "cosim_io.h"

#if defined(__AVR__)
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>

static int uart_putchar(char c, FILE *f)
{
    (void)f;
    while ((UCSR0A & (1u << UDRE0)) == 0u) {
    }
    UDR0 = (uint8_t)c;
    return 0;
}
static FILE s_uart = FDEV_SETUP_STREAM(uart_putchar, NULL, _FDEV_SETUP_WRITE);

void cosim_io_init(void)
{
    UBRR0 = 0u;
    UCSR0A = (uint8_t)(1u << U2X0);
    UCSR0B = (uint8_t)(1u << TXEN0);
    stdout = &s_uart;
}

void cosim_io_end(void)
{
    fputs("END\n", stdout);
    while ((UCSR0A & (1u << TXC0)) == 0u) {
    }
    cli();
    sleep_enable();
    sleep_cpu();
}
#else
void cosim_io_init(void) {}
void cosim_io_end(void) { fputs("END\n", stdout); }
#endif

static void put_hex32(uint32_t v)
{
    static const char hex[] = "0123456789ABCDEF";
    char s[9];
    uint16_t i;
    for (i = 0u; i < 8u; i++) {
        s[7u - i] = hex[v & 0xFu];
        v >>= 4;
    }
    s[8] = '\0';
    fputs(s, stdout);
}

void cosim_print(char tag, uint16_t n, const int32_t *v, uint16_t count)
{
    uint16_t i;
    putchar(tag);
    putchar(' ');
    put_hex32(n);
    for (i = 0u; i < count; i++) {
        putchar(' ');
        put_hex32((uint32_t)v[i]);
    }
    putchar('\n');
}
