/*
 * Closed-loop tests (closed-loop control and identification accuracy): the unchanged firmware
 * ISR against the simulated paper motor with the default realistic inverter
 * (dead time 1 us, 0.3 V drop, bus ripple) and sensors (Hall gain/offset
 * errors and noise, ADC quantisation and noise, 1000-line encoder).
 * One run of the default scenario; each test asserts one property of it.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive.h"
#include "id_sequence.h"
#include "sim_config.h"
#include "sim_run.h"

static sim_config_t g_cfg;
static sim_result_t g_res;

static int run_paper_motor(void **state)
{
    sim_options_t opt;
    char err[256];
    (void)state;
    memset(&opt, 0, sizeof opt);
    opt.scenario = SCEN_START;
    opt.quiet = 1u;
    if (sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &g_cfg, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    if (sim_run(&g_cfg, &opt, &g_res, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    printf("paper motor: error %% Rs %+.2f Rr %+.2f Lm %+.2f Lr %+.2f psi_r %+.2f Tr %+.2f; "
           "converged %.3f s after the acceleration began; max |psi_q/psi_d| %.4f; "
           "max speed error on the ramp %.1f r/min; max |i| %.2f A\n",
           g_res.error_pct.Rs_ohm, g_res.error_pct.Rr_ohm, g_res.error_pct.Lm_H,
           g_res.error_pct.Lr_H, g_res.error_pct.psi_r_Wb, g_res.error_pct.Tr_s, g_res.converge_s,
           g_res.max_flux_q_over_d, g_res.max_speed_err_rpm_ramp, g_res.max_abs_i_A);
    return 0;
}

/* Identification accuracy: every parameter within 1 % of truth, the paper motor's goal (the
 * paper reports up to 4.3 %; measured: at most 0.30 %, Tr, in both builds: a factor 3 for
 * another seed of the sensors' noise), published: every confidence within the drive's 3 %
 * (ident_conf.h). */
static void test_identification_accuracy(void **state)
{
    const double bound_pct = 1.0;
    int i;
    (void)state;
    assert_int_equal(g_res.identified, 1);
    assert_int_equal(g_res.publish_reason, DRIVE_PUB_PUBLISHED);
    for (i = 0; i < 6; i++) {
        assert_true(g_res.conf_pct[i] >= 0.0 && g_res.conf_pct[i] <= 3.0);
    }
    assert_true(fabs(g_res.error_pct.Rs_ohm) < bound_pct);
    assert_true(fabs(g_res.error_pct.Rr_ohm) < bound_pct);
    assert_true(fabs(g_res.error_pct.Lm_H) < bound_pct);
    assert_true(fabs(g_res.error_pct.Lr_H) < bound_pct);
    assert_true(fabs(g_res.error_pct.psi_r_Wb) < bound_pct);
    assert_true(fabs(g_res.error_pct.Tr_s) < bound_pct);
    /* published from a confirmed steady state, not from the time-out */
    assert_int_equal(g_res.settle_timeout, 0);
}

/* Identification accuracy: within 2 % of the final value at most 1 s after the acceleration starts. */
static void test_convergence_time(void **state)
{
    (void)state;
    assert_true(g_res.converge_s >= 0.0);
    assert_true(g_res.converge_s <= 1.0);
}

/* Closed-loop control: field orientation holds: rotor-flux q below 1 % of d with the right Tr. */
static void test_field_orientation(void **state)
{
    (void)state;
    assert_true(g_res.max_flux_q_over_d < 0.01);
}

/* Closed-loop control: speed follows its ramp.  Bound 2 % of rated speed (28 r/min): the
 * speed loop (8 Hz) lags a 2000 r/min/s ramp by about ramp/(2 pi 8 Hz) ~ 40 r/min
 * without the integral action; with it the steady ramp error goes to zero,
 * what is left is the start transient (excluded: the first 0.2 s). */
