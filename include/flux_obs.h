/**
 * @file flux_obs.h
 * Closed-loop rotor-flux observer for direct field orientation: a voltage
 * model in the stationary frame, pulled towards a current model (rotor
 * coordinates, encoder angle) below a crossover w_c, so that above w_c the
 * flux angle does not depend on Tr (Jansen & Lorenz 1994; TI's ACI_FE uses
 * the same idea with a plain PI).
 *
 * Models (pu: flux of psi_base, time of 1/w_base, complex alpha + j beta):
 *   voltage model   d psi_s / dt = u - Rs i
 *                   psi_r = (Lr/Lm) (psi_s - sigma Ls i)      needs Rs, sigma Ls, Lr/Lm
 *   current model   in rotor coordinates (i^r = i e^{-j theta_r}):
 *                   Tr d psi_r^r / dt = Lm i^r - psi_r^r,  psi_r = psi_r^r e^{j theta_r}
 *                   needs Tr, Lm and the encoder angle, no orientation
 *                   assumption (so a wrong Tr does not feed back through
 *                   the observer's own angle, unlike a flux-frame model)
 *   blend           the current model's stator flux psi_s,cm = (Lm/Lr) psi_r,cm
 *                   + sigma Ls i is compared with the observer's psi_s; the
 *                   difference drives a correction voltage u_c
 *                      s psi_s = u - Rs i + u_c,   u_c = C(s) (psi_s,cm - psi_s)
 *                      C(s) = (3 w_c^2 s + w_c^3) / (s (s + 3 w_c))
 *                   a PI (integral: no wind-up from DC offsets) followed by a
 *                   first-order roll-off at 3 w_c.
 *
 * How the result depends on speed.  With D(s) = (s + w_c)^3 and the flux
 * turning at w_e (s = j w_e in the stationary frame):
 *     psi_s^ = H_v psi_s,true + H_c psi_s,cm + H_e e_err
 *     H_c = (3 w_c^2 s + w_c^3) / D       current model weight: 1 at DC,
 *                                         |H_c| ~ 3 (w_c/w_e)^2 above w_c
 *     H_v = 1 - H_c = s^2 (s + 3 w_c) / D voltage model weight
 *     H_e = s (s + 3 w_c) / D             voltage error e_err (e.g. -dRs i,
 *                                         offsets) -> flux: 0 at DC (no drift,
 *                                         no wind-up), ~ 1/(j w_e) above w_c
 * and psi_r^ = (Lr/Lm)(psi_s^ - sigma Ls i): the current model's error (a
 * wrong Tr) reaches the output times |H_c| (3 % at w_e = 10 w_c), a plain PI
 * with the same poles would pass 2 zeta w_c / w_e (14 % with zeta = 0.707):
 * the roll-off is why this is not the textbook PI.  The voltage model's
 * errors (Rs, sigma Ls) are not attenuated above w_c: an Rs error gives an
 * angle error of about dRs / (w_e Lm^2/Lr) rad whatever the load and flux
 * (paper motor, Rs 10 % off: 4.3-4.9 deg at 0.93 pu, 6.5-8 deg at 0.6 pu;
 * sigma Ls 10 % off: 4-5 deg), growing as the speed falls until, below w_c,
 * the current model (and Tr) takes over; near w_c both errors mix and can
 * peak (tools/study/flux_obs_blend.py tabulates it).  So: Tr matters only
 * below about w_c; Rs and sigma Ls (the angle) and Lr/Lm (the magnitude
 * only) matter above it; the RLS identifies these without Tr
 * (sigma Ls = 1/K2; Rs from K1, K3').
 *
 * Discretisation: one step every n samples (n = 1, or the drive's slow
 * task, flux_obs_set_step), step period T = n Ts; inputs at sample k: i(k),
 * the mean voltage u and the mean current i_mean over the step's n periods
 * (k-n -> k), the rotor angle theta_r(k):
 *   psi_s(k) = psi_s(k-n) + T (u - Rs i_mean + u_c(k-n))
 *              (exact for u constant over each period and i linear over
 *              each: i_mean is the trapezoidal mean of the n + 1 samples;
 *              with n = 1, (i(k-1) + i(k))/2)
 *   psi_r^r(k) = psi_r^r(k-n) + kf (Lm (i^r(k-n) + i^r(k))/2 - psi_r^r(k-n)),
 *              kf = 1 - exp(-T/Tr) (first-order hold, O((T/Tr)^2); in rotor
 *              coordinates the current turns only at the slip frequency, so
 *              the step's two ends describe it)
 *   C(s) in scaled states z = w_c int(e), y = u_c / w_c (e = psi_s,cm - psi_s):
 *      z += g e,  y += g (3 e + z - 3 y),  u_c = w_c y,   g = w_c T
 *   forward Euler at g <= 0.05 (the crossover is far below the step
 *   rate: 3 Hz at 1.875 kHz is g = 0.01); every per-step gain is g, not
 *   w_c^3 T, so the rounded integrators' dead zone is only 0.5 LSB / g of
 *   flux.
 *
 * Outputs at sample k: psi_r(k) (alpha, beta), |psi_r|, its angle theta(k)
 * in [0, 1), theta_prev = theta(k-n), ws = the flux's speed over the step
 * (angle step / (n f_base Ts)), ws_f = ws low-passed (for decoupling and the
 * modulation angle, and the caller's angle between steps: ws carries the
 * current noise through sigma Ls i).
 *
 * Parameters.  The model's constants (Rs, Lm, sigma Ls, Lr/Lm, Lm/Lr, Tr,
 * kf: flux_obs_model_t) are computed in float by flux_obs_design (pu in;
 * flux_obs_init converts its SI arguments and calls it), outside the ISR:
 * the drive's background computes a whole set there and the ISR copies it
 * in (flux_obs_apply_model, a few word copies, no division).  Likewise the
 * DC re-seat at standstill: flux_obs_seat_dc computes the states (fixed
 * point, outside the ISR), flux_obs_apply_seat copies them in.  The fixed-
 * point setters (flux_obs_set_rs, flux_obs_set_tr, flux_obs_set_rs_dc)
 * remain for callers without float; the drive's ISR does not use them.
 * The inductances have no fixed-point setter: their ranges are one float
 * test (flux_obs_l_check), the one flux_obs_design_l and the table of
 * limits call.  Rate limiting and blending of identified values is
 * the caller's choice.
 */
