/*
 * Closed-loop tests of the adaptive sequence (beyond the paper): identification from a
 * wrong nameplate, and Rr drift tracking, on the simulated motors with the
 * realistic default inverter and sensors.
 *
 * The adaptive sequence under test (`[controller] orientation = 1`,
 * `[ident] standstill = 1, passes = 2, track_rr = 1`): the rotor-flux
 * observer orients; Rs and sigma Ls are measured at standstill; two RLS
 * passes, the second with the first's Lm, Lr in the observer; in RUN the
 * tracker follows Tr from the observer's slip, ifo takes over the control
 * frame on the tracked Tr, and the published set is fused (Rs standstill,
 * Rr and Tr tracked, Lm, Lr, psi_r from the RLS's K2, K4).
 *
 * What the issue asks, and the bounds here:
 *  - believed Tr, Lm, Rs each 30 % off, all sign combinations: every
 *    parameter within 3 % (the bound).  Measured (IQ_MATH, 27-case
 *    sweep, tools/sweep_start_errors.py): worst 0.62 % paper motor, 0.35 %
 *    1.1 kW, 0.83 % 15 kW; the 8 corners and the centre are run here.
 *  - Rr +40 % over 60 s under a varying load: within 3 % after a lag of at
 *    most 3 s, rotor flux q/d below 1 %.  Measured: 0.43 % at a lag of
 *    2.0 s (paper motor; 1.39 % with no lag), q/d 0.79 % (instantaneous),
 *    0.63 % (20 ms mean).
 *  - the paper's sequence stays as it was: with the same
 *    wrong nameplate it is far off (the contrast is part of the test).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive.h"
#include "sim_config.h"
#include "sim_run.h"

static sim_config_t g_paper, g_15kw, g_1kw;

static int load(const char *name, sim_config_t *c)
{
    char path[512];
    char err[256];
    snprintf(path, sizeof path, "%s/%s", MC_CONFIG_DIR, name);
    if (sim_config_load(path, c, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

static int load_all(void **state)
{
    (void)state;
    return (load("paper_motor.ini", &g_paper) != 0 || load("motor_15kw.ini", &g_15kw) != 0 ||
            load("motor_1kw.ini", &g_1kw) != 0)
               ? -1
               : 0;
}

/* The believed Rr error that gives a believed Tr error of tr_pct with the
 * believed Lm lm_pct off (the leakages are kept). */
static double rr_error_for_tr(const sim_config_t *c, double tr_pct, double lm_pct)
{
    double lr = c->plant.Lm_H + c->plant.Llr_H;
    double lr_b = c->plant.Lm_H * (1.0 + lm_pct / 100.0) + c->plant.Llr_H;
    return 100.0 * (lr_b / (lr * (1.0 + tr_pct / 100.0)) - 1.0);
}

/* A wrong nameplate: the plant's Rs, Lm, Rr off by these percentages, the
 * leakages as the plant's. */
static void wrong_nameplate(sim_config_t *c, double rs_pct, double lm_pct, double rr_pct)
{
    c->nameplate.Rs_ohm = c->plant.Rs_ohm * (1.0 + rs_pct / 100.0);
    c->nameplate.Lm_H = c->plant.Lm_H * (1.0 + lm_pct / 100.0);
    c->nameplate.Rr_ohm = c->plant.Rr_ohm * (1.0 + rr_pct / 100.0);
}

static void adaptive(sim_config_t *c)
{
    c->controller.orientation = 1.0;
    c->ident.standstill = 1.0;
    c->ident.passes = 2.0;
    c->ident.track_rr = 1.0;
}

static double worst_abs(const sim_params_t *e)
{
    double w = fabs(e->Rs_ohm);
    w = fmax(w, fabs(e->Rr_ohm));
    w = fmax(w, fabs(e->Lm_H));
    w = fmax(w, fabs(e->Lr_H));
    w = fmax(w, fabs(e->psi_r_Wb));
    return fmax(w, fabs(e->Tr_s));
}

static void run(const sim_config_t *c, sim_scenario_t scen, double duration_s, sim_result_t *r)
{
    sim_options_t opt;
    char err[256];
    memset(&opt, 0, sizeof opt);
    opt.scenario = scen;
    opt.duration_s = duration_s;
    opt.quiet = 1u;
    assert_int_equal(sim_run(c, &opt, r, err, sizeof err), 0);
}

/* One wrong nameplate, adaptive sequence: the worst error of the set
 * published at the end, or -1 if the drive refused it (then for a reason
 * from its data, not a fault or a time-out: ident_conf.h). */
