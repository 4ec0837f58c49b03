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
 * Bounds, 5 % (the request): E, the band, the fitted curve (what the drive
 * runs on) at every level's current, and each level's own point; a point
 * whose current is below one code of the current channel (the 15 kW
 * motor's 0.3 levels: 0.04 A against codes of 0.049 A) is the mean of a
 * dithered reading of less than a code: its current within 1/8 of a code
 * of the true curve's at its voltage (measured 0.07).  On the 15 kW bridge the transition's slope E/b = 195 ohm against
 * sigma Ls = 4.3 mH is a time constant of 22 us, a third of the PWM period:
 * the simulated bridge solves each period's edge currents implicitly
 * (inverter_step_implicit), as a real bridge's error follows the current
 * within the period, so its levels inside the transition settle (an
 * explicit evaluation did not, and the fit could use only 2 of the 6).
 * Measured (IQ, this tree): E -0.04 % / -0.07 % / -0.05 %, b -0.6 % / -0.8 %
 * / -0.8 % (paper, 1.1 kW, 15 kW).
 *
 * The identification does not move with the bridge's true band (nobody
 * sets the drive's: it is measured): the 1.1 kW and 15 kW motors with the
 * simulated band at 0.05, 0.2 and 0.3 A (the default 0.1 A is the
 * accuracy table's run), start scenario: the band measured within 5 % and
 * the last extraction's Rs, Rr and Tr within the 3 % of the accuracy
 * table.  (The test needs its current levels beyond 2 b: i1 = i_M / 2, so
 * b < i_M / 4, 0.5 A on the 1.1 kW motor; a wider transition is refused,
 * VI_FIT_BAND, not mismeasured.)
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

/* the current at which the bridge of @p c loses u (V) along alpha: the
 * inverse of true_err_V inside the saturation */
static double true_current_A(const sim_config_t *c, double u)
{
    const sim_inverter_t *v = &c->inverter;
    const double e = v->vdc_V * v->dead_time_s * c->board.pwm_freq_Hz + v->device_drop_V;
    const double b = v->dead_time_band_A, a = fabs(u);
    const double i = (a <= e) ? a * b / e : (3.0 * a - 2.0 * e) * b / e;   /* |I| < b, b..2b */
    return (u < 0.0) ? -i : i;
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

static void check_motor(const char *ini)
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
    /* every voltage level inside the transition gives the band */
    assert_int_equal(f->n_band, 6u);
    for (l = 0u; l < VI_CURVE_LEVELS; l++) {
        const double i = (double)f->i_A[l];
        const double u_true = true_err_V(&cfg, i);
        const double u_fit = (double)vi_curve_model_V(f->e_pole_V, f->band_A, f->i_A[l]);
        const double code = 2.0 * cfg.board.current_full_scale_A / 4096.0;
        const double i_true = true_current_A(&cfg, (double)f->u_err_V[l]);
        printf("  I %+9.4f A  u_err %+9.4f V  true %+9.4f V  %+6.2f %%  fitted curve %+6.2f %%",
               i, (double)f->u_err_V[l], u_true, 100.0 * ((double)f->u_err_V[l] / u_true - 1.0),
               100.0 * (u_fit / u_true - 1.0));
        if (fabs(i) < 4.0 * code) {
            printf("  (within 4 codes: current %+.3f code)", (i - i_true) / code);
        }
        printf("\n");
        /* the curve the drive runs on (E, b fitted) at the point */
        assert_true(fabs(u_fit - u_true) < TOL * fabs(u_true));
        if (fabs(i) >= 4.0 * code) {
            assert_true(fabs((double)f->u_err_V[l] - u_true) < TOL * fabs(u_true));
        } else if (fabs(i) >= code) {
            /* within four codes of the channel the point's current is the
             * mean of a few codes of a dithered reading: its error is the
             * reading's, within 1/4 of a code (in the band u is linear in
             * i: 5 % of u at 3.6 codes is 0.18 code, the paper motor's
             * 0.035 A level; said in the channel's unit, not the point's) */
            assert_true(fabs(i - i_true) < 0.25 * code);
        } else {
            /* below one code of the channel the point's current is the mean
             * of a dithered reading: its error is the current's, within
             * 1/8 of a code (the 15 kW's 0.3 levels: 0.04 A, codes of 0.049 A) */
            assert_true(fabs(i - i_true) < 0.125 * code);
        }
    }
}

static void test_paper(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/paper_motor.ini");
}

static void test_1kw(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/motor_1kw.ini");
}

static void test_15kw(void **state)
{
    (void)state;
    check_motor(MC_CONFIG_DIR "/motor_15kw.ini");
}

/* The whole start scenario with the simulated bridge's band at @p band_A
 * (the drive told nothing of it). */
static void check_band(const char *ini, double band_A, int retried)
{
    sim_config_t cfg;
    static sim_result_t res;
    sim_options_t opt;
    char err[256];
    assert_int_equal(sim_config_load(ini, &cfg, err, sizeof err), 0);
    assert_true(cfg.ident.vi_test == 1.0);   /* the default */
    /* the paper's sequence, whose RLS extraction is its result (the files'
     * adaptive one publishes the tracker's Rr, Tr instead) */
    sim_config_set_sequence(&cfg, SIM_SEQ_PAPER);
    cfg.inverter.dead_time_band_A = band_A;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    assert_int_equal(sim_run(&cfg, &opt, &res, err, sizeof err), 0);
    printf("%s, bridge band %.2f A: measured %.4f A (%+.2f %%); Rs %+.2f Rr %+.2f Tr %+.2f %%\n",
           ini, band_A, (double)res.vi.band_A, 100.0 * ((double)res.vi.band_A / band_A - 1.0),
           res.error_pct.Rs_ohm, res.error_pct.Rr_ohm, res.error_pct.Tr_s);
    assert_int_equal(res.vi.status, VI_FIT_OK);
    assert_int_equal(res.vi_retried, retried);
    /* the levels beyond the transition, the retry's within the torque limit */
    assert_true(res.vi_i1_A > 2.0 * (double)res.vi.band_A);
    assert_true(2.0 * res.vi_i1_A <= cfg.controller.max_torque_current_A);
    assert_int_equal(res.n_faults_seen, 0);
    assert_true(fabs((double)res.vi.band_A / band_A - 1.0) < TOL);
    assert_int_equal(res.extracted, 1);
    assert_true(fabs(res.error_pct.Rs_ohm) < 3.0);
    assert_true(fabs(res.error_pct.Rr_ohm) < 3.0);
    assert_true(fabs(res.error_pct.Tr_s) < 3.0);
}

static void test_band_varied(void **state)
{
    static const double bands[3] = {0.05, 0.2, 0.3};
    unsigned k;
    (void)state;
    for (k = 0u; k < 3u; k++) {
        check_band(MC_CONFIG_DIR "/motor_15kw.ini", bands[k], 0);
    }
    for (k = 0u; k < 3u; k++) {
        check_band(MC_CONFIG_DIR "/motor_1kw.ini", bands[k], 0);
    }
}

/* A transition wider than the test's current levels reach: the 1.1 kW
 * motor's i1 = i_M / 2 = 1.0 A against a bridge band of 0.55 A (2 b =
 * 1.1 A: the levels inside it, the fit refuses them).  The drive runs the
 * test once more with i1 = 2.5 b (1.4 A; +-2 i1 within its 3.2 A torque
 * limit) and then measures the band within 5 % and identifies within 3 %
 * (check_band), the retry in report.json.  With 0.7 A and the torque limit
 * cut to 2.4 A the retry's i1 (2.5 times the first fit's b, 1.44 A) is
 * beyond the limit's 1.2 A: no retry, the refusal stands, FAULT_VI_CURVE,
 * the bridge off, nothing identified. */
/* Run @p cfg for @p duration_s and expect the curve test refused: FAULT_VI_CURVE
 * seen and latched, the bridge off, nothing identified, the fit's verdict
 * @p status. */
static void expect_vi_refused(sim_config_t *cfg, double duration_s, vi_fit_status_t status,
                              sim_result_t *res)
{
    sim_options_t opt;
    char err[256];
    unsigned k, seen = 0u;
    memset(&opt, 0, sizeof opt);
    opt.quiet = 1u;
    opt.duration_s = duration_s;
    assert_int_equal(sim_run(cfg, &opt, res, err, sizeof err), 0);
    for (k = 0u; k < res->n_faults_seen; k++) {
        seen |= (unsigned)(res->fault_code[k] == FAULT_VI_CURVE);
    }
    printf("curve test: %s, i1 %.3f A, retried %d\n", vi_fit_str(res->vi.status), res->vi_i1_A,
           res->vi_retried);
    assert_true(seen);
    assert_int_equal(res->final_fault, FAULT_VI_CURVE);
    assert_int_equal(res->final_pwm_on, 0);
    assert_int_equal(res->vi.status, status);
    assert_int_equal(res->identified, 0);
}

static void test_band_wider_than_levels(void **state)
{
    sim_config_t cfg;
    static sim_result_t res;
    char err[256];
    (void)state;
    check_band(MC_CONFIG_DIR "/motor_1kw.ini", 0.55, 1);

    assert_int_equal(sim_config_load(MC_CONFIG_DIR "/motor_1kw.ini", &cfg, err, sizeof err), 0);
    cfg.inverter.dead_time_band_A = 0.7;
    cfg.controller.max_torque_current_A = 2.4;
    expect_vi_refused(&cfg, 2.0 * sim_vi_test_s(&cfg) + 0.5, VI_FIT_BAND, &res);
    assert_int_equal(res.vi_retried, 0);   /* no admissible retry: not run */
    assert_true(fabs(res.vi_i1_A - 1.0) < 1e-3);
}

static void test_board_disagrees(void **state)
{
    sim_config_t cfg;
    static sim_result_t res;
    char err[256];
    (void)state;
    assert_int_equal(sim_config_load(MC_CONFIG_DIR "/paper_motor.ini", &cfg, err, sizeof err), 0);
    cfg.ident.vi_test = 1.0;
    cfg.inverter.dead_time_s = cfg.board.dead_time_s;   /* the bridge keeps its 1 us */
    cfg.board.dead_time_s = 3.0 * cfg.board.dead_time_s;
    expect_vi_refused(&cfg, 2.5, VI_FIT_ERROR, &res);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper),
        cmocka_unit_test(test_1kw),
        cmocka_unit_test(test_15kw),
        cmocka_unit_test(test_band_varied),
        cmocka_unit_test(test_band_wider_than_levels),
        cmocka_unit_test(test_board_disagrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
