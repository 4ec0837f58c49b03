/*
 * The protections' plausibility checks as units (encoder, current feedback,
 * theta guard, protection priority and restart condition), and the margin
 * of the current check on healthy closed-loop runs.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "current_check.h"
#include "encoder_check.h"
#include "fault_run.h"
#include "protect.h"
#include "theta_guard.h"

#define TS (1.0f / 15000.0f)

/* Paper-motor numbers: 1000 lines, 2 pole pairs, 50 Hz base: 4 pu is
 * 4 * 25 rev/s * 4000 counts * Ts = 26.7 counts per sample -> jump_max 27. */
static void enc_setup(encoder_check_t *e)
{
    assert_int_equal(encoder_check_init(e, TS, 0.05f, 0.15f, 4.0f, 50.0f, 1000u, 2u),
                     ENCODER_CHECK_OK);
    assert_int_equal(e->jump_max, 27);
    assert_int_equal(e->frozen_max, 750);
    e->active = 1u;
}

static void test_encoder_frozen(void **state)
{
    encoder_check_t e;
    uint16_t k;
    (void)state;
    enc_setup(&e);
    e.count = 100u;
    e.i_t = _IQ(0.2);                       /* above i_t_min = 0.15 pu */
    encoder_check_step(&e);                 /* first sample: +100 counts, under 27? no: */
    encoder_check_reset(&e);                /* (start from the present count) */
    for (k = 1u; k < 750u; k++) {
        encoder_check_step(&e);
        assert_int_equal(e.fault, 0u);
    }
    encoder_check_step(&e);                 /* the 750th frozen sample */
    assert_int_equal(e.fault, 1u);
    assert_int_equal(e.cause, ENCODER_CHECK_FROZEN);
    /* latched until reset, even when the counts move again */
    e.count = 105u;
    encoder_check_step(&e);
    assert_int_equal(e.fault, 1u);
    encoder_check_reset(&e);
    assert_int_equal(e.fault, 0u);
    /* frozen without torque current (standstill) or with the bridge off: fine */
    e.i_t = _IQ(0.1);
    for (k = 0u; k < 2000u; k++) {
        encoder_check_step(&e);
    }
    assert_int_equal(e.fault, 0u);
    e.i_t = _IQ(-0.5);
    e.active = 0u;
    for (k = 0u; k < 2000u; k++) {
        encoder_check_step(&e);
    }
    assert_int_equal(e.fault, 0u);
    /* one count every 749 samples with full torque current: never trips */
    e.active = 1u;
    for (k = 0u; k < 10000u; k++) {
        if ((k % 749u) == 748u) {
            e.count = (uint16_t)(e.count - 1u);
        }
        encoder_check_step(&e);
    }
    assert_int_equal(e.fault, 0u);
}

static void test_encoder_jump_and_wrap(void **state)
{
    encoder_check_t e;
    uint16_t k;
    (void)state;
    enc_setup(&e);
    e.i_t = _IQ(0.0);
    /* 27 counts per sample through the 16-bit wrap, both directions: plausible */
    e.count = 65500u;
    encoder_check_reset(&e);
    for (k = 0u; k < 100u; k++) {
        e.count = (uint16_t)(e.count + 27u);
        encoder_check_step(&e);
    }
    for (k = 0u; k < 100u; k++) {
        e.count = (uint16_t)(e.count - 27u);
        encoder_check_step(&e);
    }
    assert_int_equal(e.fault, 0u);
    /* 28: implausible; so is the most negative difference (-32768) */
    e.count = (uint16_t)(e.count + 28u);
    encoder_check_step(&e);
    assert_int_equal(e.cause, ENCODER_CHECK_JUMP);
    encoder_check_reset(&e);
    e.count = (uint16_t)(e.count + 32768u);
    encoder_check_step(&e);
    assert_int_equal(e.fault, 1u);
    /* the jump test alone (encoder_check_jump, branch-free): |d1| at the
     * limit passes, one count beyond trips, in both directions, and nothing
     * trips while the bridge is off (active 0) */
    {
        static const int32_t d1s[] = { 27, -27, 28, -28, 0, 32767, -32768 };
        size_t j;
        for (j = 0; j < sizeof d1s / sizeof d1s[0]; j++) {
            const int32_t d1 = d1s[j];
            const uint16_t over = (uint16_t)(((d1 < 0) ? -d1 : d1) > 27);
            encoder_check_reset(&e);
            e.active = 1u;
            encoder_check_jump(&e, d1);
            assert_int_equal(e.fault, over);
            assert_int_equal(e.cause, over ? ENCODER_CHECK_JUMP : 0u);
            encoder_check_reset(&e);
            e.active = 0u;
            encoder_check_jump(&e, d1);
            assert_int_equal(e.fault, 0u);
        }
    }
    /* bad arguments: refused, and the check reports a fault */
    assert_int_equal(encoder_check_init(&e, TS, 0.0f, 0.15f, 4.0f, 50.0f, 1000u, 2u),
                     ENCODER_CHECK_ERR_ARG);
    assert_int_equal(e.fault, 1u);
    assert_int_equal(encoder_check_init(&e, TS, 0.05f, 0.15f, 4.0f, 50.0f, 10u, 2u),
                     ENCODER_CHECK_ERR_RESOLUTION);   /* 0.27 counts per sample */
    assert_int_equal(encoder_check_init(&e, TS, 0.05f, NAN, 4.0f, 50.0f, 1000u, 2u),
                     ENCODER_CHECK_ERR_ARG);
}

