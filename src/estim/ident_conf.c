/* The identification's confidence from its data.  See ident_conf.h. */
#include "ident_conf.h"

#include <string.h>

#include "estim_bfp.h"

#if RLS_N != 4
#error "ident_conf.c writes the 4 columns out"
#endif

/* ------------------------------- accumulation (with each RLS update) */

void ident_conf_acc_reset(ident_conf_acc_t *a)
{
    a->J = _IQ(0.0);
    a->J_res = _IQ(0.0);
    a->Y = _IQ(0.0);
    a->n = 0u;
    a->sat = 0u;
}

/* x clamped to [-lim, lim] (counted) */
static _iq conf_clamp(_iq x, _iq lim, uint32_t *sat)
{
    if (x > lim) {
        estim_count(sat);
        return lim;
    }
    if (x < -lim) {
        estim_count(sat);
        return -lim;
    }
    return x;
}

void ident_conf_acc_step(ident_conf_acc_t *a, const rls_t *r)
{
    /* clamps by _IQsat (not counted: the bounds are the RLS's own input
     * ranges, which its update enforces too) */
    const _iq phi_max = _IQ(RLS_PHI_MAX);
    const _iq22 eps_max = _IQ22(0.7);     /* eps1^2 + eps2^2 < 1: one Q31 term */
    _iq c, c2, d1, y1, y2;
    _iq22 e1, e2;
    _iq s1, s2;

    if (r->enable == 0u) {
        return;
    }
    /* the RLS's third regressor: 1, or K2 (paper form; the updated one), or
     * the flux form's m_Mf, with its fourth column in row 1 (rls.h) */
    c = (r->form == (uint16_t)RLS_FORM_PAPER) ? r->theta[1] : _IQ(1.0);
    c2 = _IQ(0.0);
    d1 = _IQ(0.0);
    if (r->form == (uint16_t)RLS_FORM_FLUX) {
        c = _IQsat(r->c1, phi_max, -phi_max);
        c2 = _IQsat(r->c2, phi_max, -phi_max);
        d1 = _IQsat(r->d1, phi_max, -phi_max);
    }
    y1 = _IQsat(r->y1, _IQ(64.0), -_IQ(64.0));
    y2 = _IQsat(r->y2, _IQ(64.0), -_IQ(64.0));
    /* a-posteriori residuals in Q22 (Q24 * Q24 >> 26): |y| < 64 and four
     * |phi theta| < 4 * 16: |sum| < 320, inside Q22's 512 */
    e1 = _IQtoIQ22(y1) - _IQ26mpy(_IQsat(r->i_mf, phi_max, -phi_max), r->theta[0]) -
         _IQ26mpy(_IQsat(r->u_mf, phi_max, -phi_max), r->theta[1]) - _IQ26mpy(c, r->theta[2]) -
         _IQ26mpy(d1, r->theta[3]);
    e2 = _IQtoIQ22(y2) - _IQ26mpy(_IQsat(r->i_tf, phi_max, -phi_max), r->theta[0]) -
         _IQ26mpy(_IQsat(r->u_tf, phi_max, -phi_max), r->theta[1]) - _IQ26mpy(c2, r->theta[2]) -
         _IQ26mpy(_IQsat(r->wr_f, phi_max, -phi_max), r->theta[3]);
    e1 = _IQsat(e1, eps_max, -eps_max);
    e2 = _IQsat(e2, eps_max, -eps_max);
    /* eps^2 in Q31 (Q22 * Q22 >> 13), the sum < 0.98 */
    estim_accumulate(&a->J, _IQ13mpy(e1, e1) + _IQ13mpy(e2, e2), 0, 31, &a->J_res, &a->sat);
    /* (y / 16)^2 in Q24 with |y| <= 8: each term <= 0.25 */
    s1 = _IQmpy(_IQsat(y1, _IQ(8.0), -_IQ(8.0)), _IQ(0.0625));
    s2 = _IQmpy(_IQsat(y2, _IQ(8.0), -_IQ(8.0)), _IQ(0.0625));
    a->Y = estim_add_sat(a->Y, _IQmpy(s1, s1) + _IQmpy(s2, s2), &a->sat);
    a->n++;   /* < 2^32: 3.2 days of RLS samples at 15 kHz */
}

/* ------------------------------------------------------------ background */

/* A non-negative value m 2^e, m in [0.5, 1) (Q30), or m = 0 for zero. */
typedef struct {
    _iq30 m;
    int16_t e;
} bf_t;

