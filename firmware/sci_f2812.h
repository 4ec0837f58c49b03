/**
 * @file sci_f2812.h
 * SCI-A with its 16-level FIFOs (SPRU051), polled from the background loop.
 */
#ifndef SCI_F2812_H
#define SCI_F2812_H

#include <stdint.h>
#include "telemetry.h"

/** 8 data bits, no parity, 1 stop bit, FIFOs on, no interrupts. */
void sci_f2812_init(uint16_t brr);
/** Move queued characters into the TX FIFO while it has room, and received
 *  characters from the RX FIFO into the parser.  Never waits.  Returns the
 *  last command completed (TLM_CMD_NONE if none). */
tlm_cmd_t sci_f2812_poll(telemetry_t *t);

#endif /* SCI_F2812_H */
