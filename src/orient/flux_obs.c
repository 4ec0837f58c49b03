/* Closed-loop rotor-flux observer (voltage model + current model).  See flux_obs.h. */
#include "flux_obs.h"
#include "exp_series.h"

#include "angle.h"
#include "iq_rmpy.h"

#include <math.h>

#define PSI_MAX _IQ(FLUX_OBS_PSI_MAX)
#define Z_MAX _IQ(FLUX_OBS_Z_MAX)
#define Y_MAX _IQ(FLUX_OBS_Y_MAX)
#define E_MAX _IQ(FLUX_OBS_PSI_MAX)
#define IN_MAX _IQ(FLUX_OBS_IN_MAX)
#define PSI_CM_MAX _IQ(FLUX_OBS_PSI_CM_MAX)

/* Limit x to [-m, m]; *sat set when it had to. */
static inline _iq sat_sym(_iq x, _iq m, uint16_t *sat)
{
    if (x > m) {
        *sat = 1u;
        return m;
    }
    if (x < -m) {
        *sat = 1u;
        return -m;
    }
    return x;
}

void flux_obs_reset(flux_obs_t *o)
{
    o->i_alpha = o->i_beta = _IQ(0.0);
    o->u_alpha = o->u_beta = _IQ(0.0);
    o->i_mean_alpha = o->i_mean_beta = _IQ(0.0);
    o->theta_r = _IQ(0.0);
    o->psi_alpha = o->psi_beta = _IQ(0.0);
    o->psi_mag = _IQ(0.0);
    o->theta = o->theta_prev = _IQ(0.0);
    o->ws = o->ws_f = _IQ(0.0);
    o->psi_cm_alpha = o->psi_cm_beta = _IQ(0.0);
    o->uc_alpha = o->uc_beta = _IQ(0.0);
    o->sat = 0u;
    o->psis_alpha = o->psis_beta = _IQ(0.0);
    o->z_alpha = o->z_beta = _IQ(0.0);
    o->y_alpha = o->y_beta = _IQ(0.0);
    o->psirr_d = o->psirr_q = _IQ(0.0);
    o->irr_d_prev = o->irr_q_prev = _IQ(0.0);
    o->i_alpha_prev = o->i_beta_prev = _IQ(0.0);
}

/* Gains and parameters to zero: the observer's outputs then stay 0. */
static void zero_params(flux_obs_t *o)
{
    o->rs = o->lm = o->sigma_ls = o->lr_lm = o->lm_lr = _IQ(0.0);
    o->tr = _IQ20(0.0);
    o->kf = o->ts = _IQ(0.0);
    o->ts30 = _IQ30(0.0);
    o->wc = o->g = o->kf_ws = o->inv_wc = _IQ(0.0);
    o->inv_k_theta = _IQ20(0.0);
    o->dth_max = _IQ(0.0);
}

flux_obs_status_t flux_obs_design_rs(flux_obs_model_t *m, float rs_pu)
{
    if (!(rs_pu >= 0.0f && rs_pu <= FLUX_OBS_RS_MAX)) {
        return FLUX_OBS_ERR_RS;
    }
    m->rs = _IQ(rs_pu);
    return FLUX_OBS_OK;
}

/* sigma Ls = Ls - Lm^2/Lr, pu (Lr > 0): the check's and the model's */
static float sigma_ls_pu(float lm_pu, float lr_pu, float ls_pu)
{
    return ls_pu - lm_pu * lm_pu / lr_pu;
}

flux_obs_l_fault_t flux_obs_l_check(float lm_pu, float lr_pu, float ls_pu)
{
    float sls;

    /* in this order, each before any division or conversion that needs it:
     * Lm in range makes 4 Lm and every quotient below finite, Lr > Lm > 0
     * makes Lm^2/Lr defined (NaN fails every test) */
    if (!(lm_pu > 0.0f && lm_pu <= FLUX_OBS_LM_MAX) || !(_IQ(lm_pu) > _IQ(0.0))) {
        return FLUX_OBS_L_LM;
    }
    if (!(lr_pu > lm_pu && lr_pu <= FLUX_OBS_LR_LM_MAX * lm_pu)) {
        return FLUX_OBS_L_LR;
    }
    if (!(ls_pu > lm_pu && ls_pu <= 2.0f * FLUX_OBS_LM_MAX)) {
        return FLUX_OBS_L_LS;
    }
    sls = sigma_ls_pu(lm_pu, lr_pu, ls_pu);
    if (!(sls > 0.0f && sls <= FLUX_OBS_SIGMA_LS_MAX) || !(_IQ(sls) > _IQ(0.0))) {
        return FLUX_OBS_L_SLS;
    }
    return FLUX_OBS_L_OK;
}

