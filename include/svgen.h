/**
 * @file svgen.h
 * Space-vector PWM by min-max zero-sequence injection, with the DC bus
 * measured (not assumed) and over-modulation onto the hexagon.
 *
 * Phase references of the stator voltage vector (amplitude-invariant inverse
 * Clarke, pu of V_base):
 *   va = ualpha,  vb = -ualpha/2 + (sqrt(3)/2) ubeta,  vc = -ualpha/2 - (sqrt(3)/2) ubeta
 * Zero sequence: v0 = -(max(v) + min(v)) / 2.  Upper-switch duty of phase x:
 *   d_x = 1/2 + (v_x + v0) / vdc
 * This centres the three pole voltages in the bus, which is exactly the
 * classical symmetric SVPWM (sector, dwell times T1, T2, the zero-vector
 * time split equally between 000 and 111) without computing the sector.
 * Full bus utilisation: it is linear as long as max(v) - min(v) <= vdc,
 * i.e. up to the hexagon; the inscribed circle has radius vdc/sqrt(3)
 * (= 1.0 pu at the nominal bus sqrt(3) pu, base_values.h).
 *
 * Over-modulation: if max(v) - min(v) > vdc the vector is outside the
 * hexagon; it is scaled along its own direction (angle preserved) by
 * vdc / (max(v) - min(v)), which puts it on the hexagon boundary: one phase
 * then has duty 1 and another duty 0.  overmod = 1 flags it.
 * Both cases are one formula: d_x = 1/2 + (v_x + v0) / max(vdc, max - min).
 *
 * Bus fault: vdc < SVGEN_VDC_MIN_PU (zero, negative, or collapsed) gives
 * 50 % duty on every phase (zero line-to-line voltage) and vdc_fault = 1.
 *
 * Compare values, convention of hal_pwm.h (d = (T1PR - CMPR) / T1PR):
 *   CMPR_x = T1PR - round(d_x T1PR), always within [0, T1PR].
 *
 * Valid input range: |ualpha|, |ubeta| <= 32 pu (then |max - min| <= 78,
 * |max + min| <= 91); vdc any value in [-128, 128) (below the guard it is a
 * fault; above it only its size relative to the reference matters).
 */
#ifndef SVGEN_H
#define SVGEN_H

#include <stdint.h>
#include "IQmathLib.h"
#include "foc_const.h"

/** Below this bus voltage (pu of V_base; 3 % of the nominal sqrt(3) pu) the
 *  bus is treated as failed: 50 % duty, vdc_fault = 1.  It also bounds
 *  1/vdc to 20, far from Q24 overflow. */
#define SVGEN_VDC_MIN_PU 0.05f

typedef enum {
    SVGEN_OK = 0,
    SVGEN_ERR_PERIOD   /* t1pr == 0 */
} svgen_status_t;

typedef struct {
    /* inputs */
    _iq ualpha;        /* stator voltage reference, alpha, pu of V_base, Q24, |.| <= 32 */
    _iq ubeta;         /* stator voltage reference, beta,  pu of V_base, Q24, |.| <= 32 */
    _iq vdc;           /* measured DC bus, pu of V_base, Q24 (nominal sqrt(3)) */
    /* parameters */
    uint16_t t1pr;     /* EV-A T1 period register (up/down count), e.g. 5000
                          for 15 kHz at 150 MHz */
    int32_t t1pr_x2;   /* 2 T1PR, integer, for the rounding of the compares */
    _iq vdc_min;       /* _IQ(SVGEN_VDC_MIN_PU), Q24 */
    /* outputs */
    _iq da;            /* upper-switch duty, phase a, Q24, [0, 1] */
    _iq db;            /* phase b, Q24, [0, 1] */
    _iq dc;            /* phase c, Q24, [0, 1] */
    uint16_t cmpr[3];  /* CMPR1..3, integer, [0, T1PR] */
    uint16_t overmod;  /* 1 when the reference was clamped onto the hexagon */
    uint16_t vdc_fault;/* 1 when vdc < SVGEN_VDC_MIN_PU (outputs 50 %) */
    /* state: 1/vdc of the last vdc seen, so that a caller who changes vdc
     * at a lower rate than it steps (the multi-rate ISR) divides only then */
    _iq vdc_seen;      /* Q24: the vdc inv_vdc belongs to (0: none yet) */
    _iq inv_vdc;       /* Q24: 1 / vdc_seen, <= 20 */
} svgen_t;

/** Set the period and clear inputs and outputs (outputs start at 50 %). */
svgen_status_t svgen_init(svgen_t *s, uint16_t t1pr);

/** Set the bus (Q24 pu) and, when it changed and is usable (>= vdc_min),
 *  its reciprocal now, so that svgen_step divides only beyond the linear
 *  range: the multi-rate schedule sets the bus in a slow task, and the
 *  control ISR that steps next never carries the division.  Scaling: one
 *  _IQdiv, 1/vdc <= 1/SVGEN_VDC_MIN_PU in Q24 (no saturation); a bus below
 *  vdc_min is stored as it is (svgen_step's bus fault). */
void svgen_set_vdc(svgen_t *s, _iq vdc);

/* CMPR = T1PR - round(d T1PR), d in [0, 1] (Q24).
 * round(d N) = floor(d N + 1/2) = floor((floor(2 d N) + 1) / 2), because
 * floor(y/2) = floor(floor(y)/2) for any real y.  floor(2 d N) is the
 * product of d's raw integer and the integer 2 N, shifted right by GLOBAL_Q:
 * _IQmpyIQX(d, GLOBAL_Q, 2N, GLOBAL_Q) with 2N's raw integer as the second operand
 * (the 5-cycle intrinsic; 64-bit product < 2^41, result in [0, 2N]).  In
 * FLOAT_MATH the same product in float, truncated by the cast. */
static inline uint16_t svgen_compare(const svgen_t *s, _iq d)
{
#if MATH_TYPE == IQ_MATH
    const int32_t twice = (int32_t)_IQmpyIQX(d, GLOBAL_Q, s->t1pr_x2, GLOBAL_Q);   /* [0, 2 T1PR] */
#else
    const int32_t twice = (int32_t)(d * (float)s->t1pr_x2);
#endif
    /* twice >= 0 (d >= 0): the halving as an unsigned shift */
    const uint32_t on = ((uint32_t)twice + 1u) >> 1;                     /* [0, T1PR] */
    return (uint16_t)((uint32_t)s->t1pr - on);
}

/**
 * One sample.  Scaling: one _IQdiv (1 / max(vdc, max - min); in the
 * linear range 1/vdc is kept from the last sample with the same vdc, so a
 * vdc that changes every N samples costs one division per N) and three
 * Q24*Q24 -> Q24 products per sample; with div = max(vdc, max - min) each
 * duty is within 2 + div/2 + 4/div LSB of the exact SVPWM duty (the
 * truncation of the product, the < 1 LSB error of the reciprocal times
 * |v_x + v0| <= div/2, and the few-LSB truncations of the phase references
 * divided by div): 5.2 LSB at the nominal bus sqrt(3) pu (2.8 measured).
 * Overflow: none; every duty is saturated to [0, 1] (a guard against the
 * last LSB; the formula itself is within [0, 1]), so every compare value
 * is within [0, T1PR].
 * Not inline: the control ISR's modulation and the tests' voltages
 * (drive_vi.c, never in the same ISR) share one copy of its code (about
 * 190 words of RAM) for one call per ISR.
 */
void svgen_step(svgen_t *s);

#endif /* SVGEN_H */
