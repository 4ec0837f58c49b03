/*
 * The bridge's overcurrent comparator in the simulated power stage
 * (plant.h): on the TRUE leg current, independent of the Hall sensors and
 * of the firmware.  A locked-duty plant (no firmware) drives the paper
 * motor's current up until the comparator turns the outputs off; the
 * checks are against references that do not come from the comparator's
 * code: the current's own slope over the last period before the trip (the
 * overshoot is slope x delay), the level from the INI, and the host HAL's
 * latch (the firmware cannot switch the outputs back on until the fault
 * reset with the line high).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "hal_host.h"
#include "plant.h"
#include "sim_config.h"

#define PAPER MC_CONFIG_DIR "/paper_motor.ini"

/* Phase a high for 90 % of the period, b and c low (the voltage vector
 * along a): the a current rises at ~(0.9 x 2/3 x 60 V)/sigma Ls. */
static void run_to_trip(double delay_s, double *peak, double *level, double *slope,
                        unsigned *periods, double *t_off_in_period)
{
    static plant_t p;
    sim_config_t c;
    char err[256];
    hal_host_port_t port;
    hal_pwm_compare_t cmp;
    unsigned k;
    double ia_prev = 0.0;

    assert_int_equal(sim_config_load(PAPER, &c, err, sizeof err), 0);
    c.inverter.overcurrent_hw_delay_s = delay_s;
    assert_int_equal(plant_init(&p, &c, 5000u, err, sizeof err), 0);
    hal_host_port_init(&port, 5000u);
    cmp.cmpr[0] = 500u;    /* d = 0.9: 36 V against Rs i = 23 A at 22.5 A */
    cmp.cmpr[1] = 5000u;   /* d = 0 */
    cmp.cmpr[2] = 5000u;
    *level = c.inverter.overcurrent_hw_A;
    *slope = 0.0;
    for (k = 0; k < 2000u; k++) {
        const double t0 = p.t_s;
        ia_prev = p.motor.ia_A;
        plant_period(&p, &cmp, 1u);
        if (p.hw_fired != 0u) {
            *t_off_in_period = p.t_hw_first_s - t0;
            break;
        }
        *slope = (p.motor.ia_A - ia_prev) / p.Ts_s;   /* A/s over the last full period */
        if (p.hw_pending_s >= 0.0) {
            /* crossed: the delay reaches into the next period */
            continue;
        }
    }
    *periods = k;
    *peak = p.i_leg_peak_A;
    /* the outputs are off for good: the motor's current is gone */
    plant_period(&p, &cmp, 0u);
    assert_true(fabs(p.motor.ia_A) < 1e-9);
    assert_int_equal(p.hw_trips, 1u);
}

/* The leg current stops at the level plus the current's slope times the
 * response delay: within 5 % of that overshoot (the slope changes little
 * over a few us: the electrical time constant is 4.6 ms), and never below
 * the level. */
static void test_overshoot_is_slope_times_delay(void **state)
{
    static const double delays[] = {0.0, 2e-6, 10e-6, 50e-6};
    unsigned i;
    (void)state;
    for (i = 0; i < sizeof delays / sizeof delays[0]; i++) {
        double peak, level, slope, t_off;
        unsigned n;
        run_to_trip(delays[i], &peak, &level, &slope, &n, &t_off);
        print_message("delay %4.0f us: trip after %u periods, level %.2f A, slope %.3f A/us, "
                      "peak %.4f A (overshoot %.4f A, slope x delay %.4f A)\n",
                      delays[i] * 1e6, n, level, slope * 1e-6, peak, peak - level,
                      slope * delays[i]);
        assert_true(n < 2000u);
        assert_true(fabs(level - 1.25 * 18.0) < 1e-12);   /* paper_motor.ini: 1.25 x 18 A */
        assert_true(peak >= level - 1e-3 * level);
        assert_true(fabs((peak - level) - slope * delays[i]) <= 0.05 * slope * delays[i] +
                                                                  1e-3 * level);
    }
}

/* The latch of the host HAL as the F2812's: a pulse turns the outputs off,
 * hal_pwm_tripped reports it, enable is refused until the reset path
 * clears it with the line high. */
static void test_pdpinta_latch(void **state)
{
    hal_host_port_t port;
    (void)state;
    hal_host_port_init(&port, 5000u);
    hal_host_bind(&port);
    hal_pwm_enable();
    assert_int_equal(port.outputs_enabled, 1u);
    hal_host_pdpinta_pulse(&port);
    assert_int_equal(port.outputs_enabled, 0u);
    assert_int_equal(hal_pwm_tripped(), 1u);
    hal_pwm_enable();
    assert_int_equal(port.outputs_enabled, 0u);
    port.trip_input = 1u;                       /* the line still low: stays latched */
    assert_int_equal(hal_host_clear_trip(&port), 1u);
    port.trip_input = 0u;
    assert_int_equal(hal_host_clear_trip(NULL), 0u);   /* the bound port */
    assert_int_equal(hal_pwm_tripped(), 0u);
    hal_pwm_enable();
    assert_int_equal(port.outputs_enabled, 1u);
}

/* The configuration: the default level is 1.25 x the firmware's trip; a
 * level at or below the trip is refused by name; 0 is no comparator. */
static void test_config(void **state)
{
    sim_config_t c;
    char err[512];
    FILE *f;
    const char *path = "hw_comparator_test.ini";
    (void)state;
    assert_int_equal(sim_config_load(MC_CONFIG_DIR "/motor_15kw.ini", &c, err, sizeof err), 0);
    assert_true(fabs(c.inverter.overcurrent_hw_A - 100.0) < 1e-12);
    assert_true(fabs(c.inverter.overcurrent_hw_delay_s - 2e-6) < 1e-18);
    f = fopen(path, "w");
    assert_non_null(f);
    {
        FILE *in = fopen(PAPER, "r");
        char line[256];
        assert_non_null(in);
        while (fgets(line, sizeof line, in) != NULL) {
            fputs(line, f);
            if (strncmp(line, "[inverter]", 10) == 0) {
                fputs("overcurrent_hw_A = 17\n", f);
            }
        }
        fclose(in);
    }
    fclose(f);
    assert_int_not_equal(sim_config_load(path, &c, err, sizeof err), 0);
    print_message("%s\n", err);
    assert_non_null(strstr(err, "inverter.overcurrent_hw_A"));
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overshoot_is_slope_times_delay),
        cmocka_unit_test(test_pdpinta_latch),
        cmocka_unit_test(test_config),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