static const bf_t bf_zero = {0, 0};

/* m in (0, 2) Q30 into [0.5, 1) */
static bf_t bf_norm(_iq30 m, int16_t e)
{
    bf_t r;
    if (!(m > _IQ30(0.0))) {
        return bf_zero;
    }
    while (m >= _IQ30(1.0)) {
        m = estim_ldexp(m, -1, 30, 30, NULL);
        e = (int16_t)(e + 1);
    }
    while (m < _IQ30(0.5)) {
        m = estim_ldexp(m, 1, 30, 30, NULL);
        e = (int16_t)(e - 1);
    }
    r.m = m;
    r.e = e;
    return r;
}

/* x >= 0 in Q(q) */
static bf_t bf_from(_iq x, int16_t q)
{
    int16_t e = estim_exponent(x, q);    /* |x| < 2^e */
    if (!(x > 0) || e == ESTIM_EXP_ZERO) {
        return bf_zero;
    }
    return bf_norm(estim_ldexp(x, (int16_t)-e, q, 30, NULL), e);
}

static bf_t bf_mul(bf_t a, bf_t b)
{
    if (a.m == 0 || b.m == 0) {
        return bf_zero;
    }
    return bf_norm(_IQ30mpy(a.m, b.m), (int16_t)(a.e + b.e));   /* [0.25, 1) */
}

/* a / b; b == 0 gives a huge value (2^100), which saturates downstream */
static bf_t bf_div(bf_t a, bf_t b)
{
    bf_t r;
    if (a.m == 0) {
        return bf_zero;
    }
    if (b.m == 0) {
        r.m = _IQ30(0.5);
        r.e = 100;
        return r;
    }
    return bf_norm(_IQ30div(a.m, b.m), (int16_t)(a.e - b.e));    /* (0.5, 2) */
}

static bf_t bf_sqrt(bf_t a)
{
    _iq30 m = a.m;
    int16_t e = a.e;
    if (m == 0) {
        return bf_zero;
    }
    if ((e & 1) != 0) {
        m = estim_ldexp(m, -1, 30, 30, NULL);   /* [0.25, 0.5) */
        e = (int16_t)(e + 1);
    }
    return bf_norm(_IQ30sqrt(m), (int16_t)(e / 2));           /* [0.5, 1) */
}

static int16_t bf_greater(bf_t a, bf_t b)
{
    if (a.m == 0 || b.m == 0) {
        return (int16_t)(a.m != 0 && b.m == 0);
    }
    return (int16_t)(a.e > b.e || (a.e == b.e && a.m > b.m));
}

/* Q24, saturated at IDENT_CONF_MAX (counted) */
static _iq bf_to_q24(bf_t a, uint32_t *sat)
{
    if (a.m == 0) {
        return _IQ(0.0);
    }
    if (a.e > 7) {                       /* >= 64: compare against the limit */
        if (a.e > 8 || a.m >= _IQ30(IDENT_CONF_MAX / 256.0f)) {
            estim_count(sat);
            return _IQ(IDENT_CONF_MAX);
        }
    }
    return estim_ldexp(a.m, a.e, 30, 24, sat);
}

/* a value of Q24 given as a non-negative bf: sign apart */
static _iq q24_abs(_iq x) { return (x < 0) ? -x : x; }

ident_conf_init_status_t ident_conf_init(ident_conf_t *c, float conf_max, float res_ref,
                                         float exc_ref, float y_ref)
{
    memset(c, 0, sizeof *c);
    if (!(conf_max > 0.0f && conf_max < IDENT_CONF_MAX) ||
        !(res_ref > 0.0f && res_ref < IDENT_CONF_MAX) ||
        !(exc_ref > 0.0f && exc_ref < IDENT_CONF_MAX) ||
        !(y_ref > 1e-6f && y_ref < IDENT_CONF_MAX)) {
        return IDENT_CONF_INIT_ERR_LIMIT;
    }
    c->conf_max = _IQ(conf_max);
    c->res_ref = _IQ(res_ref);
    c->exc_ref = _IQ(exc_ref);
    c->y_ref = _IQ(y_ref);
    c->mask = IDENT_MASK_ALL;
    return IDENT_CONF_INIT_OK;
}

