/**
 * @file test_iqmath_trig.c
 * _IQsin/_IQcos (radians), _IQsinPU/_IQcosPU (per-unit revolutions),
 * _IQatan2/_IQatan2PU/_IQatan against double libm, over a sweep of every
 * 2^-16 revolution, edges and a seeded random sample.
 *
 * Bounds (IQ_MATH), LSB of the output Q, and why:
 *   GLOBAL_Q = 24, all functions: 0.52 LSB = 0.5 (rounding of the result)
 *     + 0.02 (everything before it: the Q31 sine table, 2^-32 of a unit,
 *     the Q34-revolution atan table, series truncation < 3e-12 and the
 *     reduction to 2^-40 rev, all < 2^-6 LSB of Q24 together).
 *   Q30 sinPU/cosPU: 0.85 LSB = 0.5 rounding + 0.26 (table rounding,
 *     0.5 unit of Q31 = 0.25 LSB of Q30, times |cos d| + |sin d| <= 1.013)
 *     + 0.02 series/reduction + margin.
 *   Q29 sin/cos: 0.70 LSB = 0.5 + 0.13 (table at Q29) + 0.02 + margin.
 *   Q29 atan2 / Q30 atan2PU: 0.80 LSB = 0.5 + rounding of r = y/x to
 *     2^-33 (0.06 LSB of Q29 rad) + the Q34-revolution table (0.5 unit =
 *     1.8e-10 rad = 0.1 LSB of Q29) + series + margin.
 *   atan2PU results that round to 1.0 are documented to return 1.0 - 1 LSB
 *     (keeps TI's range [0, 1)); they are checked exactly.
 */
#include "iqmath_test_util.h"

static const double TWO_PI = 6.283185307179586476925286766559;

/** sin/cos(2 pi x) with x reduced exactly (floor is exact in double). */
static double ref_sinpu(double x) { return sin(TWO_PI * (x - floor(x))); }
static double ref_cospu(double x) { return cos(TWO_PI * (x - floor(x))); }
/** atan2 in revolutions, [0, 1). */
static double ref_atan2pu(double y, double x)
{
    double r = atan2(y, x) / TWO_PI;
    return (r < 0.0) ? r + 1.0 : r;
}

#if MATH_TYPE == IQ_MATH

typedef struct {
    double w[12];
} worst_t;

static void upd(double *w, double e) { if (e > *w) *w = e; }

