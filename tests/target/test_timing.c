/* target_timing: the register values of f2812_timing.c against a double-
 * precision reference computed here from the documented formulas
 * (SPRU065 T1PR and DBTCONA, SPRU051 BRR). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "f2812_timing.h"

static void test_t1pr_15kHz(void **state)
{
    f2812_timing_t t;
    (void)state;
    /* 150 MHz / (2 * 15 kHz) = 5000 exactly: no tolerance */
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, 15.0e3f), TIMING_OK);
    assert_int_equal(t.t1pr, 5000);
    /* 10 kHz -> 7500; 20 kHz -> 3750 */
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, 10.0e3f), TIMING_OK);
    assert_int_equal(t.t1pr, 7500);
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, 20.0e3f), TIMING_OK);
    assert_int_equal(t.t1pr, 3750);
    /* 1 kHz would need 75000 > 0xFFFF; 1 MHz only 75 ticks (< 1 % resolution) */
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, 1.0e3f), TIMING_ERR_PWM_FREQ);
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, 1.0e6f), TIMING_ERR_PWM_FREQ);
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, -15.0e3f), TIMING_ERR_PWM_FREQ);
    assert_int_equal(f2812_timing_t1pr(&t, 150.0e6f, NAN), TIMING_ERR_PWM_FREQ);
}

/* Reference: smallest prescaler p (0..5) with ceil(dt f / 2^p) <= 15. */
static void test_deadband_sweep(void **state)
{
    const double f = 150.0e6;
    double dt_ns;
    int checked = 0;
    (void)state;
    for (dt_ns = 10.0; dt_ns <= 3200.0; dt_ns += 10.0) {
        f2812_timing_t t;
        double ticks = dt_ns * 1e-9 * f;
        int p, ref_p = -1, ref_dbt = 0;
        for (p = 0; p <= 5; p++) {
            int d = (int)ceil(ticks / (double)(1 << p) - 1e-6);
            if (d <= 15) { ref_p = p; ref_dbt = d < 1 ? 1 : d; break; }
        }
        assert_int_equal(f2812_timing_deadband(&t, (float)f, (float)(dt_ns * 1e-9)), TIMING_OK);
        assert_int_equal(t.dbtps, ref_p);
        assert_int_equal(t.dbt, ref_dbt);
        assert_int_equal(t.dbtcona, (ref_dbt << 8) | 0x00E0 | (ref_p << 2));
        /* never shorter than asked (shoot-through), at most one prescaled
         * tick longer; 1e-3 ns: float rounding of the inputs */
        assert_true((double)t.dead_time_s * 1e9 >= dt_ns - 1e-3);
        assert_true((double)t.dead_time_s * 1e9 <= dt_ns + (double)(1 << ref_p) / f * 1e9 + 1e-3);
        checked++;
    }
    assert_int_equal(checked, 320);
}

static void test_deadband_board(void **state)
{
    f2812_timing_t t;
    (void)state;
    /* the board's 1.0 us: 150 ticks -> /16, DBT = 10 -> 1.0667 us */
    assert_int_equal(f2812_timing_deadband(&t, 150.0e6f, 1.0e-6f), TIMING_OK);
    assert_int_equal(t.dbtps, 4);
    assert_int_equal(t.dbt, 10);
    assert_int_equal(t.dbtcona, 0x0AF0);
    /* 15 * 32 / 150 MHz = 3.2 us is the longest; 3.3 us and 0 are errors */
    assert_int_equal(f2812_timing_deadband(&t, 150.0e6f, 3.2e-6f), TIMING_OK);
    assert_int_equal(f2812_timing_deadband(&t, 150.0e6f, 3.3e-6f), TIMING_ERR_DEAD_TIME);
    assert_int_equal(f2812_timing_deadband(&t, 150.0e6f, 0.0f), TIMING_ERR_DEAD_TIME);
}

static void test_brr(void **state)
{
    f2812_timing_t t;
    double baud;
    (void)state;
    /* 37.5 MHz / (8 * 115200) - 1 = 39.69 -> 40: 114329 baud, -0.76 %
     * (a UART tolerates ~2 %) */
    assert_int_equal(f2812_timing_brr(&t, 37.5e6f, 115200.0f), TIMING_OK);
    assert_int_equal(t.brr, 40);
    baud = 37.5e6 / ((t.brr + 1.0) * 8.0);
    assert_true(fabs(baud / 115200.0 - 1.0) < 0.01);
    assert_int_equal(f2812_timing_brr(&t, 37.5e6f, 9600.0f), TIMING_OK);
    assert_int_equal(t.brr, 487);   /* 487.28 -> 487 */
    assert_int_equal(f2812_timing_brr(&t, 37.5e6f, 5.0e6f), TIMING_ERR_BAUD);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_t1pr_15kHz),
        cmocka_unit_test(test_deadband_sweep),
        cmocka_unit_test(test_deadband_board),
        cmocka_unit_test(test_brr),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
