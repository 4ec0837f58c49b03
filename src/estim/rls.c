/* Recursive least squares with a block-floating-point covariance (method §3,
 * eq. 1).  The scaling plan is in rls.h. */
#include "rls.h"

#include <math.h>
#include <string.h>

#include "estim_bfp.h"

#if RLS_N != 4
#error "rls.c writes the 4-column sums out"
#endif

/* float -> Q30 / Q24, rounded to nearest (init only). */
static _iq30 rls_to_q30(float v)
{
#if MATH_TYPE == IQ_MATH
    return _IQ30(roundf(v * 1073741824.0f) / 1073741824.0f);
#else
    return v;
#endif
}

static _iq rls_to_iq(float v)
{
#if MATH_TYPE == IQ_MATH
    return _IQ(roundf(v * 16777216.0f) / 16777216.0f);
#else
    return v;
#endif
}

rls_status_t rls_init(rls_t *r, rls_form_t form, float p0, float lambda,
                      float trace_max, const float theta0[RLS_N])
{
    int x = 0;
    float f;
    int16_t i;

    memset(r, 0, sizeof *r);
    if (form != RLS_FORM_CONST && form != RLS_FORM_PAPER) { return RLS_ERR_FORM; }
    if (!(p0 >= 1e-9f) || !(p0 <= 1e12f)) { return RLS_ERR_P0; }
    if (!(lambda >= 0.9f) || !(lambda <= 1.0f)) { return RLS_ERR_LAMBDA; }
    if (trace_max == 0.0f) {
        trace_max = 4.0f * p0;
    }
    if (!(trace_max >= 4.0f * p0 * 0.999999f) || !(trace_max <= 1e30f)) { return RLS_ERR_TRACE; }
    if (theta0 != NULL) {
        for (i = 0; i < RLS_N; i++) {
            if (!(fabsf(theta0[i]) < RLS_THETA_MAX)) { return RLS_ERR_THETA0; }
        }
    }

    r->form = (uint16_t)form;
    r->forget = (lambda < 1.0f) ? 1u : 0u;
    r->inv_lambda = rls_to_q30(1.0f / lambda);
    f = frexpf(trace_max, &x);               /* trace_max = f 2^x, f in [0.5, 1) */
    r->trace_max_m = rls_to_iq(f);
    r->trace_max_e = (int16_t)x;

    /* P(0) = p0 I = 4^Pe Pn with Pn_ii in [0.25, 1) */
    f = frexpf(p0, &x);
    if ((x % 2) != 0) {
        f = 0.5f * f;                        /* [0.25, 0.5) */
        x = x + 1;
    }
    for (i = 0; i < RLS_N; i++) {
        r->Pn[i][i] = rls_to_q30(f);
        r->Pe[i] = (int16_t)(x / 2);
        r->theta[i] = (theta0 != NULL) ? rls_to_iq(theta0[i]) : _IQ(0.0);
    }
    return RLS_OK;
}

/* Off-diagonal Pn_ij clamped to [-1, 1] (counted).  While Pn is positive
 * definite with Pn_ii < 1, |Pn_ij| <= sqrt(Pn_ii Pn_jj) < 1 (Cauchy-
 * Schwarz) and the clamp never acts; it keeps the bound that makes every
 * sum of rls_update_row overflow-free (see there) when rounding has cost
 * positive definiteness. */
static inline _iq30 rls_clamp_off(rls_t *r, _iq30 v)
{
    _iq30 c = _IQsat(v, _IQ30(1.0), _IQ30(-1.0));
    if (c != v) { estim_count(&r->sat_count); }
    return c;
}

/* Bring every Pn_ii back into [0.25, 1) by rescaling row and column i by a
 * power of two (P = D Pn D is unchanged); a diagonal inside the band costs
 * two compares (no exponent).  A non-positive diagonal means rounding has
 * cost positive definiteness: reset that parameter's row and column
 * (Pn_ii = 0.5, no correlation, Pe_i kept) and count it. */
