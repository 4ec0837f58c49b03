/*
 * The bridge's voltage error measured at standstill (vi_curve.h, ident.vi_test
 * = 1) against the simulated bridge's true one, on the paper motor, the
 * 1.1 kW and the 15 kW motors.
 *
 * Reference (independent of the drive and of vi_curve.c): the simulated
 * bridge (host_sim/model/inverter_model.h) loses on each pole
 *   E s(i) + r_on i,  E = Vdc td f_pwm + v_drop,  s(i) = sat(i / b, -1, 1),
 * from its [inverter] keys (vdc_V, dead_time_s, device_drop_V, r_on_ohm,
 * dead_time_band_A).  With the test's current along alpha (i_a = I,
 * i_b = i_c = -I/2) the floating star's alpha voltage loses
 *   (2/3) E (s(I) + s(I/2)) + r_on I,
 * the last term indistinguishable from Rs (the fit's Rs carries it).
 *
 * Bounds, 5 % (the request): E and the table's error at every current
 * level, and the band; the table at the voltage levels inside the
 * transition on the paper and 1.1 kW motors.  On the 15 kW bridge the
 * transition's slope E/b = 195 ohm against sigma Ls = 4.3 mH is a time
 * constant of 22 us, a third of the PWM period: the simulated bridge,
 * evaluated once per period at the period's start current, runs into a
 * period-to-period limit cycle there (inverter_model.h: the ramp keeps the
 * coupling quiet only while that time constant exceeds Ts), so its mean
 * current at 0.6 and 0.3 of the saturated error means nothing; the fit
 * takes b from the 0.9 levels (1.6 b, outside the cycle), which are
 * checked.  Measured (IQ, this tree): E -0.02 % / -0.02 % / -0.05 %,
 * b -0.5 % / -0.5 % / -2.1 % (paper, 1.1 kW, 15 kW).
 *
 * And a board whose dead time is 3x the bridge's: the measured E is 0.4 of
 * the board's, outside the factor 2 drive_vi.c accepts: refused,
 * FAULT_VI_CURVE, and the bridge off.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "drive_types.h"
#include "protect.h"
#include "sim_config.h"
#include "sim_run.h"
#include "vi_curve.h"

#define TOL 0.05

static double sat1(double x) { return (x > 1.0) ? 1.0 : ((x < -1.0) ? -1.0 : x); }

/* the true alpha-axis error of the bridge of @p c at current i (above) */
static double true_err_V(const sim_config_t *c, double i)
{
    const sim_inverter_t *v = &c->inverter;
    const double e = v->vdc_V * v->dead_time_s * c->board.pwm_freq_Hz + v->device_drop_V;
    return (2.0 / 3.0) * e * (sat1(i / v->dead_time_band_A) + sat1(0.5 * i / v->dead_time_band_A));
}

/* the test alone, on @p ini, with its own time (the end of CALIBRATE) */
static void run_vi(const char *ini, sim_config_t *cfg, sim_result_t *res)
{
    sim_options_t opt;
    char err[256];
    double tr;
    assert_int_equal(sim_config_load(ini, cfg, err, sizeof err), 0);
    cfg->ident.vi_test = 1.0;
    tr = (cfg->nameplate.Lm_H + cfg->nameplate.Llr_H) / cfg->nameplate.Rr_ohm;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = (double)vi_curve_duration_s((float)((double)DRIVE_SLOTS /
                                                         cfg->board.pwm_freq_Hz),
                                                 (float)tr) + 0.3;
    assert_int_equal(sim_run(cfg, &opt, res, err, sizeof err), 0);
}

static void check_motor(const char *ini, int whole_table)
{
    sim_config_t cfg;
    static sim_result_t res;
    const vi_fit_t *f = &res.vi;
    double e_true;
    unsigned l;

    run_vi(ini, &cfg, &res);
    e_true = cfg.inverter.vdc_V * cfg.inverter.dead_time_s * cfg.board.pwm_freq_Hz +
             cfg.inverter.device_drop_V;
    printf("%s: E %.4f V (true %.4f, %+.2f %%), b %.4f A (true %.4f, %+.2f %%), Rs %.4f ohm "
           "(true %.4f + r_on %.4f), vdc %.2f V\n", ini, (double)f->e_pole_V, e_true,
           100.0 * ((double)f->e_pole_V / e_true - 1.0), (double)f->band_A,
           cfg.inverter.dead_time_band_A,
           100.0 * ((double)f->band_A / cfg.inverter.dead_time_band_A - 1.0), (double)f->rs_ohm,
           cfg.plant.Rs_ohm, cfg.inverter.r_on_ohm, (double)f->vdc_V);
    assert_int_equal(f->status, VI_FIT_OK);
    assert_int_equal(res.final_fault, FAULT_NONE);
    assert_true(e_true > 0.0);
    assert_true(fabs((double)f->e_pole_V / e_true - 1.0) < TOL);
    assert_true(fabs((double)f->band_A / cfg.inverter.dead_time_band_A - 1.0) < TOL);
    /* every voltage level on the paper and 1.1 kW bridges; the 0.9 levels on the 15 kW */
    assert_int_equal(f->n_band, whole_table ? 6u : 2u);
    for (l = 0u; l < VI_CURVE_LEVELS; l++) {
        const double i = (double)f->i_A[l];
        const double u_true = true_err_V(&cfg, i);
        /* levels 0, 1, 5, 6: currents; 2, 7: 0.9 of the saturated error */
        const int checked = whole_table || l == 0u || l == 1u || l == 2u || l == 5u ||
                            l == 6u || l == 7u;
        printf("  I %+9.4f A  u_err %+9.4f V  true %+9.4f V  %+6.2f %%%s\n", i,
               (double)f->u_err_V[l], u_true, 100.0 * ((double)f->u_err_V[l] / u_true - 1.0),
               checked ? "" : "  (not checked: the model's limit cycle)");
        if (checked) {
            assert_true(fabs((double)f->u_err_V[l] - u_true) < TOL * fabs(u_true));
        }
    }
}

static void test_paper(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/paper_motor.ini", 1);
}

static void test_1kw(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/motor_1kw.ini", 1);
}

static void test_15kw(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/motor_15kw.ini", 0);
}

static void test_board_disagrees(void **state)
{
    sim_config_t cfg;
    static sim_result_t res;
    sim_options_t opt;
    char err[256];
    unsigned k, seen = 0u;
    (void)state;
    assert_int_equal(sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &cfg, err, sizeof err), 0);
    cfg.ident.vi_test = 1.0;
    cfg.inverter.dead_time_s = cfg.board.dead_time_s;   /* the bridge keeps its 1 us */
    cfg.board.dead_time_s = 3.0 * cfg.board.dead_time_s;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = 2.5;
    assert_int_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    for (k = 0u; k < res.n_faults_seen; k++) {
        seen |= (unsigned)(res.fault_code[k] == FAULT_VI_CURVE);
    }
    assert_true(seen);
    assert_int_equal(res.final_fault, FAULT_VI_CURVE);
    assert_int_equal(res.final_pwm_on, 0);
    assert_int_equal(res.vi.status, VI_FIT_ERROR);
    assert_int_equal(res.identified, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper),
        cmocka_unit_test(test_1kw),
        cmocka_unit_test(test_15kw),
        cmocka_unit_test(test_board_disagrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
