/* Regression signals of method §2 through identical filters.  See
 * ident_regressor.h. */
#include "ident_regressor.h"

#include <math.h>
#include <string.h>

#include "estim_bfp.h"
#include "iq_rmpy.h"

bw_filter_status_t ident_regressor_check(float wc_rad_s, uint16_t n_pass, float Ts_s,
                                         float w_base_rad_s, uint16_t decim_log2)
{
    if (decim_log2 > IDENT_REGRESSOR_DECIM_LOG2_MAX) {
        return BW_FILTER_ERR_TS;
    }
    return bw_filter_check(wc_rad_s, n_pass, Ts_s * (float)(1u << decim_log2), w_base_rad_s);
}

bw_filter_status_t ident_regressor_init(ident_regressor_t *r, float wc_rad_s,
                                        uint16_t n_pass, float Ts_s,
                                        float w_base_rad_s, uint16_t decim_log2)
{
    bw_filter_status_t st;
    memset(r, 0, sizeof *r);
    st = ident_regressor_check(wc_rad_s, n_pass, Ts_s, w_base_rad_s, decim_log2);
    if (st != BW_FILTER_OK) {
        return st;
    }
    (void)bw_filter_init(&r->f_im, wc_rad_s, n_pass, Ts_s * (float)(1u << decim_log2),
                         w_base_rad_s);
    /* identical instances: same gain and delay for every signal (method §5) */
    r->f_it = r->f_im;
    r->f_um = r->f_im;
    r->f_ut = r->f_im;
    r->f_ws_it = r->f_im;
    r->f_ws_im = r->f_im;
    r->f_wr = r->f_im;
    r->decim_log2 = decim_log2;
    /* pi f_base Ts = w_base Ts / 2 (rad of the half step per pu speed) */
    r->k_half = _IQ(0.5f * w_base_rad_s * Ts_s);
    return BW_FILTER_OK;
}

int16_t ident_regressor_set_period_mean(ident_regressor_t *r, float Tr_s, float k2_nom_pu,
                                        float im_nom_pu, float Ts_s, float w_base_rad_s)
{
#if IDENT_PERIOD_MEAN
    const float n = (float)(1u << r->decim_log2);
    const float wt = w_base_rad_s * Ts_s;   /* Ts in pu time */

    if (!(Tr_s > n * Ts_s) || !(k2_nom_pu > 0.0f && k2_nom_pu < 16.0f) ||
        !(im_nom_pu >= 0.05f && im_nom_pu < 4.0f)) {
        return 1;
    }
    /* identical instances (method §5); f_um's state is zero after init */
    r->f_mm = r->f_um;
    r->f_mt = r->f_um;
    r->f_wmt = r->f_um;
    r->k_rip = _IQ30(wt * wt / 12.0f);          /* < 1e-2 for w_base Ts < 0.35 */
    r->k_slip = _IQ(n * wt);
    r->kf_win = _IQ(1.0f - expf(-n * Ts_s / Tr_s));   /* (0, 1); float: 1e-5 relative at 5e-3 */
    r->k2_nom = _IQ(k2_nom_pu);
    r->k2_lo = _IQ(0.5f * k2_nom_pu);
    r->k2_hi = _IQ(2.0f * k2_nom_pu);           /* < 32 pu */
    r->k_im_nom = _IQ(im_nom_pu);
    r->k_inv_im = _IQ(1.0f / im_nom_pu);        /* <= 20 */
    r->period_mean = 1u;
    return 0;
#else
    (void)r; (void)Tr_s; (void)k2_nom_pu; (void)im_nom_pu; (void)Ts_s; (void)w_base_rad_s;
    return 1;   /* compiled out (IDENT_PERIOD_MEAN 0) */
#endif
}

void ident_regressor_reset(ident_regressor_t *r)
{
    bw_filter_reset(&r->f_im, _IQ(0.0));
    bw_filter_reset(&r->f_it, _IQ(0.0));
    bw_filter_reset(&r->f_um, _IQ(0.0));
    bw_filter_reset(&r->f_ut, _IQ(0.0));
    bw_filter_reset(&r->f_ws_it, _IQ(0.0));
    bw_filter_reset(&r->f_ws_im, _IQ(0.0));
    bw_filter_reset(&r->f_wr, _IQ(0.0));
    r->s_im = r->s_it = r->s_um = r->s_ut = _IQ(0.0);
    r->s_ws_it = r->s_ws_im = r->s_ws = _IQ(0.0);
#if IDENT_PERIOD_MEAN
    bw_filter_reset(&r->f_mm, _IQ(0.0));
    bw_filter_reset(&r->f_mt, _IQ(0.0));
    bw_filter_reset(&r->f_wmt, _IQ(0.0));
    r->i0_m = r->i0_t = _IQ(0.0);
    r->dl_m = r->dl_t = _IQ(0.0);
#endif
}

