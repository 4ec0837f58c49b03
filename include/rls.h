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
 *   RLS_FORM_FLUX    the period-mean regression (tools/study/
 *                    regression_bias.md §5.1 (d)): full rows with the
 *                    rotor flux in the frame, m = psi_r / (Lm i_M,nom) =
 *                    (m_M, m_T) (near (1, 0)),
 *                        y1 = [i_Mf, u_Mf, m_Mf, -(wr m_T)f] theta
 *                        y2 = [i_Tf, u_Tf, m_Tf,  (wr m_M)f] theta
 *                    from the inputs c1 = m_Mf, d1 = -(wr m_T)f, c2 = m_Tf
 *                    and wr_f = (wr m_M)f; theta3, theta4 = K3, K4 at the
 *                    nameplate's i_M (K3 = theta3 m_M for the flux m_M)
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
 *   3. end of the sample: the diagonals of Pn back in their band (below),
 *      theta[] published.
 *
 * SCALING PLAN (IQ_MATH; FLOAT_MATH runs the same steps in float, the
 * powers of two by ldexpf, the range tests by comparison)
 *  - phi: Q24 pu, |phi_j| < RLS_PHI_MAX = 4 (one test for the four: the
 *    sign bit of the OR of phi_j + 4 as unsigned); beyond, the four are
 *    saturated to +-RLS_PHI_SAT.
 *  - y: Q24 pu per pu time; innovation e = y - phi' theta in Q22 (phi Q24
 *    times theta Q26, truncated): |y| < 128 and |phi_j theta_j| < 64 keep
 *    the sum below 1.5 2^30, no overflow; clamped to +-RLS_E_MAX; innov[]
 *    is it in Q24.
 *  - theta: the state theta_x is Q26 (|theta| < 16 is 2^30 raw, so a state
 *    plus an increment below 16 pu cannot overflow), each increment rounded
 *    to Q26 (computed one bit finer, rounded half up).  The published
 *    theta[] (Q24) is the state rounded, once per completed sample (after
 *    row 2; after every rls_update_row).  It replaces the compensated Q24
 *    sum with a Q48 residual (theta_res) of the earlier version: an
 *    increment below 1/2 LSB26 (1/8 LSB24) is now lost, the dead zone of a
 *    rounded integrator (a plain Q24 one lost K2 1.8e-4 and K3 6e-4,
 *    relative, on the tests' noiseless motor data after 1 s; Q26 loses
 *    K3 1.6e-4, within the tests' 2e-4; with measurement noise the
 *    increments are dithered by it: the difference to the double RLS is
 *    0.02 of the estimate's standard deviation, test_noisy, and the
 *    closed-loop identification moved by <= 0.003 percentage points).  |theta_i| at 16 is
 *    saturated to RLS_THETA_MAX.  (FLOAT_MATH: Kahan summation, theta_x the
 *    compensation term: a float theta ~ 1 has a 1.2e-7 ulp.)
 *  - P: symmetric positive definite, range ~1e12 (p0) down to ~1e-9,
 *    entries of very different sizes (the constant regressor is excited
 *    every sample, wr only when the speed changes; measured: diagonals
 *    4^7 apart in the first samples of the simulated runs, correlations
 *    of 0.99999), so one exponent for P does not suffice: a 4^7 smaller
 *    row would keep 16 bits, and its Schur complement, 1e-5 of it, none.
 *        P = D Pn D / w,   D = diag(2^Pe_i),   P_ij = 2^(Pe_i + Pe_j) Pn_ij / w
 *    Pn: Q30, its 10 unique entries stored once (the upper triangle, row by
 *    row: no mirror copies); |Pn_ij| <= sqrt(Pn_ii Pn_jj) < 1 while P is
 *    PD, so every entry keeps ~28 significant bits relative to its own row
 *    and column.  w (Q30, in [0.25, 1]) carries the forgetting: P / lambda
 *    is w lambda (one product per sample, Pn untouched), and 4 w with every
 *    Pe_i + 1 when w falls below 1/4.  pe_ref >= max Pe_i; dl_i = pe_ref -
 *    Pe_i and d_i = 2^-dl_i (Q30) are kept with the exponents.
 *    Invariants: after every row |Pn_ij| < 1 (i != j) and |theta_i| < 16
 *    (one test for the ten: the sign bit of the OR of x + 2^30 as
 *    unsigned); after every sample every Pn_ii in [0.25, 1) (the diagonals
 *    only decrease in a row: < 1 holds; the renormalisation multiplies row
 *    and column i by 2^s, Pn_ii by 4^s, with s from the CSB of Pn_ii, only
 *    when it fell below 0.25, i.e. when P shrank along it by 4: exact
 *    shifts while P is PD, since |Pn_ij| 2^s <= sqrt(Pn_ii 4^s) < 1).
 *  - scaled regressor v_j = d_j phi_j (Q27, |v| < 4), psi = v 2^s read as
 *    Q30 with s from the CSB of OR_j |v_j|: max |psi_j| in [0.25, 0.5);
 *    2^Pe_j phi_j = 2^a psi_j, a = pe_ref + 3 - s.
 *  - g = Pn psi: Q28 (the high word of Q30 * Q30), |g_i| < 2.
 *  - q = psi' g: Q28, 0 < q < 4; q <= 0: Pn not PD along psi (counted in
 *    pd_count) or phi = 0: the row changes nothing.
 *  - den = s / 4^f (s = 1 + phi' P phi in the units of w), f = max(a, 0):
 *    q + w 4^-a (a >= 0) or q 4^a + w (a < 0): Q28 in (0, 5).  den = dm 4^k
 *    with dm in [0.25, 1) (Q29) from the CSB of den, rho_m = _IQ29isqrt(dm)
 *    in (1, 2].
 *  - h = g rho_m 2^(a - f - k) with the sign of e: Q27, |h_i|^2 <=
 *    Pn_ii q / den < 1 while P is PD (Cauchy-Schwarz); one range test for
 *    the four (clamped below 1, flagged, if P is not PD), and Pn <- Pn - h h'
 *    (Q27 * Q27 -> Q31, rounded to Q30): the square-root split keeps every
 *    intermediate bounded even when s is huge (P(0) = 1e12) or tiny.  The
 *    shift 2^(a - f - k) is folded into rho_m when it is a right shift, and
 *    applied to h (left, <= 13, exact below 1) in the first samples of a
 *    huge P.
 *  - theta update K_i e = h_i eps 2^(t - dl_i): e normalised first (e = em
 *    2^(9 - n), em in [0.5, 1) from the CSB of |e|), eps = rho_m em (Q30,
 *    < 2), t = pe_ref - f - k + 9 - n; the product keeps ~27 significant
 *    bits however small e is, then is rounded to Q26 as above.
 *  Truncation.  Only the products whose error P or theta would integrate
 *  are rounded: the P downdate h_i h_j and the theta increments.  They are
 *  rounded bit for bit as _IQNrmpy (round half up), but computed as the
 *  5-cycle truncating intrinsic one bit finer and one arithmetic shift of
 *  y + 1 (TI's _IQ25toIQ, floor for either sign), not the 22-cycle _IQNrmpy
 *  library call nor a rounding step of four operations.  Measured on P:
 *  truncating h_i h_j (bias +1/2 LSB30 per entry per update, i.e. an extra
 *  forgetting in the nearly singular directions of Pn) moved the paper
 *  form's K3' 2.8e-3 away from the double RLS (bound 2e-3); a dither of
 *  the truncation direction (+1 LSB on every other update) is unbiased
 *  only for well spread fractions and drove the nearly singular pivots of
 *  the poor-excitation test negative.  g and q are truncated and then
 *  moved up by the mean of their four floors (2 LSB28 each): when P is
 *  huge q is ~1000 LSB28 and the part of P the update leaves along phi is
 *  ~1/(P |phi|^2) of it, so a bias of q is a large relative error there
 *  (measured: without it the P(0) = 1e12 test loses positive
 *  definiteness for good; a pad that keeps q above its exact value, 8
 *  LSB, made that part 12 % too large).  The prediction phi' theta
 *  truncates (bias < 4 LSB22 = 1e-6 pu of y, absorbed like a y offset).
 *  Overflow.  No operation wraps: every shift is by a range-checked amount
 *  on a value whose bound is stated beside it, and a value that has to be
 *  saturated or clamped (phi, e, theta, h or an off-diagonal of a P that
 *  is not PD) sets the update's flag, counted once per update in
 *  `sat_count` (the number of updates in which something was clamped, no
 *  longer the number of clamps).  A non-positive q skips the update; a
 *  non-positive diagonal of Pn, or a rescaling that would break |Pn_ij|
 *  < 1, resets the row and column of that parameter (Pn_ii = 0.5, no
 *  correlation); both count in `pd_count`.
 *
 * Cost (IQ_MATH, per row): 47 _IQNmpy (4 prediction, 4 scaling, 16 g,
 * 4 q, 4 h, 10 downdate, 1 eps, 4 theta), 1 _IQ29isqrt, 3 CSB
 * (iq_norm32), 1 _IQsat, 19 one-bit shifts (_IQ25toIQ, _IQ26toIQ), no
 * call but the one into the shared row update, no loop; lambda < 1 adds
 * one product per sample.  tools/bench_isr.py (its RLS column, worst ISR
 * of the slot, paper motor): rls_step_row1 1002 cycles (lambda = 0.999:
 * 1236 in ACCELERATE, where the exact trace test runs), rls_step_row2
 * 1046 (1360 when a renormalisation of the diagonals falls in the sampled
 * ISRs); the version before this one cost 3645-4811 and 3775-4029
 * (6285 with lambda = 0.999).
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
#define RLS_PE_LIM 60           /* |Pe_i| bound (never reached: rls.c, rls_rescale) */

typedef enum {
    RLS_FORM_CONST = 0,   /* c = 1 pu, theta3 = K3_pu (eq. 7) */
    RLS_FORM_PAPER = 1,   /* c = previous K2 estimate, theta3 = K3'_pu (eqs. 8-9) */
    RLS_FORM_FLUX = 2     /* full rows with the flux in the frame (regression_bias.md §5) */
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
    _iq i_tf, u_tf, wr_f;        /* Q24 pu: row 2 (RLS_FORM_FLUX: wr_f = (wr m_M)f) */
    _iq c1, d1, c2;              /* Q24, RLS_FORM_FLUX only: row 1's m_Mf and
                                    -(wr m_T)f, row 2's m_Tf */
    uint16_t enable;             /* 1: update this sample; 0: hold */
    /* parameters (rls_init) */
    uint16_t form;               /* rls_form_t */
    uint16_t forget;             /* 1 if lambda < 1 */
    _iq30 lambda;                /* Q30: the forgetting factor, in [0.9, 1] */
    _iq30 trace_max_m;           /* Q30 in [0.5, 1): trace_max = m 2^e */
    int16_t trace_max_e;
    int16_t pe_fast;             /* pe_ref <= pe_fast: trace(P) / lambda <= trace_max for sure */
    /* outputs */
    _iq theta[RLS_N];            /* Q24 pu: K1, K2, K3 (or K3'), K4, as of the last
                                    completed sample (row 2; FLOAT_MATH: of the last row) */
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
    int16_t pe_ref;              /* >= max_i Pe_i (max after a full recompute) */
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

/** One sample: if enable, forgetting + the two rows + the end of the
 *  sample.  See the file comment for scaling and overflow. */
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
 *  in a later call with the same inputs, row 2 (with the end of the
 *  sample: theta[] is published there).  If enable, they do what rls_step
 *  does, split in two; the caller keeps the order. */
void rls_step_row1(rls_t *r);
void rls_step_row2(rls_t *r);

/** One scalar update with row phi (Q24) and measurement y (Q24), no
 *  forgetting, then the end of a sample (theta[] published).  Returns the
 *  a-priori innovation (Q24).  A zero row carries no information: nothing
 *  changes. */
_iq rls_update_row(rls_t *r, const _iq phi[RLS_N], _iq y);

/** Forgetting step alone (once per sample; rls_step calls it). */
void rls_forget(rls_t *r);

#endif /* RLS_H */
