/**
 * @file test_model_sensors.c
 * Sensor models: the F2812 ADC transfer (codes, rails, left justification),
 * the conditioning of include/hal_adc.h, the Hall sensor's static errors,
 * noise statistics and bandwidth, the PRNG, and the encoder/QEP counter
 * (x4 counting, 16-bit wrap in both directions, direction, count loss).
 *
 * Statistical bounds: N samples of a distribution with standard deviation
 * s give a mean within 5 s/sqrt(N) and a standard deviation within
 * 5 s/sqrt(2N) of the true values except with probability < 1e-6; the
 * streams are seeded, so each run is also exactly repeatable.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "adc_f2812.h"
#include "encoder_model.h"
#include "hall_sensor.h"
#include "model_rng.h"
#include "model_check.h"

#define PI 3.14159265358979323846
#define NSTAT 20000

/* ---- ADC ------------------------------------------------------------- */

static void test_adc_transfer(void **state)
{
    adc_f2812_t a;
    adc_f2812_params_t p;
    const uint16_t codes[6] = {0u, 1u, 1000u, 2047u, 4094u, 4095u};
    int j;
    (void)state;
    adc_f2812_params_ideal(&p);
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_OK);
    /* mid-code inputs, v = (k + 0.5) 3/4095, convert to k (truncation) */
    for (j = 0; j < 5; j++) {
        const double v = ((double)codes[j] + 0.5) * 3.0 / 4095.0;
        const uint16_t raw = adc_f2812_convert(&a, v);
        printf("  v = %.6f V -> raw 0x%04X (code %u, expected %u)\n", v, raw, a.code, codes[j]);
        assert_int_equal(a.code, codes[j]);
        assert_int_equal(raw, (uint16_t)(codes[j] << 4)); /* left-justified */
        assert_int_equal(raw & 0x000Fu, 0u);
    }
    /* a code edge: just below (k) 3/4095 reads k-1, just above reads k */
    assert_int_equal(adc_f2812_convert(&a, 1000.0 * 3.0 / 4095.0 - 1e-9) >> 4, 999u);
    assert_int_equal(adc_f2812_convert(&a, 1000.0 * 3.0 / 4095.0 + 1e-9) >> 4, 1000u);
    /* rails */
    assert_int_equal(adc_f2812_convert(&a, -0.2), 0x0000u);
    assert_int_equal(adc_f2812_convert(&a, 0.0), 0x0000u);
    assert_int_equal(adc_f2812_convert(&a, 3.0), 0xFFF0u);
    assert_int_equal(adc_f2812_convert(&a, 3.7), 0xFFF0u);
    assert_int_equal(adc_f2812_convert(&a, NAN), 0x0000u);
    /* static errors: +10 LSB offset, +1 % gain at 1.5 V: floor(2047.5 * 1.01 + 10) */
    p.offset_lsb = 10.0;
    p.gain_error = 0.01;
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_OK);
    assert_int_equal(adc_f2812_convert(&a, 1.5) >> 4, (uint16_t)floor(2047.5 * 1.01 + 10.0));
    /* validation */
    p.noise_lsb_rms = -1.0;
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_ERR_NOISE);
    adc_f2812_params_ideal(&p);
    p.gain_error = -1.0;
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_ERR_GAIN);
}

/* Noise of 1 LSB rms at a mid-code input k + 0.5: truncation removes 0.5 on
 * average, so the code mean is k, and its spread is sqrt(1 + 1/12) LSB
 * (Gaussian noise plus uniform quantisation, Sheppard). */
static void test_adc_noise_statistics(void **state)
{
    adc_f2812_t a;
    adc_f2812_params_t p;
    double s1 = 0.0, s2 = 0.0, mean, sd;
    const double sd_ref = sqrt(1.0 + 1.0 / 12.0);
    int k;
    (void)state;
    adc_f2812_params_default(&p);
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_OK);
    for (k = 0; k < NSTAT; k++) {
        const double c = (double)(adc_f2812_convert(&a, 2000.5 * 3.0 / 4095.0) >> 4);
        s1 += c;
        s2 += c * c;
    }
    mean = s1 / NSTAT;
    sd = sqrt(s2 / NSTAT - mean * mean);
    CHECK_ABS("ADC noise: mean code (LSB), 5 sigma/sqrt(N)", mean, 2000.0, 5.0 * sd_ref / sqrt(NSTAT));
    CHECK_ABS("ADC noise: rms (LSB), 5 sigma/sqrt(2N)", sd, sd_ref, 5.0 * sd_ref / sqrt(2.0 * NSTAT));
}

