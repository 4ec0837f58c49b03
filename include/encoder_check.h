/**
 * @file encoder_check.h
 * Encoder plausibility (protections): the QEP counter must move while torque
 * current flows, and must not move faster than the motor can turn.
 *
 *  - frozen: T2CNT unchanged for `frozen_max` consecutive samples while
 *    |i_T| > i_t_min.  Why it is safe to call that a fault: with i_T above
 *    i_t_min the motor makes a torque well above its friction and the rotor
 *    moves one count (1/cpr rev) within a few ms (paper motor: 30 % of the
 *    i_T limit against the 0.15 N m load turns it by one count in ~5 ms);
 *    the window (50 ms from drive_init) is ten times that.  A rotor that does
 *    not move in 50 ms against that torque is locked, which also needs the
 *    bridge off.  At |i_T| <= i_t_min (standstill, magnetising, light
 *    load) the count may legitimately stand still: the run is restarted.
 *  - jump: one sample's count difference beyond `jump_max` counts, i.e. a
 *    speed above speed_max (drive_init: 4 pu, twice the highest speed the
 *    ramp can command): noise on the A/B lines or a slipping coupling.
 *
 * The check runs only while the bridge switches (active); it is re-primed
 * with the present count whenever it is inactive, so the first active
 * sample never sees a stale difference.  Once set, `fault` stays set until
 * encoder_check_reset() (the drive's fault reset).
 *
 * Scaling and overflow of encoder_check_step: the count difference is taken
 * modulo 2^16 and read as signed in int32_t (exact, wrap-safe); its
 * magnitude is formed in int32_t, so INT16_MIN cannot overflow on a 16-bit
 * int CPU.  |i_T| is _IQabs of a Q24 current (|i| <= ~2.5 pu, no overflow).
 * The frozen counter saturates at frozen_max.
 */
#ifndef ENCODER_CHECK_H
#define ENCODER_CHECK_H

#include <stdint.h>
#include "IQmathLib.h"

/** Why the check tripped (`cause`). */
#define ENCODER_CHECK_FROZEN 0x1u
#define ENCODER_CHECK_JUMP 0x2u

typedef enum {
    ENCODER_CHECK_OK = 0,
    ENCODER_CHECK_ERR_ARG,         /* a time, level or count not positive / not finite */
    ENCODER_CHECK_ERR_RESOLUTION   /* speed_max is below 2 counts per sample (cannot tell
                                      a jump from motion) or above 16384 (wrap) */
} encoder_check_status_t;

typedef struct {
    /* inputs */
    uint16_t count;        /* T2CNT this sample */
    _iq i_t;               /* Q24, pu: measured torque current */
    uint16_t active;       /* 1 while the bridge switches */
    /* parameters */
    _iq i_t_min;           /* Q24, pu: |i_T| above which the rotor must turn */
    uint16_t frozen_max;   /* samples */
    int32_t jump_max;      /* counts per sample */
    /* outputs */
    uint16_t fault;        /* 1 once tripped, until encoder_check_reset */
    uint16_t cause;        /* ENCODER_CHECK_x bits */
    /* state */
    uint16_t prev_count;
    uint16_t frozen;       /* consecutive frozen samples with torque current */
} encoder_check_t;

/** encoder_check_init's check of its arguments alone (no struct), the status
 *  it would return: _ERR_ARG, then _ERR_RESOLUTION (the counts a sample at
 *  speed_max not in [2, 16384]).  The configuration's table of limits calls
 *  it too (drive_limits.c).  Float: init only. */
encoder_check_status_t encoder_check_args_ok(float Ts_s, float frozen_s, float i_t_min_pu,
                                             float speed_max_pu, float f_base_Hz,
                                             uint16_t encoder_lines, uint16_t pole_pairs);

/**
 * Ts_s: sample period; frozen_s: frozen-count window; i_t_min_pu: torque
 * current level (pu); speed_max_pu: highest plausible electrical speed (pu
 * of f_base_Hz); encoder_lines (x4 counts); pole_pairs.  Float, once.  On
 * error the struct is zeroed with fault = 1 (a drive that cannot judge its
 * encoder must not run).
 */
encoder_check_status_t encoder_check_init(encoder_check_t *e, float Ts_s, float frozen_s,
                                          float i_t_min_pu, float speed_max_pu,
                                          float f_base_Hz, uint16_t encoder_lines,
                                          uint16_t pole_pairs);
/** The jump test alone, every sample, on the sample's count difference
 *  @p d1 (counts, already taken modulo 2^16 and signed: qep_speed.h d1):
 *  one compare.  Counted in fault/cause as encoder_check_step's. */
static inline void encoder_check_jump(encoder_check_t *e, int32_t d1)
{
    /* |d1| > jump_max as one unsigned compare, no branch (as protect_over):
     * d1 + jump_max outside [0, 2 jump_max]; |d1| <= 32768 and jump_max in
     * [2, 16384] (encoder_check_init), so a negative sum wraps far above
     * 2 jump_max <= 32768 and no sum reaches 2^32 */
    const int32_t jm = e->jump_max;
    const uint16_t jump = (uint16_t)(((uint32_t)d1 + (uint32_t)jm) > ((uint32_t)jm << 1));
    if (((uint16_t)(e->active != 0u) & jump) != 0u) {
        e->fault = 1u;
        e->cause |= ENCODER_CHECK_JUMP;
    }
}

/** The frozen test alone, at whatever rate it is called (frozen_max
 *  counts calls: encoder_check_set_rate): the count unchanged since the
 *  last call while |i_T| > i_t_min. */
static inline void encoder_check_frozen(encoder_check_t *e)
{
    const uint16_t moved = (uint16_t)(e->count != e->prev_count);
    e->prev_count = e->count;
    if (e->active == 0u || moved != 0u || !(_IQabs(e->i_t) > e->i_t_min)) {
        e->frozen = 0u;
        return;
    }
    if (e->frozen < e->frozen_max) {
        e->frozen++;
    }
    if (e->frozen >= e->frozen_max) {
        e->fault = 1u;
        e->cause |= ENCODER_CHECK_FROZEN;
    }
}

/** One sample: both tests (see the file comment for scaling). */
static inline void encoder_check_step(encoder_check_t *e)
{
    int32_t d = (int32_t)(uint16_t)(e->count - e->prev_count);   /* [0, 65535] */
    if (d >= 32768) {
        d -= 65536;                                               /* signed, wrap-safe */
    }
    encoder_check_jump(e, d);
    encoder_check_frozen(e);
}

/** The frozen test every @p calls_per_step samples (the jump test stays
 *  per sample): frozen_max divided accordingly (rounded, at least 1).
 *  Returns 0, or 1 (nothing changed) for calls_per_step 0. */
int16_t encoder_check_set_rate(encoder_check_t *e, uint16_t calls_per_step);

/** Clear the fault and restart from the present count. */
void encoder_check_reset(encoder_check_t *e);

#endif /* ENCODER_CHECK_H */
