/* Output of the co-simulation harnesses: one line per record, identical
 * text on the host and on simavr.  On the AVR, stdout goes to USART0, which
 * simavr prints; the program ends by sleeping with interrupts off, which
 * ends the simulation. */
#ifndef COSIM_IO_H
#define COSIM_IO_H

#include <stdint.h>

void cosim_io_init(void);
void cosim_io_end(void);
/** "<tag> <n> <v0> <v1> ..." with each value as 8 hex digits (int32 two's
 *  complement), short enough for simavr's UART line buffer. */
void cosim_print(char tag, uint16_t n, const int32_t *v, uint16_t count);

#endif /* COSIM_IO_H */
