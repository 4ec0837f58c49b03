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
    v->i_thresh = _IQ(i_thresh_pu);
    v->inv_i_thresh = _IQ16(1.0f / i_thresh_pu);
    return VOLT_CALC_OK;
}

/* sgn(i) with a linear zone of half-width i_thresh: sat(i / i_thresh, +-1).
 * Outside the zone (the common case: every leg but one near its zero
 * crossing) exactly +-1 by two compares, no product.  Inside, the
 * Q24*Q16 -> Q24 product is within +-1 (+ the rounding of 1/i_thresh) and
 * saturated to +-1.  The inverse is Q16 so that a narrow zone (down to
 * 0.0005 pu: a large drive's dead-time transition of a few tenths of an
 * ampere) is representable. */
static _iq volt_calc_sgn(const volt_calc_t *v, _iq i)
{
    if (i >= v->i_thresh) {
        return _IQ(1.0);
    }
    if (i <= -v->i_thresh) {
        return _IQ(-1.0);
    }
    return _IQsat(_IQmpyIQX(i, GLOBAL_Q, v->inv_i_thresh, 16), _IQ(1.0), _IQ(-1.0));
}

/* Mean pole-voltage error of one leg over the period (see volt_calc_step).
 * A leg that does not switch (d = 0 or 1) has no edge and no dead time.
 * Q24 products, each |.| <= 4 pu; sum <= 5 pu. */
static _iq volt_calc_leg_error(const volt_calc_t *v, _iq i_mid, _iq di, _iq d,
                               _iq v_dt_half)
{
    _iq e = _IQmpy(volt_calc_sgn(v, i_mid), v->v_drop);
    if (d > _IQ(0.0) && d < _IQ(1.0)) {
        const _iq half_di = _IQmpy(_IQmpy(d, _IQ(0.5)), di);   /* (d/2) di, Q24 */
        e += _IQmpy(volt_calc_sgn(v, i_mid - half_di) + volt_calc_sgn(v, i_mid + half_di),
                    v_dt_half);
    }
    return e;
}

void volt_calc_step(volt_calc_t *v)
{
    /* Pole voltages: Q24*Q24 -> Q24, truncated, in [0, 16] */
    _iq pa = _IQmpy(v->vdc, v->da);
    _iq pb = _IQmpy(v->vdc, v->db);
    _iq pc = _IQmpy(v->vdc, v->dc);
    _iq cm;

    if (v->comp_enable != 0u) {
        /* Dead time: each of the two switching edges of a centre-aligned
         * period, at (1 -+ d)/2 Ts, loses (current out of the leg) or gains
         * vdc td/2 by the sign of the current at that edge; with the current
         * linear over the period, i_edge = i_mid -+ (d/2) di.  The device
         * drop follows the period-mean current.  Q24*Q24 -> Q24 products,
         * |vdc td/Ts| <= 4, |(d/2) di| <= 32, |i_edge| <= 64 pu. */
        const _iq v_dt_half = _IQmpy(v->vdc, v->dt_half);
        pa -= volt_calc_leg_error(v, v->ia, v->dia, v->da, v_dt_half);
        pb -= volt_calc_leg_error(v, v->ib, v->dib, v->db, v_dt_half);
        pc -= volt_calc_leg_error(v, _IQ(0.0) - v->ia - v->ib,
                                  _IQ(0.0) - v->dia - v->dib, v->dc, v_dt_half);
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

/* Scaling/overflow: see volt_calc.h. */
void volt_calc_feedforward(const volt_calc_t *v, _iq vdc, _iq ia, _iq ib,
                           _iq *dalpha, _iq *dbeta)
{
    _iq ea, eb, ec, cm;
    if (v->comp_enable == 0u) {
        *dalpha = _IQ(0.0);
        *dbeta = _IQ(0.0);
        return;
    }
    {
        /* the pole error of a leg carrying i_x: vdc td/Ts + v_drop, <= 5 pu */
        const _iq verr = _IQmpy(vdc, v->dt_frac) + v->v_drop;
        ea = _IQmpy(volt_calc_sgn(v, ia), verr);
        eb = _IQmpy(volt_calc_sgn(v, ib), verr);
        ec = _IQmpy(volt_calc_sgn(v, _IQ(0.0) - ia - ib), verr);
    }
    /* floating star: remove the common mode; Clarke (amplitude-invariant) */
    cm = _IQmpyIQX(ea + eb + ec, GLOBAL_Q, FOC_ONE_THIRD_Q30, 30);
    *dalpha = ea - cm;
    *dbeta = _IQmpyIQX(eb - ec, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30);
}