static void test_speed_tracking(void **state)
{
    (void)state;
    assert_true(g_res.max_speed_err_rpm_ramp < 0.02 * g_cfg.nameplate.rated_speed_rpm);
    /* the paper motor's 60 V bus carries its rated speed: the target is not lowered */
    assert_true(fabs(g_res.target_rpm - sim_config_target_rpm(&g_cfg)) < 1e-3 &&
                !g_res.target_lowered);
    assert_true(fabs(g_res.final_speed_rpm - g_res.target_rpm) <
                0.005 * g_cfg.nameplate.rated_speed_rpm);
}

/* Closed-loop control: no current limit exceeded: the phase current stays below the
 * magnitude the limits allow, sqrt(i_M^2 + i_T,max^2) plus 10 % for ripple and
 * the current-loop overshoot, and below the trip level. */
static void test_current_limits(void **state)
{
    const sim_controller_t *k = &g_cfg.controller;
    double allowed = sqrt(k->magnetizing_current_A * k->magnetizing_current_A +
                          k->max_torque_current_A * k->max_torque_current_A);
    (void)state;
    assert_true(g_res.max_abs_i_A < 1.1 * allowed);
    assert_true(g_res.max_abs_i_A < g_cfg.controller.overcurrent_A);
    assert_int_equal(g_res.n_faults_seen, 0);
    assert_int_equal(g_res.final_pwm_on, 1);
}

/* Other motors, set up only through their own files.  Bound 3 %
 * per parameter on the RLS's extraction.  The paper's sequence is
 * biased on these motors by an error w_r Tr times larger in K3 (25 and 81),
 * and the data cannot bound Rr and Tr within 3 % (confidence of the refused
 * set, IQ_MATH: 1.1 kW Tr 3.4 %, 15 kW 4.6 %): the drive publishes nothing,
 * and says so (ident_conf.h; the adaptive sequence publishes these motors:
 * sim_adapt). */
static void check_other_motor(const char *path, const char *name)
{
    sim_config_t cfg;
    sim_result_t res;
    sim_options_t opt;
    char err[256];
    const double bound_pct = 3.0;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    assert_int_equal(sim_config_load(path, &cfg, err, sizeof err), 0);
    sim_config_set_sequence(&cfg, SIM_SEQ_PAPER);   /* the files' default is the adaptive one */
    assert_int_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    printf("%s: error %% Rs %+.2f Rr %+.2f Lm %+.2f Lr %+.2f psi_r %+.2f Tr %+.2f\n", name,
           res.error_pct.Rs_ohm, res.error_pct.Rr_ohm, res.error_pct.Lm_H, res.error_pct.Lr_H,
           res.error_pct.psi_r_Wb, res.error_pct.Tr_s);
    printf("%s: verdict %s; confidence %% Rs %.2f Rr %.2f Lm %.2f Lr %.2f psi_r %.2f Tr %.2f\n",
           name, drive_pub_reason_str(res.publish_reason), res.conf_pct[0], res.conf_pct[1],
           res.conf_pct[2], res.conf_pct[3], res.conf_pct[4], res.conf_pct[5]);
    assert_int_equal(res.identified, 0);
    assert_int_equal(res.publish_reason, DRIVE_PUB_LOW_CONFIDENCE);
    assert_true(res.conf_pct[1] > bound_pct || res.conf_pct[5] > bound_pct);
    assert_int_equal(res.extracted, 1);
    assert_true(fabs(res.error_pct.Rs_ohm) < bound_pct);
    assert_true(fabs(res.error_pct.Rr_ohm) < bound_pct);
    assert_true(fabs(res.error_pct.Lm_H) < bound_pct);
    assert_true(fabs(res.error_pct.Lr_H) < bound_pct);
    assert_true(fabs(res.error_pct.psi_r_Wb) < bound_pct);
    assert_true(fabs(res.error_pct.Tr_s) < bound_pct);
    assert_true(res.max_flux_q_over_d < 0.01);
}

/* a 1.1 kW 400 V machine */
static void test_identification_1kw(void **state)
{
    (void)state;
    check_other_motor(MC_CONFIG_DIR "/motor_1kw.ini", "1.1 kW motor");
}

