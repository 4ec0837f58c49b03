/**
 * @file datalog.h
 * A triggered, circular data log of DLOG_CHANNELS signals for the CCS graph
 * window (portable C, no registers; the instance lives in the `dlog` RAM
 * section, see main.c and linker/F2812_flash.cmd).
 *
 * Free running it writes every `prescale`-th ISR sample into a circular
 * buffer (a live CCS graph).  A sample is stored in 16 bits, as TI's DLOG_4CH
 * does: channel c as Q15 of the signal over its full scale 2^fs_exp[c] pu
 * (datalog_set_full_scale; default 2 pu), saturating at +-full scale, so that
 * 4 x DLOG_SIZE samples take 4 x 128 = 512 words of RAM instead of 1024.  Armed, it keeps writing and watches channel 0
 * for an upward crossing of `trig_level`; after the trigger it writes
 * DLOG_SIZE/2 more samples and freezes, so the frozen buffer holds half a
 * buffer before and half after the trigger, oldest first from `first`.
 */
#ifndef DATALOG_H
#define DATALOG_H

#include <stdint.h>
#include "IQmathLib.h"

#define DLOG_CHANNELS 4u
/* 4 x 128 x 16 bit = 512 words of RAM; a power of two.  128, not 256: the
 * on-chip RAM keeps 30 % of every block spare with it (linker/F2812_flash.cmd,
 * tools/bench_size.py); `prescale` stretches the window (128 samples at the
 * log slot's 1.875 kHz = 68 ms; prescale 8: 0.55 s) */
#define DLOG_SIZE     128u
#define DLOG_FS_EXP_DEFAULT 1   /* full scale 2^1 = 2 pu */
#define DLOG_FS_EXP_MIN (15 - GLOBAL_Q)   /* full scale 2^-9 pu in Q24: a shift of 0 */
#define DLOG_FS_EXP_MAX (29 - GLOBAL_Q)   /* full scale 32 pu in Q24: a shift of 14 */
#if (DLOG_SIZE & (DLOG_SIZE - 1u)) != 0u || DLOG_CHANNELS != 4u
#error "datalog_step writes 4 channels and wraps its index by a mask"
#endif

typedef enum {
    DLOG_FREE = 0,   /* writing, circular, no trigger */
    DLOG_ARMED,      /* writing, waiting for the trigger */
    DLOG_TRIGGERED,  /* writing the post-trigger half */
    DLOG_DONE        /* frozen until re-armed or set free */
} dlog_state_t;

typedef struct {
    /* inputs (written by the ISR before datalog_step) */
    _iq in[DLOG_CHANNELS];       /* Q GLOBAL_Q, any range */
    /* parameters */
    _iq trig_level;              /* channel-0 trigger level, Q GLOBAL_Q */
    uint16_t prescale;           /* log every prescale-th call, >= 1 */
    /* outputs */
    uint16_t state;              /* dlog_state_t */
    uint16_t first;              /* index of the oldest sample once DONE */
    int16_t fs_exp[DLOG_CHANNELS];   /* full scale of channel c: 2^fs_exp[c] pu */
    /* buf[c][i] = Q15 of in[c] / 2^fs_exp[c], saturated to -32768..32767:
     * value in pu = buf[c][i] * 2^fs_exp[c] / 32768 */
    int16_t buf[DLOG_CHANNELS][DLOG_SIZE];
    /* state */
    uint16_t idx;                /* next write position */
    uint16_t skip;               /* calls since the last write */
    uint16_t post;               /* samples still to write after the trigger */
    _iq prev0;                   /* channel 0 at the previous write */
    uint16_t shift[DLOG_CHANNELS];   /* GLOBAL_Q - 15 + fs_exp[c], 0..14 */
} datalog_t;

/** Clear the buffer, free running, every channel's full scale 2 pu.
 *  Returns 0, or 1 if prescale == 0. */
uint16_t datalog_init(datalog_t *d, uint16_t prescale, _iq trig_level);
/** Full scale of channel @p ch: +-2^fs_exp pu (DLOG_FS_EXP_MIN..MAX).
 *  Returns 0, or 1 (nothing changed) for a bad channel or exponent. */
uint16_t datalog_set_full_scale(datalog_t *d, uint16_t ch, int16_t fs_exp);
/** Q15 of x / 2^(shift - GLOBAL_Q + 15), saturated (the stored sample). */
int16_t datalog_q15(_iq x, uint16_t shift);
/** Arm the trigger (background). */
void datalog_arm(datalog_t *d);
/** Log one sample (ISR).  Saturating conversion to 16 bits: cannot overflow. */
void datalog_step(datalog_t *d);

#endif /* DATALOG_H */
