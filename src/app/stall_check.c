/* Rotor plausibility: count step, locked rotor.  See stall_check.h. */
#include "stall_check.h"

#include <string.h>

stall_check_status_t stall_check_init(stall_check_t *s, int32_t step_abs_counts,
                                      float w_min_pu, float tau_r_pu)
{
    memset(s, 0, sizeof *s);
    if (step_abs_counts < 1 || step_abs_counts > 32768 || !(w_min_pu > 0.0f) ||
        !(w_min_pu <= 1.0f) || !(tau_r_pu > 0.0f) || !(tau_r_pu <= 8.0f)) {
        s->enc_fault = 1u;
        return STALL_CHECK_ERR_ARG;
    }
    s->step_abs = step_abs_counts;
    s->w_min_tau = _IQ(w_min_pu * tau_r_pu);
    return STALL_CHECK_OK;
}

void stall_check_window_step(stall_check_t *s, uint16_t count, uint16_t active)
{
    int32_t dw = (int32_t)(uint16_t)(count - s->w_count);   /* [0, 65535] */
    if (dw >= 32768) {
        dw -= 65536;                                        /* signed, wrap-safe */
    }
    s->w_count = count;
    if (active == 0u) {
        s->w_primed = 0u;
        return;
    }
    /* 0/1 values combined without a branch each */
    s->enc_fault |= (uint16_t)((uint16_t)(s->w_primed >= 2u) &
                               stall_check_implausible(s, dw, s->dw_prev)) |
                    (uint16_t)((uint16_t)(s->w_primed >= 3u) &
                               stall_check_implausible(s, dw, s->dw_prev2));
    s->dw_prev2 = s->dw_prev;
    s->dw_prev = dw;
    if (s->w_primed < 3u) {
        s->w_primed++;
    }
}

uint16_t stall_check_decide(stall_check_t *s, _iq r_alpha, _iq r_beta, _iq sin_t, _iq cos_t,
                            _iq psi_e, _iq i_m, _iq i_t)
{
    /* the residual in the frame (Q24; |r| <= 4, so |r_M|, |r_T| <= 8) */
    const _iq r_m = _IQmpy(r_alpha, cos_t) + _IQmpy(r_beta, sin_t);
    const _iq r_t = _IQmpy(r_beta, cos_t) - _IQmpy(r_alpha, sin_t);
    const _iq im = _IQsat(i_m, _IQ(2.0), _IQ(-2.0));
    const _iq it = _IQsat(i_t, _IQ(2.0), _IQ(-2.0));
    /* c = (r_T i_M - r_M i_T) sgn(i_T): the residual across the current
     * (|.| < 32), positive for a rotation in the torque's direction */
    _iq c = _IQmpy(r_t, im) - _IQmpy(r_m, it);
    if (it < 0) {
        c = -c;
    }
    s->cross = c;
    s->cross_min = _IQmpy(_IQmpy(s->w_min_tau, _IQsat(_IQabs(psi_e), _IQ(2.0), _IQ(0.0))),
                          _IQabs(im));
    return (uint16_t)(c < s->cross_min);
}

void stall_check_reset(stall_check_t *s)
{
    s->enc_fault = 0u;
    s->w_primed = 0u;
}
