/* Co-simulation API: conversions against their closed forms, bad arguments,
 * and independence of instances (bit-identical outputs when interleaved). */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "imfoc_api.h"
#include "imfoc_convert.h"

#define TWO_PI 6.28318530717958647692

static void test_adc_and_qep_conversions(void **state)
{
    (void)state;
    /* 20 A full scale: 0 A -> 1.5 V -> floor(2047.5) = 2047 */
    assert_int_equal(imfoc_adc_current(0.0, 20.0), 2047u << 4);
    assert_int_equal(imfoc_adc_current(20.0, 20.0), 4095u << 4);   /* 3.0 V */
    assert_int_equal(imfoc_adc_current(-20.0, 20.0), 0u);
    assert_int_equal(imfoc_adc_current(1e9, 20.0), 4095u << 4);     /* clamped */
    /* 5 A: pin 1.875 V -> floor(2559.375) = 2559 */
    assert_int_equal(imfoc_adc_current(5.0, 20.0), 2559u << 4);
    /* bus 61.3 V of 100 V: floor(4095 * 0.613) = floor(2510.235) */
    assert_int_equal(imfoc_adc_vdc(61.3, 100.0), 2510u << 4);
    assert_int_equal(imfoc_adc_vdc(-5.0, 100.0), 0u);
    /* 1000 lines: 4000 counts per revolution, nearest edge, 16-bit wrap */
    assert_int_equal(imfoc_qep_count(TWO_PI, 1000u), 4000u);
    assert_int_equal(imfoc_qep_count(-TWO_PI / 4000.0, 1000u), 65535u);
    assert_int_equal(imfoc_qep_count(20.0 * TWO_PI, 1000u), 80000u - 65536u);
    assert_int_equal(imfoc_qep_count(-20.0 * TWO_PI, 1000u), 131072u - 80000u);
    /* unwrap across the +-pi cut */
    assert_true(fabs(imfoc_unwrap(10.0, 3.1, -3.1) - (10.0 + TWO_PI - 6.2)) < 1e-12);
    assert_true(fabs(imfoc_unwrap(10.0, -3.1, 3.1) - (10.0 - TWO_PI + 6.2)) < 1e-12);
}

static void test_bad_arguments(void **state)
{
    char err[256] = "";
    imfoc_t *h;
    imfoc_phys_in_t in = {0.0, 0.0, 60.0, 0.0, 0u};
    imfoc_out_t out;
    imfoc_signals_t s;
    drive_config_t bad;
    (void)state;

    assert_null(imfoc_create_ini("/nonexistent.ini", err, sizeof err));
    assert_non_null(strstr(err, "nonexistent"));
    memset(&bad, 0, sizeof bad);
    assert_null(imfoc_create(&bad, err, sizeof err));
    assert_non_null(strstr(err, "drive_init"));
    assert_null(imfoc_create(NULL, NULL, 0u));

    assert_int_equal(imfoc_step_phys(NULL, &in, &out), IMFOC_ERR_NULL);
    assert_int_equal(imfoc_get_signals(NULL, &s), IMFOC_ERR_NULL);
    imfoc_destroy(NULL);

    h = imfoc_create_ini(IMFOC_TEST_INI, err, sizeof err);
    assert_non_null(h);
    assert_int_equal(imfoc_step_phys(h, NULL, &out), IMFOC_ERR_NULL);
    in.ia_A = NAN;
    assert_int_equal(imfoc_step_phys(h, &in, &out), IMFOC_ERR_RANGE);
    in.ia_A = 0.0;
    in.theta_m_rad = INFINITY;
    assert_int_equal(imfoc_step_phys(h, &in, &out), IMFOC_ERR_RANGE);
    assert_int_equal(imfoc_get_signals(h, &s), IMFOC_OK);
    assert_int_equal(s.isr_count, 0u);
    assert_int_equal(imfoc_command(h, 42), IMFOC_ERR_COMMAND);
    assert_int_equal(imfoc_set_speed_rpm(h, NAN), IMFOC_ERR_RANGE);
    assert_int_equal(imfoc_set_speed_rpm(h, 1e9), IMFOC_ERR_RANGE);
    assert_int_equal(imfoc_set_speed_rpm(h, 1000.0), IMFOC_OK);
    assert_string_equal(imfoc_status_str(IMFOC_ERR_RANGE), "argument out of range or not finite");
    assert_int_equal(imfoc_api_version(), IMFOC_API_VERSION);
    imfoc_destroy(h);
}

static void inputs(uint32_t k, int variant, imfoc_phys_in_t *in)
{
    double t = (double)k / 15000.0, sgn = variant ? -1.0 : 1.0;
    in->ia_A = sgn * 0.3 * sin((double)k / 40.0);
    in->ib_A = 0.2 * cos((double)k / 33.0);
    in->vdc_V = variant ? 55.0 : 60.0;
    /* the rotor at rest within a count or so (CALIBRATE and MAGNETIZE send a
     * turning rotor back to IDLE: id_sequence_set_rest) */
    in->theta_m_rad = sgn * 0.002 * sin(60.0 * t);
    in->trip = 0u;
}

#define N_STEPS 9000u   /* 0.6 s: calibration, then magnetisation with PWM on */

static void test_instances_are_independent(void **state)
{
    static uint16_t ref[N_STEPS][4];
    imfoc_t *a, *b, *c;
    imfoc_phys_in_t in;
    imfoc_out_t out;
    imfoc_signals_t sa, sc;
    uint32_t k, on = 0u;
    (void)state;

    a = imfoc_create_ini(IMFOC_TEST_INI, NULL, 0u);
    assert_non_null(a);
    assert_int_equal(imfoc_command(a, IMFOC_CMD_START_IDENT), IMFOC_OK);
    for (k = 0; k < N_STEPS; k++) {
        inputs(k, 0, &in);
        assert_int_equal(imfoc_step_phys(a, &in, &out), IMFOC_OK);
        memcpy(ref[k], out.cmpr, sizeof out.cmpr);
        ref[k][3] = out.pwm_on;
        on += out.pwm_on;
    }
    assert_true(on > 0u);   /* the run reached the PWM-on part */
    assert_int_equal(imfoc_get_signals(a, &sa), IMFOC_OK);

    b = imfoc_create_ini(IMFOC_TEST_INI, NULL, 0u);
    c = imfoc_create_ini(IMFOC_TEST_INI, NULL, 0u);
    assert_non_null(b);
    assert_non_null(c);
    assert_int_equal(imfoc_command(b, IMFOC_CMD_START_IDENT), IMFOC_OK);
    assert_int_equal(imfoc_command(c, IMFOC_CMD_START_IDENT), IMFOC_OK);
    for (k = 0; k < N_STEPS; k++) {
        inputs(k, 1, &in);
        assert_int_equal(imfoc_step_phys(b, &in, &out), IMFOC_OK);
        inputs(k, 0, &in);
        assert_int_equal(imfoc_step_phys(c, &in, &out), IMFOC_OK);
        assert_memory_equal(out.cmpr, ref[k], sizeof out.cmpr);
        assert_int_equal(out.pwm_on, ref[k][3]);
    }
    assert_int_equal(imfoc_get_signals(c, &sc), IMFOC_OK);
    assert_memory_equal(&sa, &sc, sizeof sa);
    imfoc_destroy(a);
    imfoc_destroy(b);
    imfoc_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_adc_and_qep_conversions),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_instances_are_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
