/*
 * Design constants of the drive that no closed-loop bound is tight enough
 * to pin down (each survived a mutation of its value with every test
 * passing), checked on drive_init's result against the design stated in the
 * README and the modules' headers, computed here independently in double
 * from the INI file's values:
 *   - the current-feedback check's low-pass: a = 1 - exp(-Ts_slow / 2 ms),
 *     Ts_slow = 4 / f_pwm (it runs in the slow task);
 *   - the modulation angle advance: the inverse Park at the middle of the
 *     next period, 1.5 periods after the sample: 1.5 f_base Ts per pu speed;
 *   - the Rr tracker's wind-up guard: it learns only while |psi x i| is at
 *     least 10 % of the rated flux times the torque-current limit;
 *   - the rate limit per identification pass: the model a pass hands on
 *     (the observer's Lm, Lr, Ls) moves at most a factor 2 from the one in
 *     use, however far off the extraction (a white-box test of the blend in
 *     the slow task, through src/app's private drive_adapt.h).
 * Bounds: the Q24 conversion of each float (1 LSB) plus the float rounding of
 * the firmware's own expressions (1 LSB): 2 LSB = 1.2e-7 pu.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive_adapt.h"
#include "drive_design.h"
#include "drive_types.h"
#include "sim_config.h"

#define LSB (1.0 / 16777216.0)
#define PI_ 3.14159265358979323846

static drive_t g_d;
static sim_config_t g_c;

static void init_from(const char *ini)
{
    char err[SIM_CONFIG_ERR_LEN];
    drive_config_t dc;
    if (sim_config_load(ini, &g_c, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    sim_config_to_drive(&g_c, &dc);
    assert_int_equal(drive_init(&g_d, &dc), DRIVE_CFG_OK);
}

static void assert_q24(const char *what, _iq got, double want)
{
    double g = (double)_IQtoF(got);
    printf("  %-44s %.9f (design %.9f, %+.1f LSB)\n", what, g, want, (g - want) / LSB);
    if (fabs(g - want) > 2.0 * LSB) {
        fail_msg("%s: %.9f, the design gives %.9f", what, g, want);
    }
}

static void test_current_check_time_constant(void **state)
{
    const double ts_slow = (double)DRIVE_SLOTS / 15000.0;
    (void)state;
    init_from(MC_CONFIG_DIR "/paper_motor.ini");
    assert_q24("current check: 1 - exp(-Ts_slow / 2 ms)", g_d.prot.feedback.k_filt,
               1.0 - exp(-ts_slow / 0.002));
}

static void test_modulation_advance(void **state)
{
    (void)state;
    init_from(MC_CONFIG_DIR "/paper_motor.ini");
    /* 50 Hz base, 15 kHz: 1.5 x 50 / 15000 = 0.005 revolution per pu speed */
    assert_q24("modulation advance: 1.5 f_base Ts", g_d.k.three_half_step, 1.5 * 50.0 / 15000.0);
}

static void test_tracker_guard(void **state)
{
    double v_base, w_base, psi_pu, it_pu;
    (void)state;
    init_from(MC_CONFIG_DIR "/paper_motor_wrong_nameplate.ini");
    assert_true(g_c.ident.track_rr == 1.0);
    v_base = g_c.board.vdc_nominal_V / sqrt(3.0);
    w_base = 2.0 * PI_ * g_c.nameplate.rated_freq_Hz;
    /* the believed flux Lm i_M and the torque-current limit, in pu */
    psi_pu = g_c.nameplate.Lm_H * g_c.controller.magnetizing_current_A / (v_base / w_base);
    it_pu = g_c.controller.max_torque_current_A / g_c.board.current_full_scale_A;
    assert_q24("tracker guard: 10 % of psi_rated x i_T,max", g_d.adapt.track.phi_min,
               0.1 * psi_pu * it_pu);
}

/* One pass's extraction with Lm and Lr @p factor times the observer's: after
 * the blend (0.1 s in the slow task) the observer holds the limited model. */
