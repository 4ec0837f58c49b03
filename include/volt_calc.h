/**
 * @file volt_calc.h
 * Stator phase voltages reconstructed from the measured DC bus and the duty
 * cycles applied during the last PWM period (no voltage sensors), as the
 * paper's F2812 rig does (method §6), with optional dead-time and
 * device-drop compensation.
 *
 * Pole voltage of phase x (leg output to the negative rail, period average):
 *   ideal:        p_x = vdc d_x
 *   inverter:     with centre-aligned PWM and dead time td, while i_x > 0
 *                 (out of the leg) the lower diode conducts during the dead
 *                 time and the pole loses vdc td/Ts, plus the device drop
 *                 v_drop; while i_x < 0 it gains the same.
 *   compensated:  p_x = vdc d_x - (sgn(i_x1) + sgn(i_x2)) e_x / 2,
 *                 e_x = vdc td/Ts + v_drop             (0 < d_x < 1)
 *                 e_x = v_drop                         (d = 0 or 1: a clamped
 *                                                       leg has no edge)
 *                 where i_x1, i_x2 are the currents at the two switching
 *                 edges, (1 - d_x)/2 and (1 + d_x)/2 into the period; with
 *                 the current linear over the period (mid value i_x, change
 *                 di_x from the two samples that bound it),
 *                 i_x1,2 = i_x -+ (d_x/2) di_x.  Each edge carries half the
 *                 period's error: near a zero crossing the two edges can see
 *                 opposite signs, and the error is that of the edges' mean
 *                 sign (for the drop, which follows the current through the
 *                 period, the mean of the edges' signs is the mean sign of a
 *                 current that crosses zero between them, to first order).
 *                 With di = 0 this is sgn(i_x) (vdc td/Ts + v_drop), the
 *                 error a steady current sees (what a standstill measurement
 *                 of the bridge gives).
 * sgn() has a linear zone: sgn(i) = sat(i / i_thresh, -1, 1), so that noise
 * near a zero crossing does not make the estimate chatter (and the average
 * error there, which does shrink near zero current, is followed smoothly).
 * ic = -ia - ib (three-wire star).
 *
 * Phase-to-neutral of the floating star: the common mode is removed,
 *   v_x = p_x - (p_a + p_b + p_c) / 3,
 * then valpha = va, vbeta = (vb - vc) / sqrt(3) (amplitude-invariant Clarke).
 *
 * Timing: the compare values computed in ISR k are shadowed and act during
 * period k+1, so ISR k+2 must pass the duties computed in ISR k together
 * with the bus voltage and currents of that period.
 *
 * Valid input range: d_x in [0, 1]; vdc in [0, 16] pu (nominal sqrt(3));
 * |ia|, |ib| <= 32 pu.  Poles are then within [-5, 21] pu and every sum
 * below 64.
 */
#ifndef VOLT_CALC_H
#define VOLT_CALC_H

#include <stdint.h>
#include "IQmathLib.h"
#include "foc_const.h"

/** Largest dead-time fraction td/Ts accepted. */
#define VOLT_CALC_DT_FRAC_MAX 0.25f
/** Largest device drop accepted, pu of V_base. */
#define VOLT_CALC_DROP_MAX_PU 1.0f
/** Range of the sign threshold, pu of I_base (1/i_thresh must fit Q24). */
#define VOLT_CALC_ITH_MIN_PU 0.0005f
#define VOLT_CALC_ITH_MAX_PU 1.0f

typedef enum {
    VOLT_CALC_OK = 0,
    VOLT_CALC_ERR_PERIOD,     /* Ts_s NaN or not > 0 */
    VOLT_CALC_ERR_DEADTIME,   /* dead_time_s NaN, < 0, or td/Ts > VOLT_CALC_DT_FRAC_MAX */
    VOLT_CALC_ERR_DROP,       /* drop_pu NaN, < 0 or > VOLT_CALC_DROP_MAX_PU */
    VOLT_CALC_ERR_THRESH,     /* i_thresh_pu NaN or outside [ITH_MIN, ITH_MAX] */
    VOLT_CALC_ERR_ENABLE      /* comp_enable not 0 or 1 */
} volt_calc_status_t;

