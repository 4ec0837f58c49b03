/**
 * @file ramp_gen.h
 * Reference ramp (in the manner of TI's RMPCNTL): the output moves towards
 * the target by a fixed step per sample, so a reference change becomes a
 * ramp of a set slope (e.g. the speed reference, to keep the speed loop out
 * of current limit while accelerating).
 *
 *     out(k) = out(k-1) + sat(target' - out(k-1), -step, +step)
 *     target' = target clamped to [out_min, out_max]
 *
 * done = 1 on the sample the output reaches target' (and while it stays
 * there).  The slope is step/Ts pu per second; step = rate Ts, set once from
 * the rate in pu/s at init (its Q24 quantisation, < 1 LSB per sample, is the
 * slope's only error).
 */
#ifndef RAMP_GEN_H
#define RAMP_GEN_H

#include <stdint.h>
#include "IQmathLib.h"

/** Largest accepted |out_min|, |out_max|, pu: keeps target' - out in Q24. */
#define RAMP_GEN_LIMIT_MAX 63.0f

/** The least step, pu per sample: 2^-20 (16 LSB24), the slope's
 *  quantisation below 1/32 (1 LSB of truncation over 16). */
#define RAMP_GEN_STEP_MIN_PU 9.5367431640625e-7f

typedef enum {
    RAMP_GEN_OK = 0,
    RAMP_GEN_ERR_PERIOD,   /* Ts_s not in (0, 0.01] */
    RAMP_GEN_ERR_RATE,     /* rate not > 0, or step = rate Ts not in [2^-20, 1] pu */
    RAMP_GEN_ERR_LIMITS    /* not -63 <= out_min < out_max <= 63 */
} ramp_gen_status_t;

typedef struct {
    /* inputs */
    _iq target;      /* Q24, pu */
    /* parameters */
    _iq step;        /* Q24, pu per sample (> 0) */
    _iq out_min;     /* Q24, pu */
    _iq out_max;     /* Q24, pu */
    /* outputs */
    _iq out;         /* Q24, pu, in [out_min, out_max] */
    uint16_t done;   /* 1 when out == clamped target */
} ramp_gen_t;

/** @p rate_pu_s: slope, pu per second; @p Ts_s: sample period; output limits
 *  in pu.  Starts at out = 0 clamped into the limits, target = out. */
ramp_gen_status_t ramp_gen_init(ramp_gen_t *r, float rate_pu_s, float Ts_s, float out_min_pu,
                                float out_max_pu);

/** ramp_gen_init's check of its arguments alone (no struct), the status it
 *  would return: _PERIOD, then _RATE (rate not > 0, or the step rate x Ts
 *  not in [RAMP_GEN_STEP_MIN_PU, 1] pu per sample), then _LIMITS.  The
 *  configuration's table of limits calls it too (drive_limits.c).  Float:
 *  init only. */
ramp_gen_status_t ramp_gen_check(float rate_pu_s, float Ts_s, float out_min_pu,
                                 float out_max_pu);

/** Set the output (e.g. to the measured speed before the loop closes),
 *  clamped into the limits; done is cleared. */
void ramp_gen_reset(ramp_gen_t *r, _iq out);

/**
 * One sample.  Scaling and overflow: target' and out are within +-63, so
 * their difference is within +-126 (inside Q24's +-128); out moves by at
 * most step and never passes target', so it stays within the limits.
 * Additions only: no rounding.
 */
void ramp_gen_step(ramp_gen_t *r);

#endif /* RAMP_GEN_H */
