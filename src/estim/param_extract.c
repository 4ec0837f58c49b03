/* Motor parameters from the regression estimates (method §4, eq. 10
 * rewritten).  See param_extract.h. */
#include "param_extract.h"

#include <math.h>
#include <string.h>

#define PE_Q24_MAX PARAM_EXTRACT_PU_MAX
#define PE_Q20_MAX 2047.0f  /* largest Tr accepted, pu time (Q20 holds < 2048) */

/* v (|v| below the Q's range) to Q q, rounded to nearest; the float as is */
static _iq pe_qn(float v, float two_q)
{
#if MATH_TYPE == IQ_MATH
    return (_iq)(int32_t)roundf(v * two_q);
#else
    (void)two_q;
    return v;
#endif
}

static _iq pe_q24(float v)
{
    return pe_qn(v, 16777216.0f);
}

/* 1 if the SI range @p si = {lo, hi} on @p base is 0 <= lo < hi < @p max in pu */
static int16_t pe_range_ok(const float si[2], float base, float max)
{
    float lo = si[0] / base, hi = si[1] / base;
    return (int16_t)(lo >= 0.0f && hi > lo && hi < max);
}

/* An SI range (checked) in pu, in Q (2^q = two_q). */
static void pe_range_q(_iq out[2], const float si[2], float base, float two_q)
{
    out[0] = pe_qn(si[0] / base, two_q);
    out[1] = pe_qn(si[1] / base, two_q);
}

param_init_status_t param_extract_check(const base_values_t *b, const param_limits_t *lim,
                                        param_status_t *bad)
{
    param_status_t which = PARAM_OK;
    float im;

    if (bad != NULL) {
        *bad = PARAM_OK;
    }
    if (!(b->Z_base_ohm > 0.0f) || !(b->L_base_H > 0.0f) || !(b->psi_base_Wb > 0.0f)
        || !(b->t_base_s > 0.0f) || !(b->I_base_A > 0.0f)) {
        return PARAM_INIT_ERR_BASES;
    }
    if (pe_range_ok(lim->Rs_ohm, b->Z_base_ohm, PE_Q24_MAX) == 0) {
        which = PARAM_ERR_RS;
    } else if (pe_range_ok(lim->Rr_ohm, b->Z_base_ohm, PE_Q24_MAX) == 0) {
        which = PARAM_ERR_RR;
    } else if (pe_range_ok(lim->Lm_H, b->L_base_H, PE_Q24_MAX) == 0) {
        which = PARAM_ERR_LM;
    } else if (pe_range_ok(lim->Lr_H, b->L_base_H, PE_Q24_MAX) == 0) {
        which = PARAM_ERR_LR;
    } else if (pe_range_ok(lim->psi_Wb, b->psi_base_Wb, PE_Q24_MAX) == 0) {
        which = PARAM_ERR_PSI;
    } else if (pe_range_ok(lim->Tr_s, b->t_base_s, PE_Q20_MAX) == 0) {
        which = PARAM_ERR_TR;
    }
    if (which != PARAM_OK) {
        if (bad != NULL) {
            *bad = which;
        }
        return PARAM_INIT_ERR_RANGE;
    }
    im = lim->i_m_min_A / b->I_base_A;
    if (!(im > 0.0f) || !(im < PE_Q24_MAX)) {
        return PARAM_INIT_ERR_IM;
    }
    return PARAM_INIT_OK;
}

param_init_status_t param_extract_init(param_extract_t *p, const base_values_t *b,
                                       const param_limits_t *lim)
{
    param_init_status_t st;
    memset(p, 0, sizeof *p);
    st = param_extract_check(b, lim, NULL);
    if (st != PARAM_INIT_OK) {
        return st;
    }
    pe_range_q(p->Rs_lim, lim->Rs_ohm, b->Z_base_ohm, 16777216.0f);
    pe_range_q(p->Rr_lim, lim->Rr_ohm, b->Z_base_ohm, 16777216.0f);
    pe_range_q(p->Lm_lim, lim->Lm_H, b->L_base_H, 16777216.0f);
    pe_range_q(p->Lr_lim, lim->Lr_H, b->L_base_H, 16777216.0f);
    pe_range_q(p->psi_lim, lim->psi_Wb, b->psi_base_Wb, 16777216.0f);
    pe_range_q(p->Tr_lim, lim->Tr_s, b->t_base_s, 1048576.0f);
    p->i_m_min = pe_q24(lim->i_m_min_A / b->I_base_A);
    p->status = (uint16_t)PARAM_ERR_IM;     /* nothing computed yet */
    return PARAM_INIT_OK;
}

