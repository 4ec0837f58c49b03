/**
 * @file isr_monitor.h
 * Overruns of the control ISR: an ISR that runs past its PWM period is
 * counted, and several in a row latch FAULT_ISR_OVERRUN (the bridge goes
 * off), because the control then no longer runs once per period: its
 * samples, the current loop's delay and the slow tasks' schedule are wrong.
 *
 * One overrun alone is survivable by design: the ADC sequencer is reset and
 * the interrupt acknowledged at the top of the ISR (hal_adc_read), so the
 * next conversion lands in the right result registers and the next ISR runs
 * right after this one, late but correct.  It is counted and reported
 * (telemetry `$S`), not a fault.
 *
 * Per ISR (drive_isr, last action): isr_monitor_step(m, hal_isr_overrun()).
 */
#ifndef ISR_MONITOR_H
#define ISR_MONITOR_H

#include <stdint.h>

/** Consecutive overruns that latch the fault. */
#define ISR_MONITOR_LATCH_RUN 3u

typedef struct {
    /* input */
    uint16_t overrun;       /* 1: this ISR overran its period */
    /* outputs */
    uint16_t count;         /* overruns since start-up (saturates at 0xFFFF) */
    uint16_t run;           /* consecutive overruns up to this ISR */
    uint16_t fault;         /* 1 once ISR_MONITOR_LATCH_RUN were consecutive (latched) */
} isr_monitor_t;

void isr_monitor_init(isr_monitor_t *m);
/** One ISR.  No arithmetic that can wrap: the counters saturate. */
static inline void isr_monitor_step(isr_monitor_t *m)
{
    if (m->overrun == 0u) {
        m->run = 0u;
        return;
    }
    if (m->count < 0xFFFFu) {
        m->count++;
    }
    if (m->run < 0xFFFFu) {
        m->run++;
    }
    if (m->run >= ISR_MONITOR_LATCH_RUN) {
        m->fault = 1u;
    }
}
/** Re-arm the latch (fault reset); the count is kept. */
void isr_monitor_reset(isr_monitor_t *m);

#endif /* ISR_MONITOR_H */