#ifndef FLUX_OBS_H
#define FLUX_OBS_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"

/** Input magnitudes are saturated to this (pu): the drive's currents and
 *  voltages are below 1.2 pu; the bound keeps every product inside Q24. */
#define FLUX_OBS_IN_MAX 4.0f
/** Parameter ranges (pu), chosen so that no intermediate leaves Q24:
 *  |Rs i| <= 16, |Lm i| <= 64, |Lr/Lm (psi_s - sigma Ls i)| <= 4 (8 + 16) = 96. */
#define FLUX_OBS_RS_MAX 4.0f
#define FLUX_OBS_LM_MAX 16.0f
#define FLUX_OBS_SIGMA_LS_MAX 4.0f
#define FLUX_OBS_LR_LM_MAX 4.0f
/** Tr range: at least 10 samples (kf series, as ifo), at most 1000 pu
 *  (Tr is held in Q20, range 2048 pu: ifo.h's IFO_TR_MAX_PU, the same bound). */
#define FLUX_OBS_TR_MIN_SAMPLES 10.0f
#define FLUX_OBS_TR_MAX_PU 1000.0f
/** State bounds (pu): psi_s (and the error e), and the correction states
 *  z, y.  At DC z = 3 y and u_c = w_c y: |u_c| <= 10 w_c (0.6 pu at 3 Hz),
 *  far above the offsets it has to cancel. */