/* encoder_check_args_ok, the configuration table's test: encoder_check_init's
 * verdict at its bounds.  Ts = 2^-14 s and f_base 1024 Hz, 1 pole pair
 * (exact products): the counts a sample at speed_max, speed_max f_base /
 * pp x 4 lines Ts, in [2, 16384] (at 4 pu: one a line, from 2 lines; at
 * 64 pu: 16 a line, up to 1024 lines); i_t_min in (0, 2). */
static void test_encoder_check_args(void **state)
{
    const float ts = 6.103515625e-5f;
    const float spd[] = {4.0f, 4.0f, 64.0f, 64.0f, 4.0f, 4.0f};
    const uint16_t lines[] = {2u, 1u, 1024u, 1025u, 1000u, 1000u};
    const float itm[] = {0.15f, 0.15f, 0.15f, 0.15f, nextafterf(2.0f, 0.0f), 2.0f};
    const encoder_check_status_t want[] = {ENCODER_CHECK_OK, ENCODER_CHECK_ERR_RESOLUTION,
                                           ENCODER_CHECK_OK, ENCODER_CHECK_ERR_RESOLUTION,
                                           ENCODER_CHECK_OK, ENCODER_CHECK_ERR_ARG};
    encoder_check_t e;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(encoder_check_args_ok(ts, 0.05f, itm[i], spd[i], 1024.0f, lines[i], 1u),
                         want[i]);
        assert_int_equal(encoder_check_init(&e, ts, 0.05f, itm[i], spd[i], 1024.0f, lines[i], 1u),
                         want[i]);
    }
}

/* A constant error e: e_f = e (1 - (1-a)^k), a = 1 - exp(-Ts/tau); with
 * tau = 2 ms and e = 0.3 pu against e_max = 0.15 the trip comes after
 * tau ln 2 = 1.39 ms = 20.8 samples: at sample 21 (independent closed form). */