flux_obs_status_t flux_obs_design_l(flux_obs_model_t *m, float lm_pu, float lr_pu, float ls_pu)
{
    /* every quotient and every Q24 value below is in range once the check
     * passes */
    if (flux_obs_l_check(lm_pu, lr_pu, ls_pu) != FLUX_OBS_L_OK) {
        return FLUX_OBS_ERR_L;
    }
    m->lm = _IQ(lm_pu);
    m->lr_lm = _IQ(lr_pu / lm_pu);   /* (1, 4] */
    m->lm_lr = _IQ(lm_pu / lr_pu);   /* [0.25, 1) */
    m->sigma_ls = _IQ(sigma_ls_pu(lm_pu, lr_pu, ls_pu));
    return FLUX_OBS_OK;
}

flux_obs_status_t flux_obs_design_tr(flux_obs_model_t *m, float ts_pu, float tr_pu)
{
    /* Tr >= 10 Ts, i.e. x = Ts/Tr <= 0.1; Tr <= FLUX_OBS_TR_MAX_PU (Q20 holds < 2048) */
    if (!(ts_pu > 0.0f) || !(tr_pu >= FLUX_OBS_TR_MIN_SAMPLES * ts_pu) ||
        !(tr_pu <= FLUX_OBS_TR_MAX_PU)) {
        return FLUX_OBS_ERR_TR;
    }
    m->tr = _IQ20(tr_pu);
    m->kf = _IQ(one_minus_exp_neg(ts_pu / tr_pu));
    return FLUX_OBS_OK;
}

flux_obs_status_t flux_obs_design(flux_obs_model_t *m, float ts_pu, float rs_pu, float lm_pu,
                                  float lr_pu, float ls_pu, float tr_pu)
{
    flux_obs_status_t st = flux_obs_design_rs(m, rs_pu);
    if (st == FLUX_OBS_OK) {
        st = flux_obs_design_l(m, lm_pu, lr_pu, ls_pu);
    }
    if (st == FLUX_OBS_OK) {
        st = flux_obs_design_tr(m, ts_pu, tr_pu);
    }
    return st;
}

flux_obs_status_t flux_obs_check(const base_values_t *b, float Rs_ohm, float Ls_H, float Lr_H,
                                 float Lm_H, float Tr_s, float wc_Hz, float ws_lpf_Hz)
{
    flux_obs_model_t m;
    float fts;
    float wc_pu;
    float x_ws;

    if (b == 0 || !(b->Ts_s > 0.0f) || !(b->t_base_s > 0.0f) || !(b->Ts_pu > 0.0f) ||
        !(b->Z_base_ohm > 0.0f) || !(b->L_base_H > 0.0f) || !(b->f_base_Hz > 0.0f)) {
        return FLUX_OBS_ERR_BASE;
    }
    fts = b->f_base_Hz * b->Ts_s;   /* revolutions per sample at 1 pu speed */
    /* 1/(f_base Ts) < 2000 fits Q20; Ts_pu = 2 pi f_base Ts < 0.05 fits Q30 */
    if (!(fts > 1.0f / 2000.0f && fts < 1.0f / 128.0f)) {
        return FLUX_OBS_ERR_BASE;
    }
    wc_pu = wc_Hz / b->f_base_Hz;
    if (!(wc_pu > 0.0f && wc_pu <= FLUX_OBS_WC_MAX_PU && wc_pu * b->Ts_pu <= FLUX_OBS_G_MAX)) {
        return FLUX_OBS_ERR_WC;
    }
    x_ws = 6.2831853f * ws_lpf_Hz * b->Ts_s;
    if (!(x_ws > 0.0f && x_ws <= 1.0f)) {
        return FLUX_OBS_ERR_WS_LPF;
    }
    /* the model's ranges in pu, as the background checks a new set
     * (flux_obs_design: range checks first, then the conversions) */
    return flux_obs_design(&m, b->Ts_pu, Rs_ohm / b->Z_base_ohm, Lm_H / b->L_base_H,
                           Lr_H / b->L_base_H, Ls_H / b->L_base_H, Tr_s / b->t_base_s);
}

