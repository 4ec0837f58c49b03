/**
 * @file estim_bfp.h
 * Private helpers of the identification core (src/estim only): scaling by a
 * power of two, exponent of a value, saturating add.  They are what TI's
 * IQmath does not provide (it has no variable shift), used by the block-
 * floating-point covariance of the RLS (rls.h, "scaling plan").
 *
 * These are the only places where the IQ_MATH build touches the raw int32
 * mantissa of an _iq; the FLOAT_MATH build does the same thing in float
 * (ldexpf/frexpf), so both builds run the same algorithm.  The IQ build is
 * integer-only and free of UB: left shifts are done as multiplications of a
 * bounded int64, right shifts through iqm_asr64 (floor) of IQmathLib.h.
 */
#ifndef ESTIM_BFP_H
#define ESTIM_BFP_H

#include <stdint.h>
#include "IQmathLib.h"

#if MATH_TYPE == FLOAT_MATH
#include <math.h>
#endif

/** Exponent reported for a zero value (below every real exponent). */
#define ESTIM_EXP_ZERO ((int16_t)-1000)

/** Saturating increment of an event counter (never wraps to 0). */
static inline void estim_count(uint32_t *c)
{
    if (*c < UINT32_MAX) { (*c)++; }
}

#if MATH_TYPE == IQ_MATH

/**
 * x * 2^n, with x in Q(qin) and the result in Q(qout) (raw shift by
 * n + qout - qin).  Scaling: exact for left shifts; right shifts round half
 * up (add half an LSB, then floor), so that repeated renormalisation carries
 * no bias.  Overflow: saturates to [INT32_MIN, INT32_MAX] and increments
 * *sat (if sat != NULL).
 */
static inline _iq estim_ldexp(_iq x, int16_t n, int16_t qin, int16_t qout, uint32_t *sat)
{
    int32_t sh = (int32_t)n + (int32_t)qout - (int32_t)qin;
    int64_t v = (int64_t)x;
    if (x == 0) {
        return 0;
    }
    if (sh >= 0) {
        if (sh > 32) {
            sh = 32;                 /* |x| >= 1 raw: saturates anyway */
        }
        v = v * ((int64_t)1 << sh);  /* |v| < 2^63: no overflow */
    } else {
        int32_t r = -sh;
        if (r > 40) {
            return 0;                /* |x| < 2^31 raw: rounds to 0 */
        }
        v = iqm_asr64(v + ((int64_t)1 << (r - 1)), (int)r);
    }
    if (v > (int64_t)INT32_MAX) {
        if (sat != 0) { estim_count(sat); }
        return INT32_MAX;
    }
    if (v < (int64_t)INT32_MIN) {
        if (sat != 0) { estim_count(sat); }
        return INT32_MIN;
    }
    return (_iq)v;
}

/**
 * The smallest n with |x| < 2^n, x in Q(q) (so 2^(n-1) <= |x| < 2^n);
 * ESTIM_EXP_ZERO for x == 0.  Portable bit count (<= 32 iterations); on
 * the C28x this is one CSB (count sign bits) instruction, the compiler's
 * __norm32 intrinsic, which a target build should use here.
 */
static inline int16_t estim_exponent(_iq x, int16_t q)
{
    int64_t a = (x < 0) ? -(int64_t)x : (int64_t)x;
    int16_t bits = 0;
    if (a == 0) {
        return ESTIM_EXP_ZERO;
    }
    while (a != 0) {
        a = a >> 1;          /* a >= 0: well-defined shift */
        bits++;
    }
    return (int16_t)(bits - q);
}

/** a + b in Q(any), saturated to the int32 range; increments *sat then. */
static inline _iq estim_add_sat(_iq a, _iq b, uint32_t *sat)
{
    int64_t s = (int64_t)a + (int64_t)b;
    if (s > (int64_t)INT32_MAX) { estim_count(sat); return INT32_MAX; }
    if (s < (int64_t)INT32_MIN) { estim_count(sat); return INT32_MIN; }
    return (_iq)s;
}