static void rls_renorm(rls_t *r)
{
    int16_t i, j, n, s, e_new;
    for (i = 0; i < RLS_N; i++) {
        _iq30 d = r->Pn[i][i];
        if (d >= _IQ30(0.25) && d < _IQ30(1.0)) {
            continue;                        /* in band: the common case */
        }
        if (d <= _IQ30(0.0)) {
            estim_count(&r->pd_count);
            for (j = 0; j < RLS_N; j++) {
                r->Pn[i][j] = _IQ30(0.0);
                r->Pn[j][i] = _IQ30(0.0);
            }
            r->Pn[i][i] = _IQ30(0.5);
            continue;
        }
        n = estim_exponent(d, 30);           /* d in [2^(n-1), 2^n) */
        s = estim_floor_half((int16_t)-n);   /* n + 2s in {0, -1} */
        e_new = (int16_t)(r->Pe[i] - s);
        if (e_new > RLS_PE_LIM) { e_new = RLS_PE_LIM; }
        if (e_new < -RLS_PE_LIM) { e_new = -RLS_PE_LIM; }
        s = (int16_t)(r->Pe[i] - e_new);
        if (s == 0) {
            continue;
        }
        for (j = 0; j < RLS_N; j++) {
            if (j != i) {
                r->Pn[i][j] = rls_clamp_off(r, estim_ldexp(r->Pn[i][j], s, 30, 30,
                                                           &r->sat_count));
                r->Pn[j][i] = r->Pn[i][j];
            }
        }
        r->Pn[i][i] = estim_ldexp(d, (int16_t)(2 * s), 30, 30, &r->sat_count);
        r->Pe[i] = e_new;
    }
}

/* Scaling: P / lambda = D (Pn / lambda) D: Q30*Q30 -> Q30 rounded, |Pn| <= 1
 * and 1/lambda <= 1.112 so no overflow; off-diagonals clamped to [-1, 1]
 * (inactive while P is PD: a |Pn_ij| / lambda > 1 needs a Pn_ii / lambda
 * > 1, which the renormalisation halves), then renormalised.  The trace
 * test is done in block floating point: trace = tm 4^emax with tm in Q24
 * < 4.  Not in the default configuration (lambda = 1: one compare). */
void rls_forget(rls_t *r)
{
    int16_t i, j, emax = -RLS_PE_LIM;
    _iq tm = _IQ(0.0);
    _iq lhs, rhs;
    if (r->forget == 0u) {
        return;
    }
    for (i = 0; i < RLS_N; i++) {
        if (r->Pe[i] > emax) { emax = r->Pe[i]; }
    }
    for (i = 0; i < RLS_N; i++) {
        /* Pn_ii 4^(Pe_i - emax): Q30 -> Q24, rounded, tiny terms -> 0 */
        tm += estim_ldexp(r->Pn[i][i], (int16_t)(2 * (r->Pe[i] - emax)), 30, 24, NULL);
    }
    lhs = _IQ30rmpy(tm, r->inv_lambda);                 /* Q24*Q30 -> Q24 */
    /* trace_max / 4^emax, Q24; saturates high (-> forgetting allowed) or
     * rounds to 0 (-> held) outside Q24: both the right answer */
    rhs = estim_ldexp(r->trace_max_m, (int16_t)(r->trace_max_e - 2 * emax), 24, 24, NULL);
    if (lhs > rhs) {
        r->windup_hold = 1u;
        return;
    }
    r->windup_hold = 0u;
    for (i = 0; i < RLS_N; i++) {
        for (j = i; j < RLS_N; j++) {
            _iq30 v = _IQ30rsmpy(r->Pn[i][j], r->inv_lambda);  /* Q30*Q30 -> Q30, rounded, saturating */
            r->Pn[i][j] = (j == i) ? v : rls_clamp_off(r, v);
            r->Pn[j][i] = r->Pn[i][j];
        }
    }
    rls_renorm(r);
}

/*
 * Bounds that make the sums below overflow-free without saturation, from
 * the invariant |Pn_ij| <= 1 (off-diagonals clamped, diagonals < 1 after
 * renormalisation, < 2 in any case), |psi_j| <= 1 and at most 4 nonzero
 * regressors:  |g_i| <= 1 + 3 (< 2 + 3 with a diagonal up to 2) < 8 (Q28),
 * q <= 4 max|g| < 32 (Q26), den <= q + 1 < 32 (Q26), |g_i rm| < 2*5 < 16
 * (Q27), |h_i| clamped below 1 so |h_i h_j| < 1 and the P update stays in
 * (-2, 2) (Q30) before its clamp.  Multiplies truncate (_IQNmpy, the C28x
 * intrinsic, not the _IQNrmpy library call) except the terms of q and the
 * P downdate, rounded through iq_round_half; why, in rls.h
 * ("Truncation").  32-bit integer arithmetic only (estim_bfp.h).
 */
