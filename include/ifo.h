/**
 * @file ifo.h
 * Indirect field orientation: the current model of the rotor flux in the
 * rotating M-T frame, giving the flux angle from the rotor speed and the slip.
 *
 * With perfect orientation (psi_rT = 0, method §1) the rotor equations give
 *
 *     Tr d(imr)/dt = i_M - imr          imr = psi_r / Lm (magnetising current)
 *     w_slip       = i_T / (Tr imr)     (rad/s; in pu: i_t / (Tr_pu imr), all pu)
 *     w_s          = w_r + w_slip       (eq. 2: omega_s, the M-T frame speed)
 *     theta        = integral of w_s
 *
 * Discretisation.  imr: exact for i_M held over the sample (ZOH):
 *     imr(k+1) = imr(k) + kf (i_M(k) - imr(k)),   kf = 1 - exp(-Ts/Tr).
 * theta: forward Euler, theta(k+1) = theta(k) + w_s(k) f_base Ts (pu of a
 * revolution), exact for a w_s held over the sample.  The slip uses the
 * updated imr(k+1) (as TI's current model).
 *
 * Ordering in the ISR (sample k, at the T1 underflow that starts PWM period k):
 *   1. Park the measured currents i_a,b(k) with ifo.theta, which on entry is
 *      theta(k): the angle the previous ifo_step predicted for this instant.
 *      ifo_theta_mid() is then the angle at the middle of the period that
 *      just ended (k-1 -> k), over which the applied stator voltage was
 *      constant in the stator frame: rotate that voltage with it (method §7
 *      point 1; the start angle biased Rr by +11.8 % in the prototype).
 *   2. ifo_step(i_M(k), i_T(k), w_r(k)): imr, slip and w_s of this sample,
 *      then theta_prev = theta(k), theta = theta(k+1).
 *   3. The voltage computed now is applied from the next underflow on
 *      (shadowed compares, hal_pwm.h), i.e. over period k+1 -> k+2: its
 *      inverse Park would ideally use theta(k+1) + w_s Ts / 2, the middle of
 *      that period; that prediction is the drive's choice, made from theta
 *      and ws.
 * Integrating after the Park transform (not before) keeps the current
 * transform on the angle of the instant the currents were sampled.
 *
 * Tr may be changed online by the identification: ifo_design_tr computes
 * the Tr constants (Tr, 1/Tr, kf: ifo_tr_t) in float outside the ISR and
 * ifo_apply_tr copies them in (three words); ifo_set_tr does the same in
 * fixed point (two _IQdiv) for callers without float.  The divisions are
 * never per sample.
 */
#ifndef IFO_H
#define IFO_H

#include <stdint.h>
#include "IQmathLib.h"
#include "base_values.h"
#include "angle.h"
#include "iq_rmpy.h"

/** Tr must be at least this many samples (keeps kf's series exact to 1e-9). */
#define IFO_TR_MIN_SAMPLES 10.0f
/** Largest accepted Tr, pu time: Tr is held in Q20 (range 2048 pu, LSB
 *  9.5e-7 pu: 2e-7 of the smallest Tr, 10 Ts), so up to 1000 pu
 *  (3.2 s at 50 Hz, 2.7 s at 60 Hz; the largest motors of tens of kW have
 *  Tr of 0.3 to 1 s) with a factor of 2 for the products (Tr imr_min <= 1000,
 *  the adaptation's factor-2 step).  Beyond it kf = 1 - exp(-Ts/Tr) (Q24)
 *  would also lose resolution: Ts/Tr < 5e-5 at the usual 0.05 pu Ts. */
#define IFO_TR_MAX_PU 1000.0f
/** |i_T| is at most the sensor full scale, well below this (pu); the slip
 *  bound I_T_MAX / (Tr imr_min) is checked against IFO_SLIP_MAX at init. */
#define IFO_I_T_MAX 2.0f
#define IFO_SLIP_MAX 64.0f

typedef enum {
    IFO_OK = 0,
    IFO_ERR_BASE,         /* bases NULL or not initialised, or f_base Ts not in (1/2000, 1/128) */
    IFO_ERR_TR,           /* Tr not in [10 Ts, IFO_TR_MAX_PU t_base] */
    IFO_ERR_IMR_MIN       /* imr_min not in (0, 1], or 2 / (Tr imr_min) > 64 */
} ifo_status_t;

