/*
 * Restart after a fault (fault handling): only by an explicit command
 * (DRIVE_CMD_RESET_FAULT), and only once the cause has gone; then a new
 * start runs the drive again.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "drive.h"
#include "drive_rig.h"
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

/* Commands given in the same background period are all kept (latched
 * request bits, drive.h) and taken in a defined order whatever order they
 * came in.  PDPINTA low from 1.0 to 1.5 s latches HW_TRIP; a reset and a
 * start at the same instant, 2.0 s, must clear the fault and then start: at
 * 3.0 s + FAULT_VI_S the drive runs the sequence (past calibration, the
 * bridge's curve test and magnetisation, 0.07 + 1.65 + 0.3 s), PWM on, no
 * fault.  Both orders of the two commands: with one
 * command slot the later one replaced the earlier, so one order lost the
 * reset (the fault stayed latched) and the other lost the start. */
static void test_reset_and_start_at_the_same_instant(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const sim_fault_t f = {PLANT_FAULT_HW_TRIP, 1.0, 0.5, 0u};
    const sim_cmd_t orders[2][2] = {
        {{2.0, DRIVE_CMD_RESET_FAULT}, {2.0, DRIVE_CMD_START_IDENT}},
        {{2.0, DRIVE_CMD_START_IDENT}, {2.0, DRIVE_CMD_RESET_FAULT}},
    };
    unsigned k;
    (void)state;
    for (k = 0; k < 2u; k++) {
        assert_int_equal(fault_run(PAPER, &f, 1u, orders[k], 2u, 3.0 + FAULT_VI_S, &cfg, &r), 0);
        print_message("reset + start at 2.0 s (order %u): faults %u, final state %u fault %u "
                      "PWM %u\n", k, r.n_faults_seen, r.final_state, r.final_fault,
                      r.final_pwm_on);
        assert_int_equal(r.n_faults_seen, 1);
        assert_int_equal(r.fault_code[0], FAULT_HW_TRIP);
        assert_int_equal(r.final_fault, FAULT_NONE);
        assert_int_equal(r.final_pwm_on, 1);
        /* 1.0 s + FAULT_VI_S after the start: beyond CALIBRATE and MAGNETIZE */
        assert_true(r.final_state == ID_ACCELERATE || r.final_state == ID_SETTLE ||
                    r.final_state == ID_RUN);
        assert_int_equal(r.pwm_periods_with_fault, 0);
    }
}

/* A stop and a start in the same period: the stop wins, in either order
 * (a stop must never be overridden).  The drive runs (published at 3.1 s,
 * after the bridge's curve test); stop and start at 2.0 s + FAULT_VI_S; at
 * 3.5 s + FAULT_VI_S it is IDLE with the bridge off (the
 * ramp to zero from 1400 r/min at 2000 r/min/s takes 0.7 s).  With one
 * command slot, stop-then-start kept the start, which a running sequence
 * ignores: the drive ran on. */
static void test_stop_wins_over_start_in_the_same_period(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const sim_cmd_t orders[2][2] = {
        {{2.0 + FAULT_VI_S, DRIVE_CMD_STOP}, {2.0 + FAULT_VI_S, DRIVE_CMD_START_IDENT}},
        {{2.0 + FAULT_VI_S, DRIVE_CMD_START_IDENT}, {2.0 + FAULT_VI_S, DRIVE_CMD_STOP}},
    };
    unsigned k;
    (void)state;
    for (k = 0; k < 2u; k++) {
        assert_int_equal(fault_run(PAPER, NULL, 0u, orders[k], 2u, 3.5 + FAULT_VI_S, &cfg, &r), 0);
        print_message("stop + start at 2.0 s (order %u): final state %u PWM %u, speed %.1f "
                      "r/min\n", k, r.final_state, r.final_pwm_on, r.final_speed_rpm);
        assert_true(r.t_first_published_s > 0.0 && r.t_first_published_s < 2.0 + FAULT_VI_S);
        assert_int_equal(r.final_state, ID_IDLE);
        assert_int_equal(r.final_pwm_on, 0);
        assert_int_equal(r.n_faults_seen, 0);
    }
    /* the same from IDLE (stopped in the calibration at 0.01 s, at rest): a
     * start that came with a stop must not start the drive */
    for (k = 0; k < 2u; k++) {
        sim_cmd_t c[3];
        c[0].t_s = 0.01;
        c[0].cmd = DRIVE_CMD_STOP;
        c[1] = orders[k][0];
        c[2] = orders[k][1];
        c[1].t_s = c[2].t_s = 0.5;
        assert_int_equal(fault_run(PAPER, NULL, 0u, c, 3u, 1.0, &cfg, &r), 0);
        print_message("from IDLE, stop + start at 0.5 s (order %u): final state %u PWM %u\n", k,
                      r.final_state, r.final_pwm_on);
        assert_int_equal(r.final_state, ID_IDLE);
        assert_int_equal(r.final_pwm_on, 0);
        assert_true(r.t_accel_start_s < 0.0);
    }
}

