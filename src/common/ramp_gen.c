/* Reference ramp.  See ramp_gen.h. */
#include "ramp_gen.h"

static _iq ramp_clamp(_iq x, _iq lo, _iq hi)
{
    return (x > hi) ? hi : ((x < lo) ? lo : x);
}

ramp_gen_status_t ramp_gen_init(ramp_gen_t *r, float rate_pu_s, float Ts_s, float out_min_pu,
                                float out_max_pu)
{
    const ramp_gen_status_t st = ramp_gen_check(rate_pu_s, Ts_s, out_min_pu, out_max_pu);
    float step;

    r->target = _IQ(0.0);
    r->step = _IQ(0.0);
    r->out_min = _IQ(0.0);
    r->out_max = _IQ(0.0);
    r->out = _IQ(0.0);
    r->done = 0u;
    if (st != RAMP_GEN_OK) {
        return st;
    }
    step = rate_pu_s * Ts_s;
    r->step = _IQ(step);
    r->out_min = _IQ(out_min_pu);
    r->out_max = _IQ(out_max_pu);
    ramp_gen_reset(r, _IQ(0.0));
    r->target = r->out;
    return RAMP_GEN_OK;
}

ramp_gen_status_t ramp_gen_check(float rate_pu_s, float Ts_s, float out_min_pu,
                                 float out_max_pu)
{
    float step;

    if (!(Ts_s > 0.0f && Ts_s <= 0.01f)) {
        return RAMP_GEN_ERR_PERIOD;
    }
    /* the step in [RAMP_GEN_STEP_MIN_PU, 1] pu per sample */
    step = rate_pu_s * Ts_s;
    if (!(rate_pu_s > 0.0f) || !(step >= RAMP_GEN_STEP_MIN_PU && step <= 1.0f)) {
        return RAMP_GEN_ERR_RATE;
    }
    if (!(out_min_pu >= -RAMP_GEN_LIMIT_MAX && out_max_pu <= RAMP_GEN_LIMIT_MAX &&
          out_min_pu < out_max_pu)) {
        return RAMP_GEN_ERR_LIMITS;
    }
    return RAMP_GEN_OK;
}

void ramp_gen_reset(ramp_gen_t *r, _iq out)
{
    r->out = ramp_clamp(out, r->out_min, r->out_max);
    r->done = 0u;
}

void ramp_gen_step(ramp_gen_t *r)
{
    _iq tgt = ramp_clamp(r->target, r->out_min, r->out_max);
    _iq err = tgt - r->out;   /* within +-126: no overflow */

    if (err > r->step) {
        r->out += r->step;
        r->done = 0u;
    } else if (err < -r->step) {
        r->out -= r->step;
        r->done = 0u;
    } else {
        r->out = tgt;
        r->done = 1u;
    }
}