static void test_conditioning(void **state)
{
    sig_cond_t ci, cv;
    adc_f2812_t a;
    adc_f2812_params_t p;
    (void)state;
    assert_int_equal(sig_cond_init_current(&ci, 20.0), SIG_COND_OK);
    assert_int_equal(sig_cond_init_vdc(&cv, 100.0), SIG_COND_OK);
    CHECK_ABS("current: 0 A -> 1.5 V", sig_cond_apply(&ci, 0.0), 1.5, 1e-15);
    CHECK_ABS("current: +I_fs -> 3.0 V", sig_cond_apply(&ci, 20.0), 3.0, 1e-15);
    CHECK_ABS("current: -I_fs -> 0.0 V", sig_cond_apply(&ci, -20.0), 0.0, 1e-15);
    CHECK_ABS("current: 5 A -> 1.875 V", sig_cond_apply(&ci, 5.0), 1.875, 1e-15);
    CHECK_ABS("bus: full scale -> 3.0 V", sig_cond_apply(&cv, 100.0), 3.0, 1e-15);
    CHECK_ABS("bus: 54 V -> 1.62 V", sig_cond_apply(&cv, 54.0), 1.62, 1e-15);
    adc_f2812_params_ideal(&p);
    assert_int_equal(adc_f2812_init(&a, &p), ADC_F2812_OK);
    /* end to end: 0 A reads floor(2047.5) = 2047, over-range clamps */
    assert_int_equal(adc_f2812_convert(&a, sig_cond_apply(&ci, 0.0)), 2047u << 4);
    assert_int_equal(adc_f2812_convert(&a, sig_cond_apply(&ci, 35.0)), 0xFFF0u);
    assert_int_equal(adc_f2812_convert(&a, sig_cond_apply(&ci, -35.0)), 0x0000u);
    assert_int_equal(sig_cond_init_current(&ci, 0.0), SIG_COND_ERR_FULL_SCALE);
    assert_int_equal(sig_cond_init_vdc(&cv, -5.0), SIG_COND_ERR_FULL_SCALE);
}

/* ---- Hall sensor ------------------------------------------------------ */

static void test_hall_static_and_noise(void **state)
{
    hall_t h;
    hall_params_t p;
    double s1 = 0.0, s2 = 0.0, mean, sd, ref;
    int k;
    (void)state;
    hall_params_default(&p);  /* +0.5 % gain, 20 mA offset, 10 mA rms, 100 kHz */
    assert_int_equal(hall_init(&h, &p), HALL_OK);
    for (k = 0; k < NSTAT; k++) {
        const double y = hall_measure(&h, 3.0, 1.0 / 15000.0);
        s1 += y;
        s2 += y * y;
    }
    mean = s1 / NSTAT;
    sd = sqrt(s2 / NSTAT - mean * mean);
    ref = 3.0 * 1.005 + 0.02;
    CHECK_ABS("Hall: mean = (1+g) i + offset (A)", mean, ref, 5.0 * 0.01 / sqrt(NSTAT));
    CHECK_ABS("Hall: noise rms (A)", sd, 0.01, 5.0 * 0.01 / sqrt(2.0 * NSTAT));
    /* ideal sensor is exact */
    hall_params_ideal(&p);
    assert_int_equal(hall_init(&h, &p), HALL_OK);
    CHECK_ABS("Hall ideal: exact (A)", hall_measure(&h, -7.25, 1e-4), -7.25, 0.0);
    /* validation */
    p.gain_error = -1.0;
    assert_int_equal(hall_init(&h, &p), HALL_ERR_GAIN);
    hall_params_ideal(&p);
    p.bandwidth_Hz = -1.0;
    assert_int_equal(hall_init(&h, &p), HALL_ERR_BANDWIDTH);
    hall_params_ideal(&p);
    p.noise_rms_A = NAN;
    assert_int_equal(hall_init(&h, &p), HALL_ERR_NOISE);
}

/* Bandwidth: a first-order lag's response to a unit step, 1 - e^{-t/tau},
 * tau = 1/(2 pi f_bw); the discretisation is exact for a held input, so the
 * bound is rounding only (1e-12), whatever the call interval. */