flux_obs_status_t flux_obs_init(flux_obs_t *o, const base_values_t *b, float Rs_ohm,
                                float Ls_H, float Lr_H, float Lm_H, float Tr_s, float wc_Hz,
                                float ws_lpf_Hz)
{
    flux_obs_status_t st;
    flux_obs_model_t m;
    float fts;
    float wc_pu;
    float x_ws;

    /* zero gains first: on any error below the observer stays inert */
    zero_params(o);
    flux_obs_reset(o);

    st = flux_obs_check(b, Rs_ohm, Ls_H, Lr_H, Lm_H, Tr_s, wc_Hz, ws_lpf_Hz);
    if (st != FLUX_OBS_OK) {
        return st;   /* the observer stays inert (zero_params above) */
    }
    fts = b->f_base_Hz * b->Ts_s;
    wc_pu = wc_Hz / b->f_base_Hz;
    x_ws = 6.2831853f * ws_lpf_Hz * b->Ts_s;
    /* the model's constants in pu, as the background computes them for a
     * new set (its ranges checked above) */
    (void)flux_obs_design(&m, b->Ts_pu, Rs_ohm / b->Z_base_ohm, Lm_H / b->L_base_H,
                          Lr_H / b->L_base_H, Ls_H / b->L_base_H, Tr_s / b->t_base_s);
    flux_obs_apply_model(o, &m);
    o->n = 1u;
    o->ts = _IQ(b->Ts_pu);
    o->ts30 = _IQ30(b->Ts_pu);
    o->inv_k_theta = _IQ20(1.0f / fts);
    /* |d| <= 50 f_base Ts < 0.4 rev: |ws| <= FLUX_OBS_WS_MAX */
    o->dth_max = _IQ(FLUX_OBS_WS_MAX * fts);
    o->wc = _IQ(wc_pu);
    o->g = _IQ(wc_pu * b->Ts_pu);
    o->inv_wc = _IQ(fminf(1.0f / wc_pu, 100.0f));
    o->kf_ws = _IQ(1.0f - expf(-x_ws));
    return FLUX_OBS_OK;
}

flux_obs_status_t flux_obs_step_check(const base_values_t *b, uint16_t n, float wc_Hz,
                                      float ws_lpf_Hz, _iq20 tr_pu)
{
    float T_pu, wc_pu, x_ws;
    if (b == 0 || !(n == 1u || n == 2u || n == 4u || n == 8u)) {
        return FLUX_OBS_ERR_BASE;
    }
    T_pu = b->Ts_pu * (float)n;                 /* < 8 * 2 pi / 128 = 0.4: Q30 */
    wc_pu = wc_Hz / b->f_base_Hz;
    if (!(wc_pu * T_pu <= FLUX_OBS_G_MAX)) {
        return FLUX_OBS_ERR_WC;
    }
    x_ws = 6.2831853f * ws_lpf_Hz * b->Ts_s * (float)n;
    if (!(x_ws > 0.0f && x_ws <= 1.0f)) {
        return FLUX_OBS_ERR_WS_LPF;
    }
    /* flux_obs_design_tr's test, which flux_obs_set_step applies to the
     * float of the Q20 Tr it holds (the Q20 compare, truncated both sides,
     * passed up to one LSB below it) */
    if (!(_IQ20toF(tr_pu) >= FLUX_OBS_TR_MIN_SAMPLES * T_pu)) {
        return FLUX_OBS_ERR_TR;
    }
    return FLUX_OBS_OK;
}

flux_obs_status_t flux_obs_set_step(flux_obs_t *o, const base_values_t *b, uint16_t n,
                                    float wc_Hz, float ws_lpf_Hz)
{
    float fts, T_pu, wc_pu, x_ws, x_dth;
    /* every refusal here is FLUX_OBS_ERR_BASE (flux_obs.h) */
    if (!(o->ts > _IQ(0.0)) ||
        flux_obs_step_check(b, n, wc_Hz, ws_lpf_Hz, o->tr) != FLUX_OBS_OK) {
        return FLUX_OBS_ERR_BASE;
    }
    fts = b->f_base_Hz * b->Ts_s * (float)n;   /* revolutions per step at 1 pu speed */
    T_pu = b->Ts_pu * (float)n;
    wc_pu = wc_Hz / b->f_base_Hz;
    x_ws = 6.2831853f * ws_lpf_Hz * b->Ts_s * (float)n;
    o->n = n;
    o->ts = _IQ(T_pu);
    o->ts30 = _IQ30(T_pu);
    o->inv_k_theta = _IQ20(1.0f / fts);
    /* |ws| <= FLUX_OBS_WS_MAX, and the step below half a revolution (the
     * angle difference's own range) */
    x_dth = fminf(FLUX_OBS_WS_MAX * fts, 0.499f);
    o->dth_max = _IQ(x_dth);
    o->g = _IQ(wc_pu * T_pu);
    o->kf_ws = _IQ(1.0f - expf(-x_ws));
    /* kf for the new step, as the background designs it (flux_obs_design_tr
     * on the Q24 Tr: a set made for this Tr carries the same kf) */
    {
        flux_obs_model_t m;
        const flux_obs_status_t st = flux_obs_design_tr(&m, T_pu, _IQ20toF(o->tr));
        if (st == FLUX_OBS_OK) {
            o->kf = m.kf;
        }
        return st;
    }
}

