/**
 * @file tr_track.h
 * Rotor-time-constant tracker (drift tracking, beyond the paper): follows
 * 1/Tr (and so Rr = Lr/Tr) while the drive runs, from the slip that a
 * Tr-independent rotor-flux observer (flux_obs.h) sees.
 *
 * Why not the paper's RLS with forgetting.  In steady operation the four
 * regressors of method §2 lose rank: i_M is constant (so K1 i_M and K3 are
 * one column in row 1), u_T is affine in i_T and w_r is constant (row 2),
 * and Rr cancels from row 1 altogether (u_M = Rs i_M - w_s sigma Ls i_T).
 * A forgetting RLS then lets the unexcited directions wander; the wind-up
 * guard only stops P from growing.  Rr reaches the steady state through
 * the slip alone, so this tracker estimates the one parameter the slip
 * carries.
 *
 * Model.  Rotor equation in a frame on the rotor flux (q axis, psi_rq = 0):
 *     w_sl psi_r = (Lm / Tr) i_T,    w_sl = w_s - w_r      (exact, any load)
 * and with the flux held at psi_r = Lm i_M (the controller's i_M constant):
 *     w_sl i_M = (1/Tr) i_T.
 * The observer gives the flux vector psi (alpha, beta); with the stator
 * current i, psi.i = |psi| i_M and psi x i = |psi| i_T, so
 *     y = w_sl (psi . i) = theta (psi x i) = theta phi,   theta = 1/Tr (pu)
 * needs neither |psi| (Lr/Lm) nor Lm, only the observer's angle (Rs and
 * sigma Ls: identified before tracking starts).  y and phi pass the same
 * first-order low-pass (the relation is linear with constant theta, so it
 * survives the filter; method §7 point 2: the product is filtered as one
 * signal), then a scalar RLS with forgetting lambda per update:
 *     den = lambda + P phi^2,  theta += (P phi / den) (y - phi theta),
 *     P = P / den
 * Wind-up guard: no update (and no forgetting) while |phi| < phi_min (no
 * torque current: the slip carries no information), and P <= P_max.
 *
 * Rates: step() every sample (filters), the RLS every `decim` samples.
 *
 * Scaling and overflow (Q24 throughout; FLOAT_MATH the same in float):
 *  inputs saturated: |w_sl| <= 2, |psi| <= 4, |i| <= 4 (pu), so
 *  |psi.i|, |psi x i| <= 32 and |y| <= 64 (Q24 holds < 128); the filtered
 *  phi is clamped to +-TR_TRACK_PHI_MAX = 2 before the RLS, so P phi^2 <=
 *  P_max 4 <= 16 and den in [lambda, 17]; K = P phi / den by _IQdiv (den
 *  >= 0.9: no overflow, < 1 LSB); theta clamped to [theta_min, theta_max]
 *  (counted in sat_count: the tracker never leaves the plausible range);
 *  P = P / den by _IQdiv, kept in [1e-6, P_max].  Products rounded
 *  (_IQrmpy) where they are accumulated (filters, theta).
 */
#ifndef TR_TRACK_H
#define TR_TRACK_H

#include <stdint.h>
#include "IQmathLib.h"

#define TR_TRACK_IN_WSL_MAX 2.0f
#define TR_TRACK_IN_PSI_MAX 4.0f
#define TR_TRACK_IN_I_MAX 4.0f
#define TR_TRACK_PHI_MAX 2.0f
#define TR_TRACK_P_MAX 4.0f

typedef enum {
    TR_TRACK_OK = 0,
    TR_TRACK_ERR_RATE,     /* Ts_pu, decim or the filter corner out of range */
    TR_TRACK_ERR_MEMORY,   /* memory not in [0.2, 20] s, or lambda below 0.9 */
    TR_TRACK_ERR_RANGE,    /* theta range not 0 < min < max <= 30, or theta0 outside it */
    TR_TRACK_ERR_PHI       /* phi_min not in (0, 1] */
} tr_track_status_t;

typedef struct {
    /* inputs (every sample) */
    _iq w_sl;               /* Q24, slip w_s - w_r, pu of w_base */
    _iq psi_alpha, psi_beta;/* Q24, observer rotor flux, pu */
    _iq i_alpha, i_beta;    /* Q24, stator current, pu */
    uint16_t enable;        /* 1: learn; 0: filters run, theta and P hold */
    /* parameters */
    _iq kf;                 /* Q24, low-pass coefficient 1 - exp(-2 pi f Ts) */
    _iq lambda;             /* Q24, forgetting per RLS update */
    _iq p_max;              /* Q24, wind-up bound of P */
    _iq p0;                 /* Q24, P at (re)start */
    _iq phi_min;            /* Q24, least |phi| for an update */
    _iq theta_min, theta_max;   /* Q24, plausible 1/Tr range, pu */
    uint16_t decim;         /* RLS every decim samples */
    /* outputs */
    _iq theta;              /* Q24, 1/Tr estimate, pu of w_base */
    _iq y_f, phi_f;         /* Q24, filtered regression (diagnostic) */
    uint32_t n_updates;     /* RLS updates since the start (saturates) */
    uint32_t sat_count;     /* theta clamps + input saturations (saturates) */
    uint16_t held;          /* 1: the last RLS tick held (|phi| < phi_min) */
    /* state */
    _iq p;                  /* Q24, scalar covariance */
    uint16_t div;           /* samples since the last RLS tick */
} tr_track_t;

/**
 * Constants once (float): @p Ts_s sample period in seconds, @p decim RLS
 * decimation (1..64), @p lpf_Hz low-pass corner with @p Ts_s, @p memory_s
 * forgetting time constant (lambda = 1 - decim Ts_s / memory_s),
 * @p phi_min_pu least |psi x i| for an update, plausible 1/Tr range
 * [theta_min, theta_max] (pu) and the start value @p theta0 (pu).
 */
tr_track_status_t tr_track_init(tr_track_t *t, float Ts_s, uint16_t decim, float lpf_Hz,
                                float memory_s, float phi_min_pu, float theta_min,
                                float theta_max, float theta0);

/**
 * Seconds from a restart until the estimate stands for the motor rather than
 * for the start (float, once at init): the plant's own transient after the
 * restart, TR_TRACK_SETTLE_TR rotor time constants @p tr_s (the rotor flux
 * and the frame settle with Tr after the hand-over), then
 * TR_TRACK_SETTLE_MEMORIES forgetting time constants @p memory_s, so that
 * the estimate holds at most e^-2 = 14 % of that transient.  A fixed 1 s
 * (one memory, no Tr) judged the 55 kW 4-pole 60 Hz motor of the family
 * (Tr 0.60 s) on its own transient: Tr's confidence 3.0 %, refused.
 * Returns 0 for a non-positive or non-finite argument.
 */
#define TR_TRACK_SETTLE_TR 3.0f
#define TR_TRACK_SETTLE_MEMORIES 2.0f
float tr_track_settle_s(float memory_s, float tr_s);

/** Start from theta0 (pu, clamped into the range) with P = p0; filters zeroed. */
void tr_track_restart(tr_track_t *t, _iq theta0);

/** One sample.  See the file comment for scaling and overflow. */
void tr_track_step(tr_track_t *t);

#endif /* TR_TRACK_H */
