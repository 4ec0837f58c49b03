/**
 * @file clarke.h
 * Clarke transform (abc -> alpha-beta, amplitude invariant) for a balanced
 * three-wire machine: ic = -ia - ib, so two measured phases suffice.
 *
 *   alpha = as
 *   beta  = (as + 2 bs) / sqrt(3)
 *
 * Amplitude invariant: a balanced set of peak I gives |alpha + j beta| = I,
 * so the alpha-beta and (after park) d-q currents keep the per-unit base of
 * the phase currents (I_base, base_values.h).
 *
 * Valid input range: |as|, |bs| <= 64 pu (then |beta| <= 110.9 < 128).  The
 * currents that reach it from the ADC are within +-1 pu (sensor full scale =
 * I_base), far inside.
 */
#ifndef CLARKE_H
#define CLARKE_H

#include "IQmathLib.h"
#include "foc_const.h"

typedef struct {
    /* inputs */
    _iq as;      /* phase-a current, pu, Q24, |as| <= 64 */
    _iq bs;      /* phase-b current, pu, Q24, |bs| <= 64 */
    /* outputs */
    _iq alpha;   /* alpha-axis current, pu, Q24 */
    _iq beta;    /* beta-axis current, pu, Q24 */
} clarke_t;

/** Clear inputs and outputs (the transform has no parameters or state). */
void clarke_init(clarke_t *c);

/**
 * beta of the phase currents as, bs (alpha is as itself).  Scaling: beta is the sum of two products of a Q24 input and
 * a Q30 constant (1/sqrt(3), 2/sqrt(3)), each truncated to Q24; so beta is
 * within 2 + (|as| + |bs|)/64 LSB of the exact value (two truncations, each
 * < 1 LSB, and the constants' quantisation, < 2^-30 each, times |x|): at
 * most 4 LSB at the edge of the valid range, 2.03 LSB within +-1 pu.
 * alpha is exact.  Overflow: none inside the valid range; outside it the
 * sum wraps (inputs are bounded by the ADC, so this cannot occur in use).
 */
static inline _iq clarke_beta(_iq as, _iq bs)
{
    /* beta = (as + 2 bs)/sqrt(3), as two products so that no sum of inputs
     * is formed before scaling down (|as| + 2|bs| would exceed 128 for
     * inputs above 42.7 pu).  Q24*Q30 -> Q24 each, truncated. */
    return _IQmpyIQX(as, GLOBAL_Q, FOC_ONE_BY_SQRT3_Q30, 30)
         + _IQmpyIQX(bs, GLOBAL_Q, FOC_TWO_BY_SQRT3_Q30, 30);
}

/** One sample of the struct: alpha = as (exact), beta = clarke_beta. */
static inline void clarke_step(clarke_t *c)
{
    c->alpha = c->as;
    c->beta = clarke_beta(c->as, c->bs);
}

#endif /* CLARKE_H */
