/* Helpers shared by the foc_* tests: exact _iq <-> double conversion in
 * both MATH_TYPEs, LSB units, and a seeded PRNG (xorshift32) so that every
 * run draws the same "random" inputs. */
#ifndef FOC_TEST_UTIL_H
#define FOC_TEST_UTIL_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include "IQmathLib.h"

#define FOC_PI 3.14159265358979323846

#if MATH_TYPE == IQ_MATH
/* One LSB of Q GLOBAL_Q (6.0e-8 pu at Q24). */
#define FOC_LSB (1.0 / (double)((int64_t)1 << GLOBAL_Q))
/* _iq -> double, exact (an int32 fits a double's mantissa). */
static inline double iq2d(_iq x) { return (double)x * FOC_LSB; }
/* double -> _iq, rounded to nearest (the test's own quantiser, independent
 * of _IQ(), which truncates). */
static inline _iq d2iq(double x) { return (_iq)llround(x / FOC_LSB); }
#else
/* In FLOAT_MATH there is no LSB; bounds use FLT_EPSILON (2^-23) relative to
 * the size of the quantities instead. */
static inline double iq2d(_iq x) { return (double)x; }
static inline _iq d2iq(double x) { return (float)x; }
#endif

/* Bound helper: IQ_MATH: n_lsb LSB; FLOAT_MATH: n_eps * FLT_EPSILON * mag
 * (mag: the size of the largest operand, at least 1). */
static inline double foc_tol(double n_lsb, double n_eps, double mag)
{
#if MATH_TYPE == IQ_MATH
    (void)n_eps;
    (void)mag;
    return n_lsb * FOC_LSB;
#else
    (void)n_lsb;
    return n_eps * (double)FLT_EPSILON * (mag > 1.0 ? mag : 1.0);
#endif
}

typedef struct { uint32_t s; } foc_rng_t;

static inline uint32_t foc_rng_u32(foc_rng_t *r)
{
    uint32_t x = r->s;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    r->s = x;
    return x;
}

/* Uniform double in [lo, hi]. */
static inline double foc_rng_uniform(foc_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)foc_rng_u32(r) / 4294967295.0);
}

#endif /* FOC_TEST_UTIL_H */