_iq rls_update_row(rls_t *r, const _iq phi_in[RLS_N], _iq y)
{
    _iq phi[RLS_N];
    _iq28 psi[RLS_N], g[RLS_N];
    _iq27 h[RLS_N];
    _iq26 q, den;
    _iq29 dm, rm, eps;
    _iq30 em;
    _iq e = y;
    int16_t i, j, b, n, ne, pp = ESTIM_EXP_ZERO, hs, ks, k;

    /* regressors, saturated; a-priori innovation e = y - phi' theta over the
     * nonzero entries (a zero regressor carries no information: each motor
     * row has three of four) */
    for (j = 0; j < RLS_N; j++) {
        phi[j] = _IQsat(phi_in[j], _IQ(RLS_PHI_MAX), _IQ(-RLS_PHI_MAX));
        if (phi[j] != phi_in[j]) { estim_count(&r->sat_count); }
        if (phi[j] != _IQ(0.0)) {
            /* |phi| <= 8, |theta| < 16: |product| < 128, no wrap; truncated
             * (bias < 1 LSB24 per term, rls.h "Truncation") */
            e = estim_sub_sat(e, _IQmpy(phi[j], r->theta[j]), &r->sat_count);  /* Q24*Q24 -> Q24 */
            /* block exponent of the scaled regressor 2^Pe_j phi_j */
            n = (int16_t)(estim_exponent(phi[j], 24) + r->Pe[j]);
            if (n > pp) { pp = n; }
        }
    }
    {
        _iq es = _IQsat(e, _IQ(RLS_E_MAX), _IQ(-RLS_E_MAX));
        if (es != e) { estim_count(&r->sat_count); }
        e = es;
    }
    if (pp == ESTIM_EXP_ZERO) {
        return e;                            /* phi = 0: no information */
    }
    /* psi_j = 2^(Pe_j - pp) phi_j, |psi_j| <= 1 (Q24 -> Q28; a left shift
     * is exact and cannot overflow since exponent + Pe_j <= pp; 0 stays 0) */
    for (j = 0; j < RLS_N; j++) {
        psi[j] = (phi[j] == _IQ(0.0)) ? _IQ28(0.0)
               : estim_ldexp(phi[j], (int16_t)(r->Pe[j] - pp), 24, 28, NULL);
    }
    /* g = Pn psi (Q30*Q28 -> Q28), written out for the 4 columns (a zero
     * psi_j adds 0) */
    for (i = 0; i < RLS_N; i++) {
        g[i] = _IQ30mpy(r->Pn[i][0], psi[0]) + _IQ30mpy(r->Pn[i][1], psi[1])
             + _IQ30mpy(r->Pn[i][2], psi[2]) + _IQ30mpy(r->Pn[i][3], psi[3]);
    }
    /* q = psi' g, rounded (a truncated q would shrink den and over-shoot the
     * downdate of P when P is huge): each term Q28*Q28 -> Q27 (|.| < 16),
     * rounded to Q26 = _IQ30rmpy, bit for bit */
    q = iq_round_half(_IQ29mpy(psi[0], g[0])) + iq_round_half(_IQ29mpy(psi[1], g[1]))
      + iq_round_half(_IQ29mpy(psi[2], g[2])) + iq_round_half(_IQ29mpy(psi[3], g[3]));
    if (q <= _IQ26(0.0)) {
        estim_count(&r->pd_count);           /* Pn not PD along psi */
        return e;
    }
    /* den and the shifts of h and K (rls.h) */
    if (pp >= 0) {
        den = q + estim_ldexp(_IQ26(1.0), (int16_t)(-2 * pp), 26, 26, NULL);
        hs = 0;
        ks = (int16_t)-pp;
    } else {
        den = _IQ26(1.0) + estim_ldexp(q, (int16_t)(2 * pp), 26, 26, NULL);
        hs = pp;
        ks = 0;
    }
    /* den = dm 4^k, dm in [0.25, 1] (Q29; 1 only by rounding) */
    n = estim_exponent(den, 26);
    k = (int16_t)-estim_floor_half((int16_t)-n);          /* ceil(n/2) */
    dm = estim_ldexp(den, (int16_t)(-2 * k), 26, 29, &r->sat_count);
    rm = _IQ29isqrt(dm);                                 /* Q29, [1, 2] */

    /* h_i = g_i rm 2^(hs - k), Q27, |h_i|^2 <= Pn_ii < 1 while P is PD
     * (Cauchy-Schwarz).  Common case hs <= k: the shift is folded into rm
     * once, c = rm 2^(hs - k) <= 2 (Q29, rounded), and h_i = g_i c (Q28*Q29
     * -> Q27, |.| <= 2 |g_i| < 16).  Otherwise (huge P, small q: the first
     * samples) each t_i = g_i rm (Q27, < 16) is shifted, saturating. */
    if (hs <= k) {
        _iq29 c = estim_ldexp(rm, (int16_t)(hs - k), 29, 29, NULL);
        for (i = 0; i < RLS_N; i++) {
            h[i] = _IQ30mpy(g[i], c);
        }
    } else {
        for (i = 0; i < RLS_N; i++) {
            h[i] = estim_ldexp(_IQ30mpy(g[i], rm), (int16_t)(hs - k), 27, 27, &r->sat_count);
        }
    }
    for (i = 0; i < RLS_N; i++) {
        _iq27 hc = _IQsat(h[i], _IQ27(RLS_H_MAX), _IQ27(-RLS_H_MAX));
        if (hc != h[i]) { estim_count(&r->sat_count); }   /* only if not PD */
        h[i] = hc;
    }
    /* P update on the upper triangle, mirrored: symmetric to the bit.
     * h_i h_j rounded (P integrates these over 1e5 updates, rls.h): Q27*Q27
     * -> Q31 (|.| < 1 fits), rounded to Q30 = _IQ24rmpy, bit for bit; so
     * Pn_ij - h_i h_j is in (-2, 2). */
    for (i = 0; i < RLS_N; i++) {
        r->Pn[i][i] = r->Pn[i][i] - iq_round_half(_IQ23mpy(h[i], h[i]));
        for (j = (int16_t)(i + 1); j < RLS_N; j++) {
            r->Pn[i][j] = rls_clamp_off(r, r->Pn[i][j] - iq_round_half(_IQ23mpy(h[i], h[j])));
            r->Pn[j][i] = r->Pn[i][j];
        }
    }
    /* theta update: K_i e = 2^(Pe_i + ks - k) h_i rm e.  e is normalised
     * first (e = em 2^ne, |em| in [0.5, 1], Q30), so that the products keep
     * their significant bits however small e is: eps = rm em (Q29*Q30 ->
     * Q29, |eps| <= 2), x_i = h_i eps (Q27*Q29 -> Q27, |x_i| < 2). */
    if (e != _IQ(0.0)) {
        ne = estim_exponent(e, 24);
        em = estim_ldexp(e, (int16_t)-ne, 24, 30, NULL);
        eps = _IQ30mpy(rm, em);
        for (i = 0; i < RLS_N; i++) {
            _iq th = r->theta[i];
            b = (int16_t)(r->Pe[i] + ks - k + ne);
            /* compensated: increments below 1/2 LSB24 are kept, not lost */
            estim_accumulate(&th, _IQ29mpy(h[i], eps), b, 27, &r->theta_res[i],
                             &r->sat_count);
            r->theta[i] = _IQsat(th, _IQ(RLS_THETA_MAX), _IQ(-RLS_THETA_MAX));
            if (r->theta[i] != th) { estim_count(&r->sat_count); }
        }
    }
    rls_renorm(r);
    estim_count(&r->n_updates);
    return e;
}

