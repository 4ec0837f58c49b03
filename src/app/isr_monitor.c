/* Control-ISR overrun counting and latch.  See isr_monitor.h. */
#include "isr_monitor.h"

void isr_monitor_init(isr_monitor_t *m)
{
    m->overrun = 0u;
    m->count = 0u;
    m->run = 0u;
    m->fault = 0u;
}

void isr_monitor_reset(isr_monitor_t *m)
{
    m->run = 0u;
    m->fault = 0u;
}
