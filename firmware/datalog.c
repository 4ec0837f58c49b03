/**
 * @file datalog.c
 * Triggered circular data log (see datalog.h).
 */
#include <string.h>

#include "datalog.h"

#pragma CODE_SECTION(datalog_step, "ramfuncs_slow")
#pragma CODE_SECTION(datalog_q15, "ramfuncs_slow")

uint16_t datalog_init(datalog_t *d, uint16_t prescale, _iq trig_level)
{
    uint16_t c;

    memset(d, 0, sizeof *d);
    if (prescale == 0u) {
        return 1u;
    }
    d->prescale = prescale;
    d->trig_level = trig_level;
    d->state = (uint16_t)DLOG_FREE;
    for (c = 0u; c < DLOG_CHANNELS; c++) {
        (void)datalog_set_full_scale(d, c, DLOG_FS_EXP_DEFAULT);
    }
    return 0u;
}

uint16_t datalog_set_full_scale(datalog_t *d, uint16_t ch, int16_t fs_exp)
{
    if (ch >= DLOG_CHANNELS || fs_exp < DLOG_FS_EXP_MIN || fs_exp > DLOG_FS_EXP_MAX) {
        return 1u;
    }
    d->fs_exp[ch] = fs_exp;
    d->shift[ch] = (uint16_t)(GLOBAL_Q - 15 + fs_exp);
    return 0u;
}

int16_t datalog_q15(_iq x, uint16_t shift)
{
#if MATH_TYPE == FLOAT_MATH
    /* the host's float build: the same saturation and flooring in float */
    const float fs = (float)((uint32_t)1u << (shift + 15u)) / (float)((uint32_t)1u << GLOBAL_Q);
    float q;
    if (x >= fs) {
        return (int16_t)32767;
    }
    if (x < -fs) {
        return (int16_t)-32768;
    }
    q = x / fs * 32768.0f;
    return (int16_t)((int32_t)(q + 32768.0f) - 32768);
#else
    /* full scale in Q GLOBAL_Q: 2^(shift + 15) <= 2^29, no overflow */
    const int32_t fs = (int32_t)((uint32_t)1u << (shift + 15u));
    if (x >= fs) {
        return (int16_t)32767;
    }
    if (x < -fs) {
        return (int16_t)-32768;
    }
    /* floor(x / 2^shift) without a right shift of a negative value
     * (implementation-defined in C99): x + fs is in 0 .. 2^(shift+16) - 1 */
    return (int16_t)((int32_t)(((uint32_t)x + (uint32_t)fs) >> shift) - 32768);
#endif
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
    d->buf[0][d->idx] = datalog_q15(d->in[0], d->shift[0]);
    d->buf[1][d->idx] = datalog_q15(d->in[1], d->shift[1]);
    d->buf[2][d->idx] = datalog_q15(d->in[2], d->shift[2]);
    d->buf[3][d->idx] = datalog_q15(d->in[3], d->shift[3]);
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
