/**
 * @file test_iqmath_count.c
 * The call counters of an IQMATH_COUNT_CALLS build (target iqmath_counted):
 * each IQ operation, including the _IQN forms, adds exactly one to its own
 * counter and to no other; constant conversions (_IQ) count nothing; reset
 * zeroes all.  Also iqmath_fn_name().  FLOAT_MATH has no counters (TI's
 * float mode is plain expressions), so only the names are checked there.
 */
#include <string.h>

#include "iqmath_test_util.h"

static void test_names(void **state)
{
    (void)state;
    assert_string_equal(iqmath_fn_name(IQMATH_FN_MPY), "_IQmpy");
    assert_string_equal(iqmath_fn_name(IQMATH_FN_SINPU), "_IQsinPU");
    assert_string_equal(iqmath_fn_name(IQMATH_FN_TOQN), "_IQtoQN");
    assert_string_equal(iqmath_fn_name(IQMATH_FN_COUNT), "?");
    assert_string_equal(iqmath_fn_name(-1), "?");
    assert_string_equal(iqmath_fn_name(IQMATH_FN_NORM32), "iq_norm32");
    for (int i = 0; i < (int)IQMATH_FN_COUNT; i++) {
        /* every IQmath operation, and the one C28x intrinsic counted with them */
        assert_true(strncmp(iqmath_fn_name(i), "_IQ", 3) == 0 || i == (int)IQMATH_FN_NORM32);
    }
}

#if MATH_TYPE == IQ_MATH

/** Runs @p expr and checks that only counter @p id moved, by one. */
#define EXPECT_ONE(id, expr) do { \
        volatile int32_t sink_; \
        iqmath_count_reset(); \
        sink_ = (int32_t)(expr); \
        (void)sink_; \
        for (int k_ = 0; k_ < (int)IQMATH_FN_COUNT; k_++) { \
            assert_int_equal(iqmath_call_count[k_], (k_ == (int)(id)) ? 1u : 0u); \
        } \
    } while (0)

static void test_counts(void **state)
{
    const _iq a = _IQ(0.3), b = _IQ(-1.2);
    (void)state;
    EXPECT_ONE(IQMATH_FN_MPY, _IQmpy(a, b));
    EXPECT_ONE(IQMATH_FN_MPY, _IQ30mpy(a, b));
    EXPECT_ONE(IQMATH_FN_RMPY, _IQrmpy(a, b));
    EXPECT_ONE(IQMATH_FN_RSMPY, _IQrsmpy(a, b));
    EXPECT_ONE(IQMATH_FN_MPYI32, _IQmpyI32(a, 3));
    EXPECT_ONE(IQMATH_FN_MPYI32INT, _IQmpyI32int(a, 3));
    EXPECT_ONE(IQMATH_FN_MPYI32FRAC, _IQmpyI32frac(a, 3));
    EXPECT_ONE(IQMATH_FN_MPYIQX, _IQmpyIQX(a, Q24, b, Q24));
    EXPECT_ONE(IQMATH_FN_DIV, _IQdiv(a, b));
    EXPECT_ONE(IQMATH_FN_DIV, _IQ20div(a, b));
    EXPECT_ONE(IQMATH_FN_SQRT, _IQsqrt(a));
    EXPECT_ONE(IQMATH_FN_ISQRT, _IQisqrt(a));
    EXPECT_ONE(IQMATH_FN_MAG, _IQmag(a, b));
    EXPECT_ONE(IQMATH_FN_SIN, _IQsin(a));
    EXPECT_ONE(IQMATH_FN_COS, _IQcos(a));
    EXPECT_ONE(IQMATH_FN_SINPU, _IQsinPU(a));
    EXPECT_ONE(IQMATH_FN_COSPU, _IQcosPU(a));
    EXPECT_ONE(IQMATH_FN_ATAN2, _IQatan2(a, b));
    EXPECT_ONE(IQMATH_FN_ATAN2PU, _IQatan2PU(a, b));
    EXPECT_ONE(IQMATH_FN_ATAN, _IQatan(a));
    EXPECT_ONE(IQMATH_FN_INT, _IQint(b));
    EXPECT_ONE(IQMATH_FN_FRAC, _IQfrac(b));
    EXPECT_ONE(IQMATH_FN_SAT, _IQsat(b, a, b));
    EXPECT_ONE(IQMATH_FN_ABS, _IQabs(b));
    EXPECT_ONE(IQMATH_FN_TOF, _IQtoF(b));
    EXPECT_ONE(IQMATH_FN_TOIQN, _IQtoIQ20(b));
    EXPECT_ONE(IQMATH_FN_TOIQN, _IQ20toIQ(b));
    EXPECT_ONE(IQMATH_FN_TOQN, _IQtoQ15(b));
    /* a constant conversion counts nothing */
    iqmath_count_reset();
    {
        volatile _iq c = _IQ(1.25);
        (void)c;
    }
    for (int k = 0; k < (int)IQMATH_FN_COUNT; k++) {
        assert_int_equal(iqmath_call_count[k], 0u);
    }
    /* accumulation: a 3-multiply expression plus a loop of 10 sinPU */
    iqmath_count_reset();
    {
        volatile _iq s = _IQmpy(_IQmpy(a, b), _IQmpy(b, b));
        (void)s;
        for (int i = 0; i < 10; i++) {
            s = _IQsinPU(a);
        }
    }
    assert_int_equal(iqmath_call_count[IQMATH_FN_MPY], 3u);
    assert_int_equal(iqmath_call_count[IQMATH_FN_SINPU], 10u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_counts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#else

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
#endif