/* Elasticities e[i] = d ln p / d ln |theta_i| (Q24) of parameter @p which
 * (ident_param_t) by method §4's formulas at the final estimate; returns 0
 * if the extraction does not give them (the magnetic part alone has no Rs,
 * Rr, Tr).  With a = Lm^2/Lr, q2 = a/Lr = (Lm/Lr)^2 and g = (K3'/i_M)/Rs,
 * derivatives with respect to (K1, K2, K3', K4), K3' held:
 *     Rs = |K1|/K2 - K3'/i_M          [1+g, -(1+g), -g, 0]
 *     Rr = K3' Lr / (a i_M)           [0, 0, 1, q2 - 1]
 *     Lm = sqrt(a Lr), psi_r = Lm i_M [0, -1, 0, (1 + q2)/2]
 *     Lr = 1/K2 + a                   [0, -1, 0, q2]
 *     Tr = |K4| / (K2 K3')            [0, -1, -1, 1]
 * (a = |K4|/(K2 i_M): d ln a = d ln|K4| - d ln K2; d ln Lr = -d ln K2 +
 * q2 d ln|K4|.)  The constant regressor (eq. 7) estimates theta3 = K3 =
 * K2 K3': d ln K3' = d ln theta3 - d ln K2, so the K2 column becomes
 * e_K2 - e_K3'. */
static uint16_t elasticities(const param_extract_t *p, uint16_t which, _iq e[RLS_N])
{
    _iq q2;
    uint16_t i;

    for (i = 0u; i < RLS_N; i++) {
        e[i] = _IQ(0.0);
    }
    if (!(p->Lr > _IQ(0.0)) || !(p->Lm > _IQ(0.0)) || p->Lm >= _IQmpy(p->Lr, _IQ(2.0))) {
        return 0u;
    }
    q2 = _IQdiv(p->Lm, p->Lr);               /* < 2 */
    q2 = _IQmpy(q2, q2);                     /* < 4 */
    switch (which) {
    case IDENT_P_LM:
    case IDENT_P_PSI:
        e[1] = -_IQ(1.0);
        e[3] = _IQmpy(_IQ(1.0) + q2, _IQ(0.5));
        break;
    case IDENT_P_LR:
        e[1] = -_IQ(1.0);
        e[3] = q2;
        break;
    default:
        if (!(p->K3p > _IQ(0.0) && p->Rs > _IQ(0.0) && p->i_m > _IQ(0.0))) {
            return 0u;
        }
        if (which == IDENT_P_RS) {
            _iq k3im = _IQdiv(p->K3p, p->i_m);
            /* g < 64: K3'/i_M ~ Rr Lm^2/Lr^2, a factor of a few of Rs */
            _iq g = (k3im < _IQmpy(p->Rs, _IQ(64.0))) ? _IQdiv(k3im, p->Rs) : _IQ(64.0);
            e[0] = _IQ(1.0) + g;
            e[1] = -(_IQ(1.0) + g);
            e[2] = -g;
        } else if (which == IDENT_P_RR) {
            e[2] = _IQ(1.0);
            e[3] = q2 - _IQ(1.0);
        } else {
            e[1] = -_IQ(1.0);
            e[2] = -_IQ(1.0);
            e[3] = _IQ(1.0);
        }
        break;
    }
    if (p->form != (uint16_t)RLS_FORM_PAPER) {
        e[1] = e[1] - e[2];
    }
    return 1u;
}

static _iq param_value(const param_extract_t *p, uint16_t i)
{
    switch (i) {
    case IDENT_P_RS: return p->Rs;
    case IDENT_P_RR: return p->Rr;
    case IDENT_P_LM: return p->Lm;
    case IDENT_P_LR: return p->Lr;
    case IDENT_P_PSI: return p->psi_r;
    case IDENT_P_TR:
    default: return p->Tr;
    }
}

/* |a - b| / |a|, saturated at IDENT_CONF_MAX */
static _iq rel_diff(_iq a, _iq b, uint32_t *sat)
{
    _iq d = q24_abs(a - b);   /* both in (0, 128): |a - b| < 128, no overflow */
    _iq m = q24_abs(a);
    _iq r;
    /* below 1 pu the product m x 100 stays inside Q24; from 1 pu on the
     * quotient is below 128 */
    if (!(m > _IQ(0.0)) || (m < _IQ(1.0) && d >= _IQmpy(m, _IQ(IDENT_CONF_MAX)))) {
        estim_count(sat);
        return _IQ(IDENT_CONF_MAX);
    }
    r = _IQdiv(d, m);
    if (r > _IQ(IDENT_CONF_MAX)) {
        estim_count(sat);
        r = _IQ(IDENT_CONF_MAX);
    }
    return r;
}