flux_obs_status_t flux_obs_set_rs(flux_obs_t *o, _iq rs_pu)
{
    if (!(rs_pu >= _IQ(0.0) && rs_pu <= _IQ(FLUX_OBS_RS_MAX))) {
        return FLUX_OBS_ERR_RS;
    }
    o->rs = rs_pu;
    return FLUX_OBS_OK;
}

/* One axis of the DC re-seat: psi_s on the current model, the correction
 * holding u_c = Rs i - u (flux_obs_seat_dc), with the model @p m and 1/w_c. */
static void reseat_axis(const flux_obs_model_t *m, _iq inv_wc, _iq psi_cm, _iq i, _iq u,
                        _iq *psis, _iq *z, _iq *y, uint16_t *sat)
{
    /* |lm_lr psi_cm| <= 64, |sigma Ls i| <= 16: < 128, then bounded */
    *psis = sat_sym(_IQmpy(m->lm_lr, psi_cm) + _IQmpy(m->sigma_ls, i), PSI_MAX, sat);
    /* |Rs i| <= 16, |u| <= 4; saturated at 1 pu before the 1/w_c (<= 100)
     * product: a real DC voltage error is a few % */
    *y = sat_sym(_IQmpy(sat_sym(_IQmpy(m->rs, i) - u, _IQ(1.0), sat), inv_wc), Y_MAX, sat);
    *z = sat_sym(_IQmpy(_IQ(3.0), *y), Z_MAX, sat);
}

flux_obs_status_t flux_obs_seat_dc(const flux_obs_t *o, const flux_obs_model_t *m,
                                   _iq psi_cm_alpha, _iq psi_cm_beta, _iq u_alpha, _iq u_beta,
                                   _iq i_alpha, _iq i_beta, flux_obs_seat_t *s)
{
    uint16_t sat = 0u;

    if (!(m->rs >= _IQ(0.0) && m->rs <= _IQ(FLUX_OBS_RS_MAX))) {
        return FLUX_OBS_ERR_RS;
    }
    u_alpha = sat_sym(u_alpha, IN_MAX, &sat);
    u_beta = sat_sym(u_beta, IN_MAX, &sat);
    i_alpha = sat_sym(i_alpha, IN_MAX, &sat);
    i_beta = sat_sym(i_beta, IN_MAX, &sat);
    reseat_axis(m, o->inv_wc, psi_cm_alpha, i_alpha, u_alpha, &s->psis_alpha, &s->z_alpha,
                &s->y_alpha, &sat);
    reseat_axis(m, o->inv_wc, psi_cm_beta, i_beta, u_beta, &s->psis_beta, &s->z_beta,
                &s->y_beta, &sat);
    s->uc_alpha = _IQmpy(o->wc, s->y_alpha);
    s->uc_beta = _IQmpy(o->wc, s->y_beta);
    /* the output continues from the re-seated flux (= the current model's
     * rotor flux), at standstill: no angle step enters ws or ws_f */
    s->psi_alpha = psi_cm_alpha;
    s->psi_beta = psi_cm_beta;
    s->psi_mag = _IQmag(psi_cm_alpha, psi_cm_beta);
    s->theta = _IQatan2PU(psi_cm_beta, psi_cm_alpha);
    s->sat = sat;
    return FLUX_OBS_OK;
}

flux_obs_status_t flux_obs_set_rs_dc(flux_obs_t *o, _iq rs_pu, _iq u_alpha, _iq u_beta,
                                     _iq i_alpha, _iq i_beta)
{
    flux_obs_model_t m;
    flux_obs_seat_t s;
    flux_obs_status_t st;

    /* the model in use with the new Rs */
    flux_obs_get_model(o, &m);
    m.rs = rs_pu;
    st = flux_obs_seat_dc(o, &m, o->psi_cm_alpha, o->psi_cm_beta, u_alpha, u_beta, i_alpha,
                          i_beta, &s);
    if (st == FLUX_OBS_OK) {
        o->rs = rs_pu;
        flux_obs_apply_seat(o, &s);
    }
    return st;
}

