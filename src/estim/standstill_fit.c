/* The standstill sequence's parameters from its impedance points.  See
 * standstill_fit.h.  Float: the background's (never an ISR's). */
#include "standstill_fit.h"

#include "rls.h"
#include "rls_cov.h"

#include <math.h>
#include <string.h>

#define FIT_P0 1.0e4f        /* P(0): the rows are of order 1 (normalised); the prior's
                                pull given back exactly (prior_back).  Not 1e6: from there
                                the RLS's own rounding (P_N a difference of terms 1e6 its
                                size along the weakest direction) left Tr 3-4e-4 off the
                                batch fit on the paper motor (test_fit_is_batch); from 1e4,
                                6e-6 (IQ) / 6e-7 (FLOAT) */
#define FIT_DET_MIN 0.01f    /* det M below this: a direction the rows hardly fix
                                (p0 lambda_min < ~0.01); the RLS's fit is kept */
#define I_MIN 1.0e-6f        /* smallest |I| (a sum of 16 ampl/2: the injection's is ~1) */

static const float k_nu[STANDSTILL_LF_NH] = {1.0f, 2.0f, 4.0f};

/* Z = U / I at harmonic n of half h (h = 2: both halves), U turned back by
 * w Ts / 2.  Phasors X = sum_c - j sum_s (the sums' common gain cancels). */
static int impedance(const standstill_lf_t *z, uint16_t h, uint16_t n, float lead_rad,
                     float *r, float *x)
{
    float us = 0.0f, uc = 0.0f, is = 0.0f, ic = 0.0f;
    float ur, ui, ir, ii, den, cr, ci, tr, ti;
    uint16_t k;
    for (k = 0u; k < STANDSTILL_LF_HALVES; k++) {
        if (h == 2u || h == k) {
            us += standstill_lf_sum(z, k, n, SSLF_US);
            uc += standstill_lf_sum(z, k, n, SSLF_UC);
            is += standstill_lf_sum(z, k, n, SSLF_IS);
            ic += standstill_lf_sum(z, k, n, SSLF_IC);
        }
    }
    ur = uc;
    ui = -us;
    ir = ic;
    ii = -is;
    den = ir * ir + ii * ii;
    if (!(den > I_MIN * I_MIN)) {
        return 1;
    }
    /* U e^{j lead} */
    cr = cosf(lead_rad);
    ci = sinf(lead_rad);
    tr = ur * cr - ui * ci;
    ti = ur * ci + ui * cr;
    *r = (tr * ir + ti * ii) / den;
    *x = (ti * ir - tr * ii) / den;
    return 0;
}

/* The parameters (pu) from theta = [Rs / s, 4 w1 Tr, 4 w1 (L_M + Tr Rs) / s]
 * (standstill_fit.h); 1 if one is not > 0. */
static int params_of(const float th[3], float s, const standstill_fit_in_t *in,
                     float p[SSFIT_NP])
{
    const float rs = th[0] * s;
    const float tr = 0.25f * th[1] / in->w1_pu;
    const float lmm = 0.25f * th[2] * s / in->w1_pu - tr * rs;
    const float ls = in->sigma_ls_pu + lmm;
    if (!(rs > 0.0f) || !(tr > 0.0f) || !(lmm > 0.0f) || !(ls > 0.0f)) {
        return 1;
    }
    p[SSFIT_RS] = rs;
    p[SSFIT_TR] = tr;
    p[SSFIT_LR] = ls;                      /* Lr = Ls (method §4) */
    p[SSFIT_LM] = sqrtf(lmm * ls);         /* L_M = Lm^2 / Lr */
    p[SSFIT_RR] = ls / tr;
    p[SSFIT_PSI] = p[SSFIT_LM] * in->im_pu;
    return 0;
}

/* P_ij of the RLS's covariance (rls_cov.h: 2^(Pe_i + Pe_j) Pn_ij / w). */
static float p_of(const rls_cov_t *c, uint16_t i, uint16_t j)
{
    return ldexpf(_IQ30toF(c->Pn[i][j]), (int)c->Pe[i] + (int)c->Pe[j]) / _IQ30toF(c->w);
}

