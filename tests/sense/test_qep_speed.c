/* qep_speed: counter wrap in both directions, direction, speed at constant
 * speed against the exact value (bounds from the quantisation analysis in
 * qep_speed.h), the delay of the speed measurement under constant
 * acceleration, the exact angle after thousands of revolutions, saturation
 * and argument checks.
 *
 * The encoder is simulated exactly: the true position in counts is a double
 * p(k); the counter reads floor(p(k)) modulo 2^16 (x4 quadrature edges).
 * Rig: 1000 lines (cpr 4000), 2 pole pairs, f_base 50 Hz, Ts = 1/15000 s,
 * so 1 pu of electrical speed is 1500 r/min = 6.667 counts per sample and
 * one count in a window of W = 16 is kres = 2 / (16 * 4000 * Ts * 50) =
 * 0.009375 pu. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "base_values.h"
#include "qep_speed.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
#else
static double to_d(_iq x) { return (double)x; }
#endif
#define LSB 5.9604644775390625e-8   /* 2^-24 */
#define PI 3.14159265358979323846

#define TS_S (1.0f / 15000.0f)
#define LINES 1000u
#define CPR 4000.0
#define PP 2.0
#define W 16u
/* counts per sample at 1 pu electrical speed: f_base cpr / pp * Ts */
#define CNT_PER_PU (50.0 * CPR / PP * (double)TS_S)
/* speed of one count in the window, pu */
#define KRES (PP / ((double)W * CPR * (double)TS_S * 50.0))
/* |k_speed - KRES|: truncation to Q24 (< 1 LSB) + float init (< 0.05 LSB) */
#define K_ERR (1.05 * LSB)
/* fixed error of the angle conversion: reads low by < 1 + cpr/64 LSB */
#define ANGLE_TOL ((1.0 + CPR / 64.0) * LSB)

static base_values_t g_b;

static int setup(void **state)
{
    (void)state;
    return (base_values_init(&g_b, 20.0f, 34.6410161513775f, 50.0f, 2u, TS_S) == BASE_OK) ? 0 : -1;
}

static uint16_t counter_of(double p)
{
    int64_t c = (int64_t)floor(p);
    return (uint16_t)((uint64_t)c & 0xFFFFu);
}

/* exact angle, pu: (c mod cpr) / cpr for integer position c */
static double angle_of(int64_t c, double mult)
{
    double r = fmod((double)c * mult, CPR);
    if (r < 0.0) {
        r += CPR;
    }
    return r / CPR;
}