typedef struct {
    /* inputs */
    _iq i_m;            /* Q24, M-axis stator current, pu of I_base */
    _iq i_t;            /* Q24, T-axis stator current, pu of I_base */
    _iq wr;             /* Q24, rotor electrical speed, pu of w_base */
    /* parameters */
    _iq20 tr;           /* Q20 (not Q24: large motors' Tr exceeds 128 pu), Tr in pu time
                           (Tr_s * w_base), [10 Ts, IFO_TR_MAX_PU] */
    _iq inv_tr;         /* Q24, 1 / tr: small for a large Tr, 1.7e-5 relative LSB at 1000 pu */
    _iq kf;             /* Q24, 1 - exp(-Ts/Tr) */
    _iq ts;             /* Q24, Ts in pu time */
    _iq30 k_theta;      /* Q30, f_base Ts: revolutions per sample at 1 pu speed */
    _iq30 k_acc;        /* Q30, f_base Ts 2^(32-GLOBAL_Q): the same for an angle_acc_t (angle.h) */
    _iq imr_min;        /* Q24, pu: below it the slip is forced to 0 */
    /* outputs */
    _iq imr;            /* Q24, magnetising current psi_r / Lm, pu of I_base */
    _iq wslip;          /* Q24, slip speed, pu of w_base */
    _iq ws;             /* Q24, M-T frame (synchronous) speed, pu of w_base */
    _iq theta;          /* Q24, flux angle for the next sample, pu [0, 1) */
    angle_acc_t theta_acc; /* state: ifo_step's integral of w_s, 2^32 per revolution (theta's source) */
    _iq theta_prev;     /* Q24, flux angle of this sample, pu [0, 1) */
    uint16_t imr_low;   /* 1 while imr < imr_min (slip forced to 0) */
    /* encoder-angle mode (ifo_frame_from_rotor / ifo_step_slip) */
    _iq theta_r;        /* input, Q24: rotor electrical angle from the encoder, pu [0, 1) */
    angle_acc_t slip_acc; /* state: integral of the slip, 2^32 per revolution (angle.h: the
                           Q24 pu angle's truncated increment was 0.05-0.1 % of a slip's) */
    _iq20 inv_k_theta;  /* parameter, Q20: 1 / (f_base Ts), pu speed per revolution per sample */
    _iq ws_frame;       /* output, Q24: frame speed over the last sample, from the angle step */
    /* multi-rate slip (ifo_update_slip_gain / ifo_step_slip_fast) */
    _iq k_slip;         /* Q24: 1 / (Tr imr), 0 while imr < imr_min; |.| <= 32 */
} ifo_t;

/** The constants that depend on Tr (each one aligned 32-bit word). */
typedef struct {
    _iq20 tr;           /* Q20: Tr, pu time, [10 Ts, IFO_TR_MAX_PU] */
    _iq inv_tr;         /* Q24: 1 / Tr, [1/IFO_TR_MAX_PU, 1/(10 Ts)] */
    _iq kf;             /* Q24: 1 - exp(-Ts/Tr), (0, 0.1] */
} ifo_tr_t;

/**
 * @p Tr_s: rotor time constant, s; @p imr_min_pu: the guard (e.g. 5 % of the
 * rated magnetising current).  Starts demagnetised: imr = 0, theta = 0.
 */
ifo_status_t ifo_init(ifo_t *f, float Tr_s, const base_values_t *b, float imr_min_pu);

/** ifo_init's check of its arguments alone (no struct), before Tr's own
 *  bounds (ifo_design_tr): IFO_ERR_BASE (bases), IFO_ERR_IMR_MIN
 *  (@p imr_min_pu not in (0, 1]), IFO_ERR_TR (Tr above IFO_TR_MAX_PU: the
 *  Q20 headroom), IFO_ERR_BASE (f_base Ts not in (1/2000, 1/128)), in that
 *  order.  The configuration's table of limits calls it too
 *  (drive_limits.c).  Float: init only. */
ifo_status_t ifo_check(float Tr_s, const base_values_t *b, float imr_min_pu);

/** ifo_set_tr's check of a Q20 Tr alone, on the module's Q24 Ts (@p ts_pu,
 *  ifo_t.ts) and guard (@p imr_min_pu, ifo_t.imr_min): IFO_ERR_TR (Tr not
 *  in [10 Ts, IFO_TR_MAX_PU]), then IFO_ERR_IMR_MIN (2 / (Tr imr_min) above
 *  64 pu).  Also the table of limits' test of the believed Tr
 *  (drive_limits.c).  No float. */
