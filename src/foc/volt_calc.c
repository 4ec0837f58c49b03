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
    v->dt_half = _IQ(0.5f * dt_frac);
    v->v_drop = _IQ(drop_pu);
    v->v_drop_half = _IQ(0.5f * drop_pu);
    v->i_thresh = _IQ(i_thresh_pu);
#if MATH_TYPE == IQ_MATH
    /* the stored threshold's inverse, rounded down, so that i_thresh * inv
     * <= 1 (Q24*Q16 -> Q24, truncated): sgn() of a current limited to
     * +-i_thresh is within [-1, 1] without a second saturation, and at the
     * zone's edge below 1 by at most i_thresh * 2^8 + 1 LSB (volt_calc.h);
     * i_thresh >= 0.0005 pu keeps the quotient below 2^31 (1.3e8) */
    v->inv_i_thresh = (_iq16)(((int64_t)1 << 40) / (int64_t)v->i_thresh);
#else
    v->inv_i_thresh = _IQ16(1.0f / i_thresh_pu);
#endif
    return VOLT_CALC_OK;
}
