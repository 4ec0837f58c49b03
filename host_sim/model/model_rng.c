/**
 * @file model_rng.c
 * splitmix64 and Box-Muller; see model_rng.h.
 */
#include "model_rng.h"

#include <math.h>

void model_rng_seed(model_rng_t *r, uint64_t seed)
{
    r->s = seed;
    r->spare = 0.0;
    r->has_spare = 0u;
}

uint64_t model_rng_u64(model_rng_t *r)
{
    /* splitmix64: Weyl increment by the golden-ratio constant, then a
     * 64-bit finaliser (unsigned arithmetic wraps by definition). */
    uint64_t z = (r->s += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

double model_rng_uniform(model_rng_t *r)
{
    /* 53 random bits k in [0, 2^53); (k + 0.5) / 2^53 lies in (0, 1). */
    const uint64_t k = model_rng_u64(r) >> 11;
    return ((double)k + 0.5) * (1.0 / 9007199254740992.0);
}

double model_rng_gauss(model_rng_t *r)
{
    if (r->has_spare != 0u) {
        r->has_spare = 0u;
        return r->spare;
    }
    {
        const double two_pi = 6.283185307179586476925;
        const double u1 = model_rng_uniform(r);
        const double u2 = model_rng_uniform(r);
        const double rad = sqrt(-2.0 * log(u1));
        r->spare = rad * sin(two_pi * u2);
        r->has_spare = 1u;
        return rad * cos(two_pi * u2);
    }
}