/* a 15 kW 400 V machine on its 565 V bus: the hard case (omega_r Tr = 81 at
 * rated speed, so the resistive voltage is about 1 % of the stator
 * voltage; docs/accuracy.md) */
static void test_identification_15kw(void **state)
{
    (void)state;
    check_other_motor(MC_CONFIG_DIR "/motor_15kw.ini", "15 kW motor");
}

/* The constant load is Coulomb friction with stiction (plant.c), never a
 * torque source: a 10 000 N m one holds the paper motor's rotor through the
 * calibration and the magnetisation (no torque), exactly at rest (before:
 * held over each period as sgn(w) const, it overshot through zero and
 * turned the rotor backwards; the rest check now calls that rotor_turning);
 * and the ordinary 0.15 N m one lets the drive accelerate (test above). */
static void test_load_holds_never_drives(void **state)
{
    sim_config_t cfg = g_cfg;
    sim_result_t res;
    sim_options_t opt;
    char err[256];
    (void)state;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = 2.0;   /* calibration (the bridge's test) and magnetisation */
    cfg.load.const_Nm = 10000.0;
    assert_int_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    print_message("const_Nm 10000: final speed %g r/min, state %u, faults %u, reason %s\n",
                  res.final_speed_rpm, res.final_state, res.n_faults_seen,
                  drive_pub_reason_str(res.publish_reason));
    assert_true(res.final_speed_rpm == 0.0);
    assert_int_equal(res.n_faults_seen, 0);
    assert_int_not_equal(res.publish_reason, DRIVE_PUB_ROTOR_TURNING);
    assert_true(res.t_state_s[ID_MAGNETIZE] > 0.0);
}

/* A load the drive cannot carry at the target is named as such: the paper
 * motor at its rated torque, 250 W / 1400 r/min = 1.705 N m (a quarter
 * constant, three quarters fan, as tools/nuisance_sweep.py's full load),
 * needs i_T = T / (1.5 p Lm^2 / Lr i_M) = 19.5 A, twice its INI's
 * max_torque_current_A of 10 A: the speed stays below the target and
 * SETTLE runs out of time with the speed loop at its limit.  The verdict
 * says torque_limit (before: timeout, which told the user nothing), no
 * fault, the true current within the trip. */
static void test_torque_limit_named(void **state)
{
    sim_config_t cfg = g_cfg;
    sim_result_t res;
    sim_options_t opt;
    char err[256];
    const double t_n = 250.0 / (1400.0 * 2.0 * 3.14159265358979 / 60.0);
    const double i_t = t_n / (1.5 * 2.0 * 0.0064 * 0.0064 / 0.0092 * 6.5625);
    (void)state;
    assert_true(i_t > 1.9 * cfg.controller.max_torque_current_A);
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    cfg.load.const_Nm = 0.25 * t_n;
    cfg.load.fan_Nm = 0.75 * t_n;
    assert_int_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    print_message("rated load: final speed %g r/min, reason %s, faults %u, true peak %g A\n",
                  res.final_speed_rpm, drive_pub_reason_str(res.publish_reason),
                  res.n_faults_seen, res.max_true_phase_A);
    assert_int_equal(res.publish_reason, DRIVE_PUB_TORQUE_LIMIT);
    assert_int_equal(res.n_faults_seen, 0);
    assert_true(res.final_speed_rpm < 0.9 * 1400.0);
    assert_true(res.max_true_phase_A < cfg.controller.overcurrent_A);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identification_accuracy),
        cmocka_unit_test(test_convergence_time),
        cmocka_unit_test(test_field_orientation),
        cmocka_unit_test(test_speed_tracking),
        cmocka_unit_test(test_current_limits),
        cmocka_unit_test(test_identification_1kw),
        cmocka_unit_test(test_identification_15kw),
        cmocka_unit_test(test_load_holds_never_drives),
        cmocka_unit_test(test_torque_limit_named),
    };
    return cmocka_run_group_tests(tests, run_paper_motor, NULL);
}
