/**
 * @file ident_conf.h
 * How far each identified parameter can be trusted, from the data the RLS
 * saw (method §2-§4), and whether the drive may stand behind the set.
 *
 * What the data give (the regression y = Phi theta of method §2, pu):
 *
 *   J  = sum over the RLS samples of eps1^2 + eps2^2, the residual of both
 *        rows with the estimate after each sample's update (a-posteriori:
 *        eps = e / s with s = 1 + phi' P phi, so the start-up transient,
 *        when P is large, adds almost nothing; from then on it is the
 *        residual with the estimates as they converge);
 *   Y  = sum of y1^2 + y2^2, the energy of what the model must explain;
 *   P  = the RLS covariance (rls_cov.h), (Phi' Phi)^-1 once P(0) is
 *        forgotten.
 *
 * For a parameter p(theta) (method §4), with the elasticities e_i =
 * d ln p / d ln |theta_i| of the extraction's formulas (the Jacobian of
 * method §4 in relative form, written out in ident_conf.c), the bound
 *
 *     bound_p = sqrt(J e' Pt e),   Pt_ij = P_ij / (theta_i theta_j)
 *
 * is the largest relative change of p that an error in the regression as
 * large as its residual (||d|| = sqrt(J)) can cause: by Cauchy-Schwarz,
 * |delta theta_i| = |e_i' P Phi' d| <= sqrt(P_ii) ||d||.  It is a
 * deterministic bound, not a standard error: the errors that limit the
 * identification are systematic (dead time, the regression's period
 * model, orientation: README), not white noise, so a noise-based standard
 * error (this bound times sqrt(c / N), c the samples per independent
 * sample of the 10 Hz filtered signals, about 170 at 3.75 kHz) would
 * promise 5-10 times too much.  It factors as
 *
 *     bound_p = residual x amplification_p,  residual = sqrt(J / Y),
 *     amplification_p = sqrt(Y e' Pt e)
 *
 * residual: the fraction of the signal the model does not explain (a
 * sensor fault, a wrong model); amplification: how much the data's
 * excitation and conditioning amplify a relative regression error into p
 * (large when w_r Tr is large: K3 is the small difference of row 1, and
 * when the speed range is small).  A second, independent figure is the
 * estimate's drift: the same extraction from the estimate at the middle
 * of the RLS window (half the data), drift_p = |p_end - p_mid| / |p_end|:
 * a bias that depends on the excitation (the study in
 * tools/study/regression_bias.md: it grows with w^3 during the ramp) moves
 * the estimate as the data come in, a model that fits does not.
 *
 *     confidence_p = bound_p + drift_p     (relative; 0.01 = 1 %)
 *
 * (the sum: two separate figures, each a part of the error the data cannot
 * exclude; over the motor family the sum at 3 % let no set off by more than
 * 3 % through, the larger of the two did on a wrong nameplate with the
 * observer alone: Rr +3.8 % with bound 2.6 %, drift 1.2 %).
 *
 * The excitation: the rms of the regression's left-hand side, sqrt(Y/2n),
 * against y_ref, what a ramp to rated speed gives (the back-EMF-like term
 * w_s i_M at rated speed and the i_M reference: set by the drive).
 *
 * Verdict over the parameters selected by `mask` (the ones the drive
 * publishes from the RLS): OK when every confidence is at most conf_max
 * (and the covariance was never repaired: rls_t.pd_count, `pd`); else why,
 * the first that holds of
 *   NO_DATA         the RLS made no update, or nothing could be judged;
 *   LOW_EXCITATION  excitation < exc_ref (a small signal: the residual's
 *                   size says nothing then);
 *   HIGH_RESIDUAL   residual > res_ref (the model does not fit the data as
 *                   it does on a healthy drive: a sensor fault, ...);
 *   NOT_CONVERGED   the drift is the larger part of the largest confidence
 *                   (or no plausible mid-window estimate came when one was
 *                   expected);
 *   LOW_CONFIDENCE  otherwise (a bound: the data amplify their residual
 *                   beyond conf_max; the covariance lost positive
 *                   definiteness).
 * The limits are drive_init's (drive_design.h says where they come from).
 *
 * Scaling.  Accumulation (ident_conf_acc_step, once per completed RLS
 * sample, in the RLS's context: the drive's background, drive_rls_bg.c): the prediction phi' theta in Q22 (inputs clamped by _IQsat to
 * the RLS's |phi| <= 8, |y| <= 64; theta < 16: |sum| < 448 < 512), eps
 * clamped to +-0.7 pu, eps^2 in Q31 added to J (Q24) with the part below
 * 1/2 LSB24 kept in J_res (Q48, estim_accumulate): exact to 2^-48 per term,
 * saturating at 128 pu^2 (counted); y^2 / 256 in Q24 (|y| clamped to 8)
 * added with saturation (counted).  The input clamps are not counted.
 * Cost (tools/bench_isr.py): about 200 cycles, in the slow task's FILTERS
 * slot (drive_slow.c: on the sample the RLS completed in the last period,
 * before the new rows replace its inputs).  Evaluation (background, ident_conf_eval): block floating
 * point (mantissa Q30 in [0.5, 1), int16 exponent; estim_bfp.h) for J, Y,
 * P_ii and the bounds of each theta_i, so that values from 1e-8 to 1e4
 * keep ~28 bits; the quadratic form over normalised terms in Q26 (|.| <=
 * 16); every figure saturates at IDENT_CONF_MAX (counted in sat).  No
 * float outside ident_conf_init.
 */
