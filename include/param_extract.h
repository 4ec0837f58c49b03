/**
 * @file param_extract.h
 * Motor parameters from the RLS estimates (method §4, paper eq. 10
 * rewritten), in per unit.
 *
 * With a = -K4 / (K2 i_M) = Lm^2 / Lr (steady state: psi_r = Lm i_M; the
 * paper's assumption Ls = Lr):
 *     Ls = Lr = 1/K2 + a          Lm = sqrt(a Lr)        psi_r = Lm i_M
 *     Rr = K3' Lr / (a i_M)       Rs = -K1/K2 - K3'/i_M
 *     Tr = Lr/Rr = -K4 / (K2 K3')  (pu time: Tr_pu = Tr w_base)
 * where K3' = theta3 (paper regressor, eq. 9) or theta3/K2 (constant
 * regressor, eq. 7: theta3 = K3 = K2 K3').  The flux form (RLS_FORM_FLUX:
 * theta3, theta4 = K3, K4 at the nameplate's i_M) takes i_m as the flux's
 * m_M (pu current) and K3 = theta3 i_m / i_M,nom, K4 = theta4 i_m / i_M,nom
 * (inv_im_nom = 1 / i_M,nom; regression_bias.md §5.1 (f)).
 *
 * Never a silent wrong answer: i_M below its minimum, K2 <= 0, a quotient
 * that would overflow Q24 (division by ~0), a negative square-root argument
 * (a <= 0), K3' <= 0 (Tr undefined), or any result outside its plausibility
 * range gives a status and valid = 0 (the outputs then hold what could be
 * computed, for diagnosis only).
 *
 * Scaling and overflow of param_extract_step: Q24 throughout except Tr and
 * its range, Q20 (Tr_pu = Tr w_base reaches ~300 on motors of tens of kW:
 * Q20 holds < 2048, LSB 9.5e-7, 2e-7 of a small motor's 5 pu); divisions
 * by _IQdiv (< 1 LSB, truncating) only after checking |num| < 127 |den|
 * (Tr: _IQ20div after |num| < 2047 |den|);
 * products by _IQrsmpy (rounded, saturating) and a product >= 127 pu is
 * reported as PARAM_ERR_OVERFLOW; sqrt by _IQsqrt (<= 0.5 LSB), Lm as
 * sqrt(a) sqrt(Lr) (Lm^2 itself would leave Q24 from Lm = 11.3 pu: a small
 * motor on a high bus with sensors of several times its current).  Not in the
 * ISR (runs in the background once the RLS has converged).
 */
#ifndef PARAM_EXTRACT_H
#define PARAM_EXTRACT_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"
#include "rls.h"

/** Plausibility ranges in SI (min < max, min >= 0). */
typedef struct {
    float Rs_ohm[2];    /* {min, max} */
    float Rr_ohm[2];
    float Lm_H[2];
    float Lr_H[2];
    float psi_Wb[2];
    float Tr_s[2];
    float i_m_min_A;    /* smallest magnetising current accepted (> 0) */
} param_limits_t;

typedef enum {
    PARAM_OK = 0,
    PARAM_ERR_IM,        /* i_M below i_m_min */
    PARAM_ERR_K2,        /* K2 <= 0 or 1/K2 beyond Q24 */
    PARAM_ERR_SQRT,      /* a = Lm^2/Lr <= 0: negative square-root argument */
    PARAM_ERR_K3,        /* K3' <= 0: Rr, Tr undefined */
    PARAM_ERR_DIV,       /* another division by ~0 (quotient beyond Q24) */
    PARAM_ERR_OVERFLOW,  /* a product beyond Q24 */
    PARAM_ERR_RS,        /* result outside its range: */
    PARAM_ERR_RR,
    PARAM_ERR_LM,
    PARAM_ERR_LR,
    PARAM_ERR_PSI,
    PARAM_ERR_TR
} param_status_t;

typedef enum {
    PARAM_INIT_OK = 0,
    PARAM_INIT_ERR_BASES,   /* bases not initialised (Z, L, psi, t base not > 0) */
    PARAM_INIT_ERR_RANGE,   /* a range with min < 0, min >= max, or max >= 127 pu
                               (Tr: 2047 pu) */
    PARAM_INIT_ERR_IM       /* i_m_min_A not > 0 or >= 127 pu */
} param_init_status_t;

typedef struct {
    /* inputs */
    _iq theta[RLS_N];   /* Q24 pu: K1, K2, theta3, K4 (rls_t.theta) */
    uint16_t form;      /* rls_form_t that produced theta3 */
    _iq i_m;            /* Q24 pu: steady M current (RLS_FORM_FLUX: the flux's m_M) */
    _iq inv_im_nom;     /* Q24 1/pu: RLS_FORM_FLUX only, 1 / the nameplate's i_M (<= 20) */
    /* parameters (pu, Q24; Tr_lim Q20, pu time) */
    _iq Rs_lim[2], Rr_lim[2], Lm_lim[2], Lr_lim[2], psi_lim[2];
    _iq20 Tr_lim[2];
    _iq i_m_min;
    /* outputs (pu, Q24) */
    _iq Rs, Rr, Lm, Lr, psi_r;
    _iq20 Tr;           /* Q20 (range 2048), pu time */
    _iq K3p;            /* Q24: K3' used */
    uint16_t status;    /* param_status_t */
    uint16_t valid;     /* 1 only if status == PARAM_OK */
} param_extract_t;

/** The largest pu value of a range held in Q24 (Q24 holds < 128). */
#define PARAM_EXTRACT_PU_MAX 127.0f
/** param_extract_init's check of its arguments alone (no struct), the
 *  status it would return: _ERR_BASES, then _ERR_RANGE for the first range
 *  (Rs, Rr, Lm, Lr, psi, Tr, in param_limits_t's order) that is not
 *  0 <= min < max < PARAM_EXTRACT_PU_MAX pu (Tr: 2047 pu), naming it in
 *  @p bad (PARAM_ERR_RS .. PARAM_ERR_TR; PARAM_OK otherwise; may be NULL),
 *  then _ERR_IM.  The configuration's table of limits calls it too
 *  (drive_limits.c).  Float: init only. */
param_init_status_t param_extract_check(const base_values_t *b, const param_limits_t *lim,
                                        param_status_t *bad);

/** Convert the SI ranges with the bases.  On error the struct is zeroed
 *  (valid = 0). */
param_init_status_t param_extract_init(param_extract_t *p, const base_values_t *b,
                                       const param_limits_t *lim);

/** Compute the parameters and check them.  See the file comment. */
void param_extract_step(param_extract_t *p);

/**
 * The magnetic part only (the adaptive sequence's fused mode): Lr = Ls, Lm, psi_r from K2,
 * K4 and i_M (a = -K4/(K2 i_M), as param_extract_step), each checked
 * against its range; K1 and theta3 are not used, Rs, Rr, Tr and K3p are set
 * to 0.  Same status codes (PARAM_ERR_IM, _K2, _DIV, _SQRT, _OVERFLOW,
 * _LM, _LR, _PSI); valid = 1 only if all three are plausible.
 */
void param_extract_magnetic(param_extract_t *p);

#endif /* PARAM_EXTRACT_H */