ifo_status_t ifo_tr_check(_iq ts_pu, _iq imr_min_pu, _iq20 tr_pu);

/**
 * Change Tr (pu time, Q20, e.g. from the identification).  No float: 1/Tr
 * and Ts/Tr by _IQ20div (Q24 / Q20 -> Q24, truncated, < 1 LSB), kf =
 * 1 - exp(-x) by its Taylor series to x^5/120 (x = Ts/Tr <= 0.1: truncation
 * error < x^6/720 = 1.4e-9, below 1 LSB).  Rejects (and keeps the old Tr)
 * if Tr < 10 Ts, Tr > IFO_TR_MAX_PU or if the slip bound 2 / (Tr imr_min)
 * would exceed 64 pu.
 */
ifo_status_t ifo_set_tr(ifo_t *f, _iq20 tr_pu);

/**
 * The Tr constants from pu floats (float: not in the ISR), as ifo_init
 * computes them: Tr, 1/Tr, kf = 1 - exp(-x), x = Ts/Tr, by its series to
 * x^5/120 (error < 1.4e-9 at x <= 0.1), Tr to Q20 by _IQ20, 1/Tr and kf
 * to Q24 by _IQ (truncation, < 1 LSB, plus the float's relative 6e-8).  The
 * bounds of ifo_set_tr: Tr in [10 Ts, IFO_TR_MAX_PU] (IFO_ERR_TR) and 2 / (Tr imr_min) <= 64 with
 * @p imr_min_pu the guard ifo_init was given (IFO_ERR_IMR_MIN); a refused
 * Tr leaves @p t as it was.
 */
ifo_status_t ifo_design_tr(ifo_tr_t *t, float ts_pu, float tr_pu, float imr_min_pu);

/** Copy a Tr set in (ISR: three word copies). */
static inline void ifo_apply_tr(ifo_t *f, const ifo_tr_t *t)
{
    f->tr = t->tr;
    f->inv_tr = t->inv_tr;
    f->kf = t->kf;
}

/** Restart demagnetised at angle @p theta0 (pu, [0, 1)). */
void ifo_reset(ifo_t *f, _iq theta0);

/**
 * One sample.  Scaling and overflow: imr += kf (i_m - imr) with a rounded
 * product: imr settles within 0.5/kf LSB of i_m (Tr = 19.8 ms at 15 kHz:
 * kf = 0.00336, 149 LSB = 9e-6 pu; a 55 kW motor's Tr = 0.93 s: kf = 7.2e-5,
 * 6900 LSB = 4e-4 pu, 0.1 % of its i_M: the slip as with Tr 0.1 % off).  Slip: (i_t / Tr) / imr with
 * imr >= imr_min, so |wslip| <= 2 / (Tr imr_min) <= 64 (checked at init);
 * ws = wr + wslip (|wr| <= 63 assumed: qep_speed saturates there), so
 * |ws| < 128; with f_base Ts < 1/128 (checked at init) the angle
 * increment is below one revolution.  The angle is integrated in a phase
 * accumulator (theta_acc, 2^32 per revolution, wrapping: angle.h), the
 * increment truncated to 2^-32 of a revolution in both builds; theta is its
 * top 24 bits, rounded (< 0.5 LSB, not accumulated).
 */
void ifo_step(ifo_t *f);

/** The angle at the middle of the last sample period, (theta_prev + theta)/2
 *  taken along the shorter arc (correct across the 1 -> 0 wrap), in [0, 1). */
_iq ifo_theta_mid(const ifo_t *f);

/* Wrap a Q24 angle that is within one revolution of [0, 1) back into it
 * (angle.h: by a mask in IQ_MATH, exact in both builds). */
static inline _iq ifo_wrap(_iq th)
{
    return angle_wrap_unit(th);
}

