/**
 * @file test_iqmath_mpy.c
 * Multiplies of the host IQmath: _IQmpy, _IQrmpy, _IQrsmpy, the _IQNmpy
 * families (every N), _IQmpyIQX, _IQmpyI32, _IQmpyI32int, _IQmpyI32frac.
 *
 * IQ_MATH: bit-exact (0 LSB) against a reference written differently: a
 * 128-bit product, C division plus a floor correction, and explicit
 * modulo-2^32 / clamp, over edges and a seeded random sample.
 * FLOAT_MATH: the float expressions against double within float rounding.
 */
#include "iqmath_test_util.h"
#include "iq_rmpy.h"

#if MATH_TYPE == IQ_MATH
/* ---- 128-bit reference (host only; __int128 is a GCC/Clang extension) -- */
__extension__ typedef __int128 i128;

/** floor(n / 2^s) via C's truncating division and a correction. */
static i128 ref_floor_shift(i128 n, int s)
{
    i128 d = (i128)1 << s;
    i128 qt = n / d;
    if ((n % d) != 0 && n < 0) {
        qt -= 1;
    }
    return qt;
}

/** n modulo 2^32 as int32 (the two's-complement wrap). */
static int32_t ref_wrap(i128 n)
{
    i128 m = n % ((i128)1 << 32);
    if (m < 0) {
        m += (i128)1 << 32;
    }
    if (m >= ((i128)1 << 31)) {
        m -= (i128)1 << 32;
    }
    return (int32_t)m;
}

static int32_t ref_clamp(i128 n)
{
    return (n > INT32_MAX) ? INT32_MAX : (n < INT32_MIN) ? INT32_MIN : (int32_t)n;
}

static int32_t ref_mpy(int32_t a, int32_t b, int q)
{
    return ref_wrap(ref_floor_shift((i128)a * b, q));
}
static int32_t ref_rmpy(int32_t a, int32_t b, int q)
{
    return ref_wrap(ref_floor_shift((i128)a * b + ((i128)1 << (q - 1)), q));
}
static int32_t ref_rsmpy(int32_t a, int32_t b, int q)
{
    return ref_clamp(ref_floor_shift((i128)a * b + ((i128)1 << (q - 1)), q));
}
/* integer part toward zero (sign-magnitude) and the matching fraction */
static int32_t ref_mpyI32int(int32_t a, int32_t b, int q)
{
    return ref_wrap(((i128)a * b) / ((i128)1 << q));
}
static int32_t ref_mpyI32frac(int32_t a, int32_t b, int q)
{
    return (int32_t)(((i128)a * b) % ((i128)1 << q));
}
static int32_t ref_mpyiqx(int32_t a, int qa, int32_t b, int qb, int qr)
{
    int s = qa + qb - qr;
    i128 p = (i128)a * b;
    return (s >= 0) ? ref_wrap(ref_floor_shift(p, s)) : ref_wrap(p * ((i128)1 << -s));
}

/* ---- the _IQN families as function tables ------------------------------ */
typedef int32_t (*fn2_t)(int32_t, int32_t);
#define MK(n) \
    static int32_t mpy_##n(int32_t a, int32_t b) { return _IQ##n##mpy(a, b); } \
    static int32_t rmpy_##n(int32_t a, int32_t b) { return _IQ##n##rmpy(a, b); } \
    static int32_t rsmpy_##n(int32_t a, int32_t b) { return _IQ##n##rsmpy(a, b); } \
    static int32_t i32int_##n(int32_t a, int32_t b) { return _IQ##n##mpyI32int(a, b); } \
    static int32_t i32frac_##n(int32_t a, int32_t b) { return _IQ##n##mpyI32frac(a, b); }