/* Whether num/den fits a quotient range of 1/inv_max (Q24): 0, with status
 * `code`, if |num| >= |den| / inv_max (including den = 0), or if an earlier
 * step failed.  |num| < 128, so |num| inv_max cannot overflow. */
static int16_t pe_div_ok(_iq num, _iq den, _iq inv_max, param_status_t code, param_status_t *st)
{
    if (*st != PARAM_OK) {
        return 0;
    }
    if (_IQabs(den) <= _IQmpy(_IQabs(num), inv_max)) {   /* Q24*Q24 -> Q24 */
        *st = code;
        return 0;
    }
    return 1;
}

/* num/den in Q24 (_IQdiv, truncated, < 1 LSB) if |num| < 127 |den|, else 0
 * and status `code`. */
static _iq pe_div(_iq num, _iq den, param_status_t code, param_status_t *st)
{
    return (pe_div_ok(num, den, _IQ(1.0 / 127.0), code, st) != 0) ? _IQdiv(num, den) : _IQ(0.0);
}

/* num/den in Q20 (Q24 / Q24 -> Q20 by _IQ20div, truncated, < 1 LSB) if
 * |num| < 2047 |den|, else 0 and status `code`: for Tr, which exceeds Q24's
 * 128 pu on large motors. */
static _iq20 pe_div20(_iq num, _iq den, param_status_t code, param_status_t *st)
{
    return (pe_div_ok(num, den, _IQ(1.0 / 2047.0), code, st) != 0) ? _IQ20div(num, den)
                                                                   : _IQ20(0.0);
}

/* a*b rounded and saturated; a result of 127 pu or more is an overflow. */
static _iq pe_mul(_iq a, _iq b, param_status_t *st)
{
    _iq r = _IQrsmpy(a, b);                                        /* Q24*Q24 -> Q24 */
    if (*st == PARAM_OK && _IQabs(r) >= _IQ(PE_Q24_MAX)) {
        *st = PARAM_ERR_OVERFLOW;
    }
    return r;
}

static void pe_check(_iq v, const _iq lim[2], param_status_t code, param_status_t *st)
{
    if (*st == PARAM_OK && (v < lim[0] || v > lim[1])) {
        *st = code;
    }
}

/* Lm = sqrt(a Lr) as sqrt(a) sqrt(Lr): a Lr = Lm^2 leaves Q24 from Lm =
 * 11.3 pu (a 0.2 kW 400 V motor on its 566 V bus with 5 A sensors: Lm
 * 11.8 pu, refused as an overflow), each root stays below 11.3 and their
 * product below 127.  Both arguments > 0 here. */
static _iq pe_lm(_iq a, _iq lr, param_status_t *st)
{
    return pe_mul(_IQsqrt(a), _IQsqrt(lr), st);
}

/* The flux form's K3, K4 are at the nameplate's i_M: the factor that takes
 * them to the flux i_m, m_M / i_M,nom (rls.h RLS_FORM_FLUX;
 * regression_bias.md §5.1 (f)). */
static _iq pe_flux_ratio(const param_extract_t *p, param_status_t *st)
{
    return pe_mul(p->i_m, p->inv_im_nom, st);
}

