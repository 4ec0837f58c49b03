/* ramp_gen: slope, final value, limits and argument checks, against the
 * exact ramp out(k) = out(0) + k * rate * Ts (double). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "ramp_gen.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
#else
static double to_d(_iq x) { return (double)x; }
#endif
/* one LSB of Q24: the unit of every bound below (also in the float build,
 * where float's 24-bit mantissa gives errors of the same order) */
#define LSB 5.9604644775390625e-8

#define TS (1.0 / 15000.0)

/* Rising ramp 0 -> 1 pu at 2 pu/s.  step = 2/15000 = 1.333e-4 pu = 2236.96
 * LSB; _IQ truncates it by < 1 LSB (float: rate*Ts rounded to 24 bits,
 * < 0.5 ulp = 8e-12 pu), so after k samples |out - k rate Ts| < k LSB.
 * Asserted at k LSB + 1 LSB.  The ramp needs 1/step = 7500 samples; the
 * truncated step (2236 LSB instead of 2236.96) is up to 1/2236 slower, so
 * done rises on a sample in [7500, 7500 + 7500/2236 + 1 = 7504], with
 * out == target exactly. */
static void test_slope_and_final_value(void **state)
{
    ramp_gen_t r;
    uint32_t k;
    uint32_t k_done = 0u;
    (void)state;

    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, -1.5f, 1.5f), RAMP_GEN_OK);
    assert_true(to_d(r.out) == 0.0);
    r.target = _IQ(1.0);
    for (k = 1u; k <= 8000u; k++) {
        ramp_gen_step(&r);
        if (k_done == 0u) {
            double want = (double)k * 2.0 * TS;
            if (r.done == 0u) {
                double err = fabs(to_d(r.out) - want);
                if (!(err <= ((double)k + 1.0) * LSB)) {
                    print_error("k=%u out=%.10f want=%.10f\n", (unsigned)k, to_d(r.out), want);
                    fail();
                }
                /* never passes the target before done */
                assert_true(to_d(r.out) < 1.0);
            } else {
                k_done = k;
            }
        }
    }
    assert_true(k_done >= 7500u && k_done <= 7504u);
    assert_true(to_d(r.out) == 1.0);   /* exactly the target */
    assert_int_equal(r.done, 1);
}

/* Falling ramp to a target below out_min: clamps at the limit, reaches it
 * after (0.5 - -1.5)/step samples, slope -2 pu/s; then reversing. */
static void test_limit_and_reversal(void **state)
{
    ramp_gen_t r;
    uint32_t k;
    (void)state;

    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, -1.5f, 1.5f), RAMP_GEN_OK);
    ramp_gen_reset(&r, _IQ(0.5));
    assert_true(to_d(r.out) == 0.5);
    r.target = _IQ(-3.0);
    for (k = 1u; k <= 100u; k++) {
        ramp_gen_step(&r);
    }
    /* 100 samples down at 2/15000 per sample: bound 101 LSB as above */
    assert_true(fabs(to_d(r.out) - (0.5 - 100.0 * 2.0 * TS)) <= 101.0 * LSB);
    for (k = 101u; k <= 16000u && r.done == 0u; k++) {
        ramp_gen_step(&r);
    }
    /* 2.0 pu at 2 pu/s: 15000 samples, + up to 15000/2236 + 1 = 7.7 for the
     * truncated step */
    assert_true(k - 1u >= 15000u && k - 1u <= 15007u);
    assert_true(to_d(r.out) == -1.5);
    ramp_gen_step(&r);
    assert_true(to_d(r.out) == -1.5);   /* stays at the limit */
    assert_int_equal(r.done, 1);

    /* reverse: moves up by one step per sample immediately */
    r.target = _IQ(0.0);
    ramp_gen_step(&r);
    assert_int_equal(r.done, 0);
    assert_true(fabs(to_d(r.out) - (-1.5 + 2.0 * TS)) <= 1.0 * LSB);

    /* reset clamps into the limits */
    ramp_gen_reset(&r, _IQ(7.0));
    assert_true(to_d(r.out) == 1.5);
    assert_int_equal(r.done, 0);
}