#define FLUX_OBS_PSI_MAX 8.0f
/** Bound of the current-model target Lm i^r (pu): |i^r| can reach
 *  4 sqrt(2) (both inputs at FLUX_OBS_IN_MAX) and Lm 16, so Lm i^r is
 *  saturated here and psi^r (a low-pass of it) stays inside it: the
 *  low-pass increment target - psi^r is then below 2 x 60 = 120 < 128. */
#define FLUX_OBS_PSI_CM_MAX 60.0f
/** Largest |ws| (pu of w_base): the angle step is limited to this speed
 *  (50 times rated frequency: only an angle jump, e.g. the flux vanishing
 *  when the bridge turns off, reaches it).  ws_f, a low-pass of ws, stays
 *  inside it, so ws - ws_f is below 100 < 128 (Q24). */
#define FLUX_OBS_WS_MAX 50.0f
#define FLUX_OBS_Z_MAX 30.0f
#define FLUX_OBS_Y_MAX 10.0f
/** Largest g = w_c Ts and largest crossover (pu of w_base). */
#define FLUX_OBS_G_MAX 0.05f
#define FLUX_OBS_WC_MAX_PU 1.0f

typedef enum {
    FLUX_OBS_OK = 0,
    FLUX_OBS_ERR_BASE,    /* bases NULL or not initialised, or f_base Ts not in (1/2000, 1/128) */
    FLUX_OBS_ERR_RS,      /* Rs not in [0, 4] pu */
    FLUX_OBS_ERR_L,       /* flux_obs_l_check refuses an inductance */
    FLUX_OBS_ERR_TR,      /* Tr not in [10 Ts, FLUX_OBS_TR_MAX_PU] pu */
    FLUX_OBS_ERR_WC,      /* w_c not in (0, 1] pu, or w_c Ts > 0.05 */
    FLUX_OBS_ERR_WS_LPF   /* ws low-pass corner f not > 0 or 2 pi f Ts > 1 */
} flux_obs_status_t;

/** Which inductance flux_obs_l_check refuses, first in this order (a later
 *  test assumes the earlier ones passed). */
typedef enum {
    FLUX_OBS_L_OK = 0,
    FLUX_OBS_L_LM,    /* Lm not in (0, FLUX_OBS_LM_MAX] pu, or 0 in Q24 */
    FLUX_OBS_L_LR,    /* Lr not in (Lm, FLUX_OBS_LR_LM_MAX Lm] */
    FLUX_OBS_L_LS,    /* Ls not in (Lm, 2 FLUX_OBS_LM_MAX] pu */
    FLUX_OBS_L_SLS    /* sigma Ls = Ls - Lm^2/Lr not in (0, FLUX_OBS_SIGMA_LS_MAX] pu, or 0 in Q24 */
} flux_obs_l_fault_t;

