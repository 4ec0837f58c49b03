/**
 * @file ipark.h
 * Inverse Park transform (rotating d-q frame at angle theta -> alpha-beta).
 *
 *   alpha = ds cos(theta) - qs sin(theta)
 *   beta  = ds sin(theta) + qs cos(theta)
 *
 * Used on the current controllers' voltage outputs before svgen_t.  sine and
 * cosine are the pair computed once per sample by angle_sincos() (angle.h)
 * and shared with park_t.
 *
 * Valid input range: |ds|, |qs| <= 64 pu; sine, cosine in [-1, 1] with
 * sine^2 + cosine^2 = 1 (to a few LSB), so |alpha|, |beta| <= 90.5 < 128.
 */
#ifndef IPARK_H
#define IPARK_H

#include "IQmathLib.h"

typedef struct {
    /* inputs */
    _iq ds;      /* d (M) component, pu, Q24, |ds| <= 64 */
    _iq qs;      /* q (T) component, pu, Q24, |qs| <= 64 */
    _iq sine;    /* sin(theta), Q24, [-1, 1] */
    _iq cosine;  /* cos(theta), Q24, [-1, 1] */
    /* outputs */
    _iq alpha;   /* pu, Q24 */
    _iq beta;    /* pu, Q24 */
} ipark_t;

/** Clear inputs and outputs (no parameters or state). */
void ipark_init(ipark_t *p);

/**
 * One sample, of arguments into the caller's variables (no struct: the
 * modulator rotates the current loops' outputs straight into its own
 * inputs).  Scaling: each output is the sum or difference of two
 * Q24*Q24 -> Q24 truncated products, so it lies within [-2, +1] LSB of the
 * exact value computed from the same inputs (alpha: [-1, +1], a difference
 * of two floor()s; beta: [-2, 0]).  Overflow: none in the valid range;
 * outside it the sums wrap.
 */
static inline void ipark_rotate(_iq ds, _iq qs, _iq sine, _iq cosine, _iq *alpha, _iq *beta)
{
    /* Q24*Q24 -> Q24, truncated; each |product| <= 64, each sum <= 90.5 */
    *alpha = _IQmpy(ds, cosine) - _IQmpy(qs, sine);
    *beta = _IQmpy(ds, sine) + _IQmpy(qs, cosine);
}

/** ipark_rotate of the struct's inputs into its outputs. */
static inline void ipark_step(ipark_t *p)
{
    ipark_rotate(p->ds, p->qs, p->sine, p->cosine, &p->alpha, &p->beta);
}

#endif /* IPARK_H */