static void test_hall_bandwidth(void **state)
{
    hall_t h;
    hall_params_t p;
    const double tau = 1.0 / (2.0 * PI * 10.0e3);
    int k;
    (void)state;
    hall_params_ideal(&p);
    p.bandwidth_Hz = 10.0e3;
    assert_int_equal(hall_init(&h, &p), HALL_OK);
    (void)hall_measure(&h, 0.0, 0.0);  /* primes at 0 A */
    CHECK_ABS("Hall bw: one period (66.7 us)", hall_measure(&h, 1.0, 1.0 / 15000.0),
              1.0 - exp(-(1.0 / 15000.0) / tau), 1e-12);
    assert_int_equal(hall_init(&h, &p), HALL_OK);
    (void)hall_measure(&h, 0.0, 0.0);
    for (k = 0; k < 10; k++) {
        (void)hall_measure(&h, 1.0, 2.0e-6);
    }
    CHECK_ABS("Hall bw: 10 calls of 2 us = one of 20 us", h.i_meas_A, 1.0 - exp(-20e-6 / tau), 1e-12);
}

/* ---- PRNG ------------------------------------------------------------- */

static void test_rng(void **state)
{
    model_rng_t a, b;
    double s1 = 0.0, s2 = 0.0, s4 = 0.0, u1 = 0.0, mean, var, kurt;
    int k, same = 1;
    (void)state;
    model_rng_seed(&a, 42u);
    model_rng_seed(&b, 42u);
    for (k = 0; k < 100; k++) {
        same = same && (model_rng_u64(&a) == model_rng_u64(&b));
    }
    assert_true(same); /* deterministic */
    model_rng_seed(&b, 43u);
    assert_true(model_rng_u64(&a) != model_rng_u64(&b));
    model_rng_seed(&a, 7u);
    for (k = 0; k < NSTAT; k++) {
        const double g = model_rng_gauss(&a);
        const double u = model_rng_uniform(&a);
        assert_true(u > 0.0 && u < 1.0);
        s1 += g;
        s2 += g * g;
        s4 += g * g * g * g;
        u1 += u;
    }
    mean = s1 / NSTAT;
    var = s2 / NSTAT - mean * mean;
    kurt = s4 / NSTAT;
    CHECK_ABS("gauss: mean", mean, 0.0, 5.0 / sqrt(NSTAT));
    /* var of the sample variance of N(0,1): 2/N */
    CHECK_ABS("gauss: variance", var, 1.0, 5.0 * sqrt(2.0 / NSTAT));
    /* E g^4 = 3, var(g^4) = 105 - 9 = 96 */
    CHECK_ABS("gauss: 4th moment", kurt, 3.0, 5.0 * sqrt(96.0 / NSTAT));
    /* uniform: mean 1/2, sd 1/sqrt(12) */
    CHECK_ABS("uniform: mean", u1 / NSTAT, 0.5, 5.0 / sqrt(12.0 * NSTAT));
}

/* ---- encoder ---------------------------------------------------------- */

#define PITCH (2.0 * PI / 4000.0) /* one quadrature edge, 1000 lines */

static void test_encoder_count_and_wrap(void **state)
{
    encoder_t e;
    encoder_params_t p;
    int n;
    (void)state;
    encoder_params_default(&p);
    p.count0 = 65530u;
    /* edges at (k + 0.5) pitch: at theta = n pitch exactly n edges crossed */
    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_OK);
    assert_int_equal(encoder_sample(&e, 3.0 * PITCH), 65533u);
    assert_int_equal(encoder_sample(&e, 13.0 * PITCH), 7u);           /* wraps up 0xFFFF -> 0 */
    assert_int_equal(encoder_sample(&e, 1.0 * PITCH), 65531u);        /* and back down */
    assert_int_equal(encoder_sample(&e, -10.0 * PITCH), 65520u);
    /* one full revolution = 4 x 1000 counts */
    assert_int_equal(encoder_sample(&e, -10.0 * PITCH + 2.0 * PI), (uint16_t)(65520u + 4000u - 65536u));
    /* dithering across one edge: +1, -1, no drift */
    for (n = 0; n < 100; n++) {
        (void)encoder_sample(&e, -10.0 * PITCH + 2.0 * PI + 0.6 * PITCH);
        (void)encoder_sample(&e, -10.0 * PITCH + 2.0 * PI + 0.4 * PITCH);
    }
    assert_int_equal(e.count, 3984u);
    /* reversed direction counts down through 0 -> 0xFFFF */
    p.count0 = 5u;
    p.direction = -1;
    assert_int_equal(encoder_init(&e, &p, 1.0), ENC_OK);
    assert_int_equal(encoder_sample(&e, 1.0 + 12.0 * PITCH), 65529u);
}

/* A 1400 r/min run sampled every 66.7 us for 1 s (93 333 counts, wraps once):
 * the count tracks floor(theta / pitch + 1/2) mod 2^16 at every sample, and
 * the per-period difference modulo 2^16 (what the QEP speed code takes) is
 * 6 or 7 counts (6.22 on average). */
