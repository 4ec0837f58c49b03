/**
 * @file rls.h
 * Recursive least squares for the four regression parameters (method §3,
 * paper eq. 1), in fixed point with a block-floating-point covariance.
 *
 * Model (method §2, eqs. 3-9), two rows per sample:
 *     y1 = [i_Mf, u_Mf, c,  0   ] theta
 *     y2 = [i_Tf, u_Tf, 0,  wr_f] theta,   theta = [K1, K2, theta3, K4] (pu)
 * Third regressor c (rls_form_t):
 *   RLS_FORM_CONST   c = 1 pu, theta3 = K3_pu (eq. 7)
 *   RLS_FORM_PAPER   c = previous estimate of K2 (theta2 before this
 *                    sample's update), theta3 = K3'_pu = K3/K2 (eqs. 8-9)
 * Default: RLS_FORM_CONST (method §7 point 3: the paper's regressor is
 * poisoned by the early K2 estimates; measured again in tests/estim).
 *
 * Per enabled sample (rls_step):
 *   1. forgetting, once per sample: P <- P / lambda, unless that would make
 *      trace(P) exceed trace_max (wind-up guard: with poor excitation P
 *      grows as lambda^-k in the unexcited directions; the guard holds the
 *      trace at its bound and `windup_hold` says so).  Dividing once and
 *      then doing the two rows is the block (2-row) RLS with forgetting
 *      lambda per sample, i.e. it minimises sum lambda^(k-i) (e1^2 + e2^2).
 *   2. row 1, then row 2, as two sequential scalar updates (eq. 1):
 *         s = 1 + phi' P phi,   K = P phi / s,
 *         theta += K (y - phi' theta),   P -= (P phi)(P phi)' / s
 *      which equals the 2-row update with the 2x2 innovation covariance,
 *      without a matrix inverse.
 *
 * SCALING PLAN (IQ_MATH; FLOAT_MATH runs the same steps in float)
 *  - phi: Q24 pu, saturated to +-RLS_PHI_MAX = 8 (counted).
 *  - y:   Q24 pu per pu time.
 *  - theta: Q24 (LSB 6e-8), saturated to +-RLS_THETA_MAX = 15.99 (counted),
 *    so each |phi_j theta_j| < 128 and the prediction needs no wider type.
 *    Its updates are accumulated with error feedback: the part of each
 *    increment below 1/2 LSB24 is kept in theta_res (Q48, |.| <= 2^-25)
 *    and added to the next one (32-bit arithmetic, estim_bfp.h).  Without it, theta stops moving once
 *    |K e| < 1/2 LSB24 (K ~ 1/N): measured on the motor data of the tests
 *    after 1 s, K2 was 1.8e-4 and K3 6e-4 off (relative); with it the
 *    accumulated sum is exact to 1 LSB24.  (FLOAT_MATH: Kahan summation,
 *    for the same reason: a float theta ~ 1 has a 1.2e-7 ulp.)
 *  - innovation e = y - phi' theta over the nonzero phi_j: Q24,
 *    saturating sum (32-bit overflow test), then clamped to
 *    +-RLS_E_MAX = 15.99 (counted).
 *  - P: symmetric positive definite, range ~1e12 (p0) down to ~1e-9
 *    (1/(N |phi|^2) after 1e6 samples), entries of very different sizes
 *    (the constant regressor is excited every sample, wr only when the
 *    speed changes).  Representation: diagonal scaling + mantissas,
 *        P_ij = 2^(Pe_i + Pe_j) * Pn_ij,   Pn in Q30, Pn_ii in [0.25, 1),
 *    i.e. P = D Pn D, D = diag(2^Pe_i).  Pn is a "correlation-like"
 *    matrix: |Pn_ij| <= sqrt(Pn_ii Pn_jj) < 1 while P is PD, so every
 *    entry keeps ~28 significant bits relative to its own row and column,
 *    whatever the spread of the diagonal (a single shared exponent would
 *    leave a 1e-6 diagonal entry with 10 bits).  Pe_i in [-60, 60].
 *    Renormalised after every update (rows/columns with Pn_ii outside
 *    [0.25, 1) are rescaled by a power of 2 and Pe_i adjusted).
 *    Only the upper triangle is computed; it is copied to the lower one,
 *    so Pn is symmetric to the bit (tests check Pn_ij == Pn_ji).
 *    Invariant: |Pn_ij| <= 1 off the diagonal (clamped, counted: never
 *    active while P is PD, by Cauchy-Schwarz) and Pn_ii < 1 (< 2 if Pe_i
 *    is at its limit): it bounds every sum below without saturation.
 *    Renormalisation costs two compares per diagonal while Pn_ii is in
 *    its band; the exponent and the rescaling run only when it leaves it.
 *  - scaled regressor psi = 2^(Pe_j - pp) phi_j, Q28, with the block
 *    exponent pp = max_j (exponent(phi_j) + Pe_j) over the nonzero phi_j,
 *    so |psi_j| <= 1 and max |psi_j| >= 1/2.  Zero regressors (one in
 *    each motor row) stay 0.
 *  - g = Pn psi: Q28, |g_i| <= 2 + 1 + 1 + 1 < 8.   (P phi = 2^(Pe+pp) g)
 *  - q = psi' g: Q26, 0 < q < 20.           (phi' P phi = 2^(2 pp) q)
 *  - den = q + 2^(-2pp) if pp >= 0, else 1 + 2^(2pp) q: Q26, in (0, 21);
 *    s = 2^(2pp) den or den.  den = dm 4^k with dm in [0.25, 1] (Q29),
 *    rho = 1/sqrt(den) = _IQ29isqrt(dm) 2^-k, rho_m in [1, 2] (Q29).
 *  - h = g rho (times 2^pp if pp < 0): Q27, |h_i|^2 <= Pn_ii < 1
 *    (Cauchy-Schwarz; clamped to +-RLS_H_MAX, counted, only if not PD),
 *    and Pn <- Pn - h h' (Q27*Q27 -> Q30): the square-root split keeps
 *    every intermediate bounded even when s is huge (P(0) = 1e12) or tiny.
 *    The shift 2^(hs - k) is folded once into rho_m when it is a right
 *    shift (always, except in the first samples of a huge P(0)).
 *  - theta update K_i e = 2^(Pe_i + ks - k + ne) h_i eps, ks = -pp
 *    (pp >= 0) or 0, with e normalised first, e = em 2^ne (em Q30,
 *    |em| in [0.5, 1]), eps = rho_m em (Q29, |eps| <= 2), h_i eps in Q27
 *    (|.| < 2): ~27 significant bits however small e is; then shifted into
 *    Q24 by the compensated accumulation above.
 *  Truncation.  Only the products whose error P or theta would integrate
 *  are rounded: the P downdate h_i h_j and the terms of q (a truncated q
 *  shrinks den and over-shoots the downdate when P is huge: with P(0) =
 *  1e12 that made 196 PD repairs instead of 12).  They are rounded bit for
 *  bit as _IQNrmpy, but computed as the 5-cycle truncating intrinsic one
 *  bit finer plus a rounding shift (estim_round_half, estim_bfp.h), not the
 *  22-cycle _IQNrmpy library call.  Measured on P: truncating h_i h_j
 *  (bias +1/2 LSB30 per entry per update, i.e. an extra forgetting in the
 *  nearly singular directions of Pn) moved the paper form's K3' 2.8e-3
 *  away from the double RLS (bound 2e-3); rounded it is 3e-5.  All other
 *  products truncate (_IQNmpy): the prediction phi' theta (bias < 3 LSB24
 *  = 1.8e-7 pu of y, absorbed like a y offset: < 4e-6 of K3), g = Pn psi
 *  and h = g rho (28 and 27 bits: a gain error of 1e-8..1e-7 relative,
 *  which changes the weighting, not the fixed point of theta) and h_i eps
 *  (27 significant bits after normalising e).  Measured: the tests'
 *  constant-form errors are the same to 3 digits with every product
 *  rounded, and the closed loop (sim_closed_loop) moves by <= 0.04
 *  percentage points (1.1 kW Rr -1.91 % truncated, -1.95 % all rounded).
 *  Every shift saturates; every saturation or clamp increments
 *  `sat_count` (nothing wraps).  A non-positive q, or a non-positive
 *  diagonal of Pn (loss of positive definiteness by rounding), skips /
 *  repairs the update (the row and column of that parameter are reset to
 *  Pn_ii = 0.5 with no correlation) and increments `pd_count`.
 *
 * Cost per row (IQ_MATH, motor rows with 3 of 4 regressors nonzero):
 * 3 + 16 + 4 + 4 + 10 + 1 + 4 _IQNmpy (prediction, g, q, h, P, eps,
 * theta), 1 _IQ29isqrt, 5 exponents, ~7 shifts, 4 compensated sums, all
 * 32-bit; no _IQNrmpy call and no 64-bit operation.  With forgetting,
 * 10 _IQ30rsmpy more per sample.  Estimated with tools/bench_isr.py: see
 * BENCHMARKS.md.
 */