typedef struct {
    /* inputs */
    _iq da;            /* applied upper-switch duty, phase a, Q24, [0, 1] */
    _iq db;            /* phase b, Q24, [0, 1] */
    _iq dc;            /* phase c, Q24, [0, 1] */
    _iq vdc;           /* DC bus during that period, pu of V_base, Q24, [0, 16] */
    _iq ia;            /* phase-a current in mid-period, pu, Q24, |.| <= 32 */
    _iq ib;            /* phase-b current, pu, Q24, |.| <= 32 */
    _iq dia;           /* change of ia over the period (end - start), pu, Q24, |.| <= 32 */
    _iq dib;           /* change of ib over the period, pu, Q24, |.| <= 32 */
    /* parameters */
    uint16_t comp_enable; /* 1: dead-time / drop compensation on */
    _iq dt_frac;       /* td / Ts, Q24, [0, 0.25] */
    _iq dt_half;       /* td / (2 Ts): the error of one edge, Q24 */
    _iq v_drop;        /* device forward drop, pu of V_base, Q24, [0, 1] */
    _iq v_drop_half;   /* v_drop / 2, Q24 */
    _iq i_thresh;      /* half-width of the linear zone of sgn(), pu, Q24 */
    _iq16 inv_i_thresh;/* 1 / i_thresh, Q16, [1, 2000] */
    /* outputs */
    _iq va;            /* phase-to-neutral voltages, pu of V_base, Q24 */
    _iq vb;
    _iq vc;
    _iq valpha;        /* stator voltage, alpha, pu, Q24 */
    _iq vbeta;         /* stator voltage, beta, pu, Q24 */
} volt_calc_t;

/** The bridge's error as the compensation uses it: what the standstill
 *  measurement (vi_curve.h) decides, designed in float (background) and
 *  copied in by the ISR (volt_calc_apply_curve), all in one sample. */
typedef struct {
    _iq dt_frac;       /* td / Ts, Q24 */
    _iq dt_half;       /* td / (2 Ts), Q24 */
    _iq v_drop;        /* pu, Q24 */
    _iq v_drop_half;   /* pu, Q24 */
    _iq i_thresh;      /* pu, Q24 */
    _iq16 inv_i_thresh;/* Q16 */
} volt_calc_curve_t;

/**
 * The constants of a dead-time fraction, drop and linear zone (float: not
 * in the ISR), with volt_calc_init's checks; @p k is left as it was on an
 * error.
 */
volt_calc_status_t volt_calc_curve_design(volt_calc_curve_t *k, float dt_frac, float drop_pu,
                                          float i_thresh_pu);

/** Copy a designed curve in and turn the compensation on (ISR: six words). */
static inline void volt_calc_apply_curve(volt_calc_t *v, const volt_calc_curve_t *k)
{
    v->dt_frac = k->dt_frac;
    v->dt_half = k->dt_half;
    v->v_drop = k->v_drop;
    v->v_drop_half = k->v_drop_half;
    v->i_thresh = k->i_thresh;
    v->inv_i_thresh = k->inv_i_thresh;
    v->comp_enable = 1u;
}

/** volt_calc_init's check of its arguments alone (no struct), the status it
 *  would return: _PERIOD, _DEADTIME (td < 0 or td/Ts above
 *  VOLT_CALC_DT_FRAC_MAX), _DROP, _THRESH, _ENABLE, in that order.  The
 *  configuration's table of limits calls it too (drive_limits.c).  Float:
 *  init only. */
volt_calc_status_t volt_calc_check(float dead_time_s, float Ts_s, float drop_pu,
                                   float i_thresh_pu, uint16_t comp_enable);

/**
 * Compute the constants from SI times and pu drop/threshold and clear the
 * rest.  dead_time_s: programmed dead band; Ts_s: PWM period; drop_pu:
 * switch/diode forward drop in pu of V_base; i_thresh_pu: half-width of the
 * linear zone of sgn(); comp_enable: 0 or 1.  On an error the struct is
 * left zeroed (compensation off) and the first offending argument is named.
 */
volt_calc_status_t volt_calc_init(volt_calc_t *v, float dead_time_s, float Ts_s,
                                  float drop_pu, float i_thresh_pu, uint16_t comp_enable);