typedef struct {
    /* inputs (set before each flux_obs_step) */
    _iq i_alpha, i_beta;    /* Q24, stator current at this sample, pu of I_base */
    _iq u_alpha, u_beta;    /* Q24, mean stator voltage over the step (the n periods that just
                               ended), pu of V_base */
    _iq i_mean_alpha, i_mean_beta;  /* Q24, mean stator current over the step (trapezoidal:
                               the n periods' end samples), pu; n > 1 only: with n = 1 the
                               step forms (i(k-1) + i(k))/2 itself */
    _iq theta_r;            /* Q24, rotor electrical angle at this sample (encoder), pu [0, 1) */
    /* parameters */
    _iq rs;                 /* Q24, Rs, pu of Z_base */
    _iq lm;                 /* Q24, Lm, pu of L_base */
    _iq sigma_ls;           /* Q24, sigma Ls = Ls - Lm^2/Lr, pu of L_base */
    _iq lr_lm;              /* Q24, Lr / Lm (> 1) */
    _iq lm_lr;              /* Q24, Lm / Lr (< 1) */
    _iq20 tr;               /* Q20 (large motors' Tr exceeds Q24's 128), Tr, pu time */
    _iq kf;                 /* Q24, 1 - exp(-Ts/Tr) */
    uint16_t n;             /* samples per step (flux_obs_init): the step's period is n Ts */
    _iq ts;                 /* Q24, n Ts, pu time (kept for flux_obs_set_tr) */
    _iq30 ts30;             /* Q30, n Ts, pu time (flux integration) */
    _iq wc;                 /* Q24, crossover w_c, pu of w_base */
    _iq g;                  /* Q24, w_c n Ts (per-step gain of the correction states) */
    _iq inv_wc;             /* Q24, 1 / w_c (flux_obs_set_rs_dc), at most 100 pu */
    _iq kf_ws;              /* Q24, 1 - exp(-2 pi f_ws n Ts): ws low-pass coefficient */
    _iq20 inv_k_theta;      /* Q20, 1 / (n f_base Ts): pu speed per revolution per step */
    _iq dth_max;            /* Q24, largest angle step converted to ws (|ws| <= FLUX_OBS_WS_MAX,
                               and below half a revolution) */
    /* outputs */
    _iq psi_alpha, psi_beta;        /* Q24, rotor flux (observer), pu of psi_base */
    _iq psi_mag;                    /* Q24, |psi_r|, pu */
    _iq theta;                      /* Q24, rotor flux angle at this sample, pu [0, 1) */
    _iq theta_prev;                 /* Q24, the same at the previous sample */
    _iq ws;                         /* Q24, frame speed over the last step, pu of w_base */
    _iq ws_f;                       /* Q24, ws low-passed, pu */
    _iq psi_cm_alpha, psi_cm_beta;  /* Q24, current-model rotor flux (diagnostic), pu */
    _iq uc_alpha, uc_beta;          /* Q24, correction voltage u_c (diagnostic), pu of V_base */
    uint16_t sat;                   /* 1 if a state hit its bound this sample (diagnostic) */
    /* state */
    _iq psis_alpha, psis_beta;      /* Q24, observer stator flux, pu (|.| <= FLUX_OBS_PSI_MAX) */
    _iq z_alpha, z_beta;            /* Q24, w_c int(e), pu flux (|.| <= FLUX_OBS_Z_MAX) */
    _iq y_alpha, y_beta;            /* Q24, u_c / w_c, pu flux (|.| <= FLUX_OBS_Y_MAX) */
    _iq psirr_d, psirr_q;           /* Q24, current-model rotor flux in rotor coordinates, pu */
    _iq irr_d_prev, irr_q_prev;     /* Q24, i^r(k-1), pu */
    _iq i_alpha_prev, i_beta_prev;  /* Q24, i(k-1), pu */
} flux_obs_t;

/** The model's constants: what depends on (Rs, Lm, Lr, Ls, Tr).  All Q24,
 *  each one aligned 32-bit word (a set can be posted word by word). */
typedef struct {
    _iq rs;                 /* Rs, pu of Z_base, [0, 4] */
    _iq lm;                 /* Lm, pu of L_base, (0, 16] */
    _iq sigma_ls;           /* sigma Ls = Ls - Lm^2/Lr, pu of L_base, (0, 4] */
    _iq lr_lm;              /* Lr / Lm, (1, 4] */
    _iq lm_lr;              /* Lm / Lr, [0.25, 1) */
    _iq20 tr;               /* Q20: Tr, pu time, [10 Ts, FLUX_OBS_TR_MAX_PU] */
    _iq kf;                 /* 1 - exp(-Ts/Tr), (0, 0.1] */
} flux_obs_model_t;

/** The observer's states re-seated on the DC solution at standstill
 *  (flux_obs_seat_dc), Q24 pu, and the outputs that continue from them. */