static void test_current_check(void **state)
{
    current_check_t c;
    uint16_t k, trip_k = 0u;
    (void)state;
    assert_int_equal(current_check_init(&c, TS, 0.002f, 0.15f), CURRENT_CHECK_OK);
    c.active = 1u;
    c.i_m_ref = _IQ(0.3);
    c.i_m = _IQ(0.2);
    c.i_t_ref = _IQ(-0.1);
    c.i_t = _IQ(0.1);                        /* |e| = 0.1 + 0.2 = 0.3 pu */
    for (k = 1u; k <= 100u && trip_k == 0u; k++) {
        current_check_step(&c);
        if (c.fault != 0u) {
            trip_k = k;
        }
    }
    assert_int_equal(trip_k, 21u);
    /* at the voltage limit it holds: the same error with `limited` set
     * before each step never trips and leaves e_f where it was; each step
     * clears the flag, and without it the filter goes on from there */
    {
        current_check_t h;
        assert_int_equal(current_check_init(&h, TS, 0.002f, 0.15f), CURRENT_CHECK_OK);
        h.active = 1u;
        h.i_m_ref = c.i_m_ref;
        h.i_m = c.i_m;
        h.i_t_ref = c.i_t_ref;
        h.i_t = c.i_t;
        for (k = 0u; k < 10u; k++) {
            current_check_step(&h);           /* 10 of the 21 steps to the trip */
        }
        {
            const _iq held = h.e_f;
            for (k = 0u; k < 1000u; k++) {
                h.limited = 1u;
                current_check_step(&h);
                assert_int_equal(h.limited, 0u);
            }
            assert_int_equal(h.fault, 0u);
            assert_true(h.e_f == held);
        }
        for (k = 11u; k <= 21u && h.fault == 0u; k++) {
            current_check_step(&h);
        }
        assert_int_equal(h.fault, 1u);
        assert_int_equal(k - 1u, 21u);        /* the 21st unheld step, as above */
        h.limited = 1u;
        current_check_reset(&h);
        assert_int_equal(h.limited, 0u);
    }
    /* latched; the reset re-arms; inactive keeps the filter at 0 */
    current_check_step(&c);
    assert_int_equal(c.fault, 1u);
    current_check_reset(&c);
    c.active = 0u;
    for (k = 0u; k < 100u; k++) {
        current_check_step(&c);
    }
    assert_int_equal(c.fault, 0u);
    assert_true(c.e_f == _IQ(0.0));
    /* an error of 0.14 pu forever stays below 0.15 */
    c.active = 1u;
    c.i_t = _IQ(-0.06);                      /* 0.1 + 0.04 = 0.14 pu */
    for (k = 0u; k < 2000u; k++) {
        current_check_step(&c);
    }
    assert_int_equal(c.fault, 0u);
    assert_true(fabs((double)_IQtoF(c.e_f) - 0.14) < 1e-4);
    /* extreme inputs: bounded, no wrap */
    c.i_m_ref = _IQ(100.0);
    c.i_m = _IQ(-100.0);
    for (k = 0u; k < 2000u; k++) {
        current_check_step(&c);
    }
    assert_int_equal(c.fault, 1u);
    /* clamped: |4 - (-4)| + |-0.1 - (-0.06)| = 8.04 pu */
    assert_true(fabs((double)_IQtoF(c.e_f) - 8.04) < 1e-4);
    assert_int_equal(current_check_init(&c, TS, TS / 2.0f, 0.15f), CURRENT_CHECK_ERR_ARG);
    assert_int_equal(c.fault, 1u);
}

/* The paper motor's K in pu (method §4 check values converted as in
 * tests/estim): K1 -0.842, K2 2.12, K3 0.107, K4 -0.308 (approximately; the
 * guard needs only their signs and magnitudes within a factor 8). */
static void test_theta_guard(void **state)
{
    theta_guard_t g;
    const float k_nom[RLS_N] = {-0.842f, 2.12f, 0.107f, -0.308f};
    const float bad_sign[RLS_N] = {0.842f, 2.12f, 0.107f, -0.308f};
    uint16_t i;
    (void)state;
    assert_int_equal(theta_guard_init(&g, bad_sign, 8.0f), THETA_GUARD_ERR_ARG);
    assert_int_equal(theta_guard_init(&g, k_nom, 8.0f), THETA_GUARD_OK);
    /* theta(0) = 0: never good */
    g.updated = 1u;
    theta_guard_step(&g);
    assert_int_equal(g.good, 0u);
    assert_int_equal(g.held, 1u);
    /* a plausible theta is taken */
    for (i = 0u; i < RLS_N; i++) {
        g.theta[i] = _IQ(k_nom[i] * 1.1f);
    }
    theta_guard_step(&g);
    assert_int_equal(g.good, 1u);
    assert_int_equal(g.held, 0u);
    assert_true(g.theta_good[1] == _IQ(2.12f * 1.1f));
    /* K2 with the wrong sign, or 9x too large: held at the last good */
    g.theta[1] = _IQ(-2.0);
    theta_guard_step(&g);
    assert_int_equal(g.held, 1u);
    assert_true(g.theta_good[1] == _IQ(2.12f * 1.1f));
    g.theta[1] = _IQ(2.12f * 9.0f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 1u);
    assert_int_equal(g.reject_count, 3u);
    /* plausible but the covariance held at its trace bound (poor
     * excitation): not taken */
    g.theta[1] = _IQ(2.0);
    g.windup_hold = 1u;
    theta_guard_step(&g);
    assert_true(g.theta_good[1] == _IQ(2.12f * 1.1f));
    /* no update this sample: nothing changes */
    g.windup_hold = 0u;
    g.updated = 0u;
    theta_guard_step(&g);
    assert_true(g.theta_good[1] == _IQ(2.12f * 1.1f));
    g.updated = 1u;
    theta_guard_step(&g);
    assert_true(g.theta_good[1] == _IQ(2.0));
    theta_guard_reset(&g);
    assert_int_equal(g.good, 0u);
}