/* sgn(i) with a linear zone of half-width i_thresh is sat(i / i_thresh, +-1)
 * = sat(i, +-i_thresh) / i_thresh: the current limited to the zone (one
 * saturation, no branch, no product), scaled by 1/i_thresh (Q16: a zone
 * down to 0.0005 pu, a large drive's dead-time transition of a few tenths
 * of an ampere) only where the limited currents have been combined
 * (volt_calc_leg_error: one Q24*Q16 -> Q24 product per leg instead of one
 * per edge) or where it is used (volt_calc_feedforward).  The product of a limited
 * current is within [-1, 1] whatever |i| (1/i_thresh is rounded down:
 * volt_calc_init), and at and beyond the zone's edge below 1 by at most
 * i_thresh 2^8 + 1 LSB (the inverse's rounding and the product's
 * truncation): 6 LSB at 0.02 pu, far below what it multiplies reaches (an
 * error of e_half < 0.2 pu: < 2 LSB).  th, nth: +-i_thresh (the caller
 * loads them once per sample). */
static inline _iq volt_calc_zone(_iq i, _iq th, _iq nth)
{
    return _IQsat(i, th, nth);   /* |.| <= i_thresh <= 1 pu */
}

/* Mean pole-voltage error of one leg over the period (volt_calc_step):
 * (sgn(i_mid - h) + sgn(i_mid + h)) e_half, h = d di_half = (d/2) di, the
 * edges' currents; e_half = (vdc td/Ts + v_drop)/2 for a switching leg,
 * v_drop/2 for a clamped one.  The two limited currents are summed first
 * (exact: |.| <= 2 i_thresh) and scaled by 1/i_thresh once (Q24*Q16 ->
 * Q24, |.| <= 2), then by e_half: 2 saturations and 3 products, no branch.
 * |h| <= 16, |i_mid -+ h| <= 48 pu; the result |.| <= 5 pu. */
static inline _iq volt_calc_leg_error(_iq th, _iq nth, _iq16 inv_th, _iq i_mid, _iq di_half,
                                      _iq d, _iq e_half)
{
    const _iq h = _IQmpy(d, di_half);   /* Q24*Q24 -> Q24 */
    const _iq z = volt_calc_zone(i_mid - h, th, nth) + volt_calc_zone(i_mid + h, th, nth);
    return _IQmpy(_IQmpyIQX(z, GLOBAL_Q, inv_th, 16), e_half);
}

/* e_half for a leg with duty d: the drop alone when the leg is clamped
 * (d <= 0 or d >= 1: SVPWM clamps only in over-modulation).  IQ_MATH: 0 <
 * d < 1 as one unsigned compare of d - 1 LSB against 1 - 1 LSB (d <= 0
 * wraps to a large unsigned value). */
static inline _iq volt_calc_leg_e(_iq d, _iq e_switching, _iq e_clamped)
{
#if MATH_TYPE == IQ_MATH
    return ((uint32_t)d - 1u < (uint32_t)_IQ(1.0) - 1u) ? e_switching : e_clamped;
#else
    return (d > _IQ(0.0) && d < _IQ(1.0)) ? e_switching : e_clamped;
#endif
}

/**
 * One sample.  Scaling: poles vdc*d are Q24*Q24 -> Q24 truncated products;
 * the common mode is (sum)*(1/3 as Q30), vbeta (vb - vc)*(1/sqrt(3) as
 * Q30), both truncated to Q24.  Without compensation va, vb, vc and valpha
 * are within 3.05 LSB, vbeta within 2.2 LSB of the exact formula of the
 * same inputs (over the valid range).  The compensation adds to each pole
 * the truncations of vdc*td/Ts, of (the two edges' limited currents) /
 * i_thresh (times verr) and of that times e_half: at most 2 + verr LSB
 * more per pole, 4 + 2 verr LSB in va.  Overflow: none in the valid range
 * (every intermediate below 64 pu); the signs are saturated to [-1, 1].
 * Per sample: 3 products for the poles, 1 for the switching error, 2
 * saturations and 3 products for each leg's compensation, 2 for the
 * Clarke transform: the same on every sample.  Every input and parameter
 * is read once (locals).
 */
