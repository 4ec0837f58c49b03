/**
 * @file estim_bfp.h
 * Private helpers of the identification core (src/estim only): scaling by a
 * power of two, exponent of a value, saturating add, compensated sum, and
 * a rounded product built on the truncating multiply.  They are what TI's
 * IQmath does not provide (it has no variable shift), used by the block-
 * floating-point covariance of the RLS (rls.h, "scaling plan") and by the
 * Butterworth filters and the regression (rounded products).
 *
 * These are the only places where the IQ_MATH build touches the raw int32
 * mantissa of an _iq; the FLOAT_MATH build does the same thing in float
 * (ldexpf/frexpf), so both builds run the same algorithm.  The IQ build is
 * 32-bit integer only and free of UB: left shifts are multiplications by a
 * power of two after a range check, right shifts go through estim_asr32
 * (floor, no shift of a negative value), sums test for overflow first.
 */
#ifndef ESTIM_BFP_H
#define ESTIM_BFP_H

#include <stdint.h>
#include "IQmathLib.h"
#include "iq_rmpy.h"

#if MATH_TYPE == FLOAT_MATH
#include <math.h>
#endif

/** Exponent reported for a zero value (below every real exponent). */
#define ESTIM_EXP_ZERO ((int16_t)-1000)

/* The rounded product (formerly estim_rmpy here) is iq_rmpy,
 * shared with the observer: include/iq_rmpy.h. */

/** Saturating increment of an event counter (never wraps to 0). */
static inline void estim_count(uint32_t *c)
{
    if (*c < UINT32_MAX) { (*c)++; }
}

#if MATH_TYPE == IQ_MATH

/*
 * Everything below is 32-bit integer arithmetic (the C28x has a 32-bit ALU
 * and no 64-bit one): no int64_t, no `>>` of a negative value (implementation-
 * defined in C99), no signed overflow.  Cost on the C28x, portable C as
 * written: estim_asr32 ~4 cycles, estim_add_sat ~6, estim_ldexp ~10,
 * estim_exponent 5 compare/shift steps (~25; the CSB instruction, intrinsic
 * __norm32, would do it in 1 on a target-specific build).
 */

/** floor(x / 2^r) for any sign, 0 <= r <= 31 (an arithmetic right shift
 *  written without shifting a negative value: for x < 0, ~x = -x - 1 >= 0
 *  and floor(x / 2^r) = -(floor(~x / 2^r)) - 1).  No overflow possible. */
static inline int32_t estim_asr32(int32_t x, int16_t r)
{
    if (x >= 0) {
        return (int32_t)((uint32_t)x >> r);
    }
    return -(int32_t)((~(uint32_t)x) >> r) - 1;
}

/**
 * x * 2^n, with x in Q(qin) and the result in Q(qout) (raw shift by
 * n + qout - qin).  Scaling: exact for left shifts; right shifts round half
 * up (floor(x 2^-r + 1/2)), so that repeated renormalisation carries no
 * bias.  Overflow: saturates to [INT32_MIN, INT32_MAX] and increments
 * *sat (if sat != NULL).  32-bit only.
 */
static inline _iq estim_ldexp(_iq x, int16_t n, int16_t qin, int16_t qout, uint32_t *sat)
{
    int16_t sh = (int16_t)(n + qout - qin);
    int32_t t;
    uint32_t h;
    if (sh <= 0) {
        if (sh == 0 || sh < -32) {
            return (sh == 0) ? x : 0;   /* sh < -32: |x| 2^sh < 1/4 LSB, rounds to 0 */
        }
        /* round half up: floor((t + 1) / 2) with t = floor(x 2^(1 - r)),
         * written as floor(t / 2) + (t odd) so that t + 1 cannot overflow */
        t = estim_asr32(x, (int16_t)(-sh - 1));
        return estim_asr32(t, 1) + (int32_t)((uint32_t)t & 1u);
    }
    /* left: x 2^sh fits iff -h <= x < h, h = 2^(31-sh), i.e. iff x + h
     * (modulo 2^32) < 2h: one unsigned compare */
    h = (sh > 30) ? 0u : ((uint32_t)1 << (31 - sh));
    if ((uint32_t)x + h >= 2u * h) {          /* (always, for sh > 30) */
        if (x == 0) {
            return 0;
        }
        if (sat != 0) { estim_count(sat); }
        return (x > 0) ? INT32_MAX : INT32_MIN;
    }
    return x * (int32_t)((uint32_t)1 << sh);      /* exact, in range (sh <= 30) */
}


/**
 * The smallest n with |x| < 2^n, x in Q(q) (so 2^(n-1) <= |x| < 2^n);
 * ESTIM_EXP_ZERO for x == 0.  Binary search on the magnitude: 5 compare/
 * shift steps whatever the value (the old shift loop took up to 31).  On
 * the C28x this is one CSB (count sign bits) instruction, the compiler's
 * __norm32 intrinsic, which a target-specific build could use here.
 */
