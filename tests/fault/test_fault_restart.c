/*
 * Restart after a fault (issue 6 item 1): only by an explicit command
 * (DRIVE_CMD_RESET_FAULT), and only once the cause has gone; then a new
 * start runs the drive again.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "drive.h"
#include "fault_run.h"
#include "id_sequence.h"
#include "protect.h"

#define PAPER MC_CONFIG_DIR "/paper_motor.ini"

/* Bus sag at 2.0 s; a reset at 2.2 s while the bus is still low is refused
 * (the fault stays, the bridge stays off, a start is ignored); the sag ends at
 * 2.4 s; the reset at 2.6 s clears the fault and the start at 2.7 s runs the
 * whole sequence again: PWM on at the end, the second identification
 * published. */
static void test_restart_only_after_cause_cleared(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const sim_fault_t f[2] = {{PLANT_FAULT_BUS_SAG, 2.0, 0.5, 0u}, {PLANT_FAULT_CLEAR, 2.4, 0.0, 0u}};
    const sim_cmd_t c[4] = {{2.2, DRIVE_CMD_RESET_FAULT},
                            {2.25, DRIVE_CMD_START_IDENT},
                            {2.6, DRIVE_CMD_RESET_FAULT},
                            {2.7, DRIVE_CMD_START_IDENT}};
    (void)state;
    /* first only the refused reset and start: still faulted at 2.5 s */
    assert_int_equal(fault_run(PAPER, f, 1u, c, 2u, 2.5, &cfg, &r), 0);
    assert_int_equal(r.final_fault, FAULT_BUS_UNDERVOLTAGE);
    assert_int_equal(r.final_state, ID_FAULT);
    assert_int_equal(r.final_pwm_on, 0);
    assert_int_equal(r.pwm_periods_with_fault, 0);
    /* the whole sequence */
    assert_int_equal(fault_run(PAPER, f, 2u, c, 4u, 7.0, &cfg, &r), 0);
    print_message("restart: faults %u (first code %u at %.3f s), final state %u fault %u PWM %u, "
                  "published at %.3f s\n",
                  r.n_faults_seen, r.fault_code[0], r.fault_time_s[0], r.final_state,
                  r.final_fault, r.final_pwm_on, r.t_published_s);
    assert_int_equal(r.n_faults_seen, 1);
    assert_int_equal(r.final_fault, FAULT_NONE);
    assert_int_equal(r.final_pwm_on, 1);
    assert_int_equal(r.final_state, ID_RUN);
    assert_int_equal(r.pwm_periods_with_fault, 0);
    /* the restarted identification published again (after 2.7 s) */
    assert_true(r.t_published_s > 2.7);
    assert_int_equal(r.identified, 1);
}

/* PDPINTA held low for 0.3 s from 2.0 s: a reset at 2.1 s (line still low)
 * is refused, one at 2.5 s (line high) accepted. */
static void test_hw_trip_reset_needs_line_high(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const sim_fault_t f = {PLANT_FAULT_HW_TRIP, 2.0, 0.3, 0u};
    const sim_cmd_t c[3] = {{2.1, DRIVE_CMD_RESET_FAULT},
                            {2.5, DRIVE_CMD_RESET_FAULT},
                            {2.6, DRIVE_CMD_START_IDENT}};
    (void)state;
    assert_int_equal(fault_run(PAPER, &f, 1u, c, 1u, 2.4, &cfg, &r), 0);
    assert_int_equal(r.final_fault, FAULT_HW_TRIP);
    assert_int_equal(r.final_pwm_on, 0);
    assert_int_equal(fault_run(PAPER, &f, 1u, c, 3u, 3.2, &cfg, &r), 0);
    assert_int_equal(r.n_faults_seen, 1);
    assert_int_equal(r.final_fault, FAULT_NONE);
    assert_int_equal(r.final_pwm_on, 1);
    assert_int_equal(r.pwm_periods_with_fault, 0);
}

/* No reset command, no restart: a start alone after the cause has gone
 * leaves the drive in FAULT. */
static void test_no_restart_without_reset(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const sim_fault_t f[2] = {{PLANT_FAULT_OVERVOLTAGE, 2.0, 0.5, 0u}, {PLANT_FAULT_CLEAR, 2.1, 0.0, 0u}};
    const sim_cmd_t c = {2.2, DRIVE_CMD_START_IDENT};
    (void)state;
    assert_int_equal(fault_run(PAPER, f, 2u, &c, 1u, 2.5, &cfg, &r), 0);
    assert_int_equal(r.final_fault, FAULT_BUS_OVERVOLTAGE);
    assert_int_equal(r.final_state, ID_FAULT);
    assert_int_equal(r.final_pwm_on, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restart_only_after_cause_cleared),
        cmocka_unit_test(test_hw_trip_reset_needs_line_high),
        cmocka_unit_test(test_no_restart_without_reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
