/**
 * @file isr.h
 * The interrupt glue: the 15 kHz control ISR (ADCINT, PIE 1.6) and the
 * PDPINTA trip ISR (PIE 1.1), and what they share with the background loop.
 */
#ifndef ISR_H
#define ISR_H

#include <stdint.h>
#include "datalog.h"
#include "drive_types.h"

/** Install both vectors and enable PIE group 1 (INT1.1, INT1.6) and CPU
 *  INT1.  The drive and the data log must be initialised first. */
void isr_install(drive_t *drive, datalog_t *dlog);
/** Control periods since start (wraps at 2^16: 4.37 s at 15 kHz). */
uint16_t isr_ticks(void);
/** Largest ISR duration since the last call, in T1 ticks (6.67 ns); the
 *  period is 2 * T1PR = 10000 ticks.  Resets the maximum, with interrupts
 *  disabled for the read and the reset (background only: it enables them
 *  again). */
uint16_t isr_load_max(void);

#endif /* ISR_H */