/* A start then a stop within one slow period (both taken by the background
 * before the sequence's next step): the later command wins, the drive stays
 * IDLE with the bridge off and says it was stopped.  Before, the step took
 * the stop first and then the start, which was still pending: CALIBRATE ran
 * the sensor test's pulses, reporting "stopped". */
static void test_start_then_stop_in_one_slow_period(void **state)
{
    static drive_rig_t rig;
    drive_rig_t *r = &rig;
    uint32_t k, switched = 0u;
    (void)state;
    assert_int_equal(drive_rig_start(r, PAPER), 0);   /* the start: requested and taken */
    drive_command(&r->drive, DRIVE_CMD_STOP);
    drive_background(&r->drive);
    for (k = 0; k < 3000u; k++) {   /* 0.2 s */
        drive_rig_sample(r);
        (void)drive_isr(&r->drive);
        drive_slow_isr(&r->drive);
        switched += r->port.outputs_enabled;
        assert_int_equal(r->pv.seq->state, ID_IDLE);
        drive_rig_period(r);
    }
    drive_background(&r->drive);
    assert_int_equal(switched, 0u);
    assert_int_equal(r->pv.telemetry->publish_reason, DRIVE_PUB_STOPPED);
    assert_int_equal(r->pv.telemetry->fault, FAULT_NONE);
}

/* A start while the rotor still coasts after a stop: refused with the reason
 * rotor_turning, the bridge off, no fault (the standstill phases would meet a
 * back-EMF their models do not have); once the rotor has stopped a start
 * runs the identification again.  The paper motor stopped at 2.0 s +
 * FAULT_VI_S from 1400 r/min coasts against its load for about 0.4 s. */
static void test_start_while_coasting(void **state)
{
    sim_config_t cfg;
    sim_result_t r;
    const double t_stop = 2.0 + FAULT_VI_S;
    const sim_cmd_t early[2] = {{t_stop, DRIVE_CMD_STOP}, {t_stop + 0.1, DRIVE_CMD_START_IDENT}};
    const sim_cmd_t late[2] = {{t_stop, DRIVE_CMD_STOP}, {t_stop + 1.5, DRIVE_CMD_START_IDENT}};
    (void)state;
    assert_int_equal(fault_run(PAPER, NULL, 0u, early, 2u, t_stop + 0.6, &cfg, &r), 0);
    print_message("start 0.1 s after the stop: reason %s, state %u, PWM %u, %.0f r/min\n",
                  drive_pub_reason_str(r.publish_reason), r.final_state, r.final_pwm_on,
                  r.final_speed_rpm);
    assert_int_equal(r.publish_reason, DRIVE_PUB_ROTOR_TURNING);
    assert_int_equal(r.n_faults_seen, 0);
    assert_int_equal(r.final_state, ID_IDLE);
    assert_int_equal(r.final_pwm_on, 0);
    assert_int_equal(fault_run(PAPER, NULL, 0u, late, 2u, t_stop + 1.5 + 3.0 + FAULT_VI_S, &cfg,
                               &r), 0);
    print_message("start 1.5 s after the stop: reason %s, state %u\n",
                  drive_pub_reason_str(r.publish_reason), r.final_state);
    assert_int_equal(r.n_faults_seen, 0);
    assert_int_equal(r.publish_reason, DRIVE_PUB_PUBLISHED);
    assert_int_equal(r.final_state, ID_RUN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restart_only_after_cause_cleared),
        cmocka_unit_test(test_hw_trip_reset_needs_line_high),
        cmocka_unit_test(test_no_restart_without_reset),
        cmocka_unit_test(test_reset_and_start_at_the_same_instant),
        cmocka_unit_test(test_stop_wins_over_start_in_the_same_period),
        cmocka_unit_test(test_start_then_stop_in_one_slow_period),
        cmocka_unit_test(test_start_while_coasting),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
