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

/* The gains' ranges, kp first (NaN fails every comparison). */
static pi_status_t pi_gains_status(float kp, float ki)
{
    if (!(kp >= 0.0f && kp <= PI_KP_MAX)) { return PI_ERR_KP; }
    if (!(ki >= 0.0f && ki <= PI_KI_MAX)) { return PI_ERR_KI; }
    return PI_OK;
}

pi_status_t pi_check(float kp, float ki, float out_min, float out_max)
{
    pi_status_t st = pi_gains_status(kp, ki);
    if (st != PI_OK) { return st; }
    if (!pi_limits_ok(out_min, out_max)) { return PI_ERR_LIMITS; }
    return PI_OK;
}

pi_status_t pi_design_gains(pi_gains_t *g, float kp, float ki)
{
    pi_status_t st = pi_gains_status(kp, ki);
    if (st != PI_OK) { return st; }
    g->kp = _IQ(kp);
    g->ki = _IQ(ki);
    /* e_max = min(64, 64/kp): the error range (|e| <= 64) when kp <= 1. */
    g->e_max = (kp <= 1.0f) ? _IQ(PI_UP_MAX_PU) : _IQ(PI_UP_MAX_PU / kp);
    return PI_OK;
}

pi_status_t pi_init(pi_ctrl_t *p, float kp, float ki, float out_min, float out_max)
{
    pi_gains_t g;
    pi_status_t st;

    memset(p, 0, sizeof *p);
    st = pi_check(kp, ki, out_min, out_max);
    if (st != PI_OK) { return st; }

    (void)pi_design_gains(&g, kp, ki);
    pi_apply_gains(p, &g);
    p->out_min = _IQ(out_min);
    p->out_max = _IQ(out_max);
    return PI_OK;
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