static void assert_angle(_iq got, double want, const char *what, uint32_t k)
{
    /* IQ: the conversion reads low by less than ANGLE_TOL, never high.
     * Float: 1/cpr rounded (< 2^-24 relative, times an angle < 1: < 1 LSB)
     * and the product rounded (< 0.5 ulp of a value < 1: <= 0.5 LSB), either
     * way: |e| < 1.5 LSB, asserted at 2 LSB. */
    double e = to_d(got) - want;
#if MATH_TYPE == IQ_MATH
    if (!(e <= 0.0 && e >= -ANGLE_TOL)) {
#else
    if (!(fabs(e) <= 2.0 * LSB)) {
#endif
        print_error("%s k=%u: got %.10f want %.10f err %.2f LSB\n", what, (unsigned)k,
                    to_d(got), want, e / LSB);
        fail();
    }
}

/* Through the 0xFFFF -> 0 wrap forwards at 7 counts per sample, then
 * backwards through it again. */
static void test_wrap_both_directions(void **state)
{
    qep_speed_t q;
    uint32_t k;
    int64_t c = 0xFFF0;          /* true integer position, counts */
    (void)state;

    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    qep_speed_reset(&q, (uint16_t)c);
    for (k = 1u; k <= 40u; k++) {
        c += 7;
        q.count = (uint16_t)((uint64_t)c & 0xFFFFu);
        qep_speed_step(&q);
        assert_angle(q.theta_mech, angle_of(c - 0xFFF0, 1.0), "mech fwd", k);
        assert_angle(q.theta_elec, angle_of(c - 0xFFF0, PP), "elec fwd", k);
        if (k >= W) {
            /* 7 counts/sample = 1.05 pu; window difference 112 exactly */
            assert_true(fabs(to_d(q.speed_raw) - 112.0 * KRES) <= 112.0 * K_ERR + 2.0 * LSB);
            assert_int_equal(q.dir, 1);
        }
    }
    assert_true(c > 0x10000);    /* went through the wrap */
    for (k = 41u; k <= 120u; k++) {
        c -= 9;
        q.count = (uint16_t)((uint64_t)c & 0xFFFFu);
        qep_speed_step(&q);
        assert_angle(q.theta_mech, angle_of(c - 0xFFF0, 1.0), "mech rev", k);
        assert_angle(q.theta_elec, angle_of(c - 0xFFF0, PP), "elec rev", k);
        if (k >= 40u + W) {
            assert_true(fabs(to_d(q.speed_raw) + 144.0 * KRES) <= 144.0 * K_ERR + 2.0 * LSB);
            assert_int_equal(q.dir, -1);
        }
    }
    assert_true(c < 0xFFF0 - 400);   /* back through the wrap, below the start */
    /* standing still: the window empties of counts, dir 0, speed_raw 0 */
    for (k = 0u; k < W; k++) {
        qep_speed_step(&q);
    }
    assert_int_equal(q.dir, 0);
    assert_true(to_d(q.speed_raw) == 0.0);
}

/* Constant speeds from 30 r/min to 3000 r/min, both directions, starting
 * near the counter wrap, 3000 samples each.
 * speed_raw: the window difference is floor(p(k)) - floor(p(k-W)), within
 * 1 count of the true v W: |speed_raw - w| < KRES + |dW| K_ERR (+2 LSB for
 * float's rounding).
 * Mean of speed_raw over N = 2000 samples: the floor errors telescope, so
 * the mean count error is < W/N counts: bound KRES W / N + |dW| K_ERR.
 * speed (filtered, 50 Hz): a convex combination of speed_raw values after
 * the start-up transient (1000 samples = 21 time constants: e^-21 of 2 pu
 * < 1e-9), so also within KRES (+ the rounding bias 0.5/a LSB). */
static void test_constant_speed(void **state)
{
    static const double rpm[] = {30.0, 333.0, 700.0, 1400.0, -1400.0, -2111.0, 3000.0};
    uint32_t i;
    (void)state;

    for (i = 0u; i < sizeof rpm / sizeof rpm[0]; i++) {
        qep_speed_t q;
        double w = rpm[i] / 1500.0;               /* pu electrical */
        double v = w * CNT_PER_PU;                /* counts per sample */
        double p0 = 65536.0 * 3.0 - 250.37;       /* 250 counts below a wrap */
        double a = 1.0 - exp(-2.0 * PI * 50.0 * (double)TS_S);
        double dw_max = fabs(v) * W + 1.0;
        double tol_raw = KRES + dw_max * K_ERR + 2.0 * LSB;
        double tol_filt = tol_raw + (0.5 / a + 1.0) * LSB;
        double tol_mean = KRES * (double)W / 2000.0 + dw_max * K_ERR + 2.0 * LSB;
        double sum = 0.0;
        uint32_t k;

        assert_int_equal(qep_speed_init(&q, LINES, &g_b, 50.0f, W), QEP_SPEED_OK);
        qep_speed_reset(&q, counter_of(p0 - (double)W * v));
        /* history as if running for W samples already */
        for (k = 0u; k < W; k++) {
            q.count = counter_of(p0 - (double)(W - 1u - k) * v);
            qep_speed_step(&q);
        }
        for (k = 1u; k <= 3000u; k++) {
            q.count = counter_of(p0 + (double)k * v);
            qep_speed_step(&q);
            if (!(fabs(to_d(q.speed_raw) - w) <= tol_raw)) {
                print_error("%.0f rpm k=%u raw %.6f want %.6f\n", rpm[i], (unsigned)k,
                            to_d(q.speed_raw), w);
                fail();
            }
            assert_int_equal(q.dir, (w > 0.0) ? 1 : -1);
            if (k > 1000u) {
                if (!(fabs(to_d(q.speed) - w) <= tol_filt)) {
                    print_error("%.0f rpm k=%u speed %.6f want %.6f\n", rpm[i], (unsigned)k,
                                to_d(q.speed), w);
                    fail();
                }
                sum += to_d(q.speed_raw);
            }
        }
        if (!(fabs(sum / 2000.0 - w) <= tol_mean)) {
            print_error("%.0f rpm: mean %.8f want %.8f (tol %.3g)\n", rpm[i], sum / 2000.0, w,
                        tol_mean);
            fail();
        }
    }
}

/* Constant acceleration 10 pu/s from rest.  The window mean is the speed
 * at the window's middle (exact for a quadratic position), so speed_raw
 * lags the true speed by W/2 = 8 samples; the low-pass (100 Hz, a =
 * 0.04103) adds (1-a)/a = 23.37 samples for a ramp.  Measured lag =
 * mean over N = 2000 samples (k = 400..2399, after the filter's start-up
 * transient: (1-a)^400 = 5e-8) of (w(k) - speed(k)) / (alpha Ts).
 * Bounds: the quantisation errors telescope (mean < W/N counts) and the
 * filtered quantisation adds < 2/(aN) counts (the filter's start and end
 * terms), so the lag is within KRES (W/N + 2/(aN)) / (alpha Ts) = 0.34
 * samples (plus < 0.01 for LSB effects: 0.5/a LSB rounding bias, k_speed
 * error); asserted at 0.35 samples for `speed` and KRES W/N / (alpha Ts)
 * + 0.01 = 0.12 samples for speed_raw. */
static void test_speed_delay(void **state)
{
    qep_speed_t q;
    const double alpha_ts = 10.0 * (double)TS_S;      /* pu per sample */
    const double a = 1.0 - exp(-2.0 * PI * 100.0 * (double)TS_S);
    const double n = 2000.0;
    double lag_raw = 0.0, lag = 0.0;
    double tol_raw = KRES * (double)W / n / alpha_ts + 0.01;
    double tol = KRES * ((double)W / n + 2.0 / (a * n)) / alpha_ts + 0.01;
    uint32_t k;
    (void)state;

    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    qep_speed_reset(&q, counter_of(0.0));
    for (k = 1u; k <= 2399u; k++) {
        double w = alpha_ts * (double)k;
        /* position: integral of w, counts */
        q.count = counter_of(0.5 * alpha_ts * (double)k * (double)k * CNT_PER_PU);
        qep_speed_step(&q);
        if (k >= 400u) {
            lag_raw += (w - to_d(q.speed_raw)) / alpha_ts;
            lag += (w - to_d(q.speed)) / alpha_ts;
        }
    }
    lag_raw /= n;
    lag /= n;
    print_message("lag speed_raw %.4f samples (W/2 = %.1f), speed %.4f (W/2 + (1-a)/a = %.4f)\n",
                  lag_raw, (double)W / 2.0, lag, (double)W / 2.0 + (1.0 - a) / a);
    assert_true(fabs(lag_raw - (double)W / 2.0) <= tol_raw);
    assert_true(fabs(lag - ((double)W / 2.0 + (1.0 - a) / a)) <= tol);
}

/* 400000 samples of irregular motion (steps of -40..+119 counts, mostly
 * forwards: ~1970 net revolutions): both angles stay exact modulo the
 * counts at every sample (no drift), within the fixed conversion error. */
static void test_angle_no_drift(void **state)
{
    qep_speed_t q;
    uint32_t k;
    uint32_t lcg = 12345u;
    int64_t c = 40000;
    (void)state;

    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    qep_speed_reset(&q, (uint16_t)c);
    for (k = 1u; k <= 400000u; k++) {
        lcg = lcg * 1664525u + 1013904223u;
        c += (int64_t)((lcg >> 16) % 160u) - 40;
        q.count = (uint16_t)((uint64_t)c & 0xFFFFu);
        qep_speed_step(&q);
        if (q.pos_mech != (int32_t)(int64_t)(angle_of(c - 40000, 1.0) * CPR + 0.5)) {
            print_error("k=%u pos %ld\n", (unsigned)k, (long)q.pos_mech);
            fail();
        }
        assert_angle(q.theta_mech, angle_of(c - 40000, 1.0), "mech", k);
        assert_angle(q.theta_elec, angle_of(c - 40000, PP), "elec", k);
    }
    assert_true((c - 40000) / 4000 > 1900);
}

/* A 30000-count jump (encoder glitch) saturates speed_raw at d_max counts
 * (<= 63 pu) with the right sign instead of overflowing Q24. */
static void test_saturation(void **state)
{
    qep_speed_t q;
    (void)state;
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    qep_speed_reset(&q, 100u);
    assert_int_equal(q.d_max, (int32_t)(63.0 / KRES));
    q.count = 30100u;
    qep_speed_step(&q);
    assert_true(to_d(q.speed_raw) <= 63.0 && to_d(q.speed_raw) > 62.9);
    assert_true(to_d(q.speed) > 0.0);
    qep_speed_reset(&q, 100u);
    q.count = (uint16_t)(100u - 30000u);
    qep_speed_step(&q);
    assert_true(to_d(q.speed_raw) >= -63.0 && to_d(q.speed_raw) < -62.9);
    assert_int_equal(q.dir, -1);
    /* just beyond d_max (1.5 d_max, each sign): the same saturation, not a
     * speed above 63 pu */
    qep_speed_reset(&q, 100u);
    q.count = (uint16_t)(100 + q.d_max + q.d_max / 2);
    qep_speed_step(&q);
    assert_true(q.speed_raw == _IQmpyI32(q.k_speed, q.d_max));
    qep_speed_reset(&q, 100u);
    q.count = (uint16_t)(100 - q.d_max - q.d_max / 2);
    qep_speed_step(&q);
    assert_true(q.speed_raw == _IQmpyI32(q.k_speed, -q.d_max));
}

static void test_init_errors(void **state)
{
    qep_speed_t q;
    base_values_t b65;
    (void)state;
    assert_int_equal(qep_speed_init(&q, LINES, NULL, 100.0f, W), QEP_SPEED_ERR_BASE);
    assert_int_equal(base_values_init(&b65, 20.0f, 34.6f, 50.0f, 65u, TS_S), BASE_OK);
    assert_int_equal(qep_speed_init(&q, LINES, &b65, 100.0f, W), QEP_SPEED_ERR_BASE);
    assert_int_equal(qep_speed_init(&q, 0u, &g_b, 100.0f, W), QEP_SPEED_ERR_LINES);
    assert_int_equal(qep_speed_init(&q, 8193u, &g_b, 100.0f, W), QEP_SPEED_ERR_LINES);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, 0u), QEP_SPEED_ERR_WINDOW);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, 3u), QEP_SPEED_ERR_WINDOW);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, 128u), QEP_SPEED_ERR_WINDOW);
    /* 1 line, W = 1: one count = 150 pu of speed */
    assert_int_equal(qep_speed_init(&q, 1u, &g_b, 100.0f, 1u), QEP_SPEED_ERR_RESOLUTION);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 0.0f, W), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 7500.0f, W), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, NAN, W), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 0.1f, W), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_init(&q, 8192u, &g_b, 100.0f, 64u), QEP_SPEED_OK);
    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, 1u), QEP_SPEED_OK);
}