/* The period-mean form's window (ident_regressor.h, (a)-(c); regression_
 * bias.md §5.1), on the window means filter_a just formed: x2 the squared
 * half step, wsm the window's mean frame speed.
 * Scaling: the corrections are small against their signals (sinc >= 0.98,
 * |K2^ c| <= 32 * 7 * 7 * k_rip < 0.1 pu for w_base Ts < 0.025, the
 * current's half step per sample < 5 pu / 2): each filter input is
 * saturated again to the filters' range (ident_in); the products of c
 * truncate (a bias of 1 LSB of a 0.2 % term); Delta's update rounds
 * (iq_rmpy: a low-pass of DC gain 1 whose truncated step would bias it by
 * 1/(2 kf_N) LSB, several hundred at Tr/Ts 1 600) and Delta is clamped to
 * +-0.1 pu (its physical size: (w_e Ts)^2 / (12 sigma) of i_M, < 1 %). */
#if IDENT_PERIOD_MEAN
#define IDENT_DELTA_MAX 0.1
static void period_mean_window(ident_regressor_t *r, _iq x2, _iq wsm)
{
    const uint16_t n1 = (uint16_t)(r->decim_log2 + 1u);
    const _iq sinc = _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 6.0));   /* sin x / x, error < x^4/120 */
    const _iq um = _IQmpy(sinc, r->f_um.u);                   /* (a) the exact mean voltage */
    const _iq ut = _IQmpy(sinc, r->f_ut.u);
    /* K2^: the RLS's last estimate where it is plausible, else the nameplate's */
    const _iq k2 = (r->k2_hat > r->k2_lo && r->k2_hat < r->k2_hi) ? r->k2_hat : r->k2_nom;
    /* (b) K2^ c, c = j w_s u_bar Ts^2/12: the ripple's curvature;
     * Q24 * Q24 -> Q24 (|ws u| < 50), * Q30 -> Q24, * K2^ (< 32) -> Q24 */
    const _iq ic_m = -_IQmpy(k2, _IQmpyIQX(_IQmpy(wsm, ut), GLOBAL_Q, r->k_rip, 30));
    const _iq ic_t = _IQmpy(k2, _IQmpyIQX(_IQmpy(wsm, um), GLOBAL_Q, r->k_rip, 30));
    /* the trapezoid's mean less the samples' mean: half the window's
     * current step per sample, -(i_end - i_start) / 2N (rounded) */
    const _iq h_m = estim_div_pow2_round(r->i_m - r->i0_m, n1);
    const _iq h_t = estim_div_pow2_round(r->i_t - r->i0_t, n1);
    /* (c) the mean of i_bar - i_sampled, the slip angle of the window */
    const _iq d_m = h_m + ic_m;
    const _iq d_t = h_t + ic_t;
    /* rad: |.| <= 0.4 * 14 (k_slip = 8 w_base Ts < 0.4), a few mrad in use */
    const _iq slip = _IQmpy(r->k_slip, ident_in(wsm - r->wr));
    const _iq dl_m = r->dl_m;
    const _iq dl_t = r->dl_t;
    _iq m_m, m_t;

    r->f_um.u = um;
    r->f_ut.u = ut;
    r->f_im.u = ident_in(r->f_im.u + ic_m - h_m);
    r->f_it.u = ident_in(r->f_it.u + ic_t - h_t);
    r->f_ws_it.u = ident_in(r->f_ws_it.u + _IQmpy(wsm, ic_t - h_t));
    r->f_ws_im.u = ident_in(r->f_ws_im.u + _IQmpy(wsm, ic_m - h_m));
    /* Delta += kf_N (d - Delta) - j slip Delta */
    r->dl_m = _IQsat(dl_m + iq_rmpy(r->kf_win, d_m - dl_m) + iq_rmpy(slip, dl_t),
                     _IQ(IDENT_DELTA_MAX), _IQ(-IDENT_DELTA_MAX));
    r->dl_t = _IQsat(dl_t + iq_rmpy(r->kf_win, d_t - dl_t) - iq_rmpy(slip, dl_m),
                     _IQ(IDENT_DELTA_MAX), _IQ(-IDENT_DELTA_MAX));
    /* m = ((i_mr, 0) + Delta) / i_M,nom: per pu of the nameplate's flux
     * current, so that the K3, K4 columns are as large as the constant
     * form's (the same prior, the same convergence), m_M near 1.
     * |i_mr| <= 4 (ifo), k_inv_im <= 20: < 82 before the saturation to 7;
     * |wr m| <= 49 */
    m_m = ident_in(_IQmpy(r->imr + r->dl_m, r->k_inv_im));
    m_t = _IQmpy(r->dl_t, r->k_inv_im);
    r->f_mm.u = m_m;
    r->f_mt.u = m_t;
    r->f_wmt.u = ident_in(-_IQmpy(r->wr, m_t));
    r->f_wr.u = ident_in(_IQmpy(r->wr, m_m));
    r->i0_m = r->i_m;
    r->i0_t = r->i_t;
}
#endif

