/**
 * @file iqmath_test_util.h
 * Shared helpers of the host IQmath tests: a seeded PRNG, input generators
 * covering every magnitude, edge values, and IQ <-> double conversions done
 * independently of the library (ldexp, not _IQtoF).
 */
#ifndef IQMATH_TEST_UTIL_H
#define IQMATH_TEST_UTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "IQmathLib.h"

/** xorshift64* (Vigna): fixed seed, so every run tests the same sample. */
typedef struct {
    uint64_t s;
} prng_t;

static inline uint64_t prng_next(prng_t *p)
{
    p->s ^= p->s >> 12;
    p->s ^= p->s << 25;
    p->s ^= p->s >> 27;
    return p->s * UINT64_C(2685821657736338717);
}

/** Uniform over all 2^32 bit patterns. */
static inline int32_t prng_i32(prng_t *p)
{
    uint32_t u = (uint32_t)(prng_next(p) >> 32);
    return (u <= (uint32_t)INT32_MAX) ? (int32_t)u : (int32_t)(-(int32_t)(~u) - 1);
}

/** Log-uniform magnitude: a uniform pattern divided by 2^(0..31), so small
 *  and large values are equally represented. */
static inline int32_t prng_i32_mag(prng_t *p)
{
    int32_t v = prng_i32(p);
    int sh = (int)(prng_next(p) >> 59);          /* 0..31 */
    return (int32_t)((int64_t)v / ((int64_t)1 << sh));
}

/** Uniform double in [lo, hi). */
static inline double prng_uniform(prng_t *p, double lo, double hi)
{
    return lo + (hi - lo) * ldexp((double)(prng_next(p) >> 11), -53);
}

/** Raw Qq integer as a real number (exact). */
static inline double q_to_d(int32_t v, int q)
{
    return ldexp((double)v, -q);
}

/** Edge inputs: zero, +-1 LSB, the extremes, and values around +-1.0 in
 *  Q24 and Q30. */
static const int32_t EDGE_I32[] = {
    0, 1, -1, 2, -2, INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1,
    16777216, -16777216, 16777215, 16777217, -16777215, -16777217,
    1073741824, -1073741824, 1073741823, -1073741825, 32767, -32768, 65536,
    -65536, 8388608, -8388608, 46341, -46341, 0x40000000 + 12345
};
#define N_EDGE ((int)(sizeof(EDGE_I32) / sizeof(EDGE_I32[0])))

/** Every N of the _IQN families, for X-macro expansion. */
#define IQN_ALL(X) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9) X(10) \
    X(11) X(12) X(13) X(14) X(15) X(16) X(17) X(18) X(19) X(20) X(21) \
    X(22) X(23) X(24) X(25) X(26) X(27) X(28) X(29) X(30)

#endif /* IQMATH_TEST_UTIL_H */
