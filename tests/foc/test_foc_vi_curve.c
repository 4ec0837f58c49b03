/* foc_vi_curve: vi_curve_retry, the bridge's test run again with larger
 * current levels (drive_vi.c's retry when the first fit found its levels
 * inside the transition).  The whole test against the simulated bridge is
 * tests/sim/test_sim_vi_curve.c; here the state the ISR sees: after a
 * retry the test stands at its first level, +2 i1 through the PI, with the
 * new i1 and nothing of the finished test left (done 0, no failure, empty
 * window); a refused i1 changes nothing. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <math.h>
#include <cmocka.h>

#include "pi_ctrl.h"
#include "vi_curve.h"

#define TS_S (8.0f / 15000.0f)

static double to_d(_iq x)
{
#if MATH_TYPE == IQ_MATH
    return ldexp((double)x, -GLOBAL_Q);
#else
    return (double)x;
#endif
}

/* a test as drive_vi_background leaves it after its fit: finished, on its
 * last level, a failure flag and a full window */
static void finish(vi_curve_t *v)
{
    v->level = VI_CURVE_LEVELS;
    v->t = 7u;
    v->n = 5u;
    v->fail = 1u;
    v->fail_level = 3u;
    v->su = _IQ(1.0);
    v->ea_hat = -0.3f;
    v->mean_vdc = 1.0f;
    v->done = 1u;
}

static void test_retry_restarts_with_new_i1(void **state)
{
    vi_curve_t v;
    (void)state;
    assert_int_equal(vi_curve_init(&v, TS_S, 0.05f, 0.1f, 0.5f, 0.01f, 0.5f), VI_CURVE_OK);
    finish(&v);
    assert_int_equal(vi_curve_retry(&v, 0.08f), VI_CURVE_OK);
    assert_true(v.i1 == 0.08f);
    assert_int_equal(v.done, 0);
    assert_int_equal(v.fail, 0);
    assert_int_equal(v.level, 0);
    assert_int_equal(v.t, 0);
    assert_int_equal(v.n, 0);
    assert_int_equal(v.current, 1);
    assert_true(v.ea_hat == 0.0f && v.mean_vdc == 0.0f);
    assert_true(to_d(v.su) == 0.0);
    /* the first level: +2 i1 (0.16 pu) through the PI, to within the
     * float-to-Q24 conversion (1 LSB) */
    assert_true(fabs(to_d(v.i_ref) - 0.16) <= ldexp(1.0, -24) + 1e-7);
    assert_true(v.settle == v.settle_i_n);
}

static void test_retry_refuses_bad_i1(void **state)
{
    static const float bad[3] = {0.0f, -0.1f, 2.01f};   /* 2 i1 > VI_CURVE_I_MAX_PU = 4 */
    vi_curve_t v;
    unsigned k;
    (void)state;
    assert_int_equal(vi_curve_init(&v, TS_S, 0.05f, 0.1f, 0.5f, 0.01f, 0.5f), VI_CURVE_OK);
    for (k = 0u; k < 3u; k++) {
        finish(&v);
        assert_int_equal(vi_curve_retry(&v, bad[k]), VI_CURVE_ERR_CURRENT);
        assert_true(v.i1 == 0.05f);
        assert_int_equal(v.done, 1);   /* the finished test stands */
        assert_int_equal(v.level, VI_CURVE_LEVELS);
    }
    finish(&v);
    assert_int_equal(vi_curve_retry(&v, nanf("")), VI_CURVE_ERR_CURRENT);
    assert_int_equal(v.done, 1);
    assert_int_equal(vi_curve_retry(&v, 2.0f), VI_CURVE_OK);   /* 2 i1 = 4: the edge */
}

/* vi_curve_check, the configuration table's test too: each refusal at its
 * bound, in its order, and vi_curve_init's verdict the same.  Ts 1 s: 6 Tr
 * / Ts = 65535 exactly at Tr 10922.5 s (the settling count's 16 bits). */
static void test_check_bounds(void **state)
{
    static const struct {
        float ts, i1, tr, kp, ki;
        vi_curve_status_t want;
    } c[] = {
        {1.0f, 0.05f, 10922.5f, 0.5f, 0.01f, VI_CURVE_OK},
        {1.0f, 0.05f, 10922.501f, 0.5f, 0.01f, VI_CURVE_ERR_TIME},   /* next float */
        {0.0f, 0.05f, 0.1f, 0.5f, 0.01f, VI_CURVE_ERR_PERIOD},
        {TS_S, 0.05f, 0.0f, 0.5f, 0.01f, VI_CURVE_ERR_PERIOD},
        {TS_S, 2.0f, 0.1f, 0.5f, 0.01f, VI_CURVE_OK},                /* 2 i1 = 4 */
        {TS_S, 2.0000002f, 0.1f, 0.5f, 0.01f, VI_CURVE_ERR_CURRENT},
        {TS_S, 0.0f, 0.1f, 0.5f, 0.01f, VI_CURVE_ERR_CURRENT},
        {TS_S, 0.05f, 0.1f, PI_KP_MAX, PI_KI_MAX, VI_CURVE_OK},
        {TS_S, 0.05f, 0.1f, 100.00001f, 0.01f, VI_CURVE_ERR_GAINS},
        {TS_S, 0.05f, 0.1f, 0.5f, 1.0000001f, VI_CURVE_ERR_GAINS},
        {TS_S, 5.0f, 20000.0f, 200.0f, 0.01f, VI_CURVE_ERR_CURRENT},  /* the first named */
        {1.0f, 0.05f, 20000.0f, 200.0f, 0.01f, VI_CURVE_ERR_TIME},
    };
    vi_curve_t v;
    size_t i;
    (void)state;
    assert_true(nextafterf(10922.5f, 20000.0f) == 10922.501f);
    for (i = 0; i < sizeof c / sizeof c[0]; i++) {
        assert_int_equal(vi_curve_check(c[i].ts, c[i].i1, c[i].tr, c[i].kp, c[i].ki, 0.5f),
                         c[i].want);
        assert_int_equal(vi_curve_init(&v, c[i].ts, c[i].i1, c[i].tr, c[i].kp, c[i].ki, 0.5f),
                         c[i].want);
    }
    /* at the edge the settling count is the full 16 bits */
    assert_int_equal(vi_curve_init(&v, 1.0f, 0.05f, 10922.5f, 0.5f, 0.01f, 0.5f), VI_CURVE_OK);
    assert_int_equal(v.settle_i_n, 65535u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_retry_restarts_with_new_i1),
        cmocka_unit_test(test_retry_refuses_bad_i1),
        cmocka_unit_test(test_check_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