/**
 * Encoder-angle mode: the flux angle is the measured rotor angle plus the
 * integrated slip, theta(k) = theta_r(k) + sum(w_slip Ts).  The speed
 * measurement's lag then never enters the angle: with a lagging speed
 * (ifo_step) the angle error under acceleration a is about a * lag * Tr, which
 * the regression sees amplified by w_r Tr (method §7 point 4); here it is 0.
 *
 * Per sample: ifo_frame_from_rotor() at the start (theta_r set), which sets
 * theta_prev = theta(k-1), theta = theta(k) and ws_frame = the frame's actual
 * speed over the last period (its angle step / (f_base Ts): exactly the
 * rotation the M-T quantities saw); then, after the current control,
 * ifo_step_slip() (i_m, i_t, wr set), which updates imr, wslip, ws = wr + wslip
 * (for decoupling and modulation) and the slip angle for sample k+1.
 * Scaling: the slip angle is a phase accumulator (slip_acc, 2^32 per
 * revolution: angle.h), read as Q24 rounded; the sum with theta_r wraps
 * modulo 1 pu exactly (ifo_wrap); ws_frame
 * saturates at +-(0.5 / (f_base Ts)) pu, half a revolution per sample.
 */
static inline void ifo_frame_from_rotor(ifo_t *f)
{
    f->theta_prev = f->theta;
    /* both in [0, 1): no overflow */
    f->theta = ifo_wrap(f->theta_r + angle_acc_pu(f->slip_acc));
    /* Q24 * Q20 -> Q24; |d| <= 0.5 and 1/(f_base Ts) < 256 keep |result| < 128 */
    f->ws_frame = _IQmpyIQX(angle_diff_pu(f->theta, f->theta_prev), GLOBAL_Q,
                            f->inv_k_theta, 20);
}
void ifo_step_slip(ifo_t *f);

/**
 * The same current model, split for a multi-rate ISR so that the division
 * runs at the slow rate only:
 *  - ifo_update_slip_gain() (slow): k_slip = 1/(Tr imr) by one _IQdiv, or
 *    0 while imr < imr_min (imr_low set).  imr moves with the time constant
 *    Tr >= 10 Ts, so between two updates (a few samples) the gain changes
 *    by at most a few Ts/Tr of (i_M - imr)/imr: nothing in steady state.
 *  - ifo_step_slip_fast() (every sample): imr += kf (i_m - imr), wslip =
 *    i_t k_slip, ws = wr + wslip, the slip angle as ifo_step_slip;
 *    ifo_slip_fast() the same of i_m, i_t, wr given as arguments (the
 *    ISR's, without copying them into the struct; i_m, i_t, wr are then
 *    left as they were).
 * Scaling: k_slip = inv_tr / imr <= 1/(Tr imr_min) <= 32 (ifo_set_tr's
 * bound 2/(Tr imr_min) <= 64); |i_t| <= IFO_I_T_MAX = 2 keeps |wslip| <= 64
 * (i_t saturated there), ws and the angle as ifo_step_slip.
 */
void ifo_update_slip_gain(ifo_t *f);
static inline void ifo_slip_fast(ifo_t *f, _iq i_m, _iq i_t, _iq wr)
{
    const _iq imr = f->imr;
    _iq wslip;
    /* rotor flux lag, as ifo_update_flux (rounded, |i_m - imr| < 4 pu) */
    f->imr = imr + iq_rmpy(f->kf, i_m - imr);
    /* Q24*Q24 -> Q24: |i_t| <= 2, k_slip <= 32.  The limit acts: i_t is
     * the measured current, up to the trip level (32 pu) in a fault */
    wslip = _IQmpy(_IQsat(i_t, _IQ(IFO_I_T_MAX), _IQ(-IFO_I_T_MAX)), f->k_slip);
    f->wslip = wslip;
    f->ws = wr + wslip;
    /* Q24 * Q30 -> Q24 (truncated), wrapped modulo one revolution */
    f->slip_acc = angle_acc_step(f->slip_acc, wslip, f->k_acc);
}

/** ifo_slip_fast of the struct's inputs i_m, i_t, wr. */
static inline void ifo_step_slip_fast(ifo_t *f)
{
    ifo_slip_fast(f, f->i_m, f->i_t, f->wr);
}

/**
 * Take over from another frame without a jump (encoder-angle mode): with
 * theta_r set to this sample's rotor angle, the slip angle becomes
 * theta_frame - theta_r, so ifo_frame_from_rotor() continues from
 * @p theta_frame, and imr = @p imr_pu (the flux the other frame saw, in
 * magnetising-current pu).  theta_prev = theta (ws_frame 0 for this sample).
 * Angles in [0, 1) pu; imr_pu clamped to [0, 4].
 */
void ifo_align(ifo_t *f, _iq theta_frame, _iq imr_pu);

#endif /* IFO_H */
