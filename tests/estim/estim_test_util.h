/* Helpers of the estim_ tests: exact conversions between _iq (or _iqN) and
 * double in both MATH_TYPEs, and a small deterministic PRNG. */
#ifndef ESTIM_TEST_UTIL_H
#define ESTIM_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include "IQmathLib.h"

#if MATH_TYPE == IQ_MATH
/* value of a QN number, exactly */
static inline double qn_to_d(_iq x, int q) { return (double)x / ldexp(1.0, q); }
/* nearest QN number to v */
static inline _iq d_to_qn(double v, int q) { return (_iq)llround(v * ldexp(1.0, q)); }
#else
static inline double qn_to_d(_iq x, int q) { (void)q; return (double)x; }
static inline _iq d_to_qn(double v, int q) { (void)q; return (_iq)v; }
#endif
static inline double iq_to_d(_iq x) { return qn_to_d(x, GLOBAL_Q); }
static inline _iq d_to_iq(double v) { return d_to_qn(v, GLOBAL_Q); }

/** One LSB of Q24 in pu. */
#define LSB24 (1.0 / 16777216.0)
#define LSB20 (1.0 / 1048576.0)   /* Tr (param_extract.h) */

/* xorshift64*, deterministic */
typedef struct { uint64_t s; } test_rng_t;
static inline uint64_t test_rng_u64(test_rng_t *r)
{
    r->s ^= r->s >> 12; r->s ^= r->s << 25; r->s ^= r->s >> 27;
    return r->s * 2685821657736338717ull;
}
/* uniform in [0, 1) */
static inline double test_rng_uniform(test_rng_t *r)
{
    return (double)(test_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}
/* standard normal (Box-Muller) */
static inline double test_rng_normal(test_rng_t *r)
{
    double u1 = test_rng_uniform(r), u2 = test_rng_uniform(r);
    if (u1 < 1e-300) { u1 = 1e-300; }
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif /* ESTIM_TEST_UTIL_H */
