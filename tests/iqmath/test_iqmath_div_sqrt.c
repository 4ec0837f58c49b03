/**
 * @file test_iqmath_div_sqrt.c
 * _IQdiv (and the _IQNdiv family), _IQsqrt, _IQisqrt, _IQmag against
 * double references, over edges, sweeps and a seeded random sample.
 *
 * Bounds (IQ_MATH), in LSB of the output Q, and why:
 *   div    < 1 LSB + 1e-6:  the exact quotient truncated toward zero (the
 *          1e-6 covers the double reference, good to < 2^-21 LSB);
 *   sqrt, isqrt, mag  <= 0.5 LSB + 1e-6:  correctly rounded results; the
 *          1e-6 LSB covers the double reference itself (53-bit sqrt of a
 *          value < 2^62 is good to < 2^-20 LSB).
 * Saturation and special cases are checked exactly.
 */
#include "iqmath_test_util.h"

#if MATH_TYPE == IQ_MATH

typedef int32_t (*fn2_t)(int32_t, int32_t);
#define MK(n) static int32_t div_##n(int32_t a, int32_t b) { return _IQ##n##div(a, b); }
IQN_ALL(MK)
#undef MK
#define ENTRY(n) div_##n,
static const fn2_t DIV_N[30] = {IQN_ALL(ENTRY)};

/** max |result - exact| over the sample for every N; saturations exact. */
static void test_div(void **state)
{
    prng_t p = {UINT64_C(31)};
    double worst = 0.0;
    long bad_sat = 0;
    (void)state;
    for (int n = 1; n <= 30; n++) {
        for (int i = 0; i < 20000 + N_EDGE * N_EDGE; i++) {
            int32_t a, b, r;
            double exact;
            if (i < N_EDGE * N_EDGE) {
                a = EDGE_I32[i / N_EDGE];
                b = EDGE_I32[i % N_EDGE];
            } else {
                a = prng_i32_mag(&p);
                b = prng_i32_mag(&p);
            }
            r = DIV_N[n - 1](a, b);
            if (b == 0) {
                bad_sat += r != INT32_MAX;      /* TI: 0x7FFFFFFF, any A */
                continue;
            }
            exact = ldexp((double)a, n) / (double)b;     /* Qn units */
            if (exact >= 2147483647.0) {
                bad_sat += r != INT32_MAX;
            } else if (exact < -2147483648.0) {
                bad_sat += r != INT32_MIN;
            } else {
                double e = fabs((double)r - exact);
                if (e > worst) worst = e;
            }
        }
    }
    printf("  _IQNdiv worst error %.6f LSB\n", worst);
    assert_int_equal(bad_sat, 0);
    assert_true(worst < 1.0 + 1e-6);   /* trunc < 1 LSB; double ref < 2^-21 LSB */
    /* documented cases (Q24) */
    assert_int_equal(_IQdiv(_IQ(1.0), _IQ(4.0)), _IQ(0.25));
    assert_int_equal(_IQdiv(_IQ(-3.0), _IQ(2.0)), _IQ(-1.5));
    assert_int_equal(_IQdiv(_IQ(-1.0), 0), INT32_MAX);       /* not -max */
    assert_int_equal(_IQdiv(0, 0), INT32_MAX);
    assert_int_equal(_IQdiv(_IQ(100.0), _IQ(0.5)), INT32_MAX);
    assert_int_equal(_IQdiv(_IQ(-100.0), _IQ(0.5)), INT32_MIN);
    assert_int_equal(_IQdiv(1, 3), 5592405);   /* trunc(2^24/3) */
    assert_int_equal(_IQdiv(-1, 3), -5592405); /* toward zero */
}