/* theta_guard_check, the configuration table's test: theta_guard_init's
 * verdict, naming the first K refused: each K with the model's sign and a
 * magnitude below RLS_THETA_MAX (K1 just inside, at it, zero), span in
 * (1, 1e6) (no K named). */
static void test_theta_guard_check(void **state)
{
    const float k_nom[RLS_N] = {-0.842f, 2.12f, 0.107f, -0.308f};
    theta_guard_t g;
    float k[RLS_N];
    uint16_t bad;
    size_t i;
    (void)state;
    for (i = 0; i < RLS_N; i++) {
        k[i] = k_nom[i];
    }
    k[0] = -nextafterf(RLS_THETA_MAX, 0.0f);
    assert_int_equal(theta_guard_check(k, 8.0f, &bad), THETA_GUARD_OK);
    assert_int_equal(bad, RLS_N);
    assert_int_equal(theta_guard_init(&g, k, 8.0f), THETA_GUARD_OK);
    k[0] = -RLS_THETA_MAX;
    assert_int_equal(theta_guard_check(k, 8.0f, &bad), THETA_GUARD_ERR_ARG);
    assert_int_equal(bad, 0u);
    assert_int_equal(theta_guard_init(&g, k, 8.0f), THETA_GUARD_ERR_ARG);
    k[0] = k_nom[0];
    k[2] = 0.0f;
    k[3] = 0.308f;
    assert_int_equal(theta_guard_check(k, 8.0f, &bad), THETA_GUARD_ERR_ARG);
    assert_int_equal(bad, 2u);
    assert_int_equal(theta_guard_check(k_nom, 1.0f, &bad), THETA_GUARD_ERR_ARG);
    assert_int_equal(bad, RLS_N);
    assert_int_equal(theta_guard_init(&g, k_nom, 1.0f), THETA_GUARD_ERR_ARG);
    assert_int_equal(theta_guard_check(k_nom, 8.0f, NULL), THETA_GUARD_OK);
}

/* theta_guard_set_required (the adaptive sequence's fused mode: only K2 and K4 judged).
 * A theta with K1 of the wrong sign and K3 negative (K2, K4 plausible) is
 * rejected with all four required, taken once the mask is K2|K4 (0xA),
 * including its implausible K1, K3 as they are; K2 or K4 out of band is
 * still rejected.  A released K accepts the whole RLS range (+-16 pu).
 * Bad masks (0, bits above 0xF) are refused with nothing changed; a
 * released K stays released when the mask widens again (the header: until
 * theta_guard_init), and theta_guard_init restores all four. */
