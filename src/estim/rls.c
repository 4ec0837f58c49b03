/* Recursive least squares with a block-floating-point covariance (method §3,
 * eq. 1).  The scaling plan is in rls.h. */
#include "rls.h"

#include <math.h>
#include <string.h>

#include "estim_bfp.h"

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

/* Bring every Pn_ii back into [0.25, 1) by rescaling row and column i by a
 * power of two (P = D Pn D is unchanged).  A non-positive diagonal means
 * rounding has cost positive definiteness: reset that parameter's row and
 * column (Pn_ii = 0.5, no correlation, Pe_i kept) and count it. */
static void rls_renorm(rls_t *r)
{
    int16_t i, j, n, s, e_new;
    for (i = 0; i < RLS_N; i++) {
        _iq30 d = r->Pn[i][i];
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
        if (n == 0 || n == -1) {
            continue;                        /* already in [0.25, 1) */
        }
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
                r->Pn[i][j] = estim_ldexp(r->Pn[i][j], s, 30, 30, &r->sat_count);
                r->Pn[j][i] = r->Pn[i][j];
            }
        }
        r->Pn[i][i] = estim_ldexp(d, (int16_t)(2 * s), 30, 30, &r->sat_count);
        r->Pe[i] = e_new;
    }
}

/* Scaling: P / lambda = D (Pn / lambda) D: Q30*Q30 -> Q30 rounded, |Pn| < 1
 * and 1/lambda <= 1.112 so no overflow; then renormalised.  The trace test
 * is done in block floating point: trace = tm 4^emax with tm in Q24 < 4. */
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
            r->Pn[i][j] = _IQ30rsmpy(r->Pn[i][j], r->inv_lambda);  /* Q30*Q30 -> Q30, rounded, saturating */
            r->Pn[j][i] = r->Pn[i][j];
        }
    }
    rls_renorm(r);
}