typedef struct {
    _iq psis_alpha, psis_beta;   /* stator flux on the current model's */
    _iq z_alpha, z_beta;         /* correction states holding u_c = Rs i - u */
    _iq y_alpha, y_beta;
    _iq uc_alpha, uc_beta;       /* u_c = w_c y */
    _iq psi_alpha, psi_beta;     /* output rotor flux: the current model's */
    _iq psi_mag;                 /* its magnitude */
    _iq theta;                   /* its angle, pu [0, 1) (theta_prev too) */
    uint16_t sat;                /* 1 if an input or a state was saturated */
} flux_obs_seat_t;

/**
 * Compute every constant once (float, not in the ISR) and reset the state.
 * @p Rs_ohm, @p Ls_H, @p Lr_H, @p Lm_H, @p Tr_s: the controller's motor
 * model (Tr = Lr / Rr); @p wc_Hz: crossover (a few Hz: see the file
 * comment); @p ws_lpf_Hz: corner of the ws low-pass.  On an error the
 * observer is left reset with zero gains (its outputs stay 0).
 */
flux_obs_status_t flux_obs_init(flux_obs_t *o, const base_values_t *b, float Rs_ohm,
                                float Ls_H, float Lr_H, float Lm_H, float Tr_s, float wc_Hz,
                                float ws_lpf_Hz);

/** flux_obs_init's check of its arguments alone (no struct), the status it
 *  would return: _BASE (bases, f_base Ts not in (1/2000, 1/128)), _WC,
 *  _WS_LPF, then the model's ranges in flux_obs_design's order (_RS, _L,
 *  _TR).  The configuration's table of limits calls it too
 *  (drive_limits.c).  Float: init only. */
flux_obs_status_t flux_obs_check(const base_values_t *b, float Rs_ohm, float Ls_H, float Lr_H,
                                 float Lm_H, float Tr_s, float wc_Hz, float ws_lpf_Hz);

/** Run the observer once every @p n samples (a power of two up to 8: the
 *  drive's slow task) on the step's mean voltage and mean current: the
 *  constants follow the step n Ts (the voltage integral, the current
 *  model's kf, the correction's g, the ws scaling and low-pass).  Call
 *  after flux_obs_init (and before the setters: flux_obs_set_tr takes the
 *  step from it).  Returns FLUX_OBS_ERR_BASE (nothing changed) for an n
 *  that is not a power of two in [1, 8] or makes w_c n Ts > 0.05, a ws
 *  low-pass step above 1, or Tr below 10 steps. */
flux_obs_status_t flux_obs_set_step(flux_obs_t *o, const base_values_t *b, uint16_t n,
                                    float wc_Hz, float ws_lpf_Hz);

/** flux_obs_set_step's check alone, for the Q20 Tr @p tr_pu the observer
 *  holds (flux_obs_t.tr), each refusal named (flux_obs_set_step returns
 *  FLUX_OBS_ERR_BASE for every one): _BASE (n not a power of two in
 *  [1, 8]), _WC (w_c n Ts > 0.05), _WS_LPF (the ws low-pass step 2 pi f n Ts
 *  not in (0, 1]), _TR (Tr below 10 steps: flux_obs_design_tr's float test
 *  on _IQ20toF(tr_pu), the one that designs the step's kf).  Also the table
 *  of limits' (drive_limits.c).  Float: init only. */
flux_obs_status_t flux_obs_step_check(const base_values_t *b, uint16_t n, float wc_Hz,
                                      float ws_lpf_Hz, _iq20 tr_pu);

/** Zero the state and outputs (demagnetised machine: all fluxes 0). */
void flux_obs_reset(flux_obs_t *o);

