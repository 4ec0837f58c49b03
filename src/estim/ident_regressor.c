/* Regression signals of method §2 through identical filters.  See
 * ident_regressor.h. */
#include "ident_regressor.h"

#include <string.h>

#include "estim_bfp.h"

bw_filter_status_t ident_regressor_init(ident_regressor_t *r, float wc_rad_s,
                                        uint16_t n_pass, float Ts_s,
                                        float w_base_rad_s, uint16_t decim_log2)
{
    bw_filter_status_t st;
    memset(r, 0, sizeof *r);
    if (decim_log2 > IDENT_REGRESSOR_DECIM_LOG2_MAX) {
        return BW_FILTER_ERR_TS;
    }
    st = bw_filter_init(&r->f_im, wc_rad_s, n_pass, Ts_s * (float)(1u << decim_log2),
                        w_base_rad_s);
    if (st != BW_FILTER_OK) {
        memset(r, 0, sizeof *r);
        return st;
    }
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
}

/* The window mean of a sum of 2^n samples (n <= 3), rounded half up (no
 * bias to pass the filters' unit DC gain): floor((sum + 2^(n-1)) / 2^n),
 * the floor written without shifting a negative value (estim_asr32);
 * |sum| < 56 pu, so sum + 2^(n-1) LSB cannot overflow.  n = 0: exact.
 * FLOAT_MATH: the exact quotient. */
static inline _iq ident_mean(_iq sum, uint16_t n)
{
#if MATH_TYPE == IQ_MATH
    if (n == 0u) {
        return sum;
    }
    return estim_asr32(sum + ((int32_t)1 << (n - 1u)), (int16_t)n);
#else
    return sum / (float)(1u << n);
#endif
}

void ident_regressor_filter_a(ident_regressor_t *r)
{
    const uint16_t n = r->decim_log2;
    const _iq um = ident_mean(r->s_um, n);
    const _iq ut = ident_mean(r->s_ut, n);
    /* back to the middle of the periods: R(x), x = pi f_base Ts ws_mean,
     * |x| <= 7 pi/128 < 0.18 rad (f_base Ts < 1/128, |ws| <= 7):
     * cos x = 1 - (x^2/2)(1 - x^2/12), sin x = x (1 - x^2/6), series
     * errors below x^6/720, x^5/120 (< 2e-6 at the limit, 3e-9 at 2 pu);
     * Q24 products of factors <= 1 */
    const _iq x = _IQmpy(r->k_half, ident_mean(r->s_ws, n));
    const _iq x2 = _IQmpy(x, x);
    const _iq cx = _IQ(1.0) - _IQmpy(_IQmpy(x2, _IQ(0.5)), _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 12.0)));
    const _iq sx = _IQmpy(x, _IQ(1.0) - _IQmpy(x2, _IQ(1.0 / 6.0)));

    r->f_im.u = ident_mean(r->s_im, n);
    r->f_it.u = ident_mean(r->s_it, n);
    /* |um|, |ut| <= 7: each sum < 9.9 */
    r->f_um.u = _IQmpy(cx, um) - _IQmpy(sx, ut);
    r->f_ut.u = _IQmpy(sx, um) + _IQmpy(cx, ut);
    r->f_ws_it.u = ident_mean(r->s_ws_it, n);
    r->f_ws_im.u = ident_mean(r->s_ws_im, n);
    r->f_wr.u = r->wr;   /* already the window's mean (ident_regressor.h) */
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
