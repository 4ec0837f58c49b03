/*
 * Closed-loop tests of orientation 1 (orientation by the rotor-flux observer): the drive oriented by
 * the rotor-flux observer (flux_obs.h) instead of indirect field orientation,
 * on the simulated paper motor with the realistic default inverter and
 * sensors (as sim_closed_loop), the default start scenario (4.3 s simulated).
 *
 * What the observer must buy: identification from a wrong believed Tr.
 * Indirect orientation with the believed Rr +30 % / -30 % identifies Rr
 * +5.1 % / -27.1 % (Tr -10.7 % / +46.4 %) and turns the flux up to 14 % /
 * 18 % off the M axis (measured, IQ_MATH).  With the observer the angle does
 * not depend on Tr above its crossover (3 Hz) and the RLS runs only above
 * 10 w_c = 0.6 pu (drive_init.c).  Measured (IQ_MATH, noise seeds 1-6):
 * true parameters, worst error 0.18-1.07 %; Rr +30 %: 2.95-3.93 % (Rr);
 * Rr -30 %: 2.88-4.18 % (Tr).  Bounds: those plus about 1 point for the
 * other math build and seeds (the IQ-FLOAT difference of this motor is
 * 0.02 points with IFO), 2 % for the true parameters as sim_closed_loop.
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

static sim_config_t g_base;

static int load_paper_motor(void **state)
{
    char err[256];
    (void)state;
    if (sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &g_base, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

/* One start-scenario run with the observer and the believed Rr off by rr_pct. */
static void run_obs(double rr_pct, sim_result_t *res)
{
    sim_config_t cfg = g_base;
    sim_options_t opt;
    char err[256];
    memset(&opt, 0, sizeof opt);
    opt.scenario = SCEN_START;
    opt.quiet = 1u;
    cfg.controller.orientation = 1.0;
    cfg.nameplate.Rr_ohm = cfg.plant.Rr_ohm * (1.0 + rr_pct / 100.0);   /* a wrong nameplate */
    assert_int_equal(sim_run(&cfg, &opt, res, err, sizeof err), 0);
    printf("orientation 1, believed Rr %+.0f %%: error %% Rs %+.2f Rr %+.2f Lm %+.2f Lr %+.2f "
           "psi_r %+.2f Tr %+.2f; max |psi_q/psi_d| %.4f; converged %.3f s\n",
           rr_pct, res->error_pct.Rs_ohm, res->error_pct.Rr_ohm, res->error_pct.Lm_H,
           res->error_pct.Lr_H, res->error_pct.psi_r_Wb, res->error_pct.Tr_s,
           res->max_flux_q_over_d, res->converge_s);
}

/* Every parameter of the RLS's extraction within bound_pct; published if
 * @p published is 1, refused if 0 (either if -1); a refusal comes with a reason (ident_conf.h: a set
 * whose confidence exceeds 3 %). */
static void assert_all_within(const sim_result_t *r, double bound_pct, int published)
{
    assert_int_equal(r->extracted, 1);
    if (published >= 0) {
        assert_int_equal(r->identified, published);
    }
    if (!r->identified) {
        printf("  refused: %s\n", drive_pub_reason_str(r->publish_reason));
        assert_int_not_equal(r->publish_reason, DRIVE_PUB_PUBLISHED);
        assert_int_not_equal(r->publish_reason, DRIVE_PUB_PENDING);
    }
    assert_int_equal(r->n_faults_seen, 0);
    assert_true(fabs(r->error_pct.Rs_ohm) < bound_pct);
    assert_true(fabs(r->error_pct.Rr_ohm) < bound_pct);
    assert_true(fabs(r->error_pct.Lm_H) < bound_pct);
    assert_true(fabs(r->error_pct.Lr_H) < bound_pct);
    assert_true(fabs(r->error_pct.psi_r_Wb) < bound_pct);
    assert_true(fabs(r->error_pct.Tr_s) < bound_pct);
}

/* True parameters: the observer must not cost accuracy (bound as
 * sim_closed_loop's 2 %; measured 0.46 %).  Orientation: the q/d ratio is
 * largest at low speed, around the crossover where the current model
 * hands over (measured 0.040; 0.019 above 900 r/min against 0.003 with
 * IFO: the observer's angle carries the current noise through sigma Ls i):
 * bound 0.06.  The drive does not publish it: with the RLS above 0.6 pu
 * only, Tr's bound is 2.6 % and the estimate still moved 2.2 % over the
 * second half of the window (confidence 4.8 %, ident_conf.h); the adaptive
 * sequence, which adds the standstill Rs, two passes and the tracker,
 * publishes this motor (sim_adapt). */
static void test_true_parameters(void **state)
{
    sim_result_t r;
    (void)state;
    run_obs(0.0, &r);
    assert_all_within(&r, 2.0, 0);
    assert_true(r.max_flux_q_over_d < 0.06);
}

/* Believed Rr +30 %: every parameter within 4.5 % (measured, noise seeds
 * 1-6: 2.95-3.93 %, Rr; IFO: Tr -10.7 %), and not published: its
 * confidence (Rr: bound 2.6 % + drift 1.2 %) is above the drive's 3 %.  It was 2.75 % while the RLS
 * started from P(0) = 100 pu: that prior pulled the weakly excited
 * direction towards theta = 0 and happened to offset part of the bias the
 * wrong Tr leaves below the crossover (seeds 1-6: 1.05-2.04 %); with the
 * negligible prior of today (drive_init.c) the data alone decide.  The
 * adaptive sequence removes the bias (sim_adapt).  q/d below 0.1 (measured
 * 0.075 at low speed, where the current model with the wrong Tr steers;
 * IFO 0.138). */
static void test_rr_plus_30(void **state)
{
    sim_result_t r;
    (void)state;
    run_obs(30.0, &r);
    /* the verdict is at its 3 % boundary here: the IQ build refuses the
     * set, the float build publishes it (Rr +3.27 %, Tr -3.18 %); either
     * way every parameter within 4.5 % (-1: either verdict) */
    assert_all_within(&r, 4.5, -1);
    assert_true(r.max_flux_q_over_d < 0.1);
}

/* Believed Rr -30 %: every parameter within 6 % (measured 4.86 %, Tr; IFO:
 * Rr -27.1 %, Tr +46 %), not published (confidence above 3 %).  q/d below 0.2 (measured 0.154 at 190 r/min, the
 * current model's region; 0.020 above 900 r/min, where the RLS runs). */
static void test_rr_minus_30(void **state)
{
    sim_result_t r;
    (void)state;
    run_obs(-30.0, &r);
    assert_all_within(&r, 6.0, 0);
    assert_true(r.max_flux_q_over_d < 0.2);
}

/* Bad input: an orientation other than 0 or 1 reaching drive_init is
 * refused (field orientation), the PWM never on.  (The INI key's range
 * check is in test_sim_config.c.) */
static void test_bad_orientation(void **state)
{
    sim_config_t cfg = g_base;
    sim_options_t opt;
    sim_result_t res;
    char err[256];
    (void)state;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = 0.01;
    cfg.controller.orientation = 2.0;
    assert_int_not_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    assert_non_null(strstr(err, drive_cfg_status_str(DRIVE_CFG_ORIENTATION)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_true_parameters),
        cmocka_unit_test(test_rr_plus_30),
        cmocka_unit_test(test_rr_minus_30),
        cmocka_unit_test(test_bad_orientation),
    };
    return cmocka_run_group_tests(tests, load_paper_motor, NULL);
}
