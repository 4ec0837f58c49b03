/* Control-ISR overrun counting and latch.  See isr_monitor.h. */
#include "isr_monitor.h"

void isr_monitor_init(isr_monitor_t *m)
{
    m->overrun = 0u;
    m->count = 0u;
    m->run = 0u;
    m->fault = 0u;
}

void isr_monitor_step(isr_monitor_t *m)
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

void isr_monitor_reset(isr_monitor_t *m)
{
    m->run = 0u;
    m->fault = 0u;
}