/** sin/cos, GLOBAL_Q and Q29/Q30 forms. */
static void test_sin_cos(void **state)
{
    prng_t p = {UINT64_C(101)};
    worst_t w = {{0}};
    const double L24 = ldexp(1.0, 24), L29 = ldexp(1.0, 29), L30 = ldexp(1.0, 30);
    (void)state;
    for (int i = 0; i < (1 << 17) + N_EDGE; i++) {
        int32_t a;
        if (i < (1 << 16)) {
            a = (int32_t)((int64_t)i << (GLOBAL_Q - 16));   /* sweep 0..1 rev */
        } else if (i < (1 << 16) + N_EDGE) {
            a = EDGE_I32[i - (1 << 16)];
        } else {
            a = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
        }
        upd(&w.w[0], fabs(q_to_d(_IQsinPU(a), GLOBAL_Q) - ref_sinpu(q_to_d(a, GLOBAL_Q))) * L24);
        upd(&w.w[1], fabs(q_to_d(_IQcosPU(a), GLOBAL_Q) - ref_cospu(q_to_d(a, GLOBAL_Q))) * L24);
        upd(&w.w[2], fabs(q_to_d(_IQsin(a), GLOBAL_Q) - sin(q_to_d(a, GLOBAL_Q))) * L24);
        upd(&w.w[3], fabs(q_to_d(_IQcos(a), GLOBAL_Q) - cos(q_to_d(a, GLOBAL_Q))) * L24);
        upd(&w.w[4], fabs(q_to_d(_IQ30sinPU(a), 30) - ref_sinpu(q_to_d(a, 30))) * L30);
        upd(&w.w[5], fabs(q_to_d(_IQ30cosPU(a), 30) - ref_cospu(q_to_d(a, 30))) * L30);
        upd(&w.w[6], fabs(q_to_d(_IQ29sin(a), 29) - sin(q_to_d(a, 29))) * L29);
        upd(&w.w[7], fabs(q_to_d(_IQ29cos(a), 29) - cos(q_to_d(a, 29))) * L29);
        upd(&w.w[8], fabs(q_to_d(_IQ10sin(a), 10) - sin(q_to_d(a, 10))) * 1024.0);
        upd(&w.w[9], fabs(q_to_d(_IQ1cosPU(a), 1) - ref_cospu(q_to_d(a, 1))) * 2.0);
    }
    printf("  Q24 sinPU %.4f cosPU %.4f sin %.4f cos %.4f | Q30 sinPU %.4f cosPU %.4f"
           " | Q29 sin %.4f cos %.4f | Q10 sin %.4f Q1 cosPU %.4f LSB\n",
           w.w[0], w.w[1], w.w[2], w.w[3], w.w[4], w.w[5], w.w[6], w.w[7], w.w[8], w.w[9]);
    for (int k = 0; k < 4; k++) assert_true(w.w[k] <= 0.52);
    assert_true(w.w[4] <= 0.85 && w.w[5] <= 0.85);
    assert_true(w.w[6] <= 0.70 && w.w[7] <= 0.70);
    assert_true(w.w[8] <= 0.52 && w.w[9] <= 0.52);
    /* exact points and the per-unit wrap (only the fraction matters) */
    assert_int_equal(_IQsinPU(_IQ(0.25)), _IQ(1.0));
    assert_int_equal(_IQcosPU(_IQ(0.5)), _IQ(-1.0));
    assert_int_equal(_IQsinPU(0), 0);
    assert_int_equal(_IQcosPU(_IQ(-3.0)), _IQ(1.0));
    for (int i = 0; i < 1000; i++) {
        int32_t x = (int32_t)(prng_next(&p) >> 40);              /* [0, 1) */
        int32_t k = (int32_t)(prng_next(&p) >> 58) - 32;         /* whole revs */
        int32_t xk = x + k * (1 << GLOBAL_Q);
        assert_int_equal(_IQsinPU(xk), _IQsinPU(x));
        assert_int_equal(_IQcosPU(xk), _IQcosPU(x));
    }
}