flux_obs_status_t flux_obs_set_tr(flux_obs_t *o, _iq20 tr_pu)
{
    _iq x;

    /* Tr >= 10 Ts, i.e. x = Ts/Tr <= 0.1 (10 n Ts < 4 pu: Q24 -> Q20 to 1 LSB);
     * Tr <= FLUX_OBS_TR_MAX_PU (Q20 headroom) */
    if (!(o->ts > _IQ(0.0)) ||
        !(tr_pu >= _IQtoIQ20(_IQmpy(o->ts, _IQ(FLUX_OBS_TR_MIN_SAMPLES)))) ||
        !(tr_pu <= _IQ20(FLUX_OBS_TR_MAX_PU))) {
        return FLUX_OBS_ERR_TR;
    }
    x = _IQ20div(o->ts, tr_pu);   /* Q24 / Q20 -> Q24 (shift by 20), in (0, 0.1] */
    o->kf = one_minus_exp_neg_iq(x);   /* 1 - exp(-x), Q24 (exp_series.h) */
    o->tr = tr_pu;
    return FLUX_OBS_OK;
}

/* The correction C(s) for one axis, in the scaled states z = w_c int(e),
 * y = u_c / w_c: z += g e, y += g (3 e + z - 3 y).  Products Q24*Q24 -> Q24
 * rounded (a truncated product would bias the integrators by -0.5 LSB per
 * sample), by iq_rmpy: |g e| <= 0.05 * 8 and |g drive| <= 0.05 * 84, inside
 * its 64 pu range.  e is limited to +-8 pu (a real error is below 1 pu; |e| < 88
 * before the limit: |lm_lr psi_cm| <= 64, |sigma Ls i| <= 16, |psi_s| <= 8),
 * so |3 e + z - 3 y| <= 24 + 30 + 30 < 128. */
static void correct_axis(const flux_obs_t *o, _iq e, _iq *z, _iq *y, uint16_t *sat)
{
    _iq zn;
    _iq drive;

    e = sat_sym(e, E_MAX, sat);
    zn = sat_sym(*z + iq_rmpy(o->g, e), Z_MAX, sat);
    drive = _IQmpy(_IQ(3.0), e) + zn - _IQmpy(_IQ(3.0), *y);
    *y = sat_sym(*y + iq_rmpy(o->g, drive), Y_MAX, sat);
    *z = zn;
}