/** a - b, saturated to the int32 range; increments *sat then. */
static inline _iq estim_sub_sat(_iq a, _iq b, uint32_t *sat)
{
    int64_t s = (int64_t)a - (int64_t)b;
    if (s > (int64_t)INT32_MAX) { estim_count(sat); return INT32_MAX; }
    if (s < (int64_t)INT32_MIN) { estim_count(sat); return INT32_MIN; }
    return (_iq)s;
}

/**
 * Compensated accumulation of small increments (error feedback):
 * *acc (Q24) += d * 2^n, d in Q(qin), keeping the part below 1/2 LSB24 that
 * rounding drops in *res (Q48: |res| <= 2^23 raw = 1/2 LSB24) and adding it
 * back next time, so that the sum of many sub-LSB increments is exact to
 * one LSB24 instead of being lost (the dead zone of a rounded Q24
 * integrator).  Increments of 64 LSB24 or more skip the residual (they
 * are far above the resolution).  Overflow: *acc saturates (counted).
 */
static inline void estim_accumulate(_iq *acc, _iq d, int16_t n, int16_t qin, _iq *res,
                                    uint32_t *sat)
{
    _iq d48 = estim_ldexp(d, n, qin, 48, NULL);
    if (d48 > -(_iq)0x40000000 && d48 < (_iq)0x40000000) {
        int64_t t = (int64_t)d48 + (int64_t)*res;      /* Q48, |t| < 2^31 */
        int64_t q = iqm_asr64(t + ((int64_t)1 << 23), 24);   /* rounded to Q24 */
        *res = (_iq)(t - q * ((int64_t)1 << 24));
        *acc = estim_add_sat(*acc, (_iq)q, sat);
    } else {
        *acc = estim_add_sat(*acc, estim_ldexp(d, n, qin, 24, sat), sat);
    }
}

#else /* FLOAT_MATH: the same operations in float */

static inline _iq estim_ldexp(_iq x, int16_t n, int16_t qin, int16_t qout, uint32_t *sat)
{
    /* the IQ build's range of Q(qout) is [-2^(31-qout), 2^(31-qout)) */
    float lim = ldexpf(1.0f, 31 - (int)qout);
    float v = ldexpf(x, (int)n);
    (void)qin;
    if (v >= lim) {
        if (sat != 0) { estim_count(sat); }
        return lim * 0.99999994f;
    }
    if (v < -lim) {
        if (sat != 0) { estim_count(sat); }
        return -lim;
    }
    return v;
}

static inline int16_t estim_exponent(_iq x, int16_t q)
{
    int e = 0;
    (void)q;
    if (x == 0.0f) {
        return ESTIM_EXP_ZERO;
    }
    (void)frexpf(x, &e);   /* x = f 2^e, 0.5 <= |f| < 1 */
    return (int16_t)e;
}

/** a + b, saturated to the Q GLOBAL_Q range of the IQ build (+-128). */
static inline _iq estim_add_sat(_iq a, _iq b, uint32_t *sat)
{
    float s = a + b;
    const float lim = ldexpf(1.0f, 31 - GLOBAL_Q);
    if (s >= lim) { estim_count(sat); return lim * 0.99999994f; }
    if (s < -lim) { estim_count(sat); return -lim; }
    return s;
}


static inline _iq estim_sub_sat(_iq a, _iq b, uint32_t *sat)
{
    return estim_add_sat(a, -b, sat);
}

/** FLOAT: the same by Kahan summation (the residual keeps what the float
 *  addition to *acc rounds off). */
static inline void estim_accumulate(_iq *acc, _iq d, int16_t n, int16_t qin, _iq *res,
                                    uint32_t *sat)
{
    float y = estim_ldexp(d, n, qin, 24, sat) + *res;
    float t = estim_add_sat(*acc, y, sat);
    *res = y - (t - *acc);
    *acc = t;
}

#endif /* MATH_TYPE */

/** floor(a / 2) for any sign (C's `/` truncates toward zero). */
static inline int16_t estim_floor_half(int16_t a)
{
    return (int16_t)((a >= 0) ? (a / 2) : -((1 - a) / 2));
}

#endif /* ESTIM_BFP_H */