IQN_ALL(MK)
#undef MK
#define MPY_ENTRY(n) mpy_##n,
#define RMPY_ENTRY(n) rmpy_##n,
#define RSMPY_ENTRY(n) rsmpy_##n,
#define INT_ENTRY(n) i32int_##n,
#define FRAC_ENTRY(n) i32frac_##n,
static const fn2_t MPY_N[30] = {IQN_ALL(MPY_ENTRY)};
static const fn2_t RMPY_N[30] = {IQN_ALL(RMPY_ENTRY)};
static const fn2_t RSMPY_N[30] = {IQN_ALL(RSMPY_ENTRY)};
static const fn2_t I32INT_N[30] = {IQN_ALL(INT_ENTRY)};
static const fn2_t I32FRAC_N[30] = {IQN_ALL(FRAC_ENTRY)};

#define N_RANDOM 20000   /* per N and function: 30 x 5 x 20000 = 3e6 checks */

/** Every N-family member, edges x edges plus random pairs: 0 LSB. */
static void test_qn_families_exact(void **state)
{
    prng_t p = {UINT64_C(0x9E3779B97F4A7C15)};
    long mismatches = 0;
    (void)state;
    for (int n = 1; n <= 30; n++) {
        for (int i = 0; i < N_EDGE + N_RANDOM; i++) {
            int32_t a, b;
            if (i < N_EDGE) {
                a = EDGE_I32[i];
                b = EDGE_I32[(i * 7 + n) % N_EDGE];
            } else {
                a = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
                b = (i & 2) ? prng_i32(&p) : prng_i32_mag(&p);
            }
            mismatches += MPY_N[n - 1](a, b) != ref_mpy(a, b, n);
            mismatches += RMPY_N[n - 1](a, b) != ref_rmpy(a, b, n);
            mismatches += RSMPY_N[n - 1](a, b) != ref_rsmpy(a, b, n);
            mismatches += I32INT_N[n - 1](a, b) != ref_mpyI32int(a, b, n);
            mismatches += I32FRAC_N[n - 1](a, b) != ref_mpyI32frac(a, b, n);
        }
    }
    assert_int_equal(mismatches, 0);
}

/** GLOBAL_Q forms, all edge pairs and 2^18 random pairs: 0 LSB. */
static void test_global_mpy_exact(void **state)
{
    prng_t p = {UINT64_C(12345)};
    long mismatches = 0;
    (void)state;
    for (int i = 0; i < N_EDGE; i++) {
        for (int j = 0; j < N_EDGE; j++) {
            int32_t a = EDGE_I32[i], b = EDGE_I32[j];
            mismatches += _IQmpy(a, b) != ref_mpy(a, b, GLOBAL_Q);
            mismatches += _IQrmpy(a, b) != ref_rmpy(a, b, GLOBAL_Q);
            mismatches += _IQrsmpy(a, b) != ref_rsmpy(a, b, GLOBAL_Q);
            mismatches += _IQmpyI32(a, b) != ref_wrap((i128)a * b);
            mismatches += _IQmpyI32int(a, b) != ref_mpyI32int(a, b, GLOBAL_Q);
            mismatches += _IQmpyI32frac(a, b) != ref_mpyI32frac(a, b, GLOBAL_Q);
        }
    }
    for (int i = 0; i < (1 << 18); i++) {
        int32_t a = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
        int32_t b = (i & 2) ? prng_i32(&p) : prng_i32_mag(&p);
        mismatches += _IQmpy(a, b) != ref_mpy(a, b, GLOBAL_Q);
        mismatches += _IQrmpy(a, b) != ref_rmpy(a, b, GLOBAL_Q);
        mismatches += _IQrsmpy(a, b) != ref_rsmpy(a, b, GLOBAL_Q);
        mismatches += _IQmpyI32(a, b) != ref_wrap((i128)a * b);
        mismatches += _IQmpyI32int(a, b) != ref_mpyI32int(a, b, GLOBAL_Q);
        mismatches += _IQmpyI32frac(a, b) != ref_mpyI32frac(a, b, GLOBAL_Q);
    }
    assert_int_equal(mismatches, 0);
}

