/**
 * @file model_rng.h
 * Deterministic pseudo-random numbers for the host models: one generator per
 * sensor instance, so that a simulation is bit-for-bit repeatable and adding
 * noise to one sensor never changes the noise of another.
 *
 * Uniform: splitmix64 (Steele, Lea, Flood 2014; 64-bit state, full period
 * 2^64, passes BigCrush), top 53 bits mapped to a double in (0, 1).
 * Gaussian: Box-Muller (polar-free form), both values of each pair used.
 * Host only (uses double); no globals.
 */
#ifndef MODEL_RNG_H
#define MODEL_RNG_H

#include <stdint.h>

typedef struct {
    /* state */
    uint64_t s;          /* splitmix64 state */
    double spare;        /* second value of the last Box-Muller pair */
    uint16_t has_spare;  /* 1 while spare is unused */
} model_rng_t;

/** Start the generator from @p seed (any value, 0 included). */
void model_rng_seed(model_rng_t *r, uint64_t seed);
/** Next raw 64-bit value. */
uint64_t model_rng_u64(model_rng_t *r);
/** Uniform in the open interval (0, 1): never 0, so log() is safe. */
double model_rng_uniform(model_rng_t *r);
/** Standard normal N(0, 1). */
double model_rng_gauss(model_rng_t *r);

#endif /* MODEL_RNG_H */