void flux_obs_step_a(flux_obs_t *o)
{
    uint16_t sat = 0u;
    _iq ia, ib, ua, ub, ima, imb;
    _iq s, c;
    _iq ird, irq;
    _iq ea, eb;

    ia = sat_sym(o->i_alpha, IN_MAX, &sat);
    ib = sat_sym(o->i_beta, IN_MAX, &sat);
    ua = sat_sym(o->u_alpha, IN_MAX, &sat);
    ub = sat_sym(o->u_beta, IN_MAX, &sat);
    if (o->n == 1u) {
        /* one period: the trapezoid of its two end samples */
        ima = _IQmpy(ia + o->i_alpha_prev, _IQ(0.5));
        imb = _IQmpy(ib + o->i_beta_prev, _IQ(0.5));
    } else {
        ima = sat_sym(o->i_mean_alpha, IN_MAX, &sat);
        imb = sat_sym(o->i_mean_beta, IN_MAX, &sat);
    }

    /* voltage model: psi_s(k) = psi_s(k-n) + T (u - Rs i_mean + u_c(k-n)).
     * Integrand |.| <= 4 + 4*4 + 1*10 = 30; Q24 * Q30 -> Q24 truncated */
    ea = ua - _IQmpy(o->rs, ima) + o->uc_alpha;
    eb = ub - _IQmpy(o->rs, imb) + o->uc_beta;
    o->psis_alpha = sat_sym(o->psis_alpha + _IQmpyIQX(ea, GLOBAL_Q, o->ts30, 30), PSI_MAX, &sat);
    o->psis_beta = sat_sym(o->psis_beta + _IQmpyIQX(eb, GLOBAL_Q, o->ts30, 30), PSI_MAX, &sat);

    /* current model in rotor coordinates: i^r = i e^{-j theta_r} */
    s = _IQsinPU(o->theta_r);
    c = _IQcosPU(o->theta_r);
    ird = _IQmpy(c, ia) + _IQmpy(s, ib);
    irq = _IQmpy(c, ib) - _IQmpy(s, ia);
    /* first-order hold: Lm times the mean of i^r(k-n), i^r(k).  |i^r| <=
     * 4 sqrt(2) and Lm <= 16: |Lm i| <= 91, saturated to PSI_CM_MAX (60), so
     * psi^r, a low-pass of it (kf in (0, 0.1]), stays within 60 and the
     * increment within 120 (Q24 holds 128).  Rounded products (kf ~ 3e-3:
     * no drift) by iq_rmpy: |product| <= 12 */
    {
        const _iq tgt_d = sat_sym(_IQmpy(o->lm, _IQmpy(ird + o->irr_d_prev, _IQ(0.5))),
                                  PSI_CM_MAX, &sat);
        const _iq tgt_q = sat_sym(_IQmpy(o->lm, _IQmpy(irq + o->irr_q_prev, _IQ(0.5))),
                                  PSI_CM_MAX, &sat);
        o->psirr_d += iq_rmpy(o->kf, tgt_d - o->psirr_d);
        o->psirr_q += iq_rmpy(o->kf, tgt_q - o->psirr_q);
    }
    o->irr_d_prev = ird;
    o->irr_q_prev = irq;
    o->i_alpha_prev = ia;
    o->i_beta_prev = ib;
    /* back to the stationary frame at theta_r(k) */
    o->psi_cm_alpha = _IQmpy(c, o->psirr_d) - _IQmpy(s, o->psirr_q);
    o->psi_cm_beta = _IQmpy(s, o->psirr_d) + _IQmpy(c, o->psirr_q);

    /* e = psi_s,cm - psi_s, psi_s,cm = (Lm/Lr) psi_r,cm + sigma Ls i */
    ea = _IQmpy(o->lm_lr, o->psi_cm_alpha) + _IQmpy(o->sigma_ls, ia) - o->psis_alpha;
    eb = _IQmpy(o->lm_lr, o->psi_cm_beta) + _IQmpy(o->sigma_ls, ib) - o->psis_beta;
    correct_axis(o, ea, &o->z_alpha, &o->y_alpha, &sat);
    correct_axis(o, eb, &o->z_beta, &o->y_beta, &sat);
    o->uc_alpha = _IQmpy(o->wc, o->y_alpha);   /* |.| <= 1 * 10 */
    o->uc_beta = _IQmpy(o->wc, o->y_beta);
    o->sat = sat;
}

void flux_obs_step_b(flux_obs_t *o)
{
    uint16_t sat = o->sat;
    uint16_t ws_sat = 0u;
    /* the current of step a, as it used it */
    const _iq ia = o->i_alpha_prev;
    const _iq ib = o->i_beta_prev;
    _iq psia, psib;
    _iq d;

    /* rotor flux: (Lr/Lm)(psi_s - sigma Ls i), |.| <= 4 (8 + 16) = 96 */
    psia = _IQmpy(o->lr_lm, o->psis_alpha - _IQmpy(o->sigma_ls, ia));
    psib = _IQmpy(o->lr_lm, o->psis_beta - _IQmpy(o->sigma_ls, ib));
    o->psi_alpha = psia;
    o->psi_beta = psib;
    o->psi_mag = _IQmag(psia, psib);
    o->theta_prev = o->theta;
    o->theta = _IQatan2PU(psib, psia);   /* [0, 1); 0 for a zero flux */

    /* frame speed from the angle step; Q24 * Q20 -> Q24, |d| <= dth_max
     * keeps |ws| <= FLUX_OBS_WS_MAX = 50 (an output limit, hit when the flux
     * angle jumps, e.g. as the flux first appears or vanishes when the
     * bridge turns off: not reported in sat) */
    d = sat_sym(angle_diff_pu(o->theta, o->theta_prev), o->dth_max, &ws_sat);
    o->ws = _IQmpyIQX(d, GLOBAL_Q, o->inv_k_theta, 20);
    /* ws_f is a low-pass of ws (kf_ws in (0, 0.64]), so |ws_f| <= 50 and
     * |ws - ws_f| <= 100 < 128 (Q24); product < 64: in range; rounded */
    o->ws_f += _IQrmpy(o->kf_ws, o->ws - o->ws_f);
    o->sat = sat;
}

void flux_obs_step(flux_obs_t *o)
{
    flux_obs_step_a(o);
    flux_obs_step_b(o);
}