static inline int16_t estim_exponent(_iq x, int16_t q)
{
    /* |x| as uint32 (also for INT32_MIN: 2^31) */
    uint32_t a = (x < 0) ? (0u - (uint32_t)x) : (uint32_t)x;
    int16_t bits = 1;
    if (a == 0u) {
        return ESTIM_EXP_ZERO;
    }
    if (a >= 0x10000u) { a >>= 16; bits = (int16_t)(bits + 16); }
    if (a >= 0x100u) { a >>= 8; bits = (int16_t)(bits + 8); }
    if (a >= 0x10u) { a >>= 4; bits = (int16_t)(bits + 4); }
    if (a >= 0x4u) { a >>= 2; bits = (int16_t)(bits + 2); }
    if (a >= 0x2u) { bits = (int16_t)(bits + 1); }
    return (int16_t)(bits - q);
}

/** a + b in Q(any), saturated to the int32 range; increments *sat then.
 *  The overflow test comes first, so the addition itself never overflows
 *  (32-bit: on the C28x, ADDL with the overflow mode does the same). */
static inline _iq estim_add_sat(_iq a, _iq b, uint32_t *sat)
{
    if (b >= 0) {
        if (a > INT32_MAX - b) { estim_count(sat); return INT32_MAX; }
    } else if (a < INT32_MIN - b) {
        estim_count(sat);
        return INT32_MIN;
    }
    return a + b;
}

/** a - b, saturated to the int32 range; increments *sat then. */
static inline _iq estim_sub_sat(_iq a, _iq b, uint32_t *sat)
{
    if (b <= 0) {
        if (a > INT32_MAX + b) { estim_count(sat); return INT32_MAX; }
    } else if (a < INT32_MIN + b) {
        estim_count(sat);
        return INT32_MIN;
    }
    return a - b;
}

/**
 * Compensated accumulation of small increments (error feedback):
 * *acc (Q24) += d * 2^n, d in Q(qin), keeping the part below 1/2 LSB24 that
 * rounding drops in *res (Q48: -2^23 <= res < 2^23 raw, i.e. within
 * 1/2 LSB24) and adding it back next time, so that the sum of many sub-LSB
 * increments is exact to one LSB24 instead of being lost (the dead zone of
 * a rounded Q24 integrator).  *acc + *res is then the exact running sum to
 * 2^-24 LSB24 per call (the bits of d below Q48 are floored off: after
 * 10^6 calls < 0.06 LSB24).  Increments of 128 LSB24 or more (whose Q48
 * form does not fit 32 bits) are added rounded, without the residual (they
 * are far above the resolution).  Overflow: *acc saturates (counted).
 * 32-bit only.
 */
static inline void estim_accumulate(_iq *acc, _iq d, int16_t n, int16_t qin, _iq *res,
                                    uint32_t *sat)
{
    int16_t sh = (int16_t)(n + 48 - qin);   /* d raw -> Q48 raw: times 2^sh */
    int32_t v, w, f;
    if (d == 0) {
        return;
    }
    if (sh <= 0) {
        v = (sh < -31) ? ((d < 0) ? -1 : 0) : estim_asr32(d, (int16_t)-sh);   /* Q48, floor */
    } else if (sh <= 30 &&
               (uint32_t)d + ((uint32_t)1 << (31 - sh)) < ((uint32_t)2 << (31 - sh))) {
        v = d * (int32_t)((uint32_t)1 << sh);   /* Q48, exact: -2^(31-sh) <= d < 2^(31-sh) */
    } else {
        *acc = estim_add_sat(*acc, estim_ldexp(d, n, qin, 24, sat), sat);
        return;
    }
    /* v = w 2^24 + f, 0 <= f < 2^24: whole LSB24 and the Q48 fraction */
    w = estim_asr32(v, 24);
    f = v - w * (int32_t)0x1000000;
    f = f + *res;                    /* in [-2^23, 2^24 + 2^23): fits */
    if (f >= (int32_t)0x800000) {    /* keep the residual within 1/2 LSB24 */
        f = f - (int32_t)0x1000000;
        w = w + 1;
    }
    *res = f;
    *acc = estim_add_sat(*acc, w, sat);
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

/** x / 2^n rounded half up, 0 <= n <= 31: floor((x + 2^(n-1)) / 2^n), the
 *  floor without shifting a negative value (estim_asr32); n = 0: x.  The
 *  caller keeps x + 2^(n-1) LSB within int32 (no check: the regression's
 *  window sums stay below 56 pu, the multisine's ramp below 3.6 pu).  No
 *  bias to pass on, unlike a truncating shift.  FLOAT_MATH: the exact
 *  quotient. */
static inline _iq estim_div_pow2_round(_iq x, uint16_t n)
{
#if MATH_TYPE == IQ_MATH
    if (n == 0u) {
        return x;
    }
    return estim_asr32(x + ((int32_t)1 << (n - 1u)), (int16_t)n);
#else
    return x / (float)((uint32_t)1u << n);
#endif
}

/** floor(a / 2) for any sign (C's `/` truncates toward zero). */
static inline int16_t estim_floor_half(int16_t a)
{
    return (int16_t)((a >= 0) ? (a / 2) : -((1 - a) / 2));
}

#endif /* ESTIM_BFP_H */