static void test_theta_guard_required(void **state)
{
    theta_guard_t g, before;
    const float k_nom[RLS_N] = {-0.842f, 2.12f, 0.107f, -0.308f};
    static const uint16_t bad_masks[] = {0x0u, 0x10u, 0x1Au, 0x8000u, 0xFFFFu};
    uint16_t i;
    (void)state;
    assert_int_equal(theta_guard_init(&g, k_nom, 8.0f), THETA_GUARD_OK);
    assert_int_equal(g.required, 0xFu);
    g.updated = 1u;
    g.theta[0] = _IQ(0.5);                 /* K1 > 0: wrong sign */
    g.theta[1] = _IQ(2.12f * 1.1f);
    g.theta[2] = _IQ(-0.05);               /* K3 < 0 (15 kW, Lm 30 % low) */
    g.theta[3] = _IQ(-0.308f * 0.9f);
    theta_guard_step(&g);
    assert_int_equal(g.good, 0u);
    assert_int_equal(g.held, 1u);
    assert_int_equal(g.reject_count, 1u);

    /* bad masks: refused, nothing changed */
    before = g;
    for (i = 0u; i < sizeof bad_masks / sizeof bad_masks[0]; i++) {
        assert_int_equal(theta_guard_set_required(&g, bad_masks[i]), THETA_GUARD_ERR_ARG);
        assert_memory_equal(&g, &before, sizeof g);
    }

    assert_int_equal(theta_guard_set_required(&g, 0xAu), THETA_GUARD_OK);
    assert_int_equal(g.required, 0xAu);
    theta_guard_step(&g);
    assert_int_equal(g.good, 1u);
    assert_int_equal(g.held, 0u);
    for (i = 0u; i < RLS_N; i++) {
        assert_true(g.theta_good[i] == g.theta[i]);
    }
    /* released: anything in the RLS range */
    g.theta[0] = _IQ(15.9);
    g.theta[2] = _IQ(-15.9);
    theta_guard_step(&g);
    assert_int_equal(g.held, 0u);
    assert_true(g.theta_good[0] == _IQ(15.9) && g.theta_good[2] == _IQ(-15.9));
    /* still required: K2 9x too large, K4 of the wrong sign */
    g.theta[1] = _IQ(2.12f * 9.0f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 1u);
    assert_true(g.theta_good[1] == _IQ(2.12f * 1.1f));
    g.theta[1] = _IQ(2.12f);
    g.theta[3] = _IQ(0.308f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 1u);
    assert_int_equal(g.reject_count, 3u);
    g.theta[3] = _IQ(-0.308f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 0u);

    /* widening the mask again: the released K1, K3 stay released */
    assert_int_equal(theta_guard_set_required(&g, 0xFu), THETA_GUARD_OK);
    g.theta[0] = _IQ(0.5);
    theta_guard_step(&g);
    assert_int_equal(g.held, 0u);
    /* theta_guard_init restores the four bands */
    assert_int_equal(theta_guard_init(&g, k_nom, 8.0f), THETA_GUARD_OK);
    g.updated = 1u;
    g.theta[0] = _IQ(0.5);
    g.theta[1] = _IQ(2.12f);
    g.theta[2] = _IQ(0.107f);
    g.theta[3] = _IQ(-0.308f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 1u);
    g.theta[0] = _IQ(-0.842f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 0u);
    /* a single-K mask (K2 only) */
    assert_int_equal(theta_guard_set_required(&g, 0x2u), THETA_GUARD_OK);
    g.theta[3] = _IQ(0.308f);
    theta_guard_step(&g);
    assert_int_equal(g.held, 0u);
}

/* Priority (protect.h) and the strict restart condition. */
static void test_protect_priority_and_clear(void **state)
{
    protect_t p;
    (void)state;
    assert_int_equal(protect_init(&p, _IQ(0.9), _IQ(1.3), _IQ(0.7)), 0);
    p.vdc = _IQ(1.0);
    /* a rail with the bus inside its limits: ADC_RAIL */
    p.adc_rail = 1u;
    protect_step(&p);
    assert_int_equal(p.fault, FAULT_ADC_RAIL);
    p.adc_rail = 0u;
    assert_int_equal(protect_clear(&p), 1u);
    /* rail and overvoltage at once (the bus reading at its top rail is at
     * least the full scale): an overvoltage, what the drive must assume */
    p.adc_rail = 1u;
    p.vdc = _IQ(2.0);
    protect_step(&p);
    assert_int_equal(p.fault, FAULT_BUS_OVERVOLTAGE);
    /* first fault stays latched */
    p.adc_rail = 0u;
    p.ia = _IQ(1.0);
    protect_step(&p);
    assert_int_equal(p.fault, FAULT_BUS_OVERVOLTAGE);
    /* not cleared while a cause is present: overcurrent, or a low bus even
     * with the bridge off */
    assert_int_equal(protect_clear(&p), 0u);
    p.ia = _IQ(0.0);
    p.vdc = _IQ(0.5);
    p.pwm_on = 0u;
    assert_int_equal(protect_clear(&p), 0u);
    p.vdc = _IQ(1.0);
    p.encoder_fault = 1u;
    assert_int_equal(protect_clear(&p), 0u);
    p.encoder_fault = 0u;
    assert_int_equal(protect_clear(&p), 1u);
    assert_int_equal(p.fault, FAULT_NONE);
    /* the current check latches its own code */
    p.current_fault = 1u;
    protect_step(&p);
    assert_int_equal(p.fault, FAULT_CURRENT_SENSOR);
}