#ifndef IDENT_CONF_H
#define IDENT_CONF_H

#include <stdint.h>
#include "IQmathLib.h"
#include "param_extract.h"
#include "rls.h"
#include "rls_cov.h"

/** The parameters, in the order of the telemetry and report.json. */
typedef enum {
    IDENT_P_RS = 0,
    IDENT_P_RR,
    IDENT_P_LM,
    IDENT_P_LR,
    IDENT_P_PSI,
    IDENT_P_TR
} ident_param_t;
#define IDENT_NP 6u   /* how many (IDENT_P_TR + 1) */

#define IDENT_MASK_ALL 0x3Fu        /* every parameter */
#define IDENT_MASK_MAGNETIC 0x1Cu   /* Lm, Lr, psi_r (K2, K4: the fused set's RLS part) */
#define IDENT_CONF_MAX 100.0f       /* every figure saturates here (10 000 %) */

typedef enum {
    IDENT_CONF_OK = 0,
    IDENT_CONF_NO_DATA,
    IDENT_CONF_HIGH_RESIDUAL,
    IDENT_CONF_LOW_EXCITATION,
    IDENT_CONF_NOT_CONVERGED,
    IDENT_CONF_LOW_CONFIDENCE
} ident_conf_verdict_t;

/** The RLS's side: what its samples leave for the confidence. */
typedef struct {
    _iq J;          /* Q24 pu^2: sum of eps1^2 + eps2^2 */
    _iq J_res;      /* Q48: the part of J below 1/2 LSB24 (estim_accumulate) */
    _iq Y;          /* Q24 pu^2: sum of (y1^2 + y2^2) / 256 */
    uint32_t n;     /* RLS samples accumulated */
    uint32_t sat;   /* clamps and saturations (never wraps) */
} ident_conf_acc_t;

/** Start a new window (a new RLS pass). */
void ident_conf_acc_reset(ident_conf_acc_t *a);
/** After a completed RLS sample (both rows) of @p r, if it updated
 *  (r->enable), with its inputs still those of that sample: add its
 *  a-posteriori residual and its y to the sums. */
void ident_conf_acc_step(ident_conf_acc_t *a, const rls_t *r);