static double nameplate_case(const sim_config_t *base, double tr, double lm, double rs,
                             double duration_s)
{
    sim_config_t c = *base;
    sim_result_t r;
    const sim_params_t *e = &r.published_end_error_pct;
    adaptive(&c);
    wrong_nameplate(&c, rs, lm, rr_error_for_tr(base, tr, lm));
    /* and the bridge's curve test in CALIBRATE (on the believed Tr) */
    run(&c, SCEN_START, duration_s + sim_vi_test_s(&c), &r);
    assert_int_equal(r.n_faults_seen, 0);
    assert_int_equal(r.final_pass, 2);
    if (!r.identified) {
        printf("  believed Tr %+3.0f Lm %+3.0f Rs %+3.0f %%: refused, %s (confidence %% Rs %.2f "
               "Rr %.2f Lm %.2f Lr %.2f psi_r %.2f Tr %.2f)\n", tr, lm, rs,
               drive_pub_reason_str(r.publish_reason), r.conf_pct[0], r.conf_pct[1],
               r.conf_pct[2], r.conf_pct[3], r.conf_pct[4], r.conf_pct[5]);
        assert_true(r.publish_reason == DRIVE_PUB_LOW_CONFIDENCE ||
                    r.publish_reason == DRIVE_PUB_NOT_CONVERGED);
        return -1.0;
    }
    printf("  believed Tr %+3.0f Lm %+3.0f Rs %+3.0f %%: Rs %+.2f Rr %+.2f Lm %+.2f Lr %+.2f "
           "psi_r %+.2f Tr %+.2f %%; standstill Rs %.4f ohm\n",
           tr, lm, rs, e->Rs_ohm, e->Rr_ohm, e->Lm_H, e->Lr_H, e->psi_r_Wb, e->Tr_s,
           r.Rs_dc_ohm);
    assert_int_equal(r.publish_reason, DRIVE_PUB_PUBLISHED);
    assert_int_equal(r.params_tracked, 1);   /* the fused set, not the bare RLS one */
    return worst_abs(e);
}

/* The centre and the 8 corners of the +-30 % cube: every published
 * parameter within 3 %, the centre (the true nameplate) published, and at
 * most max_refused of the 8 corners refused (each for a reason from its
 * data).  Duration: the curve test, two passes and 5 s of tracking after
 * them. */
static void nameplate_cube(const sim_config_t *base, double duration_s, unsigned max_refused)
{
    static const double s[2] = {-30.0, 30.0};
    double worst = nameplate_case(base, 0.0, 0.0, 0.0, duration_s);
    unsigned i, refused = 0u;
    assert_true(worst >= 0.0);
    for (i = 0u; i < 8u; i++) {
        double w = nameplate_case(base, s[i & 1u], s[(i >> 1) & 1u], s[(i >> 2) & 1u],
                                  duration_s);
        if (w < 0.0) {
            refused++;
        }
        worst = fmax(worst, w);
    }
    printf("worst published parameter error over the 9 cases: %.2f %% (bound 3 %%); %u of 8 "
           "corners refused (at most %u)\n", worst, refused, max_refused);
    assert_true(worst < 3.0);
    assert_true(refused <= max_refused);
}

static void test_nameplate_paper(void **state)
{
    (void)state;
    nameplate_cube(&g_paper, 14.0, 0u);
}

/* 15 kW: the corners with the believed Tr and Lm 30 % low refused (Rr's
 * confidence 3.5 %: the tracker's 1.9 % and Lr's 1.5 %, whose mid-window
 * estimate moved 1.2 %), measured; the others published within 0.8 %. */
static void test_nameplate_15kw(void **state)
{
    (void)state;
    nameplate_cube(&g_15kw, 22.0, 2u);
}

static void test_nameplate_1kw(void **state)
{
    (void)state;
    nameplate_cube(&g_1kw, 18.0, 0u);
}

/* Item 5: the paper's sequence (indirect orientation with the nameplate Tr,
 * one pass) is still there, unchanged; with the believed Tr 30 % high it
 * cannot see past it (method §7 point 4: the RLS's Tr follows the
 * controller's), which is what the adaptive sequence is for.  Measured:
 * IFO Tr error > 10 % (README table: Rr -30 % gives Tr +46 %) in its RLS
 * extraction, which the drive does not publish (confidence above 3 %). */
