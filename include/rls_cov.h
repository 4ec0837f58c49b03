/**
 * @file rls_cov.h
 * The RLS covariance P (rls.h) for a consumer outside the ISR, without its
 * representation: a copy taken in the ISR (one assignment per word, at the
 * snapshot that hands the estimate to the background) and, in the
 * background, the standard-deviation form
 *
 *     sqrt(P_ii) = sd_m_i 2^sd_e_i     (sd_m_i Q30 in [0.5, 1), or 0)
 *     rho_ij     = P_ij / sqrt(P_ii P_jj)   (Q30, clamped to [-1, 1])
 *
 * which is what the identification's confidence (ident_conf.h) needs.  The
 * copy holds today's block-floating-point form P_ij = 2^(Pe_i + Pe_j) Pn_ij
 * (rls.h, "scaling plan"); a change of that form changes this file only.
 *
 * Scaling: Pn_ii in [0.25, 1) (rls_t's invariant) so sqrt(Pn_ii) =
 * _IQ30sqrt in [0.5, 1) (<= 0.5 LSB30); rho_ij = _IQ30div(Pn_ij,
 * sd_m_i sd_m_j) with |Pn_ij| <= sqrt(Pn_ii Pn_jj) while P is positive
 * definite, so |rho| <= 1 up to rounding (clamped).  A diagonal outside
 * its band (P not positive definite: rls_t.pd_count) gives sd_m = 0 and
 * rho = 0 in that row and column: the consumer sees "no information".
 * Not for the ISR path beyond rls_cov_save.
 */
#ifndef RLS_COV_H
#define RLS_COV_H

#include <stdint.h>
#include "IQmathLib.h"
#include "rls.h"

typedef struct {
    _iq30 Pn[RLS_N][RLS_N];   /* Q30 mantissas (rls_t.Pn) */
    int16_t Pe[RLS_N];        /* exponents (rls_t.Pe) */
    _iq30 w;                  /* Q30 in [0.25, 1] (rls_t.w): P_ij = 2^(Pe_i + Pe_j) Pn_ij / w */
} rls_cov_t;

/** Copy the covariance of @p r (ISR: 20 words, no arithmetic). */
void rls_cov_save(rls_cov_t *c, const rls_t *r);

/** sqrt(P_ii) as sd_m (Q30) 2^sd_e and the correlations rho (Q30); see the
 *  file comment.  Background only (4 square roots, 6 divisions). */
void rls_cov_factor(const rls_cov_t *c, _iq30 sd_m[RLS_N], int16_t sd_e[RLS_N],
                    _iq30 rho[RLS_N][RLS_N]);

#endif /* RLS_COV_H */