_iq ident_conf_rel_change(_iq a, _iq b)
{
    uint32_t sat = 0u;
    return rel_diff(a, b, &sat);
}

/* sqrt(u' (rho o s s') u), u_i = e_i kb_i with the signs of theta (s):
 * the relative bound of one parameter.  Normalised by the largest |u_i|
 * so that the quadratic form keeps its precision (Q30 terms, Q26 sum). */
static bf_t quad_bound(const _iq e[RLS_N], const bf_t kb[RLS_N], const int16_t sgn[RLS_N],
                       _iq30 rho[RLS_N][RLS_N])
{
    bf_t u[RLS_N], umax = bf_zero;
    _iq30 v[RLS_N];
    _iq26 q = _IQ26(0.0);
    uint16_t i, j;

    for (i = 0u; i < RLS_N; i++) {
        u[i] = bf_mul(bf_from(q24_abs(e[i]), 24), kb[i]);
        if (bf_greater(u[i], umax) != 0) {
            umax = u[i];
        }
    }
    if (umax.m == 0) {
        return bf_zero;
    }
    for (i = 0u; i < RLS_N; i++) {
        bf_t w = bf_div(u[i], umax);                          /* <= 1 */
        _iq30 x = (w.m == 0) ? _IQ30(0.0) : estim_ldexp(w.m, w.e, 30, 30, NULL);
        /* the sign of the term: of e_i and of theta_i */
        v[i] = ((e[i] < 0) != (sgn[i] < 0)) ? -x : x;
    }
    for (i = 0u; i < RLS_N; i++) {
        for (j = 0u; j < RLS_N; j++) {
            _iq30 t = _IQ30mpy(_IQ30mpy(v[i], v[j]), rho[i][j]);   /* |t| <= 1 */
            q += estim_ldexp(t, 0, 30, 26, NULL);                  /* |q| <= 16 */
        }
    }
    if (!(q > _IQ26(0.0))) {
        return bf_zero;
    }
    return bf_mul(umax, bf_from(_IQ26sqrt(q), 26));
}

