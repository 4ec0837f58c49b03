/**
 * @file iqmath_div_sqrt.c
 * Host IQmath division, square root, inverse square root and magnitude.
 * Integer only (64-bit), exact or correctly rounded:
 *   _IQdiv   exact quotient truncated toward zero      (< 1 LSB)
 *   _IQsqrt  sqrt rounded to nearest                   (<= 0.5 LSB)
 *   _IQisqrt 1/sqrt rounded to nearest                 (<= 0.5 LSB)
 *   _IQmag   sqrt(A^2 + B^2) rounded to nearest        (<= 0.5 LSB)
 * (TI states ~28 bits for each, SPRC087 §5.)
 */
#include "IQmathLib.h"

#if MATH_TYPE == IQ_MATH   /* FLOAT_MATH: the header maps to libm */

/** floor(sqrt(x)) for any x < 2^64: the bit-by-bit (digit-recurrence)
 *  method, 32 iterations at most, result < 2^32. */
static uint64_t isqrt_floor_u64(uint64_t x)
{
    uint64_t rem = x;
    uint64_t root = 0u;
    uint64_t bit = (uint64_t)1 << 62;

    while (bit > rem) {
        bit >>= 2;
    }
    while (bit != 0u) {
        if (rem >= root + bit) {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    return root;
}

/** round(sqrt(x)) (half up) for x < 2^64, result <= 2^32.
 *  With s = floor(sqrt(x)): sqrt(x) >= s + 1/2  <=>  x >= s^2 + s + 1/4
 *  <=>  x - s^2 > s for integers; s^2 <= x < 2^64 fits. */
static uint64_t isqrt_round_u64(uint64_t x)
{
    uint64_t s = isqrt_floor_u64(x);
    return (x - s * s > s) ? s + 1u : s;
}

int32_t iqm_div(int32_t a, int32_t b, int q)
{
    int64_t num;
    if (b == 0) {
        return INT32_MAX;                   /* TI: 0x7FFFFFFF if Den == 0 */
    }
    num = (int64_t)a * ((int64_t)1 << q);   /* Qq -> Q2q, |num| <= 2^61 */
    return iqm_sat32(num / b);              /* C99: truncates toward 0 */
}

int32_t iqm_sqrt(int32_t a, int q)
{
    if (a <= 0) {
        return 0;                           /* TI: negative input -> 0 */
    }
    /* sqrt(A 2^-q) 2^q = sqrt(A 2^q); A 2^q < 2^61, root < 2^30.5 */
    return (int32_t)isqrt_round_u64((uint64_t)a << q);
}

int32_t iqm_isqrt(int32_t a, int q)
{
    /* Result R = 2^q / sqrt(A 2^-q) = sqrt(X), X = 2^(3q) / A.  With
     * F = floor(4X) = floor(2^(3q+2) / A):  floor(sqrt(F)) = floor(2 sqrt X)
     * and round(sqrt X) = (floor(2 sqrt X) + 1) >> 1 exactly.  R >= 2^31
     * (saturation) exactly when 4X >= 2^64, which the division detects. */
    int p = 3 * q + 2;                      /* 5 .. 92 */
    uint64_t f, r;
    if (a <= 0) {
        return INT32_MAX;                   /* TI: saturates for A <= 0 */
    }
    if (p <= 63) {
        f = ((uint64_t)1 << p) / (uint64_t)a;
    } else {
        /* 2^p / A as a two-limb long division: 2^p = hi 2^32, hi < 2^61 */
        uint64_t hi = (uint64_t)1 << (p - 32);
        uint64_t q1 = hi / (uint64_t)a;
        uint64_t r1 = hi % (uint64_t)a;     /* < A < 2^31 */
        if (q1 >= ((uint64_t)1 << 32)) {
            return INT32_MAX;               /* 4X >= 2^64: R >= 2^31 */
        }
        f = (q1 << 32) | ((r1 << 32) / (uint64_t)a);
    }
    r = (isqrt_floor_u64(f) + 1u) >> 1;
    return (r > (uint64_t)INT32_MAX) ? INT32_MAX : (int32_t)r;
}

int32_t iqm_mag(int32_t a, int32_t b)
{
    /* A^2 + B^2 <= 2^63 fits uint64; Q2q -> sqrt -> Qq */
    uint64_t s = (uint64_t)((int64_t)a * a) + (uint64_t)((int64_t)b * b);
    uint64_t r = isqrt_round_u64(s);
    return (r > (uint64_t)INT32_MAX) ? INT32_MAX : (int32_t)r;
}

#else
/* ISO C wants at least one declaration per translation unit. */
typedef int iqm_div_sqrt_unused_t;
#endif /* MATH_TYPE == IQ_MATH */
