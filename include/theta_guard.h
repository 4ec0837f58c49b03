/**
 * @file theta_guard.h
 * Estimator safeguard (protections): what the drive takes from the RLS (the
 * steady-state snapshot that gets published, and the live estimates) is
 * the last *good* theta, held while the running estimate is implausible or
 * the excitation is poor.
 *
 * theta is good when every K has the sign the model gives it (method §2:
 * K1 < 0, K2 > 0, K3 > 0 (and K3' > 0), K4 < 0 for any physical motor) and
 * a magnitude within a factor `span` of the value computed from the
 * believed motor (drive_init: span 8; the extraction's own plausibility
 * ranges are a factor 4 on each parameter, and K1, K3, K4 combine two or
 * three parameters).  A theta is accepted only from a sample in which the
 * RLS updated (enable) and its covariance was not held at the trace bound
 * (windup_hold = 0: the excitation was enough for forgetting to be allowed,
 * rls.h), so neither the start-up transient from theta(0) = 0 nor a drift
 * under poor excitation reaches the outputs.  The RLS itself runs on
 * unchanged (it may recover); only its consumers are guarded.
 *
 * Scaling: comparisons of Q24 values only (|theta| < 16 pu, bounds
 * representable); no arithmetic, nothing can overflow.  Counters saturate.
 */
#ifndef THETA_GUARD_H
#define THETA_GUARD_H

#include <stdint.h>
#include "IQmathLib.h"
#include "rls.h"

typedef enum {
    THETA_GUARD_OK = 0,
    THETA_GUARD_ERR_ARG   /* a nominal K with the wrong sign, zero or >= 16 pu, or span < 1 */
} theta_guard_status_t;

typedef struct {
    /* inputs */
    _iq theta[RLS_N];        /* Q24 pu: rls_t.theta after this sample's update */
    uint16_t updated;        /* the RLS updated this sample */
    uint16_t windup_hold;    /* rls_t.windup_hold */
    /* parameters: accepted magnitude band of each K (Q24, pu, positive) */
    _iq lo[RLS_N], hi[RLS_N];
    int16_t sign[RLS_N];     /* +1 / -1 */
    uint16_t required;       /* bit i set: K(i+1) must be in its band (init: all four); a K
                                not required has the band [-16, 16] (any theta) */
    /* outputs */
    _iq theta_good[RLS_N];   /* Q24 pu: last good theta (0 until the first) */
    uint16_t good;           /* 1 once a good theta was seen since the last reset */
    uint16_t held;           /* 1 while the running theta is not accepted */
    uint32_t reject_count;   /* updated samples whose theta was rejected */
} theta_guard_t;

/** k_nom: K1, K2, theta3 (K3 or K3' as the RLS form estimates it), K4 in pu;
 *  span > 1.  Float, once; on error the struct is zeroed (good = 0). */
theta_guard_status_t theta_guard_init(theta_guard_t *g, const float k_nom[RLS_N], float span);
/** theta_guard_init's check of its arguments alone (no struct):
 *  THETA_GUARD_ERR_ARG for span not in (1, 1e6), then for the first K whose
 *  sign is not the model's or whose magnitude is not below RLS_THETA_MAX,
 *  with its index 0..3 in @p bad_k (may be NULL; RLS_N when no K is at
 *  fault).  The configuration's table of limits calls it too
 *  (drive_limits.c).  Float: init only. */
theta_guard_status_t theta_guard_check(const float k_nom[RLS_N], float span, uint16_t *bad_k);
/** Which K must be plausible for a theta to be taken (bit i: K(i+1)), a
 *  non-empty subset of 0xF; returns THETA_GUARD_ERR_ARG (nothing changed)
 *  otherwise.  One way: a K released stays released until theta_guard_init.  The drive's fused mode (adaptive sequence) needs only K2 and K4: it
 *  takes Rs, Rr, Tr from elsewhere, and on a motor with a large w_r Tr the
 *  RLS's K1, K3 are the ill-conditioned ones. */
theta_guard_status_t theta_guard_set_required(theta_guard_t *g, uint16_t mask);
/** Forget the last good theta (a new identification starts). */
void theta_guard_reset(theta_guard_t *g);
void theta_guard_step(theta_guard_t *g);

#endif /* THETA_GUARD_H */
