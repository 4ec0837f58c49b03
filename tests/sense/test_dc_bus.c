/* dc_bus: scaling raw -> pu against vdc = raw/65520 * V_fs / V_base, the
 * low-pass step response against the analytic exponential, the rail flag
 * and argument checks. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "base_values.h"
#include "dc_bus.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
#else
static double to_d(_iq x) { return (double)x; }
#endif
#define LSB 5.9604644775390625e-8   /* 2^-24 */
#define PI 3.14159265358979323846

#define TS_S (1.0f / 15000.0f)
#define V_FS 100.0f                 /* bus volts that read 3.0 V (code 4095) */

static base_values_t g_b;

static int setup(void **state)
{
    (void)state;
    /* 60 V nominal bus: V_base = 60 / sqrt(3) */
    return (base_values_init(&g_b, 20.0f, 34.6410161513775f, 50.0f, 2u, TS_S) == BASE_OK) ? 0 : -1;
}

/* Every ADC code against the double formula.  Bound 8 LSB: k_scale =
 * V_fs/V_base * 65536/65520 is computed in float (two roundings, 1.2e-7
 * relative of 2.887 pu: 6 LSB), truncated to Q24 (< 1 LSB; times raw/65536
 * < 1) and the product truncated (< 1 LSB).  Float build: the same init
 * error plus two roundings of values < 3 (< 3 LSB): within 8 LSB too. */
static void test_scaling(void **state)
{
    dc_bus_t d;
    uint32_t code;
    double vb = (double)g_b.V_base_V;
    (void)state;

    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 100.0f), DC_BUS_OK);
    for (code = 0u; code < 4096u; code++) {
        /* the centre of the code: (raw + 8) / 65520 (dc_bus.h) */
        double want = ((double)(code << 4) + 8.0) / 65520.0 * (double)V_FS / vb;
        d.vdc_raw = (uint16_t)(code << 4);
        dc_bus_step(&d);
        if (!(fabs(to_d(d.vdc) - want) <= 8.0 * LSB)) {
            print_error("code %u: got %.10f want %.10f\n", (unsigned)code, to_d(d.vdc), want);
            fail();
        }
        assert_int_equal(d.rail, (code == 4095u) ? 1 : 0);
    }
    /* code 4095 reads V_fs (4095.5 / 4095): 100.0122 V = 2.88710 pu (8 LSB as above) */
    assert_true(fabs(to_d(d.vdc) - 100.0 * 4095.5 / 4095.0 / 34.6410161513775) <= 8.0 * LSB);
}

/* Step 30 V -> 60 V after priming: vdc_filt(k) against
 * v1 + (v0 - v1) exp(-wc k Ts), wc = 2 pi 100 rad/s, for 600 samples
 * (6.3 time constants).  The reference takes v0, v1 from the module's own
 * vdc (the scaling is tested above), so the error is the filter's alone:
 * e(k) = (1-a) e(k-1) + r(k) + dv (a_q - a)(1-a_q)^(k-1), with r the
 * rounding of _IQrmpy (<= 0.5 LSB) and a_q the coefficient as stored
 * (1 - expf(): < 1 ulp of exp, 6e-8 = 1 LSB; truncated to Q24: < 1 LSB;
 * so |a_q - a| < 2 LSB), hence
 * |e| <= 0.5/a + |dv| |a_q - a| max_k k (1-a)^(k-1)
 *      <= 0.5/a + |dv| |a_q - a| / (e a).
 * a = 1 - exp(-2 pi 100 / 15000) = 0.04103, dv = 30 V = 0.866 pu:
 * 12.2 LSB + 0.866 * 2 LSB / 0.1115 = 12.2 + 15.5 LSB; asserted at 28 LSB.
 * Float build: each update rounds the sum (0.5 ulp of < 2 pu, <= 1 LSB),
 * accumulating to <= 1/a = 24.4 LSB, and a is within 1 LSB: 24.4 + 7.8,
 * asserted at 34 LSB. */