/** atan2 (rad), atan2PU, atan over octant-covering random vectors. */
static void test_atan2(void **state)
{
    prng_t p = {UINT64_C(202)};
    double w24 = 0, wpu24 = 0, w29 = 0, wpu30 = 0, wat = 0;
    long bad = 0;
    const double L24 = ldexp(1.0, 24), L29 = ldexp(1.0, 29), L30 = ldexp(1.0, 30);
    (void)state;
    for (int i = 0; i < (1 << 18) + N_EDGE * N_EDGE; i++) {
        int32_t y, x;
        if (i < N_EDGE * N_EDGE) {
            y = EDGE_I32[i / N_EDGE];
            x = EDGE_I32[i % N_EDGE];
        } else {
            y = (i & 1) ? prng_i32(&p) : prng_i32_mag(&p);
            x = (i & 2) ? prng_i32(&p) : prng_i32_mag(&p);
        }
        {
            double ref = atan2((double)y, (double)x);     /* scale-free */
            double rpu = ref_atan2pu((double)y, (double)x);
            int32_t r24 = _IQatan2(y, x), pu24 = _IQatan2PU(y, x);
            int32_t r29 = _IQ29atan2(y, x), pu30 = _IQ30atan2PU(y, x);
            upd(&w24, fabs(q_to_d(r24, 24) - ref) * L24);
            upd(&w29, fabs(q_to_d(r29, 29) - ref) * L29);
            /* range [0, 1) and the documented 1.0 - 1 LSB clamp */
            bad += pu24 < 0 || pu24 >= (1 << 24) || pu30 < 0 || pu30 >= (1 << 30);
            if (rpu * L24 >= L24 - 0.5) bad += pu24 != (1 << 24) - 1;
            else upd(&wpu24, fabs((double)pu24 - rpu * L24));
            if (rpu * L30 >= L30 - 0.5) bad += pu30 != (1 << 30) - 1;
            else upd(&wpu30, fabs((double)pu30 - rpu * L30));
        }
        /* _IQatan(A) = atan2(A, 1.0) */
        upd(&wat, fabs(q_to_d(_IQatan(y), 24) - atan(q_to_d(y, 24))) * L24);
    }
    printf("  Q24 atan2 %.4f atan2PU %.4f atan %.4f | Q29 atan2 %.4f | Q30 atan2PU %.4f LSB\n",
           w24, wpu24, wat, w29, wpu30);
    assert_int_equal(bad, 0);
    assert_true(w24 <= 0.52 && wpu24 <= 0.52 && wat <= 0.52);
    assert_true(w29 <= 0.80 && wpu30 <= 0.80);
    /* documented special values (SPRC087 6.13) */
    assert_int_equal(_IQatan2(0, 0), 0);
    assert_int_equal(_IQatan2PU(0, 0), 0);
    assert_int_equal(_IQatan2PU(0, _IQ(-1.0)), _IQ(0.5));      /* A = 0: +pi */
    assert_int_equal(_IQatan2PU(_IQ(1.0), 0), _IQ(0.25));
    assert_int_equal(_IQatan2PU(_IQ(-1.0), 0), _IQ(0.75));
    assert_int_equal(_IQatan2PU(_IQ(-1.0), _IQ(-1.0)), _IQ(0.625));
    assert_int_equal(_IQatan2(0, _IQ(-1.0)), 52707179);        /* round(pi 2^24) */
    assert_int_equal(_IQatan2(_IQ(-2.0), _IQ(-2.0)), -39530384); /* -3pi/4 */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sin_cos),
        cmocka_unit_test(test_atan2),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#else /* FLOAT_MATH */

/** Float mode, |x| <= 2 rev or 12.6 rad: bound 1e-6 absolute = the float
 *  rounding of the argument (2 pi x: 2^-24 of 12.6 = 7.5e-7) plus one ulp
 *  of the libm float result (6e-8). */
static void test_float_trig(void **state)
{
    prng_t p = {UINT64_C(101)};
    (void)state;
    for (int i = 0; i < 100000; i++) {
        float x = (float)prng_uniform(&p, -2.0, 2.0);
        float r = (float)prng_uniform(&p, -12.5, 12.5);
        float a = (float)prng_uniform(&p, -10.0, 10.0);
        float b = (float)prng_uniform(&p, -10.0, 10.0);
        double e;
        assert_true(fabs((double)_IQsinPU(x) - ref_sinpu((double)x)) <= 1e-6);
        assert_true(fabs((double)_IQcosPU(x) - ref_cospu((double)x)) <= 1e-6);
        assert_true(fabs((double)_IQsin(r) - sin((double)r)) <= 1e-6);
        assert_true(fabs((double)_IQcos(r) - cos((double)r)) <= 1e-6);
        assert_true(fabs((double)_IQatan2(a, b) - atan2((double)a, (double)b)) <= 1e-6);
        assert_true(fabs((double)_IQatan(a) - atan((double)a)) <= 1e-6);
        e = (double)_IQatan2PU(a, b) - ref_atan2pu((double)a, (double)b);
        e -= floor(e + 0.5);                                  /* modulo 1 rev */
        assert_true(fabs(e) <= 1e-6);
        assert_true(_IQatan2PU(a, b) >= 0.0f && _IQatan2PU(a, b) <= 1.0f);
    }
    assert_true(fabs((double)_IQatan2PU(_IQ(-1.0), 0) - 0.75) <= 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_trig),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
