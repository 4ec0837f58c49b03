/**
 * @file test_iqmath_conv.c
 * Conversions and small operations of the host IQmath: _IQ / _IQN (also
 * as static initialisers), _IQtoF / _IQNtoF, _IQtoIQN / _IQNtoIQ (every
 * N), _IQtoQN / _QNtoIQ, _IQint, _IQfrac, _IQsat, _IQabs.
 * IQ_MATH: 0 LSB against references computed in double / 64-bit
 * arithmetic by the test.  FLOAT_MATH: float tolerances.
 */
#include "iqmath_test_util.h"

/* _IQ(A) must be a constant expression (TI: "used to initialize global
 * variables and tables", SPRC087 6.1). */
static const _iq TABLE[4] = {_IQ(1.0), _IQ(2.5), _IQ(-0.2345), 0};

/** TI's documented examples (SPRC087 6.1, 6.6), both MATH_TYPEs.
 *  Bound: IQ_MATH 1 LSB of Q24 (6e-8) for non-dyadic constants, float
 *  1e-6 (a few float ulps of values <= 4). */
static void test_ti_examples(void **state)
{
    const _iq y0 = _IQ(2.3456);
    const _iq y1 = _IQ(-2.3456);
    (void)state;
    assert_true(fabs((double)_IQtoF(TABLE[0]) - 1.0) < 1e-9);
    assert_true(fabs((double)_IQtoF(TABLE[1]) - 2.5) < 1e-9);
    assert_true(fabs((double)_IQtoF(TABLE[2]) + 0.2345) < 1e-6);
    assert_int_equal(_IQint(y0), 2);
    assert_int_equal(_IQint(y1), -2);       /* toward zero, as TI */
    assert_true(fabs((double)_IQtoF(_IQfrac(y0)) - 0.3456) < 1e-6);
    assert_true(fabs((double)_IQtoF(_IQfrac(y1)) + 0.3456) < 1e-6);
    /* rebuild (SPRC087 6.6): Y = _IQmpyI32(_IQ(1.0), Yint) + Yfrac, exact */
    assert_true(_IQmpyI32(_IQ(1.0), _IQint(y1)) + _IQfrac(y1) == y1);
    /* negative whole numbers (the bug TI fixed in V1.4c): -5.0 -> -5, 0 */
    assert_int_equal(_IQint(_IQ(-5.0)), -5);
    assert_true(_IQfrac(_IQ(-5.0)) == _IQ(0.0));
    /* saturate and abs */
    assert_true(_IQsat(_IQ(3.0), _IQ(1.0), _IQ(-2.0)) == _IQ(1.0));
    assert_true(_IQsat(_IQ(-3.0), _IQ(1.0), _IQ(-2.0)) == _IQ(-2.0));
    assert_true(_IQsat(_IQ(0.5), _IQ(1.0), _IQ(-2.0)) == _IQ(0.5));
    assert_true(_IQabs(_IQ(-1.75)) == _IQ(1.75));
    assert_true(_IQabs(_IQ(1.75)) == _IQ(1.75));
    /* Q15 round trip of a Q15-exact value */
    assert_int_equal(_IQtoQ15(_IQ(0.5)), 16384);
    assert_true(_Q15toIQ(-16384) == _IQ(-0.5));
    assert_true(_IQ20toIQ(_IQtoIQ20(_IQ(-3.25))) == _IQ(-3.25));
}

#if MATH_TYPE == IQ_MATH

/** _IQN(A): TI's (long)(A * 2^N), truncation toward zero; every N, on
 *  random doubles within range.  Reference: trunc() in double.  0 LSB. */
static void test_float_to_iq_exact(void **state)
{
    prng_t p = {UINT64_C(99)};
    long mismatches = 0;
    (void)state;
    for (int i = 0; i < 20000; i++) {
        double x = prng_uniform(&p, -1.0, 1.0);   /* |x| < 1: in range for all N */
        double y = prng_uniform(&p, -127.0, 127.0);
#define CHK(n) mismatches += _IQ##n(x) != (int32_t)trunc(ldexp(x, n));
        IQN_ALL(CHK)
#undef CHK
        mismatches += _IQ(y) != (int32_t)trunc(ldexp(y, GLOBAL_Q));
        mismatches += _IQ((float)y) != (int32_t)trunc(ldexp((double)(float)y, GLOBAL_Q));
    }
    assert_int_equal(mismatches, 0);
}

/** _IQtoF / _IQNtoF: (float)A * 2^-N; reference: the double value rounded
 *  once to float (the scaling by 2^-N is exact), so 0 ulp. */
static void test_iq_to_float_exact(void **state)
{
    long mismatches = 0;
    prng_t p = {UINT64_C(5)};
    (void)state;
    for (int i = 0; i < N_EDGE + 20000; i++) {
        int32_t a = (i < N_EDGE) ? EDGE_I32[i] : prng_i32_mag(&p);
#define CHK(n) mismatches += _IQ##n##toF(a) != (float)q_to_d(a, n);
        IQN_ALL(CHK)
#undef CHK
        mismatches += _IQtoF(a) != (float)q_to_d(a, GLOBAL_Q);
    }
    assert_int_equal(mismatches, 0);
}

/** _IQtoIQN / _IQNtoIQ (every N), _IQtoQ15 / _Q15toIQ: left shifts wrap
 *  modulo 2^32 (TI: `<<`), right shifts floor (TI: arithmetic `>>`).
 *  Reference: floor() of the exact double quotient, fmod() for the wrap.
 *  0 LSB. */