static void test_filter_step_response(void **state)
{
    dc_bus_t d;
    uint32_t k;
    double a = 1.0 - exp(-2.0 * PI * 100.0 * (double)TS_S);
    double v0, v1, tol;
    uint16_t raw0 = (uint16_t)((uint32_t)(30.0 / 100.0 * 4095.0 + 0.5) << 4);
    uint16_t raw1 = (uint16_t)((uint32_t)(60.0 / 100.0 * 4095.0 + 0.5) << 4);
    (void)state;

#if MATH_TYPE == IQ_MATH
    tol = 28.0 * LSB;
#else
    tol = 34.0 * LSB;
#endif
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 100.0f), DC_BUS_OK);
    assert_true(fabs(to_d(d.k_filt) - a) <= 2.0 * LSB);
    /* first step primes the filter: no start-up transient */
    d.vdc_raw = raw0;
    dc_bus_step(&d);
    assert_true(d.vdc_filt == d.vdc);
    v0 = to_d(d.vdc);
    dc_bus_step(&d);
    assert_true(d.vdc_filt == d.vdc);   /* settled: stays */

    d.vdc_raw = raw1;
    for (k = 1u; k <= 600u; k++) {
        double want;
        dc_bus_step(&d);
        v1 = to_d(d.vdc);
        want = v1 + (v0 - v1) * exp(-2.0 * PI * 100.0 * (double)TS_S * (double)k);
        if (!(fabs(to_d(d.vdc_filt) - want) <= tol)) {
            print_error("k=%u: got %.10f want %.10f err %.2f LSB\n", (unsigned)k,
                        to_d(d.vdc_filt), want, (to_d(d.vdc_filt) - want) / LSB);
            fail();
        }
    }
    /* 600 samples = 25 time constants: settled */
    assert_true(fabs(to_d(d.vdc_filt) - to_d(d.vdc)) <= tol);
}

static void test_init_errors(void **state)
{
    dc_bus_t d;
    base_values_t zero = {0};
    (void)state;
    assert_int_equal(dc_bus_init(&d, V_FS, NULL, 100.0f), DC_BUS_ERR_BASE);
    assert_int_equal(dc_bus_init(&d, V_FS, &zero, 100.0f), DC_BUS_ERR_BASE);
    assert_int_equal(dc_bus_init(&d, 0.0f, &g_b, 100.0f), DC_BUS_ERR_FULL_SCALE);
    assert_int_equal(dc_bus_init(&d, NAN, &g_b, 100.0f), DC_BUS_ERR_FULL_SCALE);
    /* 64 V_base at full scale: no Q24 headroom left */
    assert_int_equal(dc_bus_init(&d, 64.0f * 34.65f, &g_b, 100.0f), DC_BUS_ERR_FULL_SCALE);
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 0.0f), DC_BUS_ERR_CUTOFF);
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 7500.0f), DC_BUS_ERR_CUTOFF);   /* Nyquist */
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, NAN), DC_BUS_ERR_CUTOFF);
    /* 0.1 Hz at 15 kHz: a = 4.2e-5 < 1e-4 */
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 0.1f), DC_BUS_ERR_CUTOFF);
    assert_int_equal(dc_bus_init(&d, V_FS, &g_b, 1.0f), DC_BUS_OK);
}

/* dc_bus_check, the configuration table's test: init's verdict, at each
 * bound.  Full scale: V_fs / V_base * 65536/65520 below
 * DC_BUS_FULL_SCALE_MAX_PU (64 x 34.641 V x 65520/65536 = 2216.5 V); the
 * cut-off below 1/(2 Ts) (7500 Hz) with a >= DC_BUS_FILTER_A_MIN (a = 1e-4
 * at 0.2387 Hz). */
static void test_check(void **state)
{
    const float fs_max = DC_BUS_FULL_SCALE_MAX_PU * g_b.V_base_V * (65520.0f / 65536.0f);
    const float fs[] = {fs_max * 0.9999f, fs_max * 1.0001f, V_FS, V_FS, V_FS, V_FS};
    const float fc[] = {100.0f, 100.0f, 7499.0f, 7500.0f, 0.24f, 0.238f};
    const dc_bus_status_t want[] = {DC_BUS_OK, DC_BUS_ERR_FULL_SCALE, DC_BUS_OK,
                                    DC_BUS_ERR_CUTOFF, DC_BUS_OK, DC_BUS_ERR_CUTOFF};
    dc_bus_t d;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(dc_bus_check(fs[i], &g_b, fc[i]), want[i]);
        assert_int_equal(dc_bus_init(&d, fs[i], &g_b, fc[i]), want[i]);
    }
    assert_int_equal(dc_bus_check(V_FS, NULL, 100.0f), DC_BUS_ERR_BASE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scaling),
        cmocka_unit_test(test_filter_step_response),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_check),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