static void test_paper_sequence_contrast(void **state)
{
    sim_config_t c = g_paper;
    sim_result_t r;
    (void)state;
    wrong_nameplate(&c, 0.0, 0.0, rr_error_for_tr(&g_paper, 30.0, 0.0));
    run(&c, SCEN_START, 0.0, &r);
    printf("paper sequence, believed Tr +30 %%: Tr %+.2f %%, Rr %+.2f %%\n", r.error_pct.Tr_s,
           r.error_pct.Rr_ohm);
    assert_int_equal(r.extracted, 1);
    assert_int_equal(r.identified, 0);
    assert_int_not_equal(r.publish_reason, DRIVE_PUB_PENDING);
    assert_int_equal(r.final_pass, 1);
    assert_int_equal(r.params_tracked, 0);
    assert_true(worst_abs(&r.error_pct) > 10.0);
}

/* Item 3: Rr +40 % over 60 s, load stepping 0 / +50 % / -30 % of rated
 * every 5 s (drift.h); tracked Rr within 3 % of the true Rr of at most 3 s
 * before, q/d below 1 % throughout (instantaneous, as the simulator sees
 * the true flux in the drive's frame). */
static void drift_case(const sim_config_t *base, const char *name)
{
    sim_config_t c = *base;
    sim_result_t r;
    adaptive(&c);
    run(&c, SCEN_DRIFT, 0.0, &r);
    printf("%s drift: Rr %.4f -> %.4f ohm; tracked within %.2f %% (lag 0), %.2f %% at a lag "
           "of %.1f s; q/d max %.4f (20 ms mean %.4f); speed error %.1f r/min; %u samples\n",
           name, c.plant.Rr_ohm, r.drift_rr_true_end_ohm, r.track_err_lag0_pct,
           r.track_err_best_lag_pct, r.track_best_lag_s, r.drift_max_q_over_d,
           r.drift_max_q_over_d_20ms, r.drift_speed_ripple_rpm, (unsigned)r.track_samples);
    assert_int_equal(r.n_faults_seen, 0);
    assert_true(r.drift_t_start_s > 0.0);
    /* the whole window tracked: 65 s at 100 Hz (start 2 s after RUN, the
     * tracker valid 1 s after RUN) */
    assert_true(r.track_samples >= 6400u);
    assert_true(fabs(r.drift_rr_true_end_ohm / c.plant.Rr_ohm - 1.4) < 1e-9);
    assert_true(r.track_best_lag_s <= 3.0);
    assert_true(r.track_err_best_lag_pct < 3.0);
    assert_true(r.drift_max_q_over_d < 0.01);
}

static void test_drift_paper(void **state)
{
    (void)state;
    drift_case(&g_paper, "paper motor");
}

static void test_drift_15kw(void **state)
{
    (void)state;
    drift_case(&g_15kw, "15 kW");
}

/* Without tracking the same drift leaves the published Rr where it was:
 * 40 % low at the end (the test above is not passing by accident). */
static void test_drift_untracked(void **state)
{
    sim_config_t c = g_paper;
    sim_result_t r;
    (void)state;
    adaptive(&c);
    c.ident.track_rr = 0.0;
    run(&c, SCEN_DRIFT, 0.0, &r);
    printf("untracked drift: published Rr %.4f ohm, true %.4f ohm\n", r.published_end.Rr_ohm,
           r.drift_rr_true_end_ohm);
    assert_int_equal(r.track_samples, 0u);
    assert_true(r.published_end.Rr_ohm < 0.8 * r.drift_rr_true_end_ohm);
}

/* Bad input: the adaptation options need the observer; drive_init refuses
 * them with indirect orientation (the INI layer refuses them first, with
 * the key: test_sim_config.c), and passes > 4. */
static void test_options_refused(void **state)
{
    sim_config_t c = g_paper;
    sim_options_t opt;
    sim_result_t r;
    char err[256];
    (void)state;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = 0.01;
    c.ident.track_rr = 1.0;   /* orientation 0 */
    assert_int_not_equal(sim_run(&c, &opt, &r, err, sizeof err), 0);
    assert_non_null(strstr(err, drive_cfg_status_str(DRIVE_CFG_IDENT)));
    c = g_paper;
    adaptive(&c);
    c.ident.passes = 5.0;
    assert_int_not_equal(sim_run(&c, &opt, &r, err, sizeof err), 0);
    assert_non_null(strstr(err, drive_cfg_status_str(DRIVE_CFG_IDENT)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nameplate_paper),
        cmocka_unit_test(test_nameplate_15kw),
        cmocka_unit_test(test_nameplate_1kw),
        cmocka_unit_test(test_paper_sequence_contrast),
        cmocka_unit_test(test_drift_paper),
        cmocka_unit_test(test_drift_15kw),
        cmocka_unit_test(test_drift_untracked),
        cmocka_unit_test(test_options_refused),
    };
    return cmocka_run_group_tests(tests, load_all, NULL);
}
