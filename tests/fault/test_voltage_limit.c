/* The current-feedback check at the voltage limit (current_check.h): the
 * paper's sequence on the 15 kW motor does not track Rr, and in the drift
 * scenario (the rotor warms by 40 % over 60 s, with load steps) the stale Rr
 * turns the frame until the loops ask for the bus's limit (599 V / sqrt 3)
 * and stop following their references.  That is the drive's own limit, not
 * a sensor's: the check holds there (it latched CURRENT_SENSOR at 71.6 s on a
 * healthy sensor before).  A sensor that fails there is still found, by the
 * model check (current_model_check.h), within milliseconds, with the motor's
 * TRUE currents below the trip. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fault_run.h"
#include "protect.h"

#define MOTOR_15KW MC_CONFIG_DIR "/motor_15kw.ini"
/* the drive reaches the bus's limit from about 66 s (docs/protections.md);
 * the run ends at 80 s */
#define RUN_S 80.0

static int drift_run(const sim_fault_t *f, unsigned n, sim_config_t *cfg, sim_result_t *r)
{
    /* the paper's sequence: its Rr is not tracked, the warming rotor turns the
     * frame until the loops reach the voltage limit */
    return fault_run_scenario(MOTOR_15KW, SCEN_DRIFT, SIM_SEQ_PAPER, f, n, NULL, 0u, RUN_S, cfg,
                              r);
}

static void test_no_false_trip_at_the_limit(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    (void)state;
    assert_int_equal(drift_run(NULL, 0u, &cfg, &r), 0);
    print_message("drift, paper's sequence: faults %u, final %.1f r/min (target %.0f), "
                  "max |psi_q/psi_d| %.3f, max true phase current %.1f A (trip %.0f A)\n",
                  r.n_faults_seen, r.final_speed_rpm, r.target_rpm,
                  r.max_flux_q_over_d, r.max_true_phase_A, cfg.controller.overcurrent_A);
    /* it did reach the limit's regime: the frame turned as before (q/d 0.15
     * when it tripped; a frame that stayed aligned would not test the hold) */
    assert_true(r.max_flux_q_over_d > 0.12);
    assert_int_equal(r.n_faults_seen, 0);
    assert_int_equal(r.final_fault, FAULT_NONE);
    assert_int_equal(r.final_pwm_on, 1);
    /* the motor still turns at its target (within 2 %), its true currents
     * below the trip */
    assert_true(fabs(r.final_speed_rpm - r.target_rpm) < 0.02 * r.target_rpm);
    assert_true(r.max_true_phase_A < cfg.controller.overcurrent_A);
}

/* A sensor that fails at the limit: the loops saturate against it, the
 * current-feedback check holds, the model check latches CURRENT_SENSOR. */
static void check_sensor_fault(plant_fault_t kind, double value, double t_s, double within_s)
{
    sim_config_t cfg;
    sim_result_t r;
    sim_fault_t f;
    f.kind = kind;
    f.at_state = 0u;
    f.t_s = t_s;
    f.value = value;
    assert_int_equal(drift_run(&f, 1u, &cfg, &r), 0);
    print_message("fault %d (%.2f) at %.1f s: code %u at %.4f s (+%.1f ms), max true %.1f A\n",
                  (int)kind, value, t_s, r.n_faults_seen ? r.fault_code[0] : 0u,
                  r.fault_time_s[0], 1e3 * (r.fault_time_s[0] - t_s), r.max_true_phase_A);
    assert_true(r.n_faults_seen >= 1u);
    assert_int_equal(r.fault_code[0], FAULT_CURRENT_SENSOR);
    assert_true(r.fault_time_s[0] >= t_s);
    assert_true(r.fault_time_s[0] - t_s <= within_s);
    assert_int_equal(r.final_pwm_on, 0);
    assert_true(r.max_true_phase_A < cfg.controller.overcurrent_A);
}

static void test_sensor_lost_at_the_limit(void **state)
{
    (void)state;
    /* measured 3.9 / 4.9 ms: bound 10 ms */
    check_sensor_fault(PLANT_FAULT_HALL_LOST, 0.0, 72.0, 0.010);
    check_sensor_fault(PLANT_FAULT_HALL_LOST, 0.0, 76.0, 0.010);
}

static void test_gain_error_at_the_limit(void **state)
{
    (void)state;
    /* measured 6 ms (-66 %) and 136 ms (+20 %): bounds 20 ms and 300 ms */
    check_sensor_fault(PLANT_FAULT_HALL_GAIN, -0.66, 74.0, 0.020);
    check_sensor_fault(PLANT_FAULT_HALL_GAIN, 0.20, 74.0, 0.300);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_false_trip_at_the_limit),
        cmocka_unit_test(test_sensor_lost_at_the_limit),
        cmocka_unit_test(test_gain_error_at_the_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