/**
 * The model's constants from pu floats (float: not in the ISR), as
 * flux_obs_init computes them: Rs, Lm, Tr as given, Lr/Lm, Lm/Lr,
 * sigma Ls = Ls - Lm^2/Lr and kf = 1 - exp(-x), x = Ts/Tr, by its series to
 * x^5/120 (x <= 0.1: error < x^6/720 = 1.4e-9, below the float rounding),
 * each converted to Q24 by _IQ (truncation, < 1 LSB, plus the float's
 * rounding: relative 6e-8 of the value).  Ranges: Rs in [0, 4] (as
 * flux_obs_set_rs); the inductances as flux_obs_l_check; Tr in [10 Ts, FLUX_OBS_TR_MAX_PU], to Q20 by _IQ20 (NaN fails
 * every check).  Each group (Rs; the
 * inductances; Tr) is written only when its own check passes, so a refused
 * group keeps what @p m held (as a refusing setter keeps its old value).
 * flux_obs_design: all three, in that order; returns the first refusal.
 */
flux_obs_status_t flux_obs_design_rs(flux_obs_model_t *m, float rs_pu);
/** The inductances' ranges, the one test of them: flux_obs_design_l (and so
 *  flux_obs_init and the background's estimated sets) refuses with
 *  FLUX_OBS_ERR_L exactly when this is not FLUX_OBS_L_OK, and the table of
 *  limits (drive_limits.c) names the inductance by it.  On the pu floats
 *  (NaN fails every test); Lm and sigma Ls must also be nonzero in Q24 (the
 *  model's Lm and sigma Ls are _IQ of them).  Float: not in the ISR. */
flux_obs_l_fault_t flux_obs_l_check(float lm_pu, float lr_pu, float ls_pu);
flux_obs_status_t flux_obs_design_l(flux_obs_model_t *m, float lm_pu, float lr_pu, float ls_pu);
flux_obs_status_t flux_obs_design_tr(flux_obs_model_t *m, float ts_pu, float tr_pu);
flux_obs_status_t flux_obs_design(flux_obs_model_t *m, float ts_pu, float rs_pu, float lm_pu,
                                  float lr_pu, float ls_pu, float tr_pu);

/** The model the observer runs, as a set (seven word copies). */
static inline void flux_obs_get_model(const flux_obs_t *o, flux_obs_model_t *m)
{
    m->rs = o->rs;
    m->lm = o->lm;
    m->sigma_ls = o->sigma_ls;
    m->lr_lm = o->lr_lm;
    m->lm_lr = o->lm_lr;
    m->tr = o->tr;
    m->kf = o->kf;
}

/** Copy a model set in (ISR: seven word copies, no arithmetic). */
static inline void flux_obs_apply_model(flux_obs_t *o, const flux_obs_model_t *m)
{
    o->rs = m->rs;
    o->lm = m->lm;
    o->sigma_ls = m->sigma_ls;
    o->lr_lm = m->lr_lm;
    o->lm_lr = m->lm_lr;
    o->tr = m->tr;
    o->kf = m->kf;
}

/**
 * The DC re-seat (see flux_obs_set_rs_dc) computed without touching the
 * observer: @p m the model it is to run with (Rs, Lm/Lr, sigma Ls), @p o
 * only for its fixed constants w_c and 1/w_c (flux_obs_init's), the current
 * model's stator-frame rotor flux @p psi_cm_alpha, @p psi_cm_beta and the DC
 * voltage and current (pu, low-pass filtered) at the same instant.  Fixed
 * point, no division (the angle by _IQatan2PU, the magnitude by _IQmag);
 * scaling as flux_obs_set_rs_dc.  Rejects (nothing written) Rs outside
 * [0, 4].
 */
flux_obs_status_t flux_obs_seat_dc(const flux_obs_t *o, const flux_obs_model_t *m,
                                   _iq psi_cm_alpha, _iq psi_cm_beta, _iq u_alpha, _iq u_beta,
                                   _iq i_alpha, _iq i_beta, flux_obs_seat_t *s);

/** Copy a re-seat in (ISR: fourteen word copies): the next flux_obs_step
 *  continues from it without a transient; ws, ws_f = 0 (standstill). */
