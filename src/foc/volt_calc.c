/* Phase-voltage reconstruction from bus voltage and duties.  See volt_calc.h. */
#include "volt_calc.h"
#include "foc_const.h"

#include <string.h>

volt_calc_status_t volt_calc_init(volt_calc_t *v, float dead_time_s, float Ts_s,
                                  float drop_pu, float i_thresh_pu, uint16_t comp_enable)
{
    float dt_frac;

    memset(v, 0, sizeof *v);
    /* each test is written so that NaN fails it */
    if (!(Ts_s > 0.0f)) { return VOLT_CALC_ERR_PERIOD; }
    if (!(dead_time_s >= 0.0f)) { return VOLT_CALC_ERR_DEADTIME; }
    dt_frac = dead_time_s / Ts_s;
    if (!(dt_frac <= VOLT_CALC_DT_FRAC_MAX)) { return VOLT_CALC_ERR_DEADTIME; }
    if (!(drop_pu >= 0.0f && drop_pu <= VOLT_CALC_DROP_MAX_PU)) { return VOLT_CALC_ERR_DROP; }
    if (!(i_thresh_pu >= VOLT_CALC_ITH_MIN_PU && i_thresh_pu <= VOLT_CALC_ITH_MAX_PU)) {
        return VOLT_CALC_ERR_THRESH;
    }
    if (comp_enable > 1u) { return VOLT_CALC_ERR_ENABLE; }

    v->comp_enable = comp_enable;
    v->dt_frac = _IQ(dt_frac);
    v->v_drop = _IQ(drop_pu);
    v->i_thresh = _IQ(i_thresh_pu);
    v->inv_i_thresh = _IQ16(1.0f / i_thresh_pu);
    return VOLT_CALC_OK;
}

/* sgn(i) with a linear zone of half-width i_thresh: sat(i / i_thresh, +-1).
 * i is clamped to +-i_thresh first, so the Q24*Q16 -> Q24 product is within
 * +-1 (+ the rounding of 1/i_thresh), then saturated to exactly +-1.  The
 * inverse is Q16 so that a narrow zone (down to 0.0005 pu: a large drive's
 * dead-time transition of a few tenths of an ampere) is representable. */
static _iq volt_calc_sgn(const volt_calc_t *v, _iq i)
{
    const _iq ic = _IQsat(i, v->i_thresh, -v->i_thresh);
    return _IQsat(_IQmpyIQX(ic, GLOBAL_Q, v->inv_i_thresh, 16), _IQ(1.0), _IQ(-1.0));
}

void volt_calc_step(volt_calc_t *v)
{
    /* Pole voltages: Q24*Q24 -> Q24, truncated, in [0, 16] */
    _iq pa = _IQmpy(v->vdc, v->da);
    _iq pb = _IQmpy(v->vdc, v->db);
    _iq pc = _IQmpy(v->vdc, v->dc);
    _iq cm;

    if (v->comp_enable != 0u) {
        /* Expected average pole-voltage error while the current flows out
         * of the leg: vdc td/Ts + v_drop.  Q24*Q24 -> Q24, <= 4 + 1 pu. */
        const _iq verr = _IQmpy(v->vdc, v->dt_frac) + v->v_drop;
        const _iq ic = _IQ(0.0) - v->ia - v->ib;   /* |.| <= 64 */
        /* Q24*Q24 -> Q24, |.| <= 5 */
        pa -= _IQmpy(volt_calc_sgn(v, v->ia), verr);
        pb -= _IQmpy(volt_calc_sgn(v, v->ib), verr);
        pc -= _IQmpy(volt_calc_sgn(v, ic), verr);
    }

    /* Common mode of the floating star: (pa + pb + pc)/3, sum <= 63.
     * Q24*Q30 -> Q24. */
    cm = _IQmpyIQX(pa + pb + pc, GLOBAL_Q, FOC_ONE_THIRD_Q30, 30);
    v->va = pa - cm;
    v->vb = pb - cm;
    v->vc = pc - cm;

    v->valpha = v->va;
    /* vbeta = (vb - vc)/sqrt(3), Q24*Q30 -> Q24; |vb - vc| = |pb - pc| <= 26 */
    v->vbeta = _IQmpyIQX(v->vb - v->vc, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30);
}