_iq rls_update_row(rls_t *r, const _iq phi_in[RLS_N], _iq y)
{
    _iq phi[RLS_N];
    _iq28 psi[RLS_N], g[RLS_N], h[RLS_N];
    _iq27 q = _IQ27(0.0), den;
    _iq29 dm, rm;
    _iq e = y;
    int16_t i, j, n, pp = ESTIM_EXP_ZERO, hs, ks, k;

    /* regressors, saturated; a-priori innovation e = y - phi' theta */
    for (j = 0; j < RLS_N; j++) {
        phi[j] = _IQsat(phi_in[j], _IQ(RLS_PHI_MAX), _IQ(-RLS_PHI_MAX));
        if (phi[j] != phi_in[j]) { estim_count(&r->sat_count); }
        /* |phi| <= 8, |theta| < 16: |product| < 128, no wrap */
        e = estim_add_sat(e, -_IQrmpy(phi[j], r->theta[j]), &r->sat_count);   /* Q24*Q24 -> Q24 */
    }
    {
        _iq es = _IQsat(e, _IQ(RLS_E_MAX), _IQ(-RLS_E_MAX));
        if (es != e) { estim_count(&r->sat_count); }
        e = es;
    }

    /* block exponent of the scaled regressor 2^Pe_j phi_j */
    for (j = 0; j < RLS_N; j++) {
        n = estim_exponent(phi[j], 24);
        if (n != ESTIM_EXP_ZERO && (int16_t)(n + r->Pe[j]) > pp) {
            pp = (int16_t)(n + r->Pe[j]);
        }
    }
    if (pp == ESTIM_EXP_ZERO) {
        return e;                            /* phi = 0: no information */
    }
    for (j = 0; j < RLS_N; j++) {
        psi[j] = estim_ldexp(phi[j], (int16_t)(r->Pe[j] - pp), 24, 28, &r->sat_count);   /* |psi| < 1 */
    }
    /* g = Pn psi (Q30*Q28 -> Q28), q = psi' g (Q28*Q28 -> Q27) */
    for (i = 0; i < RLS_N; i++) {
        g[i] = _IQ28(0.0);
        for (j = 0; j < RLS_N; j++) {
            g[i] = estim_add_sat(g[i], _IQ30rmpy(r->Pn[i][j], psi[j]), &r->sat_count);
        }
        q = estim_add_sat(q, _IQ29rmpy(psi[i], g[i]), &r->sat_count);
    }
    if (q <= _IQ27(0.0)) {
        estim_count(&r->pd_count);           /* Pn not PD along psi */
        return e;
    }
    /* den and the shifts of h and K (rls.h) */
    if (pp >= 0) {
        den = estim_add_sat(q, estim_ldexp(_IQ27(1.0), (int16_t)(-2 * pp), 27, 27, NULL),
                            &r->sat_count);
        hs = 0;
        ks = (int16_t)-pp;
    } else {
        den = estim_add_sat(_IQ27(1.0), estim_ldexp(q, (int16_t)(2 * pp), 27, 27, NULL),
                            &r->sat_count);
        hs = pp;
        ks = 0;
    }
    /* den = dm 4^k, dm in [0.25, 1) */
    n = estim_exponent(den, 27);
    k = (int16_t)-estim_floor_half((int16_t)-n);          /* ceil(n/2) */
    dm = estim_ldexp(den, (int16_t)(-2 * k), 27, 29, &r->sat_count);
    rm = _IQ29isqrt(dm);                                 /* Q29, (1, 2] */

    for (i = 0; i < RLS_N; i++) {
        h[i] = estim_ldexp(_IQ29rmpy(g[i], rm), (int16_t)(hs - k), 28, 28, &r->sat_count);   /* Q28*Q29 -> Q28 */
    }
    /* P update on the upper triangle, mirrored: symmetric to the bit */
    for (i = 0; i < RLS_N; i++) {
        for (j = i; j < RLS_N; j++) {
            /* Q28*Q28 -> Q30; |h_i h_j| < 1 and |Pn_ij| < 1 while P is PD, so the
             * saturation only acts on an already ill-conditioned P (counted) */
            r->Pn[i][j] = estim_sub_sat(r->Pn[i][j], _IQ26rmpy(h[i], h[j]), &r->sat_count);
            r->Pn[j][i] = r->Pn[i][j];
        }
    }
    /* theta update: K_i e = 2^(Pe_i + ks - k) (h_i rm) e */
    for (i = 0; i < RLS_N; i++) {
        _iq28 m = _IQ29rmpy(h[i], rm);                   /* Q28*Q29 -> Q28, |m| < 2 */
        _iq26 me = _IQ26rmpy(m, e);                      /* Q28*Q24 -> Q26, |me| < 32 */
        _iq th = r->theta[i];
        /* compensated: increments below 1/2 LSB24 are kept, not lost */
        estim_accumulate(&th, me, (int16_t)(r->Pe[i] + ks - k), 26, &r->theta_res[i],
                         &r->sat_count);
        r->theta[i] = _IQsat(th, _IQ(RLS_THETA_MAX), _IQ(-RLS_THETA_MAX));
        if (r->theta[i] != th) { estim_count(&r->sat_count); }
    }
    rls_renorm(r);
    estim_count(&r->n_updates);
    return e;
}

void rls_step(rls_t *r)
{
    _iq row[RLS_N];
    _iq c3;
    if (r->enable == 0u) {
        return;
    }
    rls_forget(r);
    /* third regressor (eq. 7 or eq. 9), from theta2 BEFORE this sample */
    c3 = (r->form == (uint16_t)RLS_FORM_PAPER) ? r->theta[1] : _IQ(1.0);
    row[0] = r->i_mf;
    row[1] = r->u_mf;
    row[2] = c3;
    row[3] = _IQ(0.0);
    r->innov[0] = rls_update_row(r, row, r->y1);
    row[0] = r->i_tf;
    row[1] = r->u_tf;
    row[2] = _IQ(0.0);
    row[3] = r->wr_f;
    r->innov[1] = rls_update_row(r, row, r->y2);
}