static inline void flux_obs_apply_seat(flux_obs_t *o, const flux_obs_seat_t *s)
{
    o->psis_alpha = s->psis_alpha;
    o->psis_beta = s->psis_beta;
    o->z_alpha = s->z_alpha;
    o->z_beta = s->z_beta;
    o->y_alpha = s->y_alpha;
    o->y_beta = s->y_beta;
    o->uc_alpha = s->uc_alpha;
    o->uc_beta = s->uc_beta;
    o->psi_alpha = s->psi_alpha;
    o->psi_beta = s->psi_beta;
    o->psi_mag = s->psi_mag;
    o->theta = s->theta;
    o->theta_prev = s->theta;
    o->ws = _IQ(0.0);
    o->ws_f = _IQ(0.0);
    o->sat = s->sat;
}

/** Rs in pu (e.g. identified).  Rejects (old value kept) outside [0, 4]. */
flux_obs_status_t flux_obs_set_rs(flux_obs_t *o, _iq rs_pu);

/**
 * Rs changed at DC steady state (standstill after >= 5 Tr of constant
 * current), and the observer re-seated on the DC solution: psi_s on the
 * current model's stator flux (Lm/Lr) psi_r,cm + sigma Ls i (at DC the
 * current model weighs 1, H_c(0) = 1), and the correction holding what the
 * voltage model needs at DC, u_c = Rs i - u (y = u_c / w_c, z = 3 y), so
 * that the next sample continues without a transient.  Whatever the
 * voltage model did with the old Rs (believed Rs +30 %: its flux reversed
 * 7 ms into the magnetisation) is discarded.  @p u_alpha.. @p i_beta: the
 * DC voltage and current (pu; low-pass filtered by the caller: a sample of
 * the instantaneous ones carries ripple and noise that u_c would then hold
 * as an offset).  Rejects (nothing changed) Rs outside [0, 4]; inputs are
 * saturated as in flux_obs_step and the re-seated states at their bounds
 * (sat set).
 */
flux_obs_status_t flux_obs_set_rs_dc(flux_obs_t *o, _iq rs_pu, _iq u_alpha, _iq u_beta,
                                     _iq i_alpha, _iq i_beta);

/**
 * Tr in pu time, Q20.  As ifo_set_tr: Ts/Tr by _IQ20div (Q24 / Q20 ->
 * Q24), kf by its Taylor series to x^5/120 (x = Ts/Tr <= 0.1: error
 * < 1.4e-9).  Rejects (old value kept) outside [10 Ts, FLUX_OBS_TR_MAX_PU].
 */
flux_obs_status_t flux_obs_set_tr(flux_obs_t *o, _iq20 tr_pu);

/**
 * One sample (inputs set).  Scaling and overflow: inputs saturated to
 * +-FLUX_OBS_IN_MAX; with the parameter ranges above every product is
 * below 128 pu; psi_s and e saturated to +-FLUX_OBS_PSI_MAX, z and y to
 * +-FLUX_OBS_Z_MAX, +-FLUX_OBS_Y_MAX (anti-wind-up; sat reports it); the integrators use
 * rounded products (no drift from truncation), the flux step Ts e is
 * truncated (-0.5 LSB per sample, a 1.4e-6 pu voltage the loop removes).
 * Angle by _IQatan2PU, magnitude by _IQmag; ws saturates at half a
 * revolution per sample.
 */
void flux_obs_step(flux_obs_t *o);

/** flux_obs_step in two parts, for two ISRs of a slow schedule: (a) the
 *  inputs, the voltage and current models and the correction; (b) the
 *  rotor flux, its magnitude, angle and speed (from the state and current
 *  part a left: the inputs may change in between).  a then b =
 *  flux_obs_step, bit for bit. */
void flux_obs_step_a(flux_obs_t *o);
void flux_obs_step_b(flux_obs_t *o);


#endif /* FLUX_OBS_H */