/* Within one step of the target: lands on it in one sample. */
static void test_small_change(void **state)
{
    ramp_gen_t r;
    (void)state;
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, -1.0f, 1.0f), RAMP_GEN_OK);
    r.target = _IQ(0.0001);   /* < step = 0.000133 */
    ramp_gen_step(&r);
    assert_true(r.out == r.target);
    assert_int_equal(r.done, 1);
}

static void test_init_errors(void **state)
{
    ramp_gen_t r;
    (void)state;
    assert_int_equal(ramp_gen_init(&r, 2.0f, 0.0f, -1.0f, 1.0f), RAMP_GEN_ERR_PERIOD);
    assert_int_equal(ramp_gen_init(&r, 2.0f, 0.02f, -1.0f, 1.0f), RAMP_GEN_ERR_PERIOD);
    assert_int_equal(ramp_gen_init(&r, 2.0f, NAN, -1.0f, 1.0f), RAMP_GEN_ERR_PERIOD);
    assert_int_equal(ramp_gen_init(&r, 0.0f, (float)TS, -1.0f, 1.0f), RAMP_GEN_ERR_RATE);
    assert_int_equal(ramp_gen_init(&r, -2.0f, (float)TS, -1.0f, 1.0f), RAMP_GEN_ERR_RATE);
    assert_int_equal(ramp_gen_init(&r, NAN, (float)TS, -1.0f, 1.0f), RAMP_GEN_ERR_RATE);
    /* 0.01 pu/s at 15 kHz: step 6.7e-7 < 2^-20 (too coarse a quantisation) */
    assert_int_equal(ramp_gen_init(&r, 0.01f, (float)TS, -1.0f, 1.0f), RAMP_GEN_ERR_RATE);
    /* more than 1 pu per sample */
    assert_int_equal(ramp_gen_init(&r, 20000.0f, (float)TS, -1.0f, 1.0f), RAMP_GEN_ERR_RATE);
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, 1.0f, 1.0f), RAMP_GEN_ERR_LIMITS);
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, 1.0f, -1.0f), RAMP_GEN_ERR_LIMITS);
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, -64.0f, 1.0f), RAMP_GEN_ERR_LIMITS);
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, -1.0f, 63.5f), RAMP_GEN_ERR_LIMITS);
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, NAN, 1.0f), RAMP_GEN_ERR_LIMITS);
    /* limits not containing 0: starts at the nearer limit */
    assert_int_equal(ramp_gen_init(&r, 2.0f, (float)TS, 0.25f, 1.0f), RAMP_GEN_OK);
    assert_true(to_d(r.out) == 0.25);
}

/* ramp_gen_check, the configuration table's test: ramp_gen_init's verdict
 * at each bound of ramp_gen.h.  Ts = 2^-10 s, so that the step rate x Ts is
 * exact: [RAMP_GEN_STEP_MIN_PU = 2^-20, 1] pu per sample is a rate in
 * [2^-10, 1024] pu/s; Ts in (0, 0.01]; the limits within
 * +-RAMP_GEN_LIMIT_MAX. */
static void test_check(void **state)
{
    const float ts = 9.765625e-4f;
    const float rate[] = {9.765625e-4f, nextafterf(9.765625e-4f, 0.0f), 1024.0f,
                          nextafterf(1024.0f, 2048.0f), 2.0f, 2.0f, 2.0f, 2.0f};
    const float per[] = {ts, ts, ts, ts, 0.01f, nextafterf(0.01f, 1.0f), ts, ts};
    const float hi[] = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, RAMP_GEN_LIMIT_MAX,
                        nextafterf(RAMP_GEN_LIMIT_MAX, 100.0f)};
    const ramp_gen_status_t want[] = {RAMP_GEN_OK, RAMP_GEN_ERR_RATE, RAMP_GEN_OK,
                                      RAMP_GEN_ERR_RATE, RAMP_GEN_OK, RAMP_GEN_ERR_PERIOD,
                                      RAMP_GEN_OK, RAMP_GEN_ERR_LIMITS};
    ramp_gen_t r;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(ramp_gen_check(rate[i], per[i], -1.0f, hi[i]), want[i]);
        assert_int_equal(ramp_gen_init(&r, rate[i], per[i], -1.0f, hi[i]), want[i]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slope_and_final_value),
        cmocka_unit_test(test_limit_and_reversal),
        cmocka_unit_test(test_small_change),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