static void test_encoder_run(void **state)
{
    encoder_t e;
    encoder_params_t p;
    const double w = 1400.0 * 2.0 * PI / 60.0, ts = 1.0 / 15000.0;
    uint16_t prev;
    int k, ok = 1;
    (void)state;
    encoder_params_default(&p);
    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_OK);
    prev = e.count;
    for (k = 1; k <= 15000; k++) {
        const double th = w * ts * (double)k;
        const uint16_t c = encoder_sample(&e, th);
        const uint16_t d = (uint16_t)(c - prev);
        const int64_t ref = (int64_t)floor(th / PITCH + 0.5);
        ok = ok && (c == (uint16_t)(ref & 0xFFFF)) && (d == 6u || d == 7u);
        prev = c;
    }
    printf("  after 1 s: count %u (%.1f edges)\n", (unsigned)e.count, w / PITCH);
    assert_true(ok);
}

/* A diverged plant (the shaft angle at 1e30 rad, +-inf, NaN) gives the QEP
 * no new information: the count stays, and the next finite angle counts
 * from the last finite one (an edge index beyond 2^62 once overflowed the
 * edge difference: undefined behaviour, then a garbage count).  With edge
 * loss on, a step beyond 2^16 edges is not drawn edge by edge (it would
 * have looped 1e33 times). */
static void test_encoder_diverged_angle(void **state)
{
    encoder_t e;
    encoder_params_t p;
    const double bad[5] = {1e30, -1e30, INFINITY, -INFINITY, NAN};
    unsigned i;
    (void)state;
    encoder_params_default(&p);
    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_OK);
    assert_int_equal(encoder_sample(&e, 100.0 * PITCH), 100u);
    for (i = 0; i < 5u; i++) {
        assert_int_equal(encoder_sample(&e, bad[i]), 100u);
    }
    assert_int_equal(encoder_sample(&e, 150.0 * PITCH), 150u);
    assert_int_equal(encoder_init(&e, &p, 1e30), ENC_ERR_ANGLE);
    p.loss_prob = 0.5;
    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_OK);
    assert_int_equal(encoder_sample(&e, 1e6 * PITCH), (uint16_t)(1000000u & 0xFFFFu));
    assert_int_equal(encoder_sample(&e, 1e30), (uint16_t)(1000000u & 0xFFFFu));
}

static void test_encoder_loss(void **state)
{
    encoder_t e;
    encoder_params_t p;
    const int n_edges = 40000;
    double kept, sd;
    (void)state;
    encoder_params_default(&p);
    p.loss_prob = 0.1;
    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_OK);
    (void)encoder_sample(&e, (double)n_edges * PITCH);
    kept = (double)e.count / n_edges;
    sd = sqrt(0.1 * 0.9 / n_edges);
    CHECK_ABS("loss: counted fraction (binomial)", kept, 0.9, 5.0 * sd);
    encoder_inject_counts(&e, -5);
    assert_int_equal(e.count, (uint16_t)(kept * n_edges + 0.5) - 5u);
    encoder_params_default(&p);
    p.lines = 0u;         assert_int_equal(encoder_init(&e, &p, 0.0), ENC_ERR_LINES);
    encoder_params_default(&p);
    p.lines = 20000u;     assert_int_equal(encoder_init(&e, &p, 0.0), ENC_ERR_LINES);
    encoder_params_default(&p);
    p.direction = 0;      assert_int_equal(encoder_init(&e, &p, 0.0), ENC_ERR_DIRECTION);
    encoder_params_default(&p);
    p.loss_prob = 1.5;    assert_int_equal(encoder_init(&e, &p, 0.0), ENC_ERR_LOSS);
    encoder_params_default(&p);
    p.theta_offset = 1.0; assert_int_equal(encoder_init(&e, &p, 0.0), ENC_ERR_OFFSET);
    encoder_params_default(&p);
    assert_int_equal(encoder_init(&e, &p, INFINITY), ENC_ERR_ANGLE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_adc_transfer),
        cmocka_unit_test(test_adc_noise_statistics),
        cmocka_unit_test(test_conditioning),
        cmocka_unit_test(test_hall_static_and_noise),
        cmocka_unit_test(test_hall_bandwidth),
        cmocka_unit_test(test_rng),
        cmocka_unit_test(test_encoder_count_and_wrap),
        cmocka_unit_test(test_encoder_run),
        cmocka_unit_test(test_encoder_loss),
        cmocka_unit_test(test_encoder_diverged_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
