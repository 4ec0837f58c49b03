/* Butterworth low-pass by improved Euler, as a precomputed map.  See
 * bw_filter.h (method §5, eqs. 11-18). */
#include "bw_filter.h"

#include <math.h>
#include <string.h>

#include "estim_bfp.h"

#define BW_SQRT2 1.41421356237309505f

/* float -> Q30 / Q29, rounded to nearest (TI's _IQN(A) truncates; the
 * coefficients are computed once, so round them).  FLOAT_MATH: unchanged. */
static _iq30 bw_to_q30(float v)
{
#if MATH_TYPE == IQ_MATH
    return _IQ30(roundf(v * 1073741824.0f) / 1073741824.0f);
#else
    return v;
#endif
}

static _iq29 bw_to_q29(float v)
{
#if MATH_TYPE == IQ_MATH
    return _IQ29(roundf(v * 536870912.0f) / 536870912.0f);
#else
    return v;
#endif
}

bw_filter_status_t bw_filter_check(float wc_rad_s, uint16_t n_pass, float Ts_s,
                                   float w_base_rad_s)
{
    /* "!(x > 0)" also rejects NaN */
    if (!(w_base_rad_s > 0.0f)) { return BW_FILTER_ERR_BASE; }
    /* 0 < Wc < BW_FILTER_WC_MAX_PU w_base */
    if (!(wc_rad_s > 0.0f) || !(wc_rad_s / w_base_rad_s < BW_FILTER_WC_MAX_PU)) {
        return BW_FILTER_ERR_WC;
    }
    if (!(Ts_s > 0.0f) || Ts_s > 0.01f) { return BW_FILTER_ERR_TS; }
    if (n_pass < 1u || n_pass > BW_FILTER_N_MAX) { return BW_FILTER_ERR_N; }
    /* a = Wc Ts = h Wc_pu: pu time cancels */
    if (wc_rad_s * Ts_s > BW_FILTER_A_MAX) { return BW_FILTER_ERR_STEP; }
    return BW_FILTER_OK;
}

bw_filter_status_t bw_filter_init(bw_filter_t *f, float wc_rad_s, uint16_t n_pass,
                                  float Ts_s, float w_base_rad_s)
{
    float a;
    float m[2][2];      /* M = (a/2) Fn */
    float p[2][2];      /* P = I + M + ... + M^N */
    float t[2][2];
    float d11, d12, d21, d22;
    uint16_t j;
    bw_filter_status_t st;

    memset(f, 0, sizeof *f);
    st = bw_filter_check(wc_rad_s, n_pass, Ts_s, w_base_rad_s);
    if (st != BW_FILTER_OK) { return st; }
    a = wc_rad_s * Ts_s;       /* = h * Wc_pu: pu time cancels */

    /* M = (a/2) [0 1; -1 -sqrt2] */
    m[0][0] = 0.0f;
    m[0][1] = 0.5f * a;
    m[1][0] = -0.5f * a;
    m[1][1] = -0.5f * a * BW_SQRT2;
    /* Horner: P <- I + M P, N times, from P = I: P = sum_{i=0..N} M^i.
     * No cancellation: every term added is smaller than the one before. */
    p[0][0] = 1.0f; p[0][1] = 0.0f; p[1][0] = 0.0f; p[1][1] = 1.0f;
    for (j = 0u; j < n_pass; j++) {
        t[0][0] = 1.0f + (m[0][0] * p[0][0] + m[0][1] * p[1][0]);
        t[0][1] = m[0][0] * p[0][1] + m[0][1] * p[1][1];
        t[1][0] = m[1][0] * p[0][0] + m[1][1] * p[1][0];
        t[1][1] = 1.0f + (m[1][0] * p[0][1] + m[1][1] * p[1][1]);
        memcpy(p, t, sizeof p);
    }
    /* D = P a Fn,  a Fn = [0 a; -a -sqrt2 a] */
    d11 = -a * p[0][1];
    d12 = a * (p[0][0] - BW_SQRT2 * p[0][1]);
    d21 = -a * p[1][1];
    d22 = a * (p[1][0] - BW_SQRT2 * p[1][1]);

    f->c1 = bw_to_q30(d11 / d12);
    f->d12 = bw_to_q30(d12);
    f->c2 = bw_to_q29(d22 / d21);
    f->d21 = bw_to_q30(d21);
    f->a = bw_to_q30(a);
    f->a_half = bw_to_q30(0.5f * a);
    f->wc_pu = bw_to_q29(wc_rad_s / w_base_rad_s);
    f->n_pass = n_pass;
    return BW_FILTER_OK;
}

void bw_filter_reset(bw_filter_t *f, _iq y0)
{
    _iq u = _IQsat(y0, _IQ(BW_FILTER_U_MAX), _IQ(-BW_FILTER_U_MAX));
    f->x1 = _IQtoIQ27(u);      /* exact: |u| <= 7 < 16 */
    f->z2 = _IQ27(0.0);
    f->y = u;
    f->dy = _IQ(0.0);
}

/* f~(s) = [z2, -(x1 - u) - sqrt2 z2] in Q26 (f = Wc_pu f~; the Wc_pu h = a
 * factor is applied by the caller).  |f~2| < 14.7 + 1.42*7 < 25 < 32. */
static void bw_fn(_iq27 x1, _iq27 z2, _iq27 u27, _iq26 *f1, _iq26 *f2)
{
    /* Q27 -> Q26 through an IQmath multiply by 1.0 (Q27*Q29 >> 30), so the
     * FLOAT_MATH build computes the same value (x * 1) */
    *f1 = _IQ30rmpy(z2, _IQ29(1.0));                              /* Q26 */
    *f2 = -_IQ30rmpy(x1 - u27, _IQ29(1.0))
          - _IQ30rmpy(z2, _IQ29(1.41421356237309505));           /* Q27*Q29 -> Q26 */
}

void bw_filter_step_npass(bw_filter_t *f)
{
    _iq u = _IQsat(f->u, _IQ(BW_FILTER_U_MAX), _IQ(-BW_FILTER_U_MAX));
    _iq27 u27 = _IQtoIQ27(u);
    _iq26 f01, f02, fc1, fc2;
    _iq27 g01, g02;            /* (a/2) f~(s(k-1)): the same in every pass */
    _iq27 c1, c2;              /* latest corrector (first: the predictor) */
    uint16_t j;

    bw_fn(f->x1, f->z2, u27, &f01, &f02);
    /* predictor (eqs. 15-16): s_p = s + a f~(s) */
    c1 = f->x1 + _IQ29rmpy(f01, f->a);       /* Q26*Q30 -> Q27 */
    c2 = f->z2 + _IQ29rmpy(f02, f->a);
    g01 = _IQ29rmpy(f01, f->a_half);         /* Q26*Q30 -> Q27 */
    g02 = _IQ29rmpy(f02, f->a_half);
    /* corrector (eqs. 17-18, method §5), N times with the latest estimate */
    for (j = 0u; j < f->n_pass; j++) {
        bw_fn(c1, c2, u27, &fc1, &fc2);
        c1 = f->x1 + g01 + _IQ29rmpy(fc1, f->a_half);
        c2 = f->z2 + g02 + _IQ29rmpy(fc2, f->a_half);
    }
    f->x1 = c1;
    f->z2 = c2;
    f->y = _IQ27toIQ(f->x1);
    f->dy = _IQmpyIQX(f->z2, 27, f->wc_pu, 29);   /* Q27*Q29 -> Q24 */
}