/* The determinant of a 3x3 (float; the background's). */
static float det3(const float a[3][3])
{
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* The prior's pull given back (standstill_fit.h): with M = I - P_N / p0
 * (eigenvalues p0 lambda / (1 + p0 lambda): 15/16 at the paper motor's
 * weakest direction, lambda = 1.5e-3), the batch fit theta* = M^-1
 * theta_N and its covariance (Phi' Phi)^-1 = M^-1 P_N, by Cramer's rule.
 * det M below FIT_DET_MIN (a direction the rows hardly fix): nothing
 * changed.  The fourth unknown has no regressor (its P row is p0 e_4,
 * theta_N 0): left out.  P (3x3) in and out: P_N in, (Phi' Phi)^-1 out. */
static void prior_back(float P[3][3], float th[3])
{
    float m[3][3], q[3][3];
    float t[3] = {0.0f, 0.0f, 0.0f};   /* all written (c = 0) before read */
    float det;
    uint16_t i, j, k, c;

    for (i = 0u; i < 3u; i++) {
        for (j = 0u; j < 3u; j++) {
            m[i][j] = ((i == j) ? 1.0f : 0.0f) - P[i][j] / FIT_P0;
        }
    }
    det = det3(m);
    if (!(det > FIT_DET_MIN)) {
        return;
    }
    /* column c of M^-1 [theta_N P_N]: M with column k replaced (Cramer) */
    for (c = 0u; c < 4u; c++) {
        float x[3];
        for (k = 0u; k < 3u; k++) {
            float a[3][3];
            for (i = 0u; i < 3u; i++) {
                for (j = 0u; j < 3u; j++) {
                    a[i][j] = (j == k) ? ((c == 0u) ? th[i] : P[i][c - 1u]) : m[i][j];
                }
            }
            x[k] = det3(a) / det;
        }
        for (k = 0u; k < 3u; k++) {
            if (c == 0u) {
                t[k] = x[k];
            } else {
                q[k][c - 1u] = x[k];
            }
        }
    }
    for (i = 0u; i < 3u; i++) {
        th[i] = t[i];
        for (j = 0u; j < 3u; j++) {
            P[i][j] = 0.5f * (q[i][j] + q[j][i]);   /* symmetric as it is, to rounding */
        }
    }
}

/* Each parameter's standard deviation (relative) from the fit's covariance
 * s2 P (P = (Phi' Phi)^-1, prior_back's; the rows' misfit s2 per degree of freedom), through
 * the parameters' derivatives in theta (central differences). */
static void deviations(const float P[3][3], const float th[3], float s, float s2,
                       const standstill_fit_in_t *in, const float p[SSFIT_NP],
                       float sd[SSFIT_NP])
{
    float jac[SSFIT_NP][3];
    uint16_t i, j, k;

    for (j = 0u; j < 3u; j++) {
        float tp[3] = {th[0], th[1], th[2]};
        float tm[3] = {th[0], th[1], th[2]};
        float pp[SSFIT_NP], pm[SSFIT_NP];
        const float h = 1e-3f * fmaxf(fabsf(th[j]), 1e-3f);
        tp[j] += h;
        tm[j] -= h;
        if (params_of(tp, s, in, pp) != 0 || params_of(tm, s, in, pm) != 0) {
            for (k = 0u; k < (uint16_t)SSFIT_NP; k++) {
                sd[k] = 1.0f;   /* the fit sits at the edge of the model: no figure */
            }
            return;
        }
        for (k = 0u; k < (uint16_t)SSFIT_NP; k++) {
            jac[k][j] = (pp[k] - pm[k]) / (2.0f * h);
        }
    }
    for (k = 0u; k < (uint16_t)SSFIT_NP; k++) {
        float v = 0.0f;
        for (i = 0u; i < 3u; i++) {
            for (j = 0u; j < 3u; j++) {
                v += jac[k][i] * jac[k][j] * P[i][j];
            }
        }
        sd[k] = sqrtf(fmaxf(v * s2, 0.0f)) / p[k];
    }
}

/* One fit of half h (2: both) into p[] (pu); the relative rms misfit, and
 * (sd != NULL) each parameter's relative standard deviation. */
static standstill_fit_status_t fit_half(const standstill_lf_t *z, const standstill_fit_in_t *in,
                                        rls_t *r, uint16_t h, float p[SSFIT_NP], float *res,
                                        float sd[SSFIT_NP], float rr[STANDSTILL_LF_NH],
                                        float xx[STANDSTILL_LF_NH])
{
    float s = 0.0f;
    float th[3];
    float P[3][3];
    float e2 = 0.0f, y2 = 0.0f;
    uint16_t n, j;

    for (n = 0u; n < STANDSTILL_LF_NH; n++) {
        const float w = k_nu[n] * in->w1_pu;
        if (impedance(z, h, n, w * in->half_ts_pu, &rr[n], &xx[n]) != 0) {
            return STANDSTILL_FIT_ERR_CURRENT;
        }
        xx[n] -= w * in->sigma_ls_pu;   /* X_r */
        s += rr[n] * rr[n] + xx[n] * xx[n];
    }
    s = sqrtf(s / (float)STANDSTILL_LF_NH);   /* the rows' scale: |Z_r| rms */
    if (!(s > 0.0f)) {
        return STANDSTILL_FIT_ERR_CURRENT;
    }
    (void)rls_init(r, RLS_FORM_CONST, FIT_P0, 1.0f, 0.0f, NULL);
    for (n = 0u; n < STANDSTILL_LF_NH; n++) {
        /* theta = [Rs / s, 4 w1 Tr, 4 w1 (L_M + Tr Rs) / s, 0]; the rows
         * divided by s: each entry of order 1 (|phi| < 4: nu/4 <= 1, |Z_r|/s
         * <= sqrt 3) */
        const float nu4 = 0.25f * k_nu[n];
        const float rn = rr[n] / s, xn = xx[n] / s;
        _iq phi1[RLS_N] = {_IQ(1.0), 0, 0, 0};
        _iq phi2[RLS_N] = {0, 0, 0, 0};
        phi1[1] = _IQ(nu4 * xn);
        phi2[1] = _IQ(-nu4 * rn);
        phi2[2] = _IQ(nu4);
        (void)rls_update_row(r, phi1, _IQ(rn));
        (void)rls_update_row(r, phi2, _IQ(xn));
    }
    for (j = 0u; j < 3u; j++) {
        th[j] = _IQtoF(r->theta[j]);
    }
    {
        rls_cov_t c;
        uint16_t i;
        rls_cov_save(&c, r);
        for (i = 0u; i < 3u; i++) {
            for (j = 0u; j < 3u; j++) {
                P[i][j] = p_of(&c, i, j);
            }
        }
    }
    prior_back(P, th);   /* the batch least-squares fit (standstill_fit.h) */
    for (n = 0u; n < STANDSTILL_LF_NH; n++) {
        const float nu4 = 0.25f * k_nu[n];
        const float rn = rr[n] / s, xn = xx[n] / s;
        const float e1 = rn - (th[0] + th[1] * nu4 * xn);
        const float e2r = xn - (-th[1] * nu4 * rn + th[2] * nu4);
        e2 += e1 * e1 + e2r * e2r;
        y2 += rn * rn + xn * xn;
    }
    *res = sqrtf(e2 / y2);
    if (params_of(th, s, in, p) != 0) {
        return STANDSTILL_FIT_ERR_MODEL;
    }
    if (sd != NULL) {
        /* six rows, three unknowns: the misfit per degree of freedom */
        deviations(P, th, s, e2 / 3.0f, in, p, sd);
    }
    return STANDSTILL_FIT_OK;
}

standstill_fit_status_t standstill_fit(standstill_fit_t *f, const standstill_lf_t *z,
                                       const standstill_fit_in_t *in, rls_t *work)
{
    float sd[SSFIT_NP];
    float pa[SSFIT_NP], pb[SSFIT_NP];
    float ra, rb;
    float r_h[STANDSTILL_LF_NH], x_h[STANDSTILL_LF_NH];
    standstill_fit_status_t st;
    uint16_t j;

    memset(f, 0, sizeof *f);
    if (!(in->w1_pu > 0.0f) || !(in->sigma_ls_pu > 0.0f) || !(in->im_pu > 0.0f) ||
        !(in->half_ts_pu >= 0.0f)) {
        f->status = (uint16_t)STANDSTILL_FIT_ERR_INPUT;
        return STANDSTILL_FIT_ERR_INPUT;
    }
    if (z->done == 0u) {
        f->status = (uint16_t)STANDSTILL_FIT_ERR_CURRENT;   /* never ran to its end: no phasors */
        return STANDSTILL_FIT_ERR_CURRENT;
    }
    st = fit_half(z, in, work, 2u, f->p, &f->residual, sd, f->r, f->x);
    if (st == STANDSTILL_FIT_OK) {
        st = fit_half(z, in, work, 0u, pa, &ra, NULL, r_h, x_h);
    }
    if (st == STANDSTILL_FIT_OK) {
        st = fit_half(z, in, work, 1u, pb, &rb, NULL, r_h, x_h);
    }
    f->status = (uint16_t)st;
    if (st != STANDSTILL_FIT_OK) {
        return st;
    }
    for (j = 0u; j < (uint16_t)SSFIT_NP; j++) {
        f->spread[j] = 0.5f * fabsf(pa[j] - pb[j]) / f->p[j];
        f->sd[j] = sd[j];
        f->conf[j] = STANDSTILL_FIT_K_SD * sd[j] + f->spread[j] + STANDSTILL_FIT_CONF_FLOOR;
    }
    return STANDSTILL_FIT_OK;
}
