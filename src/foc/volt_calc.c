/* Phase-voltage reconstruction from bus voltage and duties.  See volt_calc.h. */
#include "volt_calc.h"
#include "foc_const.h"

#include <string.h>

volt_calc_status_t volt_calc_curve_design(volt_calc_curve_t *k, float dt_frac, float drop_pu,
                                          float i_thresh_pu)
{
    /* each test is written so that NaN fails it */
    if (!(dt_frac >= 0.0f && dt_frac <= VOLT_CALC_DT_FRAC_MAX)) { return VOLT_CALC_ERR_DEADTIME; }
    if (!(drop_pu >= 0.0f && drop_pu <= VOLT_CALC_DROP_MAX_PU)) { return VOLT_CALC_ERR_DROP; }
    if (!(i_thresh_pu >= VOLT_CALC_ITH_MIN_PU && i_thresh_pu <= VOLT_CALC_ITH_MAX_PU)) {
        return VOLT_CALC_ERR_THRESH;
    }
    k->dt_frac = _IQ(dt_frac);
    k->dt_half = _IQ(0.5f * dt_frac);
    k->v_drop = _IQ(drop_pu);
    k->v_drop_half = _IQ(0.5f * drop_pu);
    k->i_thresh = _IQ(i_thresh_pu);
#if MATH_TYPE == IQ_MATH
    /* the stored threshold's inverse, rounded down, so that i_thresh * inv
     * <= 1 (Q24*Q16 -> Q24, truncated): sgn() of a current limited to
     * +-i_thresh is within [-1, 1] without a second saturation, and at the
     * zone's edge below 1 by at most i_thresh * 2^8 + 1 LSB (volt_calc.h);
     * i_thresh >= 0.0005 pu keeps the quotient below 2^31 (1.3e8) */
    k->inv_i_thresh = (_iq16)(((int64_t)1 << 40) / (int64_t)k->i_thresh);
#else
    k->inv_i_thresh = _IQ16(1.0f / i_thresh_pu);
#endif
    return VOLT_CALC_OK;
}

volt_calc_status_t volt_calc_check(float dead_time_s, float Ts_s, float drop_pu,
                                   float i_thresh_pu, uint16_t comp_enable)
{
    volt_calc_curve_t k;   /* scratch: the curve's own checks */
    volt_calc_status_t st;

    if (!(Ts_s > 0.0f)) { return VOLT_CALC_ERR_PERIOD; }
    if (!(dead_time_s >= 0.0f)) { return VOLT_CALC_ERR_DEADTIME; }
    st = volt_calc_curve_design(&k, dead_time_s / Ts_s, drop_pu, i_thresh_pu);
    if (st != VOLT_CALC_OK) { return st; }
    if (comp_enable > 1u) { return VOLT_CALC_ERR_ENABLE; }
    return VOLT_CALC_OK;
}

volt_calc_status_t volt_calc_init(volt_calc_t *v, float dead_time_s, float Ts_s,
                                  float drop_pu, float i_thresh_pu, uint16_t comp_enable)
{
    volt_calc_curve_t k;
    volt_calc_status_t st;

    memset(v, 0, sizeof *v);
    st = volt_calc_check(dead_time_s, Ts_s, drop_pu, i_thresh_pu, comp_enable);
    if (st != VOLT_CALC_OK) { return st; }
    (void)volt_calc_curve_design(&k, dead_time_s / Ts_s, drop_pu, i_thresh_pu);
    volt_calc_apply_curve(v, &k);
    v->comp_enable = comp_enable;
    return VOLT_CALC_OK;
}