/* The window means below: a sum of 2^n samples (n <= 3) over 2^n, rounded
 * half up (no bias to pass the filters' unit DC gain); |sum| < 56 pu, so
 * the rounding's half LSB cannot overflow. */
void ident_regressor_filter_a(ident_regressor_t *r)
{
    const uint16_t n = r->decim_log2;
    const _iq um = estim_div_pow2_round(r->s_um, n);
    const _iq ut = estim_div_pow2_round(r->s_ut, n);
    /* back to the middle of the periods: R(x), x = pi f_base Ts ws_mean,
     * |x| <= 7 pi/128 < 0.18 rad (f_base Ts < 1/128, |ws| <= 7):
     * cos x = 1 - (x^2/2)(1 - x^2/12), sin x = x (1 - x^2/6), series
     * errors below x^6/720, x^5/120 (< 2e-6 at the limit, 3e-9 at 2 pu);
     * Q24 products of factors <= 1 */
    const _iq x = _IQmpy(r->k_half, estim_div_pow2_round(r->s_ws, n));
    const _iq x2 = _IQmpy(x, x);
    const _iq cx = _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(0.5)), _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 12.0)));
    const _iq sx = _IQmpy(x, _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 6.0)));

    r->f_im.u = estim_div_pow2_round(r->s_im, n);
    r->f_it.u = estim_div_pow2_round(r->s_it, n);
    /* |um|, |ut| <= 7: each sum < 9.9 */
    r->f_um.u = _IQmpy(cx, um) - _IQmpy(sx, ut);
    r->f_ut.u = _IQmpy(sx, um) + _IQmpy(cx, ut);
    r->f_ws_it.u = estim_div_pow2_round(r->s_ws_it, n);
    r->f_ws_im.u = estim_div_pow2_round(r->s_ws_im, n);
    r->f_wr.u = r->wr;   /* already the window's mean (ident_regressor.h) */
#if IDENT_PERIOD_MEAN
    if (r->period_mean != 0u) {
        period_mean_window(r, x2, estim_div_pow2_round(r->s_ws, n));
    }
#endif
    r->s_im = r->s_it = r->s_um = r->s_ut = _IQ(0.0);
    r->s_ws_it = r->s_ws_im = r->s_ws = _IQ(0.0);

    /* only i_M and i_T need the derivative output */
    bw_filter_step(&r->f_im);
    bw_filter_step(&r->f_it);
}

void ident_regressor_filter_b(ident_regressor_t *r)
{
    bw_filter_update(&r->f_um);
    bw_filter_update(&r->f_ut);
    bw_filter_update(&r->f_ws_it);
#if IDENT_PERIOD_MEAN
    if (r->period_mean != 0u) {
        bw_filter_update(&r->f_mm);
    }
#endif
}

void ident_regressor_filter_c(ident_regressor_t *r)
{
    bw_filter_update(&r->f_ws_im);
    bw_filter_update(&r->f_wr);

    /* eq. 5 (row 2 with +, method §2) */
    r->y1 = r->f_im.dy - r->f_ws_it.y;
    r->y2 = r->f_it.dy + r->f_ws_im.y;
    r->i_mf = r->f_im.y;
    r->u_mf = r->f_um.y;
    r->i_tf = r->f_it.y;
    r->u_tf = r->f_ut.y;
    r->wr_f = r->f_wr.y;
#if IDENT_PERIOD_MEAN
    if (r->period_mean != 0u) {
        bw_filter_update(&r->f_mt);
        bw_filter_update(&r->f_wmt);
        r->m_mf = r->f_mm.y;
        r->m_tf = r->f_mt.y;
        r->wm_tf = r->f_wmt.y;
    }
#endif
}

void ident_regressor_filter(ident_regressor_t *r)
{
    ident_regressor_filter_a(r);
    ident_regressor_filter_b(r);
    ident_regressor_filter_c(r);
}

void ident_regressor_step(ident_regressor_t *r)
{
    ident_regressor_accumulate(r);
    ident_regressor_filter(r);
}