typedef struct {
    /* input (the background sets it before ident_conf_eval) */
    uint16_t mask;            /* parameters to judge: bit ident_param_t */
    _iq y_ref;                /* Q24 pu: the rms signal of a ramp to rated speed */
    /* parameters (ident_conf_init), Q24 fractions */
    _iq conf_max;             /* the largest confidence (bound or drift) published */
    _iq res_ref;              /* a refusal with a residual above: HIGH_RESIDUAL */
    _iq exc_ref;              /* ... with an excitation below: LOW_EXCITATION */
    /* outputs, Q24 relative (0.01 = 1 %), saturated at IDENT_CONF_MAX */
    _iq bound[IDENT_NP];      /* residual-sized regression error -> parameter */
    _iq drift[IDENT_NP];      /* |end - mid| / |end| (0 without a mid estimate) */
    _iq conf[IDENT_NP];       /* bound + drift; the judged ones only, else 0 */
    _iq residual;             /* sqrt(J / Y) */
    _iq amp;                  /* the largest amplification over the judged parameters */
    _iq excitation;           /* sqrt(Y / 2n) / y_ref */
    uint16_t verdict;         /* ident_conf_verdict_t */
    uint16_t worst;           /* ident_param_t with the largest confidence (judged) */
    uint32_t sat;             /* saturations in the evaluation */
} ident_conf_t;

typedef enum {
    IDENT_CONF_INIT_OK = 0,
    IDENT_CONF_INIT_ERR_LIMIT   /* a limit not in (0, IDENT_CONF_MAX) */
} ident_conf_init_status_t;

/** The limits (fractions, e.g. 0.03 for 3 %) and the reference signal
 *  @p y_ref (pu, > 0).  Float, once; on error the struct is zeroed. */
ident_conf_init_status_t ident_conf_init(ident_conf_t *c, float conf_max, float res_ref,
                                         float exc_ref, float y_ref);

/**
 * Evaluate the window: @p cov the RLS covariance at its end, @p acc its
 * sums, @p pd the RLS's covariance repairs in it (rls_t.pd_count: P is then
 * no description of the data); @p end the extraction of the final estimate
 * (its theta, form, i_m and outputs; param_extract_step, or
 * param_extract_magnetic when only the magnetic part is judged), @p mid the
 * same extraction of the estimate at the middle of the window with the
 * final i_m (NULL: none was taken; drift not judged).  The judged
 * parameters must be plausible in @p end (the caller checks valid first).
 */
void ident_conf_eval(ident_conf_t *c, const rls_cov_t *cov, const ident_conf_acc_t *acc,
                     uint32_t pd, const param_extract_t *end, const param_extract_t *mid);

/** |a - b| / |a| (Q24 relative) of two values of one sign, a != 0
 *  (|a - b| < 128); IDENT_CONF_MAX when a is 0 or the ratio beyond it. */
_iq ident_conf_rel_change(_iq a, _iq b);

/**
 * A one-parameter fit y = theta phi sampled from outside (the Rr/Tr
 * tracker's filtered regression, tr_track.h): its relative bound
 * sqrt(sum (y - theta phi)^2 / sum (theta phi)^2).  For a scalar RLS with
 * forgetting lambda, P ~ (1 - lambda) / phi^2 and the weighted residual sum
 * ~ sigma^2 / (1 - lambda), so the bound sqrt(J P) / theta above reduces to
 * this relative residual.  Scaling: |phi| clamped to 2, theta phi to +-4
 * pu and the residual to +-0.99 pu (counted); the residual's square in Q31,
 * theta phi's in Q24, each summed into Q24 with its Q48 residue
 * (estim_accumulate), saturating at 128 (counted).
 */
typedef struct {
    _iq J, J_res;   /* Q24 (+ Q48): sum of (y - theta phi)^2 */
    _iq S, S_res;   /* Q24 (+ Q48): sum of (theta phi)^2 */
    uint32_t n;     /* samples */
    uint32_t sat;
} ident_conf_fit_t;

void ident_conf_fit_reset(ident_conf_fit_t *f);
void ident_conf_fit_add(ident_conf_fit_t *f, _iq y, _iq phi, _iq theta);
/** sqrt(J / S), Q24 relative, IDENT_CONF_MAX when S is 0 or the ratio
 *  beyond it. */
_iq ident_conf_fit_bound(const ident_conf_fit_t *f);

#endif /* IDENT_CONF_H */
