/*
 * Dead-time and device-drop compensation in the voltage reconstruction
 * (dead-time compensation): the paper motor on its default realistic bridge (60 V,
 * 1 us dead time at 15 kHz, 0.3 V device drop, 0.1 A transition band), run
 * twice, with `[controller] dead_time_comp` 1 and 0.  The simulator compares
 * the drive's reconstructed voltage of every period with the bridge's and
 * averages the difference along the current over the steady state
 * (sim_result_t.v_err_along_i_V).
 *
 * Independent reference: without compensation each pole loses
 * V_dt = vdc td/Ts + v_drop against the sign of its current; the fundamental
 * of that square wave (describing function, common mode removed: only
 * triplens go) is a phase voltage of (4/pi) V_dt along the current, i.e. an
 * apparent series resistance (4/pi) V_dt / |i|.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sim_config.h"
#include "sim_run.h"

static sim_config_t g_cfg;
static sim_result_t g_on;   /* compensation on (the default) */
static sim_result_t g_off;  /* compensation off */

static int run_one(double comp, sim_result_t *res)
{
    sim_options_t opt;
    char err[256];
    memset(&opt, 0, sizeof opt);
    opt.scenario = SCEN_START;
    opt.quiet = 1u;
    if (sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &g_cfg, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    g_cfg.controller.dead_time_comp = comp;
    if (sim_run(&g_cfg, &opt, res, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

static int run_both(void **state)
{
    (void)state;
    if (run_one(1.0, &g_on) != 0 || run_one(0.0, &g_off) != 0) {
        return -1;
    }
    printf("dead-time compensation on:  voltage error along i %+.4f V, across %+.4f V; "
           "identified Rs %+.2f %%, Rr %+.2f %%\n",
           g_on.v_err_along_i_V, g_on.v_err_across_i_V, g_on.error_pct.Rs_ohm,
           g_on.error_pct.Rr_ohm);
    printf("dead-time compensation off: voltage error along i %+.4f V, across %+.4f V; "
           "identified Rs %+.2f %%, Rr %+.2f %%; mean |i| %.3f A\n",
           g_off.v_err_along_i_V, g_off.v_err_across_i_V, g_off.error_pct.Rs_ohm,
           g_off.error_pct.Rr_ohm, g_off.i_mag_steady_A);
    return 0;
}

/* (4/pi) (vdc td/Ts + v_drop): 1.528 V for the paper motor's bridge. */
static double describing_function_V(void)
{
    const sim_inverter_t *inv = &g_cfg.inverter;
    const double v_dt = inv->vdc_V * inv->dead_time_s * g_cfg.board.pwm_freq_Hz + inv->device_drop_V;
    return 4.0 / M_PI * v_dt;
}

/* Uncompensated, the drive over-states the voltage along the current by the
 * describing function.  Bound 3 %: the 0.1 A band (the error ramps through
 * it: about 2/pi band/|i| = 0.8 % of the period at 8.4 A) and the bus sag
 * and ripple around the nominal 60 V (< 1 %).  Measured: 1.520 V against
 * 1.528 V (-0.5 %). */
static void test_uncompensated_error_is_the_dead_time(void **state)
{
    const double ref = describing_function_V();
    (void)state;
    assert_true(g_off.n_v_err > 1000u);
    printf("uncompensated error %.4f V, describing function %.4f V (%+.2f %%)\n",
           g_off.v_err_along_i_V, ref, 100.0 * (g_off.v_err_along_i_V / ref - 1.0));
    assert_true(fabs(g_off.v_err_along_i_V / ref - 1.0) < 0.03);
    /* and it is a resistance: nothing across the current (bound 2 % of it) */
    assert_true(fabs(g_off.v_err_across_i_V) < 0.02 * ref);
}

/* Compensated, the remaining error along the current is below 2 % of the
 * uncompensated one (measured -0.003 V, 0.2 %); across it below 0.03 V
 * (measured -0.004 V). */
static void test_compensation_removes_it(void **state)
{
    (void)state;
    assert_true(g_on.n_v_err > 1000u);
    assert_true(fabs(g_on.v_err_along_i_V) < 0.02 * describing_function_V());
    assert_true(fabs(g_on.v_err_across_i_V) < 0.03);
}

/* What it does to the identification.  Compensated: Rs within 1 % (the
 * 2 % accuracy bound with margin; measured +0.04 %), published.
 * Uncompensated: Rs takes the apparent resistance (4/pi) V_dt / |i| = 17.5 %
 * of Rs, and more (measured +20.0 %: the same error also pulls Rr down by
 * 10 %, which enters Rs = -K1/K2 - K3'/i_M): asserted between 0.9 and 1.4
 * times the apparent resistance, in the RLS's extraction; the drive does
 * not publish it (a confidence above 3 %: ident_conf.h). */
static void test_rs_bias_with_and_without(void **state)
{
    double apparent_pct;
    (void)state;
    assert_int_equal(g_on.identified, 1);
    assert_int_equal(g_off.identified, 0);
    assert_int_equal(g_off.extracted, 1);
    assert_int_not_equal(g_off.publish_reason, DRIVE_PUB_PUBLISHED);
    assert_int_not_equal(g_off.publish_reason, DRIVE_PUB_PENDING);
    apparent_pct = 100.0 * g_off.v_err_along_i_V / g_off.i_mag_steady_A / g_cfg.plant.Rs_ohm;
    printf("Rs bias: apparent resistance %+.2f %% of Rs, identified %+.2f %% (off), %+.2f %% (on)\n",
           apparent_pct, g_off.error_pct.Rs_ohm, g_on.error_pct.Rs_ohm);
    assert_true(fabs(g_on.error_pct.Rs_ohm) < 1.0);
    assert_true(g_off.error_pct.Rs_ohm > 0.9 * apparent_pct);
    assert_true(g_off.error_pct.Rs_ohm < 1.4 * apparent_pct);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uncompensated_error_is_the_dead_time),
        cmocka_unit_test(test_compensation_removes_it),
        cmocka_unit_test(test_rs_bias_with_and_without),
    };
    return cmocka_run_group_tests(tests, run_both, NULL);
}
