/* PI controller with feed-forward and clamping anti-windup.  See pi_ctrl.h. */
#include "pi_ctrl.h"

#include <string.h>

/* Bound of the proportional term |kp e| (pu).  It must be at least
 * (out_max - out_min) + max|ff| = 48 so that clamping e can never change
 * the output (see pi_step), and small enough that kp e + ui + ff stays
 * within Q24: 64 + 16 + 16 = 96 < 128. */
#define PI_UP_MAX_PU 64.0f

static int pi_limits_ok(float lo, float hi)
{
    /* written so that NaN fails every comparison */
    return (lo >= -PI_OUT_MAX_PU) && (hi <= PI_OUT_MAX_PU) && (lo < hi);
}

pi_status_t pi_set_gains(pi_ctrl_t *p, _iq kp, _iq ki)
{
    if (!(kp >= _IQ(0.0) && kp <= _IQ(PI_KP_MAX))) {
        return PI_ERR_KP;
    }
    if (!(ki >= _IQ(0.0) && ki <= _IQ(PI_KI_MAX))) {
        return PI_ERR_KI;
    }
    /* 64 / kp for kp > 1: Q24 / Q24 -> Q24 in (0.64, 64), < 1 LSB */
    p->e_max = (kp <= _IQ(1.0)) ? _IQ(PI_UP_MAX_PU) : _IQdiv(_IQ(PI_UP_MAX_PU), kp);
    p->kp = kp;
    p->ki = ki;
    return PI_OK;
}

pi_status_t pi_init(pi_ctrl_t *p, float kp, float ki, float out_min, float out_max)
{
    memset(p, 0, sizeof *p);
    if (!(kp >= 0.0f && kp <= PI_KP_MAX)) { return PI_ERR_KP; }
    if (!(ki >= 0.0f && ki <= PI_KI_MAX)) { return PI_ERR_KI; }
    if (!pi_limits_ok(out_min, out_max)) { return PI_ERR_LIMITS; }

    p->kp = _IQ(kp);
    p->ki = _IQ(ki);
    p->out_min = _IQ(out_min);
    p->out_max = _IQ(out_max);
    /* e_max = min(64, 64/kp): the error range (|e| <= 64) when kp <= 1. */
    p->e_max = (kp <= 1.0f) ? _IQ(PI_UP_MAX_PU) : _IQ(PI_UP_MAX_PU / kp);
    return PI_OK;
}

void pi_reset(pi_ctrl_t *p)
{
    p->ui = _IQ(0.0);
    p->out = _IQ(0.0);
    p->sat = 0u;
}

pi_status_t pi_set_limits(pi_ctrl_t *p, _iq out_min, _iq out_max)
{
    if (!(out_min >= _IQ(-PI_OUT_MAX_PU) && out_max <= _IQ(PI_OUT_MAX_PU)
          && out_min < out_max)) {
        return PI_ERR_LIMITS;
    }
    p->out_min = out_min;
    p->out_max = out_max;
    p->ui = _IQsat(p->ui, out_max, out_min);
    return PI_OK;
}

void pi_step(pi_ctrl_t *p)
{
    /* |ref|, |fbk| <= 32, so |e| <= 64: no overflow */
    const _iq e = p->ref - p->fbk;
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
    const _iq di = _IQrmpy(p->ki, e);
    /* Headroom of the integrator before the output reaches a limit:
     * |.| <= 16 + 64 + 16 = 96 */
    const _iq ui_hi = p->out_max - up - p->ff;
    const _iq ui_lo = p->out_min - up - p->ff;
    _iq ui = p->ui + di;   /* |.| <= 16 + 64 = 80 */
    _iq v;

    /* Clamping anti-windup: an upward increment may take the integrator at
     * most to the point where the output reaches out_max, and never below
     * where it already was (it does not unwind because the proportional
     * term alone saturates); symmetrically downward.  An increment that
     * points away from the saturated limit is always taken, so the output
     * leaves the limit as soon as kp e + ui + ff allows. */
    if (di > _IQ(0.0)) {
        if (ui > ui_hi) {
            ui = (ui_hi > p->ui) ? ui_hi : p->ui;
        }
    } else if (di < _IQ(0.0)) {
        if (ui < ui_lo) {
            ui = (ui_lo < p->ui) ? ui_lo : p->ui;
        }
    }
    /* The integrator itself stays inside the output range. */
    ui = _IQsat(ui, p->out_max, p->out_min);
    p->ui = ui;

    v = up + ui + p->ff;   /* |.| <= 64 + 16 + 16 = 96 */
    p->out = _IQsat(v, p->out_max, p->out_min);
    /* at or beyond a limit: the integrator is then held in that direction */
    p->sat = (v >= p->out_max || v <= p->out_min) ? 1u : 0u;
}
