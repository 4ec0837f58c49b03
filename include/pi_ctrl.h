/**
 * @file pi_ctrl.h
 * Discrete PI controller, parallel form, with feed-forward and clamping
 * anti-windup: the current (M, T) and speed loops of the drive.
 *
 *   e(k)  = ref(k) - fbk(k)
 *   ui(k) = ui(k-1) + ki e(k)                 (ki = Kp Ts / Ti, per sample)
 *   out(k) = sat(kp e(k) + ui(k) + ff(k), out_min, out_max)
 *
 * so, unsaturated, out = ff + (kp + ki z/(z-1)) e: the integrator includes
 * the current sample (backward Euler), and the zero of the controller is at
 * z = kp / (kp + ki).
 *
 * Anti-windup (clamping / conditional integration): the integrator never
 * moves in the direction that deepens a saturation.  When e pushes upward it
 * may rise only until kp e + ui + ff reaches out_max (and never falls because
 * of the clamp); symmetrically downward.  It is also kept inside
 * [out_min, out_max].  So during a saturation the integrator holds the value
 * it had when the output reached the limit, and the output leaves the limit
 * in the first sample in which kp e + ui + ff comes back inside it
 * (no unwinding delay).
 *
 * Valid ranges (so that no intermediate sum can exceed Q24's +-128):
 *   ref, fbk        |.| < 32 pu     (so |e| < 64 and, ki <= 1, |ki e| < 64:
 *                                    the range of the rounded product iq_rmpy)
 *   ff              |.| <= 16 pu
 *   kp              [0, 100]        (the proportional path clamps e to
 *                                    +-64/kp, so |kp e| <= 64; this changes
 *                                    nothing because the output then
 *                                    saturates anyway, see pi_step)
 *   ki              [0, 1]          (more than the whole error per sample
 *                                    is not a meaningful integral gain)
 *   out_min, out_max  [-16, 16], out_min < out_max.
 */
#ifndef PI_CTRL_H
#define PI_CTRL_H

#include <stdint.h>
#include "IQmathLib.h"
#include "iq_rmpy.h"

/** Largest |ref|, |fbk| (pu). */
#define PI_IN_MAX_PU   32.0f
/** Largest |ff|, |out_min|, |out_max| (pu). */
#define PI_OUT_MAX_PU  16.0f
/** Largest kp. */
#define PI_KP_MAX      100.0f
/** Largest ki (per sample). */
#define PI_KI_MAX      1.0f

typedef enum {
    PI_OK = 0,
    PI_ERR_KP,       /* kp NaN, < 0 or > PI_KP_MAX */
    PI_ERR_KI,       /* ki NaN, < 0 or > PI_KI_MAX */
    PI_ERR_LIMITS    /* a limit NaN or outside +-PI_OUT_MAX_PU, or out_min >= out_max */
} pi_status_t;

typedef struct {
    /* inputs */
    _iq ref;       /* reference, pu, Q24, |ref| <= 32 */
    _iq fbk;       /* feedback, pu, Q24, |fbk| <= 32 */
    _iq ff;        /* feed-forward added to the output, pu, Q24, |ff| <= 16 */
    /* parameters */
    _iq kp;        /* proportional gain, Q24, [0, 100] */
    _iq ki;        /* integral gain per sample (Kp Ts / Ti), Q24, [0, 1] */
    _iq out_max;   /* output upper limit, pu, Q24 */
    _iq out_min;   /* output lower limit, pu, Q24, < out_max */
    _iq e_max;     /* error clamp of the proportional path, Q24:
                      min(64, 64 / kp), computed by pi_init */
    /* outputs */
    _iq out;       /* controller output, pu, Q24, in [out_min, out_max] */
    uint16_t sat;  /* 1 while the output is at (or clamped to) a limit */
    /* state */
    _iq ui;        /* integrator, pu, Q24, in [out_min, out_max] */
} pi_ctrl_t;

/** The gains and what follows from them (Q24, each one aligned 32-bit word). */
typedef struct {
    _iq kp;        /* [0, 100] */
    _iq ki;        /* [0, 1] */
    _iq e_max;     /* min(64, 64 / kp) */
} pi_gains_t;

/**
 * The gains from floats (float: not in the ISR), as pi_init sets them:
 * kp, ki to Q24 by _IQ, e_max = min(64, 64/kp) in float.  Rejects (and
 * leaves @p g as it was) kp outside [0, 100] or ki outside [0, 1] (NaN
 * too), kp first.
 */
pi_status_t pi_design_gains(pi_gains_t *g, float kp, float ki);

/** Copy a gain set in (ISR: three word copies; the integrator is kept, as
 *  pi_set_gains). */
static inline void pi_apply_gains(pi_ctrl_t *p, const pi_gains_t *g)
{
    p->kp = g->kp;
    p->ki = g->ki;
    p->e_max = g->e_max;
}

/** pi_init's check of its arguments alone (no struct), the status it
 *  would return: PI_ERR_KP (kp outside [0, PI_KP_MAX]), PI_ERR_KI (ki
 *  outside [0, PI_KI_MAX]), PI_ERR_LIMITS, in that order; NaN fails.  The
 *  configuration's table of limits calls it for every PI the drive sets
 *  up (drive_limits.c).  Float: init only. */
pi_status_t pi_check(float kp, float ki, float out_min, float out_max);

/**
 * Set gains and limits (pu) and reset the state.  On an error the struct is
 * left zeroed (gains 0, limits 0: output 0) and the first offending argument
 * is named.  NaN is rejected by every check.
 */
