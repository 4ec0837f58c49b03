/* Indirect field orientation (current model).  See ifo.h. */
#include "ifo.h"
#include "exp_series.h"

#include "angle.h"
#include "iq_rmpy.h"

ifo_status_t ifo_init(ifo_t *f, float Tr_s, const base_values_t *b, float imr_min_pu)
{
    ifo_status_t st;
    float tr_pu;

    f->i_m = _IQ(0.0);
    f->i_t = _IQ(0.0);
    f->wr = _IQ(0.0);
    f->tr = _IQ20(0.0);
    f->inv_tr = _IQ(0.0);
    f->kf = _IQ(0.0);
    f->ts = _IQ(0.0);
    f->k_theta = _IQ30(0.0);
    f->k_acc = _IQ30(0.0);
    f->imr_min = _IQ(0.0);
    ifo_reset(f, _IQ(0.0));

    st = ifo_check(Tr_s, b, imr_min_pu);
    if (st != IFO_OK) {
        return st;
    }
    tr_pu = Tr_s / b->t_base_s;
    f->ts = _IQ(b->Ts_pu);
    f->k_theta = _IQ30(b->f_base_Hz * b->Ts_s);
    f->k_acc = angle_acc_k(b->f_base_Hz * b->Ts_s);   /* < 2: f_base Ts < 1/128, above */
    f->inv_k_theta = _IQ20(1.0f / (b->f_base_Hz * b->Ts_s));
    f->imr_min = _IQ(imr_min_pu);
    {
        ifo_tr_t t;
        st = ifo_design_tr(&t, b->Ts_pu, tr_pu, imr_min_pu);
        if (st == IFO_OK) {
            ifo_apply_tr(f, &t);
        }
        return st;
    }
}

ifo_status_t ifo_check(float Tr_s, const base_values_t *b, float imr_min_pu)
{
    if (b == 0 || !(b->Ts_s > 0.0f) || !(b->t_base_s > 0.0f) || !(b->Ts_pu > 0.0f) ||
        !(b->f_base_Hz > 0.0f)) {
        return IFO_ERR_BASE;
    }
    if (!(imr_min_pu > 0.0f && imr_min_pu <= 1.0f)) {
        return IFO_ERR_IMR_MIN;
    }
    if (!(Tr_s / b->t_base_s <= IFO_TR_MAX_PU)) {   /* also NaN; the lower bound: ifo_design_tr */
        return IFO_ERR_TR;
    }
    /* |ws| <= |wr| + |wslip| < 63 + 64 < 128, so f_base Ts < 1/128 keeps
     * the angle increment of ifo_step below one revolution (one wrap) */
    if (!(b->f_base_Hz * b->Ts_s < 1.0f / 128.0f)) {
        return IFO_ERR_BASE;
    }
    /* 1/(f_base Ts) is held in Q20 (< 2048): at least 1/2000 of a revolution
     * per sample at 1 pu speed (e.g. 7.5 Hz base at 15 kHz) */
    if (!(b->f_base_Hz * b->Ts_s > 1.0f / 2000.0f)) {
        return IFO_ERR_BASE;
    }
    return IFO_OK;
}

ifo_status_t ifo_design_tr(ifo_tr_t *t, float ts_pu, float tr_pu, float imr_min_pu)
{
    /* Tr >= 10 Ts (x = Ts/Tr <= 0.1), Tr <= IFO_TR_MAX_PU (Q20 headroom); NaN fails */
    if (!(ts_pu > 0.0f) || !(tr_pu >= IFO_TR_MIN_SAMPLES * ts_pu) || !(tr_pu <= IFO_TR_MAX_PU)) {
        return IFO_ERR_TR;
    }
    /* slip bound: I_T_MAX / (Tr imr_min) <= SLIP_MAX */
    if (!(tr_pu * imr_min_pu >= IFO_I_T_MAX / IFO_SLIP_MAX)) {
        return IFO_ERR_IMR_MIN;
    }
    t->tr = _IQ20(tr_pu);            /* <= 1000 < 2048 */
    t->inv_tr = _IQ(1.0f / tr_pu);   /* <= 1/(10 Ts) < 128 */
    t->kf = _IQ(one_minus_exp_neg(ts_pu / tr_pu));
    return IFO_OK;
}

ifo_status_t ifo_tr_check(_iq ts_pu, _iq imr_min_pu, _iq20 tr_pu)
{
    /* Tr >= 10 Ts, i.e. x = Ts/Tr <= 0.1 (10 Ts < 0.5 pu: Q24 -> Q20 exact
     * to 1 LSB); Tr <= IFO_TR_MAX_PU (Q20 headroom) */
    if (!(tr_pu >= _IQtoIQ20(_IQmpy(ts_pu, _IQ(IFO_TR_MIN_SAMPLES)))) ||
        !(tr_pu <= _IQ20(IFO_TR_MAX_PU))) {
        return IFO_ERR_TR;
    }
    /* slip bound: I_T_MAX / (Tr imr_min) <= SLIP_MAX  <=>  Tr imr_min >= 2/64.
     * Q20*Q24 -> Q20 (_IQmpy shifts by 24): Tr <= 1000, imr_min <= 1, no overflow */
    if (!(_IQmpy(tr_pu, imr_min_pu) >= _IQ20(IFO_I_T_MAX / IFO_SLIP_MAX))) {
        return IFO_ERR_IMR_MIN;
    }
    return IFO_OK;
}

