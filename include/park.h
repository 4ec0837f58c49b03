/**
 * @file park.h
 * Park transform (alpha-beta -> rotating d-q frame at angle theta).
 *
 *   ds =  alpha cos(theta) + beta sin(theta)
 *   qs = -alpha sin(theta) + beta cos(theta)
 *
 * In the rotor-flux-oriented drive d = M (flux) and q = T (torque), method
 * §1.  sine/cosine are computed once per sample by the caller
 * (angle_sincos(), angle.h) and shared with ipark_t.
 *
 * Valid input range: |alpha|, |beta| <= 64 pu; sine, cosine in [-1, 1]
 * with sine^2 + cosine^2 = 1 (within a few LSB, as _IQsinPU/_IQcosPU give),
 * so |ds|, |qs| <= sqrt(2) * 64 = 90.5 < 128.
 */
#ifndef PARK_H
#define PARK_H

#include "IQmathLib.h"

typedef struct {
    /* inputs */
    _iq alpha;   /* pu, Q24, |alpha| <= 64 */
    _iq beta;    /* pu, Q24, |beta| <= 64 */
    _iq sine;    /* sin(theta), Q24, [-1, 1] */
    _iq cosine;  /* cos(theta), Q24, [-1, 1] */
    /* outputs */
    _iq ds;      /* d (M) component, pu, Q24 */
    _iq qs;      /* q (T) component, pu, Q24 */
} park_t;

/** Clear inputs and outputs (no parameters or state). */
void park_init(park_t *p);

/**
 * One sample of the currents alpha, beta given as arguments (the caller
 * need not copy them into the struct first), at the struct's sine and
 * cosine; writes ds, qs.  Scaling: each output is the sum of two Q24*Q24 -> Q24
 * products, each truncated (_IQmpy), so it lies within [-2, 0] LSB of the
 * exact value computed from the same inputs.  Overflow: none in the valid
 * range (each product <= 64, each sum <= 90.5); outside it the sums wrap.
 */
static inline void park_rotate(park_t *p, _iq alpha, _iq beta)
{
    const _iq s = p->sine;
    const _iq c = p->cosine;
    /* Q24*Q24 -> Q24, truncated; each |product| <= 64, each sum <= 90.5 */
    p->ds = _IQmpy(alpha, c) + _IQmpy(beta, s);
    p->qs = _IQmpy(beta, c) - _IQmpy(alpha, s);
}

/** park_rotate of the struct's own alpha, beta. */
static inline void park_step(park_t *p)
{
    park_rotate(p, p->alpha, p->beta);
}

#endif /* PARK_H */