#ifndef RLS_H
#define RLS_H

#include <stdint.h>
#include "IQmathLib.h"

#define RLS_N 4                 /* parameters */
#define RLS_NP 10               /* unique entries of the symmetric P */
#define RLS_PHI_MAX 4.0f        /* pu, |phi_j| < RLS_PHI_MAX (a power of two: one test) */
#define RLS_PHI_SAT 3.9999f     /* pu, a regressor beyond it is saturated to this */
#define RLS_THETA_MAX 15.99f    /* pu, estimate saturation */
#define RLS_E_MAX 15.99f        /* pu, innovation clamp */
#define RLS_PE_LIM 60           /* |Pe_i| bound */

typedef enum {
    RLS_FORM_CONST = 0,   /* c = 1 pu, theta3 = K3_pu (eq. 7) */
    RLS_FORM_PAPER = 1    /* c = previous K2 estimate, theta3 = K3'_pu (eqs. 8-9) */
} rls_form_t;

typedef enum {
    RLS_OK = 0,
    RLS_ERR_FORM,       /* form not a rls_form_t */
    RLS_ERR_P0,         /* p0 not in [1e-9, 1e12] */
    RLS_ERR_LAMBDA,     /* lambda not in [0.9, 1] */
    RLS_ERR_TRACE,      /* trace_max < 4 p0, or > 1e30 (0 selects 4 p0) */
    RLS_ERR_THETA0      /* |theta0_i| >= RLS_THETA_MAX */
} rls_status_t;