static inline void volt_calc_step(volt_calc_t *v)
{
    const _iq vdc = v->vdc;
    const _iq da = v->da;
    const _iq db = v->db;
    const _iq dc = v->dc;
    /* Pole voltages: Q24*Q24 -> Q24, truncated, in [0, 16] */
    _iq pa = _IQmpy(vdc, da);
    _iq pb = _IQmpy(vdc, db);
    _iq pc = _IQmpy(vdc, dc);
    _iq cm, vb, vc;

    if (v->comp_enable != 0u) {
        /* Dead time: each of the two switching edges of a centre-aligned
         * period, at (1 -+ d)/2 Ts, loses (current out of the leg) or gains
         * vdc td/2 by the sign of the current at that edge; with the current
         * linear over the period, i_edge = i_mid -+ (d/2) di.  The device
         * drop follows the period-mean current.  Q24*Q24 -> Q24 products,
         * |vdc td/Ts| <= 4, |(d/2) di| <= 32, |i_edge| <= 64 pu. */
        const _iq th = v->i_thresh;
        const _iq nth = -th;
        const _iq16 inv_th = v->inv_i_thresh;
        const _iq ia = v->ia;
        const _iq ib = v->ib;
        const _iq e_cl = v->v_drop_half;
        const _iq e_sw = _IQmpy(vdc, v->dt_half) + e_cl;   /* (vdc td/Ts + v_drop)/2 */
        const _iq dia_h = _IQdiv2(v->dia);                 /* |.| <= 16 */
        const _iq dib_h = _IQdiv2(v->dib);
        pa -= volt_calc_leg_error(th, nth, inv_th, ia, dia_h, da, volt_calc_leg_e(da, e_sw, e_cl));
        pb -= volt_calc_leg_error(th, nth, inv_th, ib, dib_h, db, volt_calc_leg_e(db, e_sw, e_cl));
        pc -= volt_calc_leg_error(th, nth, inv_th, _IQ(0.0) - ia - ib, _IQ(0.0) - dia_h - dib_h,
                                  dc, volt_calc_leg_e(dc, e_sw, e_cl));
    }

    /* Common mode of the floating star: (pa + pb + pc)/3, sum <= 63.
     * Q24*Q30 -> Q24. */
    cm = _IQmpyIQX(pa + pb + pc, GLOBAL_Q, FOC_ONE_THIRD_Q30, 30);
    vb = pb - cm;
    vc = pc - cm;
    v->va = pa - cm;
    v->vb = vb;
    v->vc = vc;
    v->valpha = v->va;
    /* vbeta = (vb - vc)/sqrt(3), Q24*Q30 -> Q24; |vb - vc| = |pb - pc| <= 26 */
    v->vbeta = _IQmpyIQX(vb - vc, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30);
}

/**
 * Dead-time and drop feed-forward for the modulator: the alpha-beta voltage
 * the bridge will lose in a period whose phase currents are ia, ib (and
 * -ia-ib), so that the reference plus this is what the duties must ask for.
 * Same sgn() and constants as the reconstruction; zero with comp_enable 0.
 * Each leg's error is sgn(i_x) verr: the limited current times 1/i_thresh
 * (Q24*Q16 -> Q24, in [-1, 1]), times verr (Q24*Q24 -> Q24, |.| <= 5 pu),
 * each truncated; the parameters are read once.  Scaling: |e_x| <= 5 pu,
 * sums <= 15, Q24*Q30 -> Q24; no overflow for vdc in [0, 16] pu.
 */
static inline void volt_calc_feedforward(const volt_calc_t *v, _iq vdc, _iq ia, _iq ib,
                                         _iq *dalpha, _iq *dbeta)
{
    _iq th, nth, ea, eb, ec, cm, verr;
    _iq16 inv_th;
    if (v->comp_enable == 0u) {
        *dalpha = _IQ(0.0);
        *dbeta = _IQ(0.0);
        return;
    }
    th = v->i_thresh;
    nth = -th;
    inv_th = v->inv_i_thresh;
    /* the pole error of a leg carrying i_x: vdc td/Ts + v_drop, <= 5 pu */
    verr = _IQmpy(vdc, v->dt_frac) + v->v_drop;
    ea = _IQmpy(_IQmpyIQX(volt_calc_zone(ia, th, nth), GLOBAL_Q, inv_th, 16), verr);
    eb = _IQmpy(_IQmpyIQX(volt_calc_zone(ib, th, nth), GLOBAL_Q, inv_th, 16), verr);
    ec = _IQmpy(_IQmpyIQX(volt_calc_zone(_IQ(0.0) - ia - ib, th, nth), GLOBAL_Q, inv_th, 16),
                verr);
    /* floating star: remove the common mode; Clarke (amplitude-invariant) */
    cm = _IQmpyIQX(ea + eb + ec, GLOBAL_Q, FOC_ONE_THIRD_Q30, 30);
    *dalpha = ea - cm;
    *dbeta = _IQmpyIQX(eb - ec, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30);
}

#endif /* VOLT_CALC_H */
