/**
 * @file datalog.c
 * Triggered circular data log (see datalog.h).
 */
#include <string.h>

#include "datalog.h"

#pragma CODE_SECTION(datalog_step, "ramfuncs")

uint16_t datalog_init(datalog_t *d, uint16_t prescale, _iq trig_level)
{
    memset(d, 0, sizeof *d);
    if (prescale == 0u) {
        return 1u;
    }
    d->prescale = prescale;
    d->trig_level = trig_level;
    d->state = (uint16_t)DLOG_FREE;
    return 0u;
}

void datalog_arm(datalog_t *d)
{
    /* the ISR may preempt between these writes: post first, state last, so
     * the ISR never sees ARMED with a stale post count */
    d->post = (uint16_t)(DLOG_SIZE / 2u);
    d->prev0 = d->in[0];
    d->state = (uint16_t)DLOG_ARMED;
}

void datalog_step(datalog_t *d)
{
    _iq x0;

    if (d->state == (uint16_t)DLOG_DONE) {
        return;
    }
    d->skip++;
    if (d->skip < d->prescale) {
        return;
    }
    d->skip = 0u;

    /* the four channels written out (no loop in the ISR); DLOG_SIZE is a
     * power of two: the index wraps by a mask */
    d->buf[0][d->idx] = d->in[0];
    d->buf[1][d->idx] = d->in[1];
    d->buf[2][d->idx] = d->in[2];
    d->buf[3][d->idx] = d->in[3];
    d->idx = (uint16_t)((d->idx + 1u) & (DLOG_SIZE - 1u));

    x0 = d->in[0];
    if (d->state == (uint16_t)DLOG_ARMED) {
        /* upward crossing: previous below the level, this one at/above it */
        if (d->prev0 < d->trig_level && x0 >= d->trig_level) {
            d->state = (uint16_t)DLOG_TRIGGERED;
        }
    } else if (d->state == (uint16_t)DLOG_TRIGGERED) {
        d->post--;
        if (d->post == 0u) {
            d->first = d->idx;   /* the next write position is the oldest */
            d->state = (uint16_t)DLOG_DONE;
        }
    } else {
        /* DLOG_FREE: nothing else to do */
    }
    d->prev0 = x0;
}