/* qep_speed_check and qep_speed_decim_check, the configuration table's
 * tests: init's and set_decim's verdicts, at each bound.  One count in one
 * sample below 1 pu: pp / (cpr Ts f_base) < 1, cpr > 600, more than 150
 * lines; the speed filter's corner below 1/(2 decim Ts) (937.5 Hz at
 * decim 8), decim a power of two up to W. */
static void test_check(void **state)
{
    qep_speed_t q;
    (void)state;
    assert_int_equal(qep_speed_check(151u, &g_b, 100.0f, W), QEP_SPEED_OK);
    assert_int_equal(qep_speed_check(150u, &g_b, 100.0f, W), QEP_SPEED_ERR_RESOLUTION);
    assert_int_equal(qep_speed_init(&q, 150u, &g_b, 100.0f, W), QEP_SPEED_ERR_RESOLUTION);
    assert_int_equal(qep_speed_check(QEP_SPEED_LINES_MAX, &g_b, 100.0f, W), QEP_SPEED_OK);
    assert_int_equal(qep_speed_check(QEP_SPEED_LINES_MAX + 1u, &g_b, 100.0f, W),
                     QEP_SPEED_ERR_LINES);
    assert_int_equal(qep_speed_check(LINES, &g_b, 7499.0f, W), QEP_SPEED_OK);
    assert_int_equal(qep_speed_check(LINES, &g_b, 7500.0f, W), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_check(LINES, &g_b, 100.0f, 3u), QEP_SPEED_ERR_WINDOW);
    assert_int_equal(qep_speed_check(LINES, NULL, 100.0f, W), QEP_SPEED_ERR_BASE);

    assert_int_equal(qep_speed_init(&q, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    assert_int_equal(qep_speed_decim_check(8u, W, &g_b, 937.0f), QEP_SPEED_OK);
    assert_int_equal(qep_speed_set_decim(&q, 8u, &g_b, 937.0f), QEP_SPEED_OK);
    assert_int_equal(qep_speed_decim_check(8u, W, &g_b, 938.0f), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_set_decim(&q, 8u, &g_b, 938.0f), QEP_SPEED_ERR_CUTOFF);
    assert_int_equal(qep_speed_decim_check(W, W, &g_b, 100.0f), QEP_SPEED_OK);
    assert_int_equal(qep_speed_decim_check(2u * W, W, &g_b, 100.0f), QEP_SPEED_ERR_WINDOW);
    assert_int_equal(qep_speed_decim_check(6u, W, &g_b, 100.0f), QEP_SPEED_ERR_WINDOW);
    assert_int_equal(qep_speed_decim_check(8u, W, NULL, 100.0f), QEP_SPEED_ERR_BASE);
}

/* speed_1, the one-sample speed of a W = 16 instance, is exactly (to the bit)
 * the speed_raw of a W = 1 instance fed the same counts: irregular steps of
 * -40..+40 counts through both wraps of the 16-bit counter and beyond the
 * saturation (d_max1 = 63 pu / 0.15 pu per count = 420 counts).  And against
 * the formula: one count in one sample is pp / (cpr Ts f_base) = 0.15 pu. */
static void test_one_sample_speed(void **state)
{
    qep_speed_t q16, q1;
    uint16_t c = 65500u;
    uint32_t x = 12345u;
    int k;
    (void)state;
    assert_int_equal(qep_speed_init(&q16, LINES, &g_b, 100.0f, W), QEP_SPEED_OK);
    assert_int_equal(qep_speed_init(&q1, LINES, &g_b, 100.0f, 1u), QEP_SPEED_OK);
    qep_speed_reset(&q16, c);
    qep_speed_reset(&q1, c);
    for (k = 0; k < 20000; k++) {
        int32_t step;
        x = x * 1103515245u + 12345u;
        step = (int32_t)((x >> 16) % 81u) - 40;
        if (k == 10000) {
            step = 1000;   /* beyond d_max1: saturates in both */
        }
        c = (uint16_t)((int32_t)c + step);
        q16.count = c;
        q1.count = c;
        qep_speed_step(&q16);
        qep_speed_step(&q1);
        assert_true(q16.speed_1 == q1.speed_raw);
        if (k != 10000) {
            /* |step| <= 40 counts: within one Q24 LSB per count of the formula */
            assert_true(fabs(to_d(q16.speed_1) - (double)step * PP / (CPR * (double)TS_S * 50.0)) <=
                        (fabs((double)step) + 1.0) * LSB + 1e-6 * fabs((double)step));
        }
    }
}

/* qep_diff (branch-free) against its definition, a - b modulo 2^16 read
 * as a two's complement number in [-32768, 32767]: every difference, at
 * several b (the wrap of the counter at every place). */
static void test_qep_diff_every_step(void **state)
{
    static const uint16_t base[] = { 0u, 1u, 32767u, 32768u, 65535u, 12345u };
    size_t j;
    uint32_t d;
    (void)state;
    for (j = 0; j < sizeof base / sizeof base[0]; j++) {
        for (d = 0u; d <= 0xFFFFu; d++) {
            const uint16_t a = (uint16_t)(base[j] + d);
            const int32_t want = (d < 32768u) ? (int32_t)d : (int32_t)d - 65536;
            assert_int_equal(qep_diff(a, base[j]), want);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_qep_diff_every_step),
        cmocka_unit_test(test_wrap_both_directions),
        cmocka_unit_test(test_constant_speed),
        cmocka_unit_test(test_speed_delay),
        cmocka_unit_test(test_angle_no_drift),
        cmocka_unit_test(test_saturation),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_one_sample_speed),
        cmocka_unit_test(test_check),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
