/* app_sensor_test: the sensors' pulse test (sensor_test.h) against a
 * stator simulated here in double precision (the paper motor's Rs,
 * sigma Ls and the rotor's transient resistance Rr Lm^2/Lr^2, exact
 * per-period R-L solution; the bridge's dead time as a voltage loss of
 * vdc td/Ts per leg by the sign of each phase current; the sensors with
 * a gain each, an offset each, 0.02 A of noise): the timing of hal_pwm.h
 * (the voltage asked in ISR k acts over period k+1; the outputs off act
 * at once).  Healthy sensors pass, with the response within 3 % of 2 D
 * and across it below 3 % (the noise: 0.02 A in three samples of each
 * sensor against 8 A); a dead phase, a reversed phase, a 20 % gain
 * error on one phase and a common 40 % error are refused with the right
 * bits; a common 10 % error passes (the limit is the size tolerance); a
 * current beyond the limit stops it at once; bad arguments are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "sensor_test.h"

#define TS (1.0 / 15000.0)
#define RS_OHM 1.031
#define RT_OHM (1.031 + 0.465 * (6.4 / 9.2) * (6.4 / 9.2))   /* transient resistance */
#define SLS_H 4.748e-3
#define VBASE 34.641
#define IBASE 20.0
#define VDC 60.0
#define TD_FRAC 0.015   /* 1 us at 15 kHz */

typedef struct {
    double ga, gb;      /* sensor gains (1: healthy; 0: dead; -1: reversed) */
    double oa, ob;      /* offsets, A */
    double noise;       /* A rms */
    double short_A;     /* a current added to both sensors' readings (a short), A */
} sensors_t;