typedef struct {
    /* inputs (from ident_regressor) */
    _iq y1, y2;                  /* Q24 pu / pu time */
    _iq i_mf, u_mf;              /* Q24 pu: row 1 */
    _iq i_tf, u_tf, wr_f;        /* Q24 pu: row 2 */
    uint16_t enable;             /* 1: update this sample; 0: hold */
    /* parameters (rls_init) */
    uint16_t form;               /* rls_form_t */
    uint16_t forget;             /* 1 if lambda < 1 */
    _iq30 lambda;                /* Q30: the forgetting factor, in [0.9, 1] */
    _iq30 trace_max_m;           /* Q30 in [0.5, 1): trace_max = m 2^e */
    int16_t trace_max_e;
    int16_t pe_fast;             /* pe_ref <= pe_fast: trace(P) / lambda <= trace_max for sure */
    /* outputs */
    _iq theta[RLS_N];            /* Q24 pu: K1, K2, K3 (or K3'), K4 */
    _iq innov[2];                /* Q24: a-priori errors of rows 1, 2 */
    uint16_t windup_hold;        /* 1: the last sample skipped forgetting */
    uint32_t sat_count;          /* updates in which a value was saturated or clamped
                                    (counted once per update; never wraps) */
    uint32_t pd_count;           /* skipped/repaired non-PD updates */
    uint32_t n_updates;          /* scalar updates done */
    /* state */
    _iq30 Pn[RLS_NP];            /* Q30 mantissas of the symmetric Pn: the upper triangle,
                                    row by row (00 01 02 03 11 12 13 22 23 33) */
    int16_t Pe[RLS_N];           /* P_ij = 2^(Pe_i + Pe_j) Pn_ij / w */
    int16_t pe_ref;              /* max_i Pe_i */
    int16_t dl[RLS_N];           /* min(pe_ref - Pe_i, 31) */
    _iq30 d[RLS_N];              /* Q30: 2^-dl_i (0 if dl_i > 30) */
    _iq30 w;                     /* Q30 in [0.25, 1]: the forgetting steps so far */
    _iq theta_x[RLS_N];          /* IQ: theta in Q26 (the state; theta[] is it rounded
                                    to Q24); FLOAT: the Kahan term of theta[] */
    uint16_t row_next;           /* rls_step_row: 0 = row 1 next, 1 = row 2 next */
} rls_t;

/**
 * P(0) = p0 I (pu), theta(0) = theta0 (pu; NULL: 0), forgetting factor
 * lambda in [0.9, 1] (1 = none, the paper), trace bound trace_max (pu;
 * 0 selects 4 p0 = trace(P(0))).  Float, once.  On error the struct is
 * zeroed (enable = 0: rls_step does nothing).
 */
rls_status_t rls_init(rls_t *r, rls_form_t form, float p0, float lambda,
                      float trace_max, const float theta0[RLS_N]);

/** One sample: if enable, forgetting + the two rows.  See the file comment
 *  for scaling and overflow. */
void rls_step(rls_t *r);

/** Half the work of rls_step per call, for a 15 kHz ISR that cannot
 *  afford both rows: if enable, alternately (forgetting + row 1) and
 *  row 2, each from the inputs of the call that does it.  Each row is then
 *  used at half the sample rate; the regression signals are low-pass
 *  filtered (10 Hz against 15 kHz) so consecutive samples carry almost the
 *  same information, and tests/estim shows the same convergence bounds.
 *  lambda then applies per pair of calls.  Use either rls_step or this on
 *  one instance, not both. */
void rls_step_row(rls_t *r);

/** The two halves of rls_step for a multi-rate ISR that gives each its own
 *  period (drive_step.c): row 1 (with the sample's forgetting step), then,
 *  in a later call with the same inputs, row 2.  If enable, they do what
 *  rls_step does, split in two; the caller keeps the order. */
void rls_step_row1(rls_t *r);
void rls_step_row2(rls_t *r);

/** One scalar update with row phi (Q24) and measurement y (Q24), no
 *  forgetting (rls_step uses it twice).  Returns the a-priori innovation
 *  (Q24).  A zero row carries no information: nothing changes. */
_iq rls_update_row(rls_t *r, const _iq phi[RLS_N], _iq y);

/** Forgetting step alone (once per sample; rls_step calls it). */
void rls_forget(rls_t *r);

#endif /* RLS_H */