pi_status_t pi_init(pi_ctrl_t *p, float kp, float ki, float out_min, float out_max);

/** Clear the integrator and the outputs (gains and limits kept).  Inline:
 *  the ISR runs it every period the bridge is off (three stores, cheaper
 *  than the call). */
static inline void pi_reset(pi_ctrl_t *p)
{
    p->ui = _IQ(0.0);
    p->out = _IQ(0.0);
    p->sat = 0u;
}

/**
 * Change the output limits at run time (the speed loop's torque-current
 * limit, for instance).  No float: callable from the ISR.  Rejects (and
 * leaves everything unchanged) out_min >= out_max or a limit outside
 * +-PI_OUT_MAX_PU.  On success the integrator is clamped into the new
 * range at once, so a tightened limit cannot leave it wound up.
 */
pi_status_t pi_set_limits(pi_ctrl_t *p, _iq out_min, _iq out_max);

/**
 * Change the gains at run time (e.g. scaled by identified parameters).  No
 * float: callable from the ISR; e_max = min(64, 64/kp) by _IQdiv.  Rejects
 * (and leaves everything unchanged) kp outside [0, 100] or ki outside [0, 1].
 * The integrator is kept (bumpless: the output moves only by the
 * proportional path's change).
 */
pi_status_t pi_set_gains(pi_ctrl_t *p, _iq kp, _iq ki);

/**
 * One sample, of the feedback @p fbk and feed-forward @p ff given as
 * arguments (the current loops': no copy into the struct; p->fbk, p->ff
 * are left as they were) and the struct's reference.  Scaling: all Q24; kp*e is truncated (_IQmpy, within 1 LSB
 * below the exact product), ki*e rounded (iq_rmpy = _IQrmpy, within 1/2 LSB,
 * no bias),
 * so unsaturated the output is within 1.5 LSB of the exact kp e + ui + ff of
 * the same (Q24) gains and state, and the integrator moves within 1/2 LSB
 * of ki e per sample (it ignores |e| < 1/(2 ki) LSB).  Overflow: none in the valid ranges (|kp e| <= 64 by the
 * clamp, |ui| <= 16, |ff| <= 16, so every sum is within +-96); the output
 * saturates at out_min/out_max, the integrator at the same limits.
 */
static inline void pi_step_in(pi_ctrl_t *p, _iq fbk, _iq ff)
{
    /* the limits and the integrator, each read once */
    const _iq out_max = p->out_max;
    const _iq out_min = p->out_min;
    const _iq ui0 = p->ui;
    /* |ref|, |fbk| <= 32, so |e| <= 64: no overflow */
    const _iq e = p->ref - fbk;
    /* Proportional path.  e is clamped to +-e_max = +-64/kp first so that
     * the Q24*Q24 -> Q24 product cannot exceed 64.  The clamp is invisible
     * at the output: when it acts |kp e| >= 64 >= (out_max - out_min) + |ff|,
     * so kp e + ui + ff is beyond a limit whether e is clamped or not. */
    const _iq up = _IQmpy(p->kp, _IQsat(e, p->e_max, -p->e_max));
    /* Integral increment, Q24*Q24 -> Q24 rounded, |di| <= ki |e| <= 64.
     * Rounded rather than truncated: truncation would bias every increment
     * by -1/2 LSB on average, a constant disturbance the loop would have to
     * hold an error of 1/(2 ki) LSB against.  With rounding the integrator
     * is unbiased and only ignores |e| < 1/(2 ki) LSB (1.5e-5 pu at
     * ki = 2^-8, well below the 12-bit ADC's 4.9e-4 pu). */
    const _iq di = iq_rmpy(p->ki, e);   /* = _IQrmpy bit for bit: |ki e| < 64 (iq_rmpy.h) */
    /* Headroom of the integrator before the output reaches a limit:
     * |.| <= 16 + 64 + 16 = 96 */
    const _iq upff = up + ff;   /* |.| <= 64 + 16 */
    const _iq ui_hi = out_max - upff;
    const _iq ui_lo = out_min - upff;
    _iq v;

    /* Clamping anti-windup: an upward increment may take the integrator at
     * most to the point where the output reaches out_max, and never below
     * where it already was (it does not unwind because the proportional
     * term alone saturates); symmetrically downward; and the integrator
     * stays inside the output range.  As limits of ui + di:
     *   upper = min(max(ui_hi, ui), out_max),  lower = max(min(ui_lo, ui), out_min)
     * (an upward step can only meet the upper one, a downward step the
     * lower one: lower <= ui <= upper, since ui is inside the output range)
     * - three saturations, no branch.  An increment that points away from
     * the saturated limit is always taken, so the output leaves the limit
     * as soon as kp e + ui + ff allows. */
    const _iq upper = _IQsat(ui_hi, out_max, ui0);
    const _iq lower = _IQsat(ui_lo, ui0, out_min);
    const _iq ui = _IQsat(ui0 + di, upper, lower);   /* |ui + di| <= 16 + 64 = 80 */
    p->ui = ui;

    v = upff + ui;   /* |.| <= 64 + 16 + 16 = 96 */
    p->out = _IQsat(v, out_max, out_min);
    /* at or beyond a limit: the integrator is then held in that direction */
    p->sat = (uint16_t)((v >= out_max) | (v <= out_min));   /* no branch */
}

/** pi_step_in of the struct's own feedback and feed-forward. */
static inline void pi_step(pi_ctrl_t *p)
{
    pi_step_in(p, p->fbk, p->ff);
}

#endif /* PI_CTRL_H */