static int32_t ref_convert(int32_t a, int from, int to)
{
    double v = ldexp((double)a, to - from);   /* exact: < 2^61 */
    double w = floor(v);
    w = fmod(w, 4294967296.0);                 /* exact */
    if (w < -2147483648.0) w += 4294967296.0;
    if (w >= 2147483648.0) w -= 4294967296.0;
    return (int32_t)w;
}

static void test_q_conversions_exact(void **state)
{
    long mismatches = 0;
    prng_t p = {UINT64_C(17)};
    (void)state;
    for (int i = 0; i < N_EDGE + 20000; i++) {
        int32_t a = (i < N_EDGE) ? EDGE_I32[i] : prng_i32_mag(&p);
#define CHK(n) mismatches += _IQtoIQ##n(a) != ref_convert(a, GLOBAL_Q, n); \
               mismatches += _IQ##n##toIQ(a) != ref_convert(a, n, GLOBAL_Q);
        IQN_ALL(CHK)
#undef CHK
        mismatches += _IQtoQ15(a) != ref_convert(a, GLOBAL_Q, 15);
        mismatches += _Q15toIQ((int16_t)a) != ref_convert((int16_t)a, 15, GLOBAL_Q);
    }
    assert_int_equal(mismatches, 0);
}

/** _IQint / _IQfrac (every N), _IQabs, _IQsat on edges and random values.
 *  Reference: trunc() of the exact double; frac = A - int * 2^N; abs of
 *  INT32_MIN saturates (documented choice).  0 LSB. */
static void test_int_frac_abs_sat_exact(void **state)
{
    long mismatches = 0;
    prng_t p = {UINT64_C(23)};
    (void)state;
    for (int i = 0; i < N_EDGE + 20000; i++) {
        int32_t a = (i < N_EDGE) ? EDGE_I32[i] : prng_i32(&p);
        int32_t lim1 = prng_i32_mag(&p), lim2 = prng_i32_mag(&p);
        int32_t pos = (lim1 > lim2) ? lim1 : lim2, neg = (lim1 > lim2) ? lim2 : lim1;
#define CHK(n) { double t = trunc(q_to_d(a, n)); \
                 mismatches += _IQ##n##int(a) != (int32_t)t; \
                 mismatches += (double)_IQ##n##frac(a) != (double)a - ldexp(t, n); }
        IQN_ALL(CHK)
#undef CHK
        mismatches += _IQabs(a) != ((a == INT32_MIN) ? INT32_MAX : (int32_t)fabs((double)a));
        mismatches += _IQ24abs(a) != _IQabs(a);
        mismatches += _IQsat(a, pos, neg) != (int32_t)fmin(fmax((double)a, (double)neg), (double)pos);
    }
    assert_int_equal(mismatches, 0);
}

/* iq_norm32 (the C28x's CSB, c28x_intrinsics.h) against its definition:
 * the largest n in [0, 31] with x * 2^n inside int32, by brute force in
 * 64 bits, on every power of two and its neighbours of both signs, and on a
 * pseudo-random sweep. */
static int16_t norm_ref(int32_t x)
{
    int16_t n = 0;
    while (n < 31) {
        int64_t y = (int64_t)x * ((int64_t)1 << (n + 1));
        if (y > INT32_MAX || y < INT32_MIN) {
            break;
        }
        n++;
    }
    return n;
}

static void test_norm32(void **state)
{
    int k, d;
    uint32_t r = 12345u;
    (void)state;
    assert_int_equal(iq_norm32(0), 31);
    assert_int_equal(iq_norm32(-1), 31);
    assert_int_equal(iq_norm32(INT32_MAX), 0);
    assert_int_equal(iq_norm32(INT32_MIN), 0);
    for (k = 0; k < 31; k++) {
        for (d = -1; d <= 1; d++) {
            int32_t x = (int32_t)((int64_t)1 << k) + d;
            assert_int_equal(iq_norm32(x), norm_ref(x));
            assert_int_equal(iq_norm32(-x), norm_ref(-x));
        }
    }
    for (k = 0; k < 100000; k++) {
        int32_t x;
        r = r * 1664525u + 1013904223u;
        x = (int32_t)(r >> (r & 31u));
        x = (r & 0x80000000u) ? -x : x;
        assert_int_equal(iq_norm32(x), norm_ref(x));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_norm32),
        cmocka_unit_test(test_ti_examples),
        cmocka_unit_test(test_float_to_iq_exact),
        cmocka_unit_test(test_iq_to_float_exact),
        cmocka_unit_test(test_q_conversions_exact),
        cmocka_unit_test(test_int_frac_abs_sat_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#else /* FLOAT_MATH */

/** Float mode: _IQint truncates toward zero and _IQfrac keeps the sign,
 *  for random values; int + frac reproduces A to 1 float ulp of A (the
 *  subtraction A - (float)int is exact for |A| < 2^23, Sterbenz). */
static void test_float_int_frac(void **state)
{
    prng_t p = {UINT64_C(23)};
    (void)state;
    for (int i = 0; i < 100000; i++) {
        float a = (float)prng_uniform(&p, -1000.0, 1000.0);
        assert_int_equal(_IQint(a), (int32_t)trunc((double)a));
        assert_true((double)_IQfrac(a) == (double)a - trunc((double)a));
        assert_true(_IQtoF(a) == a);
        assert_true(_IQtoIQ20(a) == a && _IQ20toIQ(a) == a);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ti_examples),
        cmocka_unit_test(test_float_int_frac),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