static double gauss(void)
{
    /* Box-Muller on rand(): a fixed sequence per run (srand in each case) */
    double u1 = ((double)rand() + 1.0) / ((double)RAND_MAX + 2.0);
    double u2 = ((double)rand() + 1.0) / ((double)RAND_MAX + 2.0);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* Run the test to its end; returns the final state. */
static sensor_test_state_t run(const sensors_t *s, sensor_test_t *t)
{
    double ia = 0.0, ib = 0.0;            /* true phase currents, A (c = -a - b) */
    double u_next_a = 0.0, u_next_b = 0.0;   /* asked for the next period, V (alpha, beta) */
    unsigned k;
    srand(7u);
    assert_int_equal(sensor_test_init(t, (float)TS, (float)SLS_H, (float)VBASE, (float)IBASE,
                                      (float)VDC, 4.0f, 0.25f, 0.06f),
                     SENSOR_TEST_OK);
    t->armed = 1u;
    t->run = 1u;
    for (k = 0; k < 2000u && (k < 2u || t->state == SENSOR_TEST_RUNNING ||
                              t->state == SENSOR_TEST_JUDGING);
         k++) {
        /* the ISR: this sample's readings (pu) */
        t->ia = _IQ((float)((s->ga * ia + s->oa + s->short_A + s->noise * gauss()) / IBASE));
        t->ib = _IQ((float)((s->gb * ib + s->ob - s->short_A + s->noise * gauss()) / IBASE));
        sensor_test_step(t);
        /* the period that follows: the voltage asked in the last ISR, the
         * bridge off at once if this ISR says so */
        if (t->off != 0u) {
            ia = ib = 0.0;
        } else {
            const double ic = -ia - ib;
            /* dead time: each leg loses vdc td/Ts by its current's sign;
             * the floating star keeps the differential part */
            const double la = -VDC * TD_FRAC * ((ia > 0.0) - (ia < 0.0));
            const double lb = -VDC * TD_FRAC * ((ib > 0.0) - (ib < 0.0));
            const double lc = -VDC * TD_FRAC * ((ic > 0.0) - (ic < 0.0));
            const double l0 = (la + lb + lc) / 3.0;
            const double ua = u_next_a + (la - l0);
            const double ub = u_next_b + ((lb - l0) - (lc - l0)) / sqrt(3.0);
            const double a = exp(-TS * RT_OHM / SLS_H);
            double i_al = ia, i_be = (ia + 2.0 * ib) / sqrt(3.0);
            i_al = a * i_al + (1.0 - a) * ua / RT_OHM;
            i_be = a * i_be + (1.0 - a) * ub / RT_OHM;
            ia = i_al;
            ib = -0.5 * i_al + 0.5 * sqrt(3.0) * i_be;
        }
        u_next_a = (double)_IQtoF(t->u_alpha) * VBASE;
        u_next_b = (double)_IQtoF(t->u_beta) * VBASE;
        /* the drive's slow task (its SAFETY slot, one period in 8) */
        if ((k % 8u) == 7u && sensor_test_judge_due(t) != 0u) {
            sensor_test_judge(t);
        }
    }
    return t->state;
}

static void check(const char *what, const sensors_t *s, sensor_test_state_t want,
                  uint16_t bits_any)
{
    sensor_test_t t;
    sensor_test_state_t st = run(s, &t);
    double e = (double)_IQtoF(t.s_exp);
    print_message("%-28s N %u, u %.1f V, 2D %.2f A: par/2D %.3f %.3f %.3f, perp/par %+.3f "
                  "%+.3f %+.3f, bits 0x%02x, %s\n", what, t.n, (double)_IQtoF(t.u) * VBASE,
                  e * IBASE, (double)_IQtoF(t.par[0]) / e, (double)_IQtoF(t.par[1]) / e,
                  (double)_IQtoF(t.par[2]) / e,
                  (double)_IQtoF(t.perp[0]) / (double)_IQtoF(t.par[0]),
                  (double)_IQtoF(t.perp[1]) / (double)_IQtoF(t.par[1]),
                  (double)_IQtoF(t.perp[2]) / (double)_IQtoF(t.par[2]), t.fail_bits,
                  (st == SENSOR_TEST_PASSED) ? "passed" : "FAILED");
    assert_int_equal(st, want);
    if (want == SENSOR_TEST_FAILED) {
        assert_true((t.fail_bits & bits_any) != 0u);
    } else {
        unsigned v;
        assert_int_equal(t.fail_bits, 0u);
        for (v = 0; v < 3u; v++) {
            /* the response within 3 % of 2 D times the sensors' common gain */
            assert_true(fabs((double)_IQtoF(t.par[v]) / (e * 0.5 * (s->ga + s->gb)) - 1.0) < 0.03);
        }
    }
}

static void test_healthy(void **state)
{
    const sensors_t s = {1.0, 1.0, 0.05, -0.03, 0.02, 0.0};
    sensor_test_t t;
    unsigned v;
    (void)state;
    check("healthy", &s, SENSOR_TEST_PASSED, 0u);
    (void)run(&s, &t);
    for (v = 0; v < 3u; v++) {
        assert_true(fabs((double)_IQtoF(t.perp[v])) < 0.03 * (double)_IQtoF(t.par[v]));
    }
    /* sizing: N = ceil(4 A x 4.748 mH / (32 V x Ts)) = 9, u = 4 A sigma Ls / (N Ts) */
    assert_int_equal(t.n, 9u);
    assert_true(fabs((double)_IQtoF(t.u) * VBASE - 4.0 * SLS_H / (9.0 * TS)) < 0.01);
}

static void test_faulty(void **state)
{
    const sensors_t dead_b = {1.0, 0.0, 0.0, 0.0, 0.02, 0.0};
    const sensors_t rev_a = {-1.0, 1.0, 0.0, 0.0, 0.02, 0.0};
    const sensors_t gain_a = {1.2, 1.0, 0.0, 0.0, 0.02, 0.0};
    const sensors_t gain_b = {1.0, 0.8, 0.0, 0.0, 0.02, 0.0};
    const sensors_t both_hi = {1.4, 1.4, 0.0, 0.0, 0.02, 0.0};
    const sensors_t both_10 = {1.1, 1.1, 0.0, 0.0, 0.02, 0.0};
    const sensors_t shorted = {1.0, 1.0, 0.0, 0.0, 0.02, 15.0};
    (void)state;
    check("phase b dead", &dead_b, SENSOR_TEST_FAILED, 0x07u);
    check("phase a reversed", &rev_a, SENSOR_TEST_FAILED, 0x07u);
    check("phase a gain +20 %", &gain_a, SENSOR_TEST_FAILED, 0x07u);
    check("phase b gain -20 %", &gain_b, SENSOR_TEST_FAILED, 0x07u);
    check("both gains +40 %", &both_hi, SENSOR_TEST_FAILED, 0x38u);
    check("both gains +10 % (passes)", &both_10, SENSOR_TEST_PASSED, 0u);
    check("15 A in both readings", &shorted, SENSOR_TEST_FAILED, SENSOR_TEST_LIMIT);
}

static void test_args_and_rearm(void **state)
{
    sensor_test_t t;
    const sensors_t s = {1.0, 1.0, 0.0, 0.0, 0.0, 0.0};
    (void)state;
    assert_int_equal(sensor_test_init(&t, 0.0f, (float)SLS_H, (float)VBASE, (float)IBASE,
                                      (float)VDC, 4.0f, 0.25f, 0.06f), SENSOR_TEST_ERR_ARG);
    assert_int_equal(t.state, SENSOR_TEST_FAILED);
    assert_int_equal(sensor_test_init(&t, (float)TS, (float)SLS_H, (float)VBASE, (float)IBASE,
                                      (float)VDC, 4.0f, 1.0f, 0.06f), SENSOR_TEST_ERR_ARG);
    /* a large sigma Ls: N capped at N_MAX with 80 % of (2/3) vdc, less current */
    assert_int_equal(sensor_test_init(&t, (float)TS, 0.5f, (float)VBASE, (float)IBASE,
                                      (float)VDC, 4.0f, 0.25f, 0.06f), SENSOR_TEST_OK);
    assert_int_equal(t.n, SENSOR_TEST_N_MAX);
    assert_true(fabs((double)_IQtoF(t.u) * VBASE - 0.8 * 40.0) < 0.01);
    /* disarmed: idle, the zero vector; a new run after a pass starts again */
    assert_int_equal(run(&s, &t), SENSOR_TEST_PASSED);
    t.armed = 0u;
    sensor_test_step(&t);
    assert_int_equal(t.state, SENSOR_TEST_IDLE);
    assert_true(t.u_alpha == _IQ(0.0) && t.u_beta == _IQ(0.0));
    t.armed = 1u;
    t.run = 0u;
    sensor_test_step(&t);
    assert_int_equal(t.state, SENSOR_TEST_IDLE);
    t.run = 1u;
    sensor_test_step(&t);
    assert_int_equal(t.state, SENSOR_TEST_RUNNING);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_healthy),
        cmocka_unit_test(test_faulty),
        cmocka_unit_test(test_args_and_rearm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