void param_extract_step(param_extract_t *p)
{
    param_status_t st = PARAM_OK;
    _iq K1 = p->theta[0], K2 = p->theta[1], K3 = p->theta[2], K4 = p->theta[3];
    _iq inv_k2, a, k2im;

    p->Rs = _IQ(0.0); p->Rr = _IQ(0.0); p->Lm = _IQ(0.0);
    p->Lr = _IQ(0.0); p->psi_r = _IQ(0.0); p->Tr = _IQ20(0.0); p->K3p = _IQ(0.0);

    if (p->i_m < p->i_m_min) {
        st = PARAM_ERR_IM;
    }
    if (st == PARAM_OK && K2 <= _IQ(0.0)) {
        st = PARAM_ERR_K2;                  /* K2 = 1/(sigma Ls) > 0 */
    }
    inv_k2 = pe_div(_IQ(1.0), K2, PARAM_ERR_K2, &st);
    if (p->form == (uint16_t)RLS_FORM_FLUX) {
        const _iq ratio = pe_flux_ratio(p, &st);
        K3 = pe_mul(K3, ratio, &st);
        K4 = pe_mul(K4, ratio, &st);
    }
    /* K3' = K3/K2 for the constant regressor (eq. 7 vs eq. 9) */
    p->K3p = (p->form == (uint16_t)RLS_FORM_PAPER) ? p->theta[2]
                                                   : pe_div(K3, K2, PARAM_ERR_DIV, &st);
    if (st == PARAM_OK && p->K3p <= _IQ(0.0)) {
        st = PARAM_ERR_K3;                  /* K3' = Lm Rr psi_r / Lr^2 > 0 */
    }
    k2im = pe_mul(K2, p->i_m, &st);
    a = pe_div(-K4, k2im, PARAM_ERR_DIV, &st);          /* a = Lm^2/Lr */
    if (st == PARAM_OK && a <= _IQ(0.0)) {
        st = PARAM_ERR_SQRT;                /* Lm = sqrt(a Lr) needs a > 0 */
    }
    if (st == PARAM_OK) {
        _iq lr = inv_k2 + a;                /* both < 127, > 0: no overflow of the sum */
        p->Lr = lr;
        p->Lm = pe_lm(a, lr, &st);
        p->psi_r = pe_mul(p->Lm, p->i_m, &st);
        p->Rr = pe_div(pe_mul(p->K3p, lr, &st), pe_mul(a, p->i_m, &st), PARAM_ERR_DIV, &st);
        {
            _iq k1k2 = pe_div(K1, K2, PARAM_ERR_DIV, &st);
            _iq k3im = pe_div(p->K3p, p->i_m, PARAM_ERR_DIV, &st);
            p->Rs = -k1k2 - k3im;           /* each < 127 in magnitude */
        }
        /* Q24 / Q24 -> Q20: Tr_pu reaches ~300 on motors of tens of kW */
        p->Tr = pe_div20(-K4, pe_mul(K2, p->K3p, &st), PARAM_ERR_DIV, &st);
    }
    pe_check(p->Rs, p->Rs_lim, PARAM_ERR_RS, &st);
    pe_check(p->Rr, p->Rr_lim, PARAM_ERR_RR, &st);
    pe_check(p->Lm, p->Lm_lim, PARAM_ERR_LM, &st);
    pe_check(p->Lr, p->Lr_lim, PARAM_ERR_LR, &st);
    pe_check(p->psi_r, p->psi_lim, PARAM_ERR_PSI, &st);
    pe_check(p->Tr, p->Tr_lim, PARAM_ERR_TR, &st);
    p->status = (uint16_t)st;
    p->valid = (st == PARAM_OK) ? 1u : 0u;
}

void param_extract_magnetic(param_extract_t *p)
{
    param_status_t st = PARAM_OK;
    _iq K2 = p->theta[1], K4 = p->theta[3];
    _iq inv_k2, a;

    p->Rs = _IQ(0.0); p->Rr = _IQ(0.0); p->Lm = _IQ(0.0);
    p->Lr = _IQ(0.0); p->psi_r = _IQ(0.0); p->Tr = _IQ20(0.0); p->K3p = _IQ(0.0);
    if (p->i_m < p->i_m_min) {
        st = PARAM_ERR_IM;
    }
    if (st == PARAM_OK && K2 <= _IQ(0.0)) {
        st = PARAM_ERR_K2;
    }
    inv_k2 = pe_div(_IQ(1.0), K2, PARAM_ERR_K2, &st);
    if (p->form == (uint16_t)RLS_FORM_FLUX) {
        K4 = pe_mul(K4, pe_flux_ratio(p, &st), &st);
    }
    a = pe_div(-K4, pe_mul(K2, p->i_m, &st), PARAM_ERR_DIV, &st);
    if (st == PARAM_OK && a <= _IQ(0.0)) {
        st = PARAM_ERR_SQRT;
    }
    if (st == PARAM_OK) {
        _iq lr = inv_k2 + a;
        p->Lr = lr;
        p->Lm = pe_lm(a, lr, &st);
        p->psi_r = pe_mul(p->Lm, p->i_m, &st);
    }
    pe_check(p->Lm, p->Lm_lim, PARAM_ERR_LM, &st);
    pe_check(p->Lr, p->Lr_lim, PARAM_ERR_LR, &st);
    pe_check(p->psi_r, p->psi_lim, PARAM_ERR_PSI, &st);
    p->status = (uint16_t)st;
    p->valid = (st == PARAM_OK) ? 1u : 0u;
}