static void pass_with(double factor, double *lm_ratio, double *lr_ratio)
{
    param_extract_t p;
    _iq lm0, lr0;
    int k;
    init_from(MC_CONFIG_DIR "/paper_motor_wrong_nameplate.ini");
    lm0 = g_d.frame.fobs.lm;
    lr0 = _IQmpy(g_d.frame.fobs.lm, g_d.frame.fobs.lr_lm);
    memset(&p, 0, sizeof p);
    p.valid = 1u;
    p.Rs = g_d.frame.fobs.rs;
    p.Lm = _IQ((double)_IQtoF(lm0) * factor);
    p.Lr = _IQ((double)_IQtoF(lr0) * factor);
    p.Tr = g_d.frame.fobs.tr;
    g_d.seq.state = ID_REFINE;   /* between passes: the mail is taken */
    drive_adapt_post(&g_d, &p, 1u);
    assert_int_equal(g_d.adapt.bg.m_ready, 1);
    /* the two contexts in turn: the background makes each blend step, the
     * ISR's slow task applies it (0.1 s of slow ticks: 188) */
    for (k = 0; k < 400; k++) {
        drive_adapt_background(&g_d);
        drive_adapt_slow(&g_d);
    }
    assert_int_equal(g_d.adapt.bg.blending, 0);
    *lm_ratio = (double)_IQtoF(g_d.frame.fobs.lm) / (double)_IQtoF(lm0);
    *lr_ratio = (double)_IQtoF(_IQmpy(g_d.frame.fobs.lm, g_d.frame.fobs.lr_lm)) / (double)_IQtoF(lr0);
}

static void test_rate_limit_per_pass(void **state)
{
    double lm, lr;
    (void)state;
    pass_with(4.0, &lm, &lr);
    printf("  extraction x4:   observer Lm x%.6f, Lr x%.6f\n", lm, lr);
    assert_true(fabs(lm - 2.0) < 1e-5 && fabs(lr - 2.0) < 1e-5);
    pass_with(0.25, &lm, &lr);
    printf("  extraction x1/4: observer Lm x%.6f, Lr x%.6f\n", lm, lr);
    assert_true(fabs(lm - 0.5) < 1e-5 && fabs(lr - 0.5) < 1e-5);
    /* within the factor: taken as it is */
    pass_with(1.5, &lm, &lr);
    printf("  extraction x1.5: observer Lm x%.6f, Lr x%.6f\n", lm, lr);
    assert_true(fabs(lm - 1.5) < 1e-5 && fabs(lr - 1.5) < 1e-5);
}

/* The drive's own rules, drive_init's and the table's one test each: the
 * torque-current limit in (0, 1] pu, the trip below the sensors' full
 * scale, at their edges (adjacent floats) and for NaN. */
static void test_drive_rules_at_edges(void **state)
{
    drive_board_t bd;
    (void)state;
    assert_int_equal(drive_design_imax_ok(1.0f), 1);
    assert_int_equal(drive_design_imax_ok(nextafterf(1.0f, 2.0f)), 0);
    assert_int_equal(drive_design_imax_ok(nextafterf(0.0f, 1.0f)), 1);
    assert_int_equal(drive_design_imax_ok(0.0f), 0);
    assert_int_equal(drive_design_imax_ok(nanf("")), 0);
    memset(&bd, 0, sizeof bd);
    bd.current_full_scale_A = 20.0f;
    bd.overcurrent_A = nextafterf(20.0f, 0.0f);
    assert_int_equal(drive_design_oc_ok(&bd), 1);
    bd.overcurrent_A = 20.0f;
    assert_int_equal(drive_design_oc_ok(&bd), 0);
    bd.overcurrent_A = nanf("");
    assert_int_equal(drive_design_oc_ok(&bd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_current_check_time_constant),
        cmocka_unit_test(test_modulation_advance),
        cmocka_unit_test(test_tracker_guard),
        cmocka_unit_test(test_rate_limit_per_pass),
        cmocka_unit_test(test_drive_rules_at_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