void ident_conf_eval(ident_conf_t *c, const rls_cov_t *cov, const ident_conf_acc_t *acc,
                     uint32_t pd, const param_extract_t *end, const param_extract_t *mid)
{
    _iq30 sd_m[RLS_N], rho[RLS_N][RLS_N];
    int16_t sd_e[RLS_N], sgn[RLS_N];
    _iq e[RLS_N];
    bf_t J, Y, res, sJ, kb[RLS_N];
    uint16_t i, judged = 0u;
    _iq worst = _IQ(-1.0);

    for (i = 0u; i < IDENT_NP; i++) {
        c->bound[i] = _IQ(0.0);
        c->drift[i] = _IQ(0.0);
        c->conf[i] = _IQ(0.0);
    }
    c->residual = _IQ(0.0);
    c->amp = _IQ(0.0);
    c->excitation = _IQ(0.0);
    c->worst = 0u;
    c->sat = 0u;
    if (acc->n == 0u) {
        c->verdict = (uint16_t)IDENT_CONF_NO_DATA;
        return;
    }
    /* J (with its residue when J itself is below an LSB) and Y = 256 Y24 */
    J = bf_from(acc->J, 24);
    if (J.m == 0) {
        J = bf_from(acc->J_res, 48);
    }
    Y = bf_from(acc->Y, 24);
    Y.e = (int16_t)(Y.e + 8);
    res = bf_sqrt(bf_div(J, Y));
    c->residual = bf_to_q24(res, &c->sat);
    sJ = bf_sqrt(J);
    {
        /* sqrt(Y / 2n) / y_ref: the count as a Q0 value (below 2^31), doubled */
        bf_t n2 = bf_from((_iq)((acc->n < 0x7FFFFFFFu) ? acc->n : 0x7FFFFFFFu), 0);
        n2.e = (int16_t)(n2.e + 1);
        c->excitation = bf_to_q24(bf_div(bf_sqrt(bf_div(Y, n2)), bf_from(c->y_ref, 24)),
                                  &c->sat);
    }

    /* relative bound of each theta_i: sqrt(J P_ii) / |theta_i| */
    rls_cov_factor(cov, sd_m, sd_e, rho);
    for (i = 0u; i < RLS_N; i++) {
        _iq th = end->theta[i];
        bf_t sd;
        sgn[i] = (int16_t)((th < 0) ? -1 : 1);
        sd.m = sd_m[i];
        sd.e = sd_e[i];
        if (sd.m == 0 || pd != 0u) {
            /* no information along theta_i (P not positive definite), or P
             * repaired (rls.h: it no longer describes the data): the
             * largest bound */
            kb[i].m = _IQ30(0.5);
            kb[i].e = 100;
        } else {
            kb[i] = bf_div(bf_mul(sJ, sd), bf_from(q24_abs(th), 24));
        }
    }

    for (i = 0u; i < IDENT_NP; i++) {
        bf_t b;
        if (elasticities(end, i, e) == 0u) {
            continue;
        }
        b = quad_bound(e, kb, sgn, rho);
        c->bound[i] = bf_to_q24(b, &c->sat);
        if ((c->mask & (uint16_t)(1u << i)) == 0u) {
            continue;
        }
        judged = (uint16_t)(judged | (1u << i));
        {
            _iq amp = bf_to_q24(bf_div(b, res), &c->sat);
            if (amp > c->amp) {
                c->amp = amp;
            }
        }
        if (mid != NULL) {
            c->drift[i] = (mid->valid != 0u)
                              ? rel_diff(param_value(end, i), param_value(mid, i), &c->sat)
                              : _IQ(IDENT_CONF_MAX);
        }
        /* two separate figures: what a residual-sized error can do, and how far
         * the estimate still moved; both < 100, the sum < 128 */
        c->conf[i] = c->bound[i] + c->drift[i];
        if (c->conf[i] > _IQ(IDENT_CONF_MAX)) {
            c->conf[i] = _IQ(IDENT_CONF_MAX);
        }
        if (c->conf[i] > worst) {
            worst = c->conf[i];
            c->worst = i;
        }
    }
    if (judged == 0u) {
        c->verdict = (uint16_t)IDENT_CONF_NO_DATA;   /* nothing could be judged */
    } else if (worst <= c->conf_max) {
        c->verdict = (uint16_t)IDENT_CONF_OK;
    } else if (c->excitation < c->exc_ref) {
        c->verdict = (uint16_t)IDENT_CONF_LOW_EXCITATION;
    } else if (c->residual > c->res_ref) {
        c->verdict = (uint16_t)IDENT_CONF_HIGH_RESIDUAL;
    } else if (c->drift[c->worst] > c->bound[c->worst]) {
        c->verdict = (uint16_t)IDENT_CONF_NOT_CONVERGED;
    } else {
        c->verdict = (uint16_t)IDENT_CONF_LOW_CONFIDENCE;
    }
}

/* ------------------------------------------------------ one-parameter fit */

void ident_conf_fit_reset(ident_conf_fit_t *f)
{
    memset(f, 0, sizeof *f);
}

void ident_conf_fit_add(ident_conf_fit_t *f, _iq y, _iq phi, _iq theta)
{
    /* |theta phi| <= 4 and |y - theta phi| <= 4 after the clamps: squares < 16 */
    _iq p = conf_clamp(_IQmpy(conf_clamp(theta, _IQ(32.0), &f->sat),
                              conf_clamp(phi, _IQ(2.0), &f->sat)), _IQ(4.0), &f->sat);
    /* the residual clamped below 1 so that its square is a Q31 value (Q24 *
     * Q24 >> 17): kept to 2^-31, not 2^-24 (a residual of 1e-3 squared is
     * 17 LSB24) */
    _iq e = conf_clamp(conf_clamp(y, _IQ(64.0), &f->sat) - p, _IQ(0.99), &f->sat);
    estim_accumulate(&f->J, _IQ17mpy(e, e), 0, 31, &f->J_res, &f->sat);
    estim_accumulate(&f->S, _IQmpy(p, p), 0, 24, &f->S_res, &f->sat);
    if (f->n < 0xFFFFFFFFu) {
        f->n++;
    }
}

_iq ident_conf_fit_bound(const ident_conf_fit_t *f)
{
    uint32_t sat = 0u;
    bf_t J = bf_from(f->J, 24), S = bf_from(f->S, 24);
    if (J.m == 0) {
        J = bf_from(f->J_res, 48);
    }
    if (S.m == 0) {
        return _IQ(IDENT_CONF_MAX);
    }
    return bf_to_q24(bf_sqrt(bf_div(J, S)), &sat);
}
