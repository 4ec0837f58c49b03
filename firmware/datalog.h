/**
 * @file datalog.h
 * A triggered, circular data log of DLOG_CHANNELS signals for the CCS graph
 * window (portable C, no registers; the instance lives in the `dlog` RAM
 * section, see main.c and linker/F2812_flash.cmd).
 *
 * Free running it writes every `prescale`-th ISR sample into a circular
 * buffer (a live CCS graph).  Armed, it keeps writing and watches channel 0
 * for an upward crossing of `trig_level`; after the trigger it writes
 * DLOG_SIZE/2 more samples and freezes, so the frozen buffer holds half a
 * buffer before and half after the trigger, oldest first from `first`.
 */
#ifndef DATALOG_H
#define DATALOG_H

#include <stdint.h>
#include "IQmathLib.h"

#define DLOG_CHANNELS 4u
#define DLOG_SIZE     256u   /* 4 x 256 x 32 bit = 2048 words of RAM; a power of two */
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
    _iq buf[DLOG_CHANNELS][DLOG_SIZE];
    /* state */
    uint16_t idx;                /* next write position */
    uint16_t skip;               /* calls since the last write */
    uint16_t post;               /* samples still to write after the trigger */
    _iq prev0;                   /* channel 0 at the previous write */
} datalog_t;

/** Clear the buffer, free running.  Returns 0, or 1 if prescale == 0. */
uint16_t datalog_init(datalog_t *d, uint16_t prescale, _iq trig_level);
/** Arm the trigger (background). */
void datalog_arm(datalog_t *d);
/** Log one sample (ISR).  No arithmetic on the data: cannot overflow. */
void datalog_step(datalog_t *d);

#endif /* DATALOG_H */