/* protect_over against |i| > i_trip over the whole int32_t range: both sides
 * of the trip by one LSB and the extremes (the IQ build's unsigned range test
 * must not wrap into "in range"). */
static void test_protect_over_range(void **state)
{
    protect_t p;
    static const int32_t extremes[] = { INT32_MIN, INT32_MIN + 1, -1, 0, 1,
                                        INT32_MAX - 1, INT32_MAX };
    (void)state;
    assert_int_equal(protect_init(&p, _IQ(0.9), _IQ(1.3), _IQ(0.7)), 0);
    assert_int_equal(protect_over(&p, p.i_trip), 0u);
    assert_int_equal(protect_over(&p, -p.i_trip), 0u);
#if MATH_TYPE == IQ_MATH
    assert_int_equal(protect_over(&p, p.i_trip + 1), 1u);
    assert_int_equal(protect_over(&p, -p.i_trip - 1), 1u);
    for (size_t k = 0; k < sizeof extremes / sizeof extremes[0]; ++k) {
        const int64_t mag = extremes[k] < 0 ? -(int64_t)extremes[k] : (int64_t)extremes[k];
        assert_int_equal(protect_over(&p, extremes[k]), (uint16_t)(mag > p.i_trip));
    }
#else
    (void)extremes;
    assert_int_equal(protect_over(&p, p.i_trip * 1.0001f), 1u);
    assert_int_equal(protect_over(&p, -p.i_trip * 1.0001f), 1u);
#endif
    /* a level the unsigned test cannot hold is refused */
    assert_int_equal(protect_init(&p, _IQ(40.0), _IQ(41.0), _IQ(0.7)), 1);
}

/* protect_args_ok, the configuration table's test: protect_init's verdict
 * at each bound of protect.h, the first level refused named: i_trip in
 * (0, 32) pu, vdc_min > 0, vdc_max > vdc_min, each to the LSB. */
static void test_protect_args(void **state)
{
#if MATH_TYPE == IQ_MATH
    const _iq below32 = _IQ(32.0) - 1, above07 = _IQ(0.7) + 1;
#else
    const _iq below32 = nextafterf(32.0f, 0.0f), above07 = nextafterf(0.7f, 1.0f);
#endif
    const _iq trip[] = {below32, _IQ(32.0), _IQ(0.0), _IQ(0.9), _IQ(0.9), _IQ(0.9), _IQ(0.9)};
    const _iq vmax[] = {_IQ(1.3), _IQ(1.3), _IQ(1.3), _IQ(1.3), _IQ(1.3), above07, _IQ(0.7)};
    const _iq vmin[] = {_IQ(0.7), _IQ(0.7), _IQ(0.7), _IQ(0.0), _IQ(0.7), _IQ(0.7), _IQ(0.7)};
    const protect_args_t want[] = {PROTECT_ARGS_OK, PROTECT_ERR_TRIP, PROTECT_ERR_TRIP,
                                   PROTECT_ERR_VDC_MIN, PROTECT_ARGS_OK, PROTECT_ARGS_OK,
                                   PROTECT_ERR_VDC_MAX};
    protect_t p;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(protect_args_ok(trip[i], vmax[i], vmin[i]), want[i]);
        assert_int_equal(protect_init(&p, trip[i], vmax[i], vmin[i]),
                         (want[i] == PROTECT_ARGS_OK) ? 0 : 1);
    }
    /* the trip judged first, then the undervoltage (a level not yet known
     * passed as 0: drive_limits.c) */
    assert_int_equal(protect_args_ok(_IQ(0.0), _IQ(0.0), _IQ(0.0)), PROTECT_ERR_TRIP);
    assert_int_equal(protect_args_ok(_IQ(0.9), _IQ(0.0), _IQ(0.0)), PROTECT_ERR_VDC_MIN);
}

/* Healthy runs (no fault injected) of every scenario on the paper motor and
 * of the 1.1 kW motor: no protection trips, and the current check stays
 * below two thirds of its trip level.  Measured: the worst is the
 * magnetising step of the paper motor (0.33 pu of i_M at the voltage limit),
 * 0.073 pu at 0.071 s; the 1.1 kW motor 0.035 pu. */