/** The documented semantics, value by value (Q24). */
static void test_mpy_semantics(void **state)
{
    (void)state;
    /* exact products of dyadic values */
    assert_int_equal(_IQmpy(_IQ(1.5), _IQ(-2.25)), _IQ(-3.375));
    /* truncation toward -inf (C28x arithmetic shift): -1 LSB * 1 LSB */
    assert_int_equal(_IQmpy(-1, 1), -1);
    assert_int_equal(_IQmpy(1, 1), 0);
    /* rounding adds half an LSB: 0.5 LSB products round up, -0.5 to 0 */
    assert_int_equal(_IQrmpy(_IQ(0.5), 1), 1);
    assert_int_equal(_IQrmpy(_IQ(-0.5), 1), 0);
    assert_int_equal(_IQmpy(_IQ(-0.5), 1), -1);
    /* overflow: 100 * 2 = 200 wraps to 200 - 256 = -56 in Q24 */
    assert_int_equal(_IQmpy(_IQ(100.0), _IQ(2.0)), _IQ(-56.0));
    assert_int_equal(_IQrmpy(_IQ(100.0), _IQ(2.0)), _IQ(-56.0));
    /* ... while _IQrsmpy saturates to +-(128 - 1 LSB) / -128 */
    assert_int_equal(_IQrsmpy(_IQ(100.0), _IQ(2.0)), INT32_MAX);
    assert_int_equal(_IQrsmpy(_IQ(100.0), _IQ(-2.0)), INT32_MIN);
    assert_int_equal(_IQrsmpy(INT32_MIN, INT32_MIN), INT32_MAX);
    /* TI's DAC example (SPRC087 6.10): +-1.0 to +-512 */
    assert_int_equal(_IQmpyI32int(_IQ(0.75), 512), 384);
    assert_int_equal(_IQmpyI32int(_IQ(-0.75), 512), -384);
    /* int toward zero, frac with the product's sign: -2.5 = -2 + (-0.5) */
    assert_int_equal(_IQmpyI32int(_IQ(-1.25), 2), -2);
    assert_int_equal(_IQmpyI32frac(_IQ(-1.25), 2), _IQ(-0.5));
    assert_int_equal(_IQmpyI32(_IQ(1.25), -3), _IQ(-3.75));
}

/** _IQmpyIQX and _IQNmpyIQX: every (IQA, IQB) pair for a few result Qs,
 *  including IQA + IQB < result Q (a left shift), 0 LSB. */
static void test_mpyiqx_exact(void **state)
{
    prng_t p = {UINT64_C(777)};
    long mismatches = 0;
    (void)state;
    for (int qa = 1; qa <= 30; qa++) {
        for (int qb = 1; qb <= 30; qb++) {
            for (int i = 0; i < 40; i++) {
                int32_t a = prng_i32_mag(&p), b = prng_i32_mag(&p);
                mismatches += _IQmpyIQX(a, qa, b, qb) != ref_mpyiqx(a, qa, b, qb, GLOBAL_Q);
                mismatches += _IQ30mpyIQX(a, qa, b, qb) != ref_mpyiqx(a, qa, b, qb, 30);
                mismatches += _IQ15mpyIQX(a, qa, b, qb) != ref_mpyiqx(a, qa, b, qb, 15);
                mismatches += _IQ1mpyIQX(a, qa, b, qb) != ref_mpyiqx(a, qa, b, qb, 1);
            }
        }
    }
    /* TI's example (SPRC087 6.9): IQ20 x Q15 -> GLOBAL_Q */
    assert_int_equal(_IQmpyIQX(_IQ20(1.5), Q20, _IQ15(-0.25), Q15), _IQ(-0.375));
    assert_int_equal(mismatches, 0);
}

/** The core's iq_rmpy (include/iq_rmpy.h: _IQmpyIQX one bit finer, then
 *  iq_round_half) is _IQrmpy bit for bit wherever its header says it is
 *  valid, |a b| < 2^(30 - GLOBAL_Q) pu: pairs whose product spans that range
 *  (both signs, odd and even intermediate results, the exact halves that
 *  round up) and the edge values within it: 0 LSB. */