ifo_status_t ifo_set_tr(ifo_t *f, _iq20 tr_pu)
{
    _iq x;
    const ifo_status_t st = ifo_tr_check(f->ts, f->imr_min, tr_pu);

    if (st != IFO_OK) {
        return st;
    }
    x = _IQ20div(f->ts, tr_pu);   /* Q24 / Q20 -> Q24 (shift by 20), in (0, 0.1] */
    f->kf = one_minus_exp_neg_iq(x);   /* 1 - exp(-x), Q24 (exp_series.h) */
    f->inv_tr = _IQ20div(_IQ(1.0), tr_pu);   /* Q24 / Q20 -> Q24, in [0.001, 1/(10 Ts_pu)] */
    f->tr = tr_pu;
    return IFO_OK;
}

void ifo_reset(ifo_t *f, _iq theta0)
{
    f->imr = _IQ(0.0);
    f->wslip = _IQ(0.0);
    f->ws = _IQ(0.0);
    f->theta = ifo_wrap(theta0);
    f->theta_acc = angle_acc_from_pu(f->theta);
    f->theta = angle_acc_pu(f->theta_acc);   /* FLOAT_MATH: on the accumulator's grid */
    f->theta_prev = f->theta;
    f->imr_low = 1u;
    f->k_slip = _IQ(0.0);
    f->slip_acc = 0u;
    f->ws_frame = _IQ(0.0);
}

/* The current model of the rotor flux, shared by both modes: i_mr, slip and
 * the frame speed w_s = w_r + w_slip. */
static void ifo_update_flux(ifo_t *f)
{
    /* rotor flux lag, exact ZOH discretisation; Q24*Q24 -> Q24 rounded,
     * |i_m - imr| < 4 pu */
    f->imr += _IQrmpy(f->kf, f->i_m - f->imr);

    if (f->imr < f->imr_min) {
        /* no division by a vanishing flux: no slip until magnetised */
        f->wslip = _IQ(0.0);
        f->imr_low = 1u;
    } else {
        /* (Q24*Q24 -> Q24) / Q24 -> Q24; |result| <= 2/(Tr imr_min) <= 64 */
        f->wslip = _IQdiv(_IQmpy(f->i_t, f->inv_tr), f->imr);
        f->imr_low = 0u;
    }
    f->ws = f->wr + f->wslip;
}

void ifo_step(ifo_t *f)
{
    ifo_update_flux(f);
    f->theta_prev = f->theta;
    /* in 2^-32 of a revolution (angle.h), modulo one revolution */
    f->theta_acc = angle_acc_step(f->theta_acc, f->ws, f->k_acc);
    f->theta = angle_acc_pu(f->theta_acc);
}

_iq ifo_theta_mid(const ifo_t *f)
{
    return ifo_wrap(f->theta_prev + _IQmpy(angle_diff_pu(f->theta, f->theta_prev), _IQ(0.5)));
}

void ifo_step_slip(ifo_t *f)
{
    ifo_update_flux(f);
    /* in 2^-32 of a revolution (angle.h), modulo one revolution */
    f->slip_acc = angle_acc_step(f->slip_acc, f->wslip, f->k_acc);
}

void ifo_update_slip_gain(ifo_t *f)
{
    if (f->imr < f->imr_min) {
        f->k_slip = _IQ(0.0);
        f->imr_low = 1u;
    } else {
        /* Q24 / Q24 -> Q24; <= 1/(Tr imr_min) <= 32 (ifo.h) */
        f->k_slip = _IQdiv(f->inv_tr, f->imr);
        f->imr_low = 0u;
    }
}

void ifo_align(ifo_t *f, _iq theta_frame, _iq imr_pu)
{
    /* both in [0, 1): the difference in (-1, 1), wrapped exactly */
    f->slip_acc = angle_acc_from_pu(ifo_wrap(ifo_wrap(theta_frame) - ifo_wrap(f->theta_r)));
    f->theta = ifo_wrap(theta_frame);
    f->theta_acc = angle_acc_from_pu(f->theta);
    f->theta_prev = f->theta;
    f->ws_frame = _IQ(0.0);
    f->imr = _IQsat(imr_pu, _IQ(4.0), _IQ(0.0));
    f->imr_low = (uint16_t)(f->imr < f->imr_min);
}