/** sqrt and isqrt over edges, all powers of two and a random sample. */
static void test_sqrt_isqrt(void **state)
{
    prng_t p = {UINT64_C(37)};
    double wsq = 0.0, wisq = 0.0;
    long bad_sat = 0;
    (void)state;
    for (int n = 1; n <= 30; n++) {
        for (int i = 0; i < 20000 + N_EDGE + 31; i++) {
            int32_t a;
            if (i < N_EDGE) a = EDGE_I32[i];
            else if (i < N_EDGE + 31) a = (int32_t)(((int64_t)1 << (i - N_EDGE)) - (i & 1));
            else a = (i & 1) ? prng_i32_mag(&p) : prng_i32(&p);
            int32_t s, is;
            switch (n) {   /* the GLOBAL_Q forms and a spread of N */
            case 30: s = _IQ30sqrt(a); is = _IQ30isqrt(a); break;
            case 29: s = _IQ29sqrt(a); is = _IQ29isqrt(a); break;
            case 24: s = _IQsqrt(a); is = _IQisqrt(a); break;
            case 20: s = _IQ20sqrt(a); is = _IQ20isqrt(a); break;
            case 15: s = _IQ15sqrt(a); is = _IQ15isqrt(a); break;
            case 8: s = _IQ8sqrt(a); is = _IQ8isqrt(a); break;
            case 1: s = _IQ1sqrt(a); is = _IQ1isqrt(a); break;
            default: continue;
            }
            if (a <= 0) {
                bad_sat += s != 0;             /* negative: 0 (TI) */
                bad_sat += is != INT32_MAX;    /* <= 0: saturate (TI) */
                continue;
            }
            {
                double e = fabs((double)s - sqrt(ldexp((double)a, n)));
                double ir = ldexp(1.0, n) / sqrt(q_to_d(a, n));   /* Qn */
                if (e > wsq) wsq = e;
                if (ir >= 2147483647.5) {
                    bad_sat += is != INT32_MAX;
                } else {
                    e = fabs((double)is - ir);
                    if (e > wisq) wisq = e;
                }
            }
        }
    }
    printf("  sqrt worst %.6f LSB, isqrt worst %.6f LSB\n", wsq, wisq);
    assert_int_equal(bad_sat, 0);
    assert_true(wsq <= 0.5 + 1e-6);
    assert_true(wisq <= 0.5 + 1e-6);
    assert_int_equal(_IQsqrt(_IQ(2.25)), _IQ(1.5));
    assert_int_equal(_IQisqrt(_IQ(0.25)), _IQ(2.0));
    assert_int_equal(_IQsqrt(-_IQ(4.0)), 0);
    /* isqrt saturation boundary, Q24: 1/sqrt(x) < 128 <=> x > 2^-14 */
    assert_int_equal(_IQisqrt(1024), INT32_MAX);       /* x = 2^-14: 128 */
    assert_true(_IQisqrt(1025) < INT32_MAX);
}

/** _IQmag = sqrt(A^2 + B^2), same Q in and out (the Q cancels). */
static void test_mag(void **state)
{
    prng_t p = {UINT64_C(41)};
    double worst = 0.0;
    long bad_sat = 0;
    (void)state;
    for (int i = 0; i < (1 << 18) + N_EDGE * N_EDGE; i++) {
        int32_t a, b, r;
        double exact;
        if (i < N_EDGE * N_EDGE) {
            a = EDGE_I32[i / N_EDGE];
            b = EDGE_I32[i % N_EDGE];
        } else {
            a = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
            b = (i & 2) ? prng_i32(&p) : prng_i32_mag(&p);
        }
        r = (i & 4) ? _IQmag(a, b) : _IQ15mag(a, b);
        exact = hypot((double)a, (double)b);
        if (exact >= 2147483647.5) {
            bad_sat += r != INT32_MAX;
        } else {
            double e = fabs((double)r - exact);
            if (e > worst) worst = e;
        }
    }
    printf("  mag worst %.6f LSB\n", worst);
    assert_int_equal(bad_sat, 0);
    assert_true(worst <= 0.5 + 1e-6);
    assert_int_equal(_IQmag(_IQ(3.0), _IQ(-4.0)), _IQ(5.0));
    assert_int_equal(_IQmag(INT32_MIN, INT32_MIN), INT32_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_div),
        cmocka_unit_test(test_sqrt_isqrt),
        cmocka_unit_test(test_mag),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#else /* FLOAT_MATH */

/** Float mode: relative error within 2 float ulps (2^-22): one rounding
 *  of the libm result plus one of the float input products (mag). */
static void test_float_div_sqrt(void **state)
{
    prng_t p = {UINT64_C(31)};
    const double tol = ldexp(1.0, -22);
    (void)state;
    for (int i = 0; i < 100000; i++) {
        float a = (float)prng_uniform(&p, -100.0, 100.0);
        float b = (float)prng_uniform(&p, -100.0, 100.0);
        float c = (float)prng_uniform(&p, 1e-3, 100.0);
        double r;
        r = (double)a / (double)b;
        assert_true(fabs((double)_IQdiv(a, b) - r) <= fabs(r) * tol);
        r = sqrt((double)c);
        assert_true(fabs((double)_IQsqrt(c) - r) <= r * tol);
        r = 1.0 / sqrt((double)c);
        assert_true(fabs((double)_IQisqrt(c) - r) <= r * tol);
        r = hypot((double)a, (double)b);
        assert_true(fabs((double)_IQmag(a, b) - r) <= r * tol);
    }
    assert_true(_IQsqrt(_IQ(2.25)) == _IQ(1.5));
    assert_true(_IQmag(_IQ(3.0), _IQ(-4.0)) == _IQ(5.0));
    assert_true(_IQdiv(_IQ(-3.0), _IQ(2.0)) == _IQ(-1.5));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_div_sqrt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
