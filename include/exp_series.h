/**
 * @file exp_series.h
 * 1 - exp(-x) by its series to x^5/120, Horner, for the first-order holds'
 * x = Ts/Tr (at most 0.1 by the modules' own limits):
 *  - one_minus_exp_neg: float, for the design functions (init and
 *    background only), relative error below 2e-9 for x <= 0.1; the same
 *    float operations on every target, so that a constant designed in the
 *    background equals the one the init designed from the same value;
 *  - one_minus_exp_neg_iq: Q24, for a set_tr on the ISR path (ifo, flux_obs).
 */
#ifndef EXP_SERIES_H
#define EXP_SERIES_H

#include "IQmathLib.h"

static inline float one_minus_exp_neg(float x)
{
    float t = 1.0f - x * 0.2f;
    t = 1.0f - x * 0.25f * t;
    t = 1.0f - x * (1.0f / 3.0f) * t;
    t = 1.0f - x * 0.5f * t;
    return x * t;
}

/** x in Q24, (0, 0.1] -> 1 - exp(-x) in Q24.  Scaling: every factor of the
 *  Horner form x (1 - x/2 (1 - x/3 (1 - x/4 (1 - x/5)))) is in (0.9, 1]:
 *  no overflow; truncated (_IQmpy), below 1 LSB per product. */
static inline _iq one_minus_exp_neg_iq(_iq x)
{
    _iq t = _IQ(1.0) - _IQmpy(x, _IQ(0.2));
    t = _IQ(1.0) - _IQmpy(_IQmpy(x, _IQ(0.25)), t);
    t = _IQ(1.0) - _IQmpy(_IQmpy(x, _IQ(0.33333333)), t);
    t = _IQ(1.0) - _IQmpy(_IQmpy(x, _IQ(0.5)), t);
    return _IQmpy(x, t);
}

#endif /* EXP_SERIES_H */