/* Row 1 (eq. 7 or eq. 9): [i_Mf, u_Mf, c, 0], c from theta2 as it is now */
static void rls_row1(rls_t *r)
{
    _iq row[RLS_N];
    row[0] = r->i_mf;
    row[1] = r->u_mf;
    row[2] = (r->form == (uint16_t)RLS_FORM_PAPER) ? r->theta[1] : _IQ(1.0);
    row[3] = _IQ(0.0);
    r->innov[0] = rls_update_row(r, row, r->y1);
}

/* Row 2: [i_Tf, u_Tf, 0, wr_f] */
static void rls_row2(rls_t *r)
{
    _iq row[RLS_N];
    row[0] = r->i_tf;
    row[1] = r->u_tf;
    row[2] = _IQ(0.0);
    row[3] = r->wr_f;
    r->innov[1] = rls_update_row(r, row, r->y2);
}

void rls_step(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_forget(r);
    /* the third regressor comes from theta2 BEFORE this sample: row 1 first */
    rls_row1(r);
    rls_row2(r);
}

void rls_step_row1(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_forget(r);
    rls_row1(r);
}

void rls_step_row2(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    rls_row2(r);
}

void rls_step_row(rls_t *r)
{
    if (r->enable == 0u) {
        return;
    }
    if (r->row_next == 0u) {
        rls_forget(r);
        rls_row1(r);
        r->row_next = 1u;
    } else {
        rls_row2(r);
        r->row_next = 0u;
    }
}
