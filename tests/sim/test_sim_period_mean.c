/*
 * The period-mean regression ([ident] period_mean = 1, include/ident_regressor.h,
 * tools/study/regression_bias.md §5 and §10) in closed loop: the issue's
 * small-leakage motor at high speed (1 kW, sigma 0.077, w_r Tr = 69 at 3000 r/min)
 * on the ideal plant (tests/sim/motor_1kw_s077_ideal.ini), the paper's sequence.
 *
 * What it must show: the paper's rows (eq. 7) are biased there by the flux
 * following the period-mean current, not the sampled one, amplified by w_r Tr
 * (measured: Rr +7.1 %, Tr -6.8 % in IQ_MATH, +6.9 / -6.6 % in FLOAT_MATH), and
 * their error swings with the operating choices (no load: Rr +13.7 %); the
 * period-mean rows remove it: Rr +0.44 / +0.20 %, and the same on the two
 * choices that swung it most (half the ramp rate, no load: within 0.25 %).
 * Bounds: 1 % for the period-mean rows (a factor 2 over the largest measured,
 * the ramp x2 choice of tools/study/regression_bias.py motor_sim: +0.71 %,
 * which is not in this test); at least 5 % for the paper's rows on the
 * nominal run (so that the comparison cannot pass on a plant that lost the
 * effect).  The RLS's last extraction is judged (the set is not published:
 * the confidence's bound on Rr and Tr, 4-5 %, is above the drive's 3 %).
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

static void run(int period_mean, double ramp_scale, double load_scale, sim_result_t *res)
{
    sim_config_t cfg;
    sim_options_t opt;
    char err[256];
    memset(&opt, 0, sizeof opt);
    opt.scenario = SCEN_START;
    opt.quiet = 1u;
    assert_int_equal(sim_config_load(MC_TEST_DIR "/motor_1kw_s077_ideal.ini", &cfg, err,
                                     sizeof err), 0);
    cfg.ident.period_mean = (double)period_mean;
    cfg.controller.speed_ramp_rpm_s *= ramp_scale;
    cfg.load.const_Nm *= load_scale;
    cfg.load.fan_Nm *= load_scale;
    if (sim_run(&cfg, &opt, res, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
    printf("period_mean %d, ramp x%.1f, load x%.0f: extraction error %% Rs %+.2f Rr %+.2f "
           "Lm %+.2f Lr %+.2f psi_r %+.2f Tr %+.2f\n", period_mean, ramp_scale, load_scale,
           res->error_pct.Rs_ohm, res->error_pct.Rr_ohm, res->error_pct.Lm_H, res->error_pct.Lr_H,
           res->error_pct.psi_r_Wb, res->error_pct.Tr_s);
    assert_int_equal(res->extracted, 1);
}

static double worst_pct(const sim_params_t *e)
{
    const double v[6] = {e->Rs_ohm, e->Rr_ohm, e->Lm_H, e->Lr_H, e->psi_r_Wb, e->Tr_s};
    double w = 0.0;
    int i;
    for (i = 0; i < 6; i++) {
        if (fabs(v[i]) > w) {
            w = fabs(v[i]);
        }
    }
    return w;
}

/* the nominal run: the paper's rows biased, the period-mean rows not */
static void test_nominal(void **state)
{
    sim_result_t paper, pm;
    (void)state;
    run(0, 1.0, 1.0, &paper);
    run(1, 1.0, 1.0, &pm);
    assert_true(fabs(paper.error_pct.Rr_ohm) >= 5.0);
    assert_true(worst_pct(&pm.error_pct) <= 1.0);
}

/* the operating choices that moved the paper's rows most */
static void test_operating_choices(void **state)
{
    sim_result_t r;
    (void)state;
    run(1, 0.5, 1.0, &r);   /* half the ramp rate (paper's rows: Rr +8.7 %) */
    assert_true(worst_pct(&r.error_pct) <= 1.0);
    run(1, 1.0, 0.0, &r);   /* no load (paper's rows: Rr +13.7 %) */
    assert_true(worst_pct(&r.error_pct) <= 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nominal),
        cmocka_unit_test(test_operating_choices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