/* Overcurrent in each phase alone, either sign, one LSB beyond the trip
 * level (and not at it): phase c, computed from a and b, is the only one that
 * sees a fault current between a and b returning through c (ia = ib = 0.5,
 * ic = -1.0 with a 0.9 pu trip). */
static void test_protect_overcurrent_each_phase(void **state)
{
    protect_t p;
    _iq *phase[3];
    unsigned k;
    int sgn;
#if MATH_TYPE == IQ_MATH
    const _iq lsb = 1;            /* one Q24 LSB */
#else
    const _iq lsb = 0.9f * 1e-6f;   /* a few float ulps of 0.9 */
#endif
    (void)state;
    for (k = 0; k < 3u; k++) {
        for (sgn = -1; sgn <= 1; sgn += 2) {
            const _iq s = (sgn < 0) ? -_IQ(1.0) : _IQ(1.0);
            assert_int_equal(protect_init(&p, _IQ(0.9), _IQ(1.3), _IQ(0.7)), 0);
            phase[0] = &p.ia;
            phase[1] = &p.ib;
            phase[2] = &p.ic;
            p.vdc = _IQ(1.0);
            p.pwm_on = 1u;
            *phase[k] = _IQmpy(s, _IQ(0.9));   /* at the level: no trip */
            protect_step(&p);
            assert_int_equal(p.fault, FAULT_NONE);
            *phase[k] = _IQmpy(s, _IQ(0.9) + lsb);
            protect_step(&p);
            if (p.fault != FAULT_OVERCURRENT) {
                fail_msg("phase %c at %+d (trip + 1 LSB): fault %d, not OVERCURRENT", 'a' + (int)k,
                         sgn, (int)p.fault);
            }
        }
    }
    /* a-b short returning through c: a and b inside, c beyond */
    assert_int_equal(protect_init(&p, _IQ(0.9), _IQ(1.3), _IQ(0.7)), 0);
    p.vdc = _IQ(1.0);
    p.ia = _IQ(0.5);
    p.ib = _IQ(0.5);
    p.ic = _IQ(-1.0);
    protect_step(&p);
    assert_int_equal(p.fault, FAULT_OVERCURRENT);
}

static void test_healthy_runs_margin(void **state)
{
    static const struct { const char *ini; sim_scenario_t scen; } runs[] = {
        {MC_CONFIG_DIR "/paper_motor.ini", SCEN_START},
        {MC_CONFIG_DIR "/paper_motor.ini", SCEN_REVERSAL},
        {MC_CONFIG_DIR "/paper_motor.ini", SCEN_LOAD_STEPS},
        {MC_CONFIG_DIR "/motor_1kw.ini", SCEN_START},
    };
    unsigned i;
    (void)state;
    for (i = 0; i < sizeof runs / sizeof runs[0]; i++) {
        sim_config_t cfg;
        sim_result_t r;
        sim_options_t opt;
        char err[256];
        memset(&opt, 0, sizeof opt);
        opt.scenario = runs[i].scen;
        opt.quiet = 1u;
        assert_int_equal(sim_config_load(runs[i].ini, &cfg, err, sizeof err), 0);
        assert_int_equal(sim_run(&cfg, &opt, &r, err, sizeof err), 0);
        print_message("%s %s: faults %u, max filtered current error %.4f pu at %.4f s "
                      "(trip 0.15)\n",
                      runs[i].ini, sim_scenario_name(runs[i].scen), r.n_faults_seen,
                      r.max_cur_check_pu, r.t_max_cur_check_s);
        assert_int_equal(r.n_faults_seen, 0);
        assert_true(r.max_cur_check_pu < 0.1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_encoder_frozen),
        cmocka_unit_test(test_encoder_jump_and_wrap),
        cmocka_unit_test(test_encoder_check_args),
        cmocka_unit_test(test_current_check),
        cmocka_unit_test(test_theta_guard),
        cmocka_unit_test(test_theta_guard_required),
        cmocka_unit_test(test_theta_guard_check),
        cmocka_unit_test(test_protect_priority_and_clear),
        cmocka_unit_test(test_protect_over_range),
        cmocka_unit_test(test_protect_args),
        cmocka_unit_test(test_protect_overcurrent_each_phase),
        cmocka_unit_test(test_healthy_runs_margin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