static void test_core_rmpy_exact(void **state)
{
    prng_t p = {UINT64_C(4242)};
    const double lim = ldexp(1.0, 30 - GLOBAL_Q);   /* pu */
    long mismatches = 0, tried = 0;
    (void)state;
    for (int i = 0; i < (1 << 18); i++) {
        int32_t a = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
        int32_t b = (i & 2) ? prng_i32(&p) : prng_i32_mag(&p);
        if (!(fabs(ldexp((double)a, -GLOBAL_Q) * ldexp((double)b, -GLOBAL_Q)) < lim)) {
            b = (int32_t)(b >> 16);   /* into range: the same sign, a smaller factor */
        }
        if (fabs(ldexp((double)a, -GLOBAL_Q) * ldexp((double)b, -GLOBAL_Q)) < lim) {
            mismatches += iq_rmpy(a, b) != ref_rmpy(a, b, GLOBAL_Q);
            tried++;
        }
    }
    /* the halves: a b = (2k + 1) / 2 LSB rounds up (towards +inf), both signs */
    for (int32_t k = -8; k <= 8; k++) {
        mismatches += iq_rmpy((int32_t)(2 * k + 1), _IQ(0.5)) != ref_rmpy(2 * k + 1, _IQ(0.5), GLOBAL_Q);
        mismatches += iq_rmpy(_IQ(0.5), (int32_t)(2 * k + 1)) != k + 1;
    }
    print_message("iq_rmpy: %ld pairs within its range, %ld mismatches\n", tried, mismatches);
    assert_true(tried > (1 << 16));
    assert_int_equal(mismatches, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_core_rmpy_exact),
        cmocka_unit_test(test_qn_families_exact),
        cmocka_unit_test(test_global_mpy_exact),
        cmocka_unit_test(test_mpy_semantics),
        cmocka_unit_test(test_mpyiqx_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#else /* FLOAT_MATH */

/** Float mode: each macro is the float product; compared with the double
 *  product of the same float inputs, within half a float ulp (2^-24
 *  relative: one IEEE rounding). */
static void test_float_mpy(void **state)
{
    prng_t p = {UINT64_C(12345)};
    (void)state;
    for (int i = 0; i < 100000; i++) {
        float a = (float)prng_uniform(&p, -100.0, 100.0);
        float b = (float)prng_uniform(&p, -100.0, 100.0);
        double ref = (double)a * (double)b;
        double tol = fabs(ref) * ldexp(1.0, -24);
        assert_true(fabs((double)_IQmpy(a, b) - ref) <= tol);
        assert_true(fabs((double)_IQrmpy(a, b) - ref) <= tol);
        assert_true(fabs((double)_IQrsmpy(a, b) - ref) <= tol);
        assert_true(fabs((double)_IQ24mpy(a, b) - ref) <= tol);
        assert_true(fabs((double)_IQ30mpy(a, b) - ref) <= tol);
        assert_true(fabs((double)_IQmpyIQX(a, Q20, b, Q15) - ref) <= tol);
    }
    /* the same value checks as the IQ build, exact in float too */
    assert_true(_IQmpy(_IQ(1.5), _IQ(-2.25)) == _IQ(-3.375));
    assert_int_equal(_IQmpyI32int(_IQ(0.75), 512), 384);
    assert_int_equal(_IQmpyI32int(_IQ(-0.75), 512), -384);
    assert_int_equal(_IQmpyI32int(_IQ(-1.25), 2), -2);
    assert_true(_IQmpyI32frac(_IQ(-1.25), 2) == _IQ(-0.5));
    assert_true(_IQmpyI32(_IQ(1.25), -3) == _IQ(-3.75));
    assert_true(_IQmpyIQX(_IQ20(1.5), Q20, _IQ15(-0.25), Q15) == _IQ(-0.375));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_mpy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
