/* estim_rls: the fixed-point RLS (method §3, eq. 1) with its block-floating-
 * point covariance, against
 *   - the true parameters of synthetic motor data (estim_motor_data.h: the
 *     paper's motor through an acceleration, eq. 2 in pu), noiseless and
 *     with measurement noise (statistical bound from the LS covariance),
 *   - a double-precision RLS (eq. 1, two sequential scalar rows) written
 *     here, on the same (quantised) data,
 * and checks P's symmetry and positive definiteness over 200 000 updates,
 * the forgetting factor's wind-up guard, the three regressor forms, enable,
 * and the init rejections. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "rls.h"
#include "estim_motor_data.h"
#include "estim_test_util.h"

/* ---- double reference RLS ------------------------------------------- */
typedef struct {
    double P[4][4], th[4];
    int paper;      /* third regressor = previous theta2 */
} dls_t;

static void dls_init(dls_t *d, double p0, int paper)
{
    memset(d, 0, sizeof *d);
    for (int i = 0; i < 4; i++) { d->P[i][i] = p0; }
    d->paper = paper;
}

static void dls_row(dls_t *d, const double phi[4], double y)
{
    double pp[4], s = 1.0, e = y;
    for (int i = 0; i < 4; i++) {
        pp[i] = 0.0;
        for (int j = 0; j < 4; j++) { pp[i] += d->P[i][j] * phi[j]; }
        s += phi[i] * pp[i];
        e -= phi[i] * d->th[i];
    }
    for (int i = 0; i < 4; i++) {
        d->th[i] += pp[i] / s * e;
        for (int j = 0; j < 4; j++) { d->P[i][j] -= pp[i] * pp[j] / s; }
    }
}

/* Pn_ij of the module (stored once: the upper triangle, row by row) */
static double rls_pn(const rls_t *r, int i, int j)
{
    static const int ix[4][4] = {{0, 1, 2, 3}, {1, 4, 5, 6}, {2, 5, 7, 8}, {3, 6, 8, 9}};
    return qn_to_d(r->Pn[ix[i][j]], 30);
}

/* P of the module, in double: P = D Pn D / w */
static double rls_P(const rls_t *r, int i, int j)
{
    return ldexp(rls_pn(r, i, j), r->Pe[i] + r->Pe[j]) / qn_to_d(r->w, 30);
}

/* Feed sample k of the motor data (quantised to Q24, optional noise on y)
 * to the module and to the double reference (same quantised values). */
static void feed(rls_t *r, dls_t *d, const md_motor_t *m, int32_t k, double noise,
                 test_rng_t *rng)
{
    md_sample_t s;
    double row[4];
    double c3;
    md_sample(m, k, &s);
    r->y1 = d_to_iq(s.y1 + (rng ? noise * test_rng_normal(rng) : 0.0));
    r->y2 = d_to_iq(s.y2 + (rng ? noise * test_rng_normal(rng) : 0.0));
    r->i_mf = d_to_iq(s.i_m);
    r->u_mf = d_to_iq(s.u_m);
    r->i_tf = d_to_iq(s.i_t);
    r->u_tf = d_to_iq(s.u_t);
    r->wr_f = d_to_iq(s.wr);
    r->enable = 1u;
    if (d != NULL) {
        c3 = d->paper ? d->th[1] : 1.0;
        row[0] = iq_to_d(r->i_mf); row[1] = iq_to_d(r->u_mf); row[2] = c3; row[3] = 0.0;
        dls_row(d, row, iq_to_d(r->y1));
        row[0] = iq_to_d(r->i_tf); row[1] = iq_to_d(r->u_tf); row[2] = 0.0; row[3] = iq_to_d(r->wr_f);
        dls_row(d, row, iq_to_d(r->y2));
    }
    rls_step(r);
}

static void true_theta(const md_motor_t *m, int paper, double th[4])
{
    th[0] = m->K1; th[1] = m->K2; th[2] = paper ? m->K3p : m->K3; th[3] = m->K4;
}

/* Noiseless convergence, constant regressor (eq. 7), P(0) = 1e6 I, 1 s of
 * data (15000 samples, acceleration 0..0.7 s).  The data are exact to
 * Q24 quantisation (|dy| <= 3e-8); the LS solution of the quantised data
 * differs from the true K by ~ quantisation / excitation ~ 1e-6 relative
 * (the double reference shows it).  Bounds: relative error of every K
 * <= 2e-4 in IQ (Q24 theta has 6e-8 resolution and the rounded updates of
 * theta stop once K e < 1/2 LSB: the dead zone of a Q24 integrator, ~
 * n_eff * 3e-8 with n_eff ~ 1e3 effective samples of the slowest
 * direction, relative to K3 = 0.05: 6e-4 worst case, measured below)
 * and <= 2e-4 in FLOAT (24-bit mantissa, the same argument).  Against the
 * double RLS on the same data: |theta - theta_d| <= 2e-4 |K| + 2e-6.
 * (With theta kept in Q24 and rounded increments the measured errors were
 * 1.8e-4 (K2) and 6e-4 (K3).  With a compensated Q24 sum (a Q48 residual)
 * they were <= 1.5e-6.  The IQ build now keeps theta in Q26 with rounded
 * increments, a quarter of the Q24 dead zone, for the cost of the ISR
 * (rls.h): measured K3 1.6e-4, K4 6.4e-5, K1 2.7e-5 relative against the
 * true K and the same against the double (8e-6 absolute on K3 against the
 * 1.2e-5 bound) - within the bounds, which did not change, with less
 * margin; the closed-loop identification (sim_closed_loop) moved by
 * <= 0.003 percentage points.  FLOAT (Kahan) <= 3e-7.) */
static void run_convergence(int paper, double p0, double rel_vs_double, int expect_no_sat,
                            double *err_out)
{
    md_motor_t m;
    rls_t r;
    dls_t d;
    double th[4], emax = 0.0, dmax = 0.0;
    md_motor(&m);
    assert_int_equal(rls_init(&r, paper ? RLS_FORM_PAPER : RLS_FORM_CONST, (float)p0, 1.0f, 0.0f, NULL),
                     RLS_OK);
    dls_init(&d, p0, paper);
    uint32_t sat100 = 0, pd100 = 0;
    for (int32_t k = 1; k <= 15000; k++) {
        feed(&r, &d, &m, k, 0.0, NULL);
        if (k == 100) { sat100 = r.sat_count; pd100 = r.pd_count; }
    }
    true_theta(&m, paper, th);
    for (int i = 0; i < 4; i++) {
        double e = fabs(iq_to_d(r.theta[i]) - th[i]) / fabs(th[i]);
        double ed = fabs(iq_to_d(r.theta[i]) - d.th[i]);
        print_message("%s p0=%.0e K%d: true %.6f  iq %.6f (%.2e rel)  double %.6f (%.2e rel)\n",
                      paper ? "paper" : "const", p0, i + 1, th[i], iq_to_d(r.theta[i]), e, d.th[i],
                      fabs(d.th[i] - th[i]) / fabs(th[i]));
        if (e > emax) { emax = e; }
        assert_true(ed <= rel_vs_double * fabs(th[i]) + 2e-6);
        if (ed > dmax) { dmax = ed; }
    }
    print_message("  sat_count %u, pd_count %u\n", (unsigned)r.sat_count, (unsigned)r.pd_count);
    if (expect_no_sat) {
        assert_int_equal(r.sat_count, 0);
        assert_int_equal(r.pd_count, 0);
    } else {
        /* events only in the ill-conditioned start, none after sample 100 */
        assert_true(r.sat_count == sat100 && r.pd_count == pd100);
        assert_true(r.pd_count <= 40u && r.sat_count <= 20u);
    }
    assert_true(r.n_updates >= 30000u - r.pd_count);
    *err_out = emax;
}

static void test_converge_const(void **state)
{
    double e;
    (void)state;
    run_convergence(0, 1e6, 2e-4, 1, &e);
    assert_true(e <= 2e-4);
}

/* P(0) = 1e12 I: the exponent representation carries the huge start.  The
 * first rows are then conditioned far beyond a 30-bit mantissa (P is 1e12
 * along the directions not yet excited and ~1 along those excited), so in
 * the first ~10 samples the fixed-point estimate leaves the double one:
 * theta hits its +-16 bound a few times and rounding makes q or a
 * diagonal of Pn non-positive (skipped/repaired, rls.h), all COUNTED
 * (measured: IQ 2 updates with a clamp + 13 PD repairs, FLOAT 2 + 12; the
 * clamps are those of h, which act only while P is not PD; earlier
 * versions: IQ 9 + 12 counting every clamp, 28 + 196 with a truncated q,
 * never recovering without the 2-LSB pads of g and q: rls.h).  Bound: at
 * most 20 + 40, none after sample 100, and the end result within the
 * same bounds as with P(0) = 1e6.  (P(0) = 1e6 has no such event.) */
static void test_converge_huge_p0(void **state)
{
    double e;
    (void)state;
    run_convergence(0, 1e12, 2e-4, 0, &e);
    assert_true(e <= 2e-4);
}

/* The paper's regressor (eq. 9): third regressor = previous K2 estimate,
 * theta3 -> K3'.  Method §7 point 3: the early K2 estimates poison the
 * row-1 information (the regressor is wrong while K2 is), and without
 * forgetting that error decays only as the poisoned samples are
 * outweighed.  Measured on the same noiseless data after 1 s: K1 -1.6 %,
 * K2 +2.3 %, K3' +3.4 %, K4 up to 5.9 %, in the double reference as well
 * as here (the
 * prototype of method §7 saw Rr +3.4 % at 1 s), against <= 1.4e-5 for the
 * constant regressor (now 1.6e-4, rls.h: theta in Q26).  This is the measurement behind the default
 * (RLS_FORM_CONST).  Bounds: the paper form within 10 % (it converges, just
 * slowly), and at least 100 times worse than the constant form (the
 * finding itself).  Against the double RLS running the same recursion:
 * 2e-3 |K| (the regressor depends on the estimate, so the early
 * fixed-point differences feed back; measured 1.6e-4 relative (3e-5 with
 * the compensated Q24 theta, 3.2e-4 before the theta update normalised
 * the innovation, 2.8e-3 (failing) with the P downdate truncated, rls.h
 * "Truncation").  The ratio paper / constant is now 360, was 4e4.) */
static void test_converge_paper(void **state)
{
    double e_paper, e_const;
    (void)state;
    run_convergence(1, 1e6, 2e-3, 1, &e_paper);
    run_convergence(0, 1e6, 2e-4, 1, &e_const);
    print_message("paper form: max relative error %.3g, constant form %.3g\n", e_paper, e_const);
    assert_true(e_paper <= 1e-1);
    assert_true(e_paper >= 100.0 * e_const);
}

/* RLS_FORM_FLUX (rls.h): full rows with the flux in the frame, m = (m_M,
 * m_T).  The synthetic motor's regressors, with a flux that moves (m_M = 1
 * + 2 % sin over 0.2 s, m_T = 0.3 % cos over 0.13 s: the excursions of a
 * flux build-up and an orientation error, larger than the period-mean
 * effects it carries in the drive) and y from the rows and the true K
 * (the constant form's: theta3, theta4 are K3, K4 at m_M = 1), so that the
 * rows hold exactly up to the Q24 quantisation.  Against the true K and
 * the double RLS on the same full rows: the bounds of test_converge_const
 * (2e-4 relative; 2e-4 |K| + 2e-6), whose argument (the Q26 theta's dead
 * zone over ~1e3 effective samples) holds for any row of this scale. */
static void test_converge_flux(void **state)
{
    md_motor_t m;
    rls_t r;
    dls_t d;
    double th[4], emax = 0.0;
    (void)state;
    md_motor(&m);
    true_theta(&m, 0, th);
    assert_int_equal(rls_init(&r, RLS_FORM_FLUX, 1e6f, 1.0f, 0.0f, NULL), RLS_OK);
    dls_init(&d, 1e6, 0);
    for (int32_t k = 1; k <= 15000; k++) {
        md_sample_t s;
        double row1[4], row2[4], y1 = 0.0, y2 = 0.0;
        const double mm = 1.0 + 0.02 * sin(2.0 * MD_PI * k / 3000.0);
        const double mt = 0.003 * cos(2.0 * MD_PI * k / 2000.0);
        md_sample(&m, k, &s);
        r.i_mf = d_to_iq(s.i_m);
        r.u_mf = d_to_iq(s.u_m);
        r.c1 = d_to_iq(mm);
        r.d1 = d_to_iq(-s.wr * mt);
        r.i_tf = d_to_iq(s.i_t);
        r.u_tf = d_to_iq(s.u_t);
        r.c2 = d_to_iq(mt);
        r.wr_f = d_to_iq(s.wr * mm);
        row1[0] = iq_to_d(r.i_mf); row1[1] = iq_to_d(r.u_mf);
        row1[2] = iq_to_d(r.c1);   row1[3] = iq_to_d(r.d1);
        row2[0] = iq_to_d(r.i_tf); row2[1] = iq_to_d(r.u_tf);
        row2[2] = iq_to_d(r.c2);   row2[3] = iq_to_d(r.wr_f);
        for (int i = 0; i < 4; i++) {
            y1 += row1[i] * th[i];
            y2 += row2[i] * th[i];
        }
        r.y1 = d_to_iq(y1);
        r.y2 = d_to_iq(y2);
        r.enable = 1u;
        dls_row(&d, row1, iq_to_d(r.y1));
        dls_row(&d, row2, iq_to_d(r.y2));
        rls_step(&r);
    }
    for (int i = 0; i < 4; i++) {
        double e = fabs(iq_to_d(r.theta[i]) - th[i]) / fabs(th[i]);
        double ed = fabs(iq_to_d(r.theta[i]) - d.th[i]);
        print_message("flux K%d: true %.6f  iq %.6f (%.2e rel)  double %.6f\n", i + 1, th[i],
                      iq_to_d(r.theta[i]), e, d.th[i]);
        assert_true(e <= 2e-4);
        assert_true(ed <= 2e-4 * fabs(th[i]) + 2e-6);
        if (e > emax) { emax = e; }
    }
    assert_int_equal(r.sat_count, 0);
    assert_int_equal(r.pd_count, 0);
    print_message("flux form: worst %.2e relative\n", emax);
}

/* rls_step_row: one row per call, alternating (row 1 on odd samples, row 2
 * on even ones), so each row is used at half the rate.  The same noiseless
 * data and P(0) as test_converge_const, against the double RLS running the
 * same alternation; the same bounds as there (2e-4 relative against the
 * true K, 2e-4 |K| + 2e-6 against the double): the filtered regression
 * signals change slowly (10 Hz), so dropping every other row costs no
 * accuracy at this data length (measured: IQ <= 7.6e-5 relative, K3:
 * theta in Q26, see test_converge_const; 2e-6 with the compensated Q24
 * theta). */
static void test_converge_split_rows(void **state)
{
    md_motor_t m;
    rls_t r;
    dls_t d;
    double th[4];
    (void)state;
    md_motor(&m);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 1.0f, 0.0f, NULL), RLS_OK);
    dls_init(&d, 1e6, 0);
    for (int32_t k = 1; k <= 15000; k++) {
        md_sample_t s;
        double row[4];
        md_sample(&m, k, &s);
        r.y1 = d_to_iq(s.y1);
        r.y2 = d_to_iq(s.y2);
        r.i_mf = d_to_iq(s.i_m);
        r.u_mf = d_to_iq(s.u_m);
        r.i_tf = d_to_iq(s.i_t);
        r.u_tf = d_to_iq(s.u_t);
        r.wr_f = d_to_iq(s.wr);
        r.enable = 1u;
        if ((k % 2) == 1) {
            row[0] = iq_to_d(r.i_mf); row[1] = iq_to_d(r.u_mf); row[2] = 1.0; row[3] = 0.0;
            dls_row(&d, row, iq_to_d(r.y1));
        } else {
            row[0] = iq_to_d(r.i_tf); row[1] = iq_to_d(r.u_tf); row[2] = 0.0; row[3] = iq_to_d(r.wr_f);
            dls_row(&d, row, iq_to_d(r.y2));
        }
        rls_step_row(&r);
    }
    true_theta(&m, 0, th);
    for (int i = 0; i < 4; i++) {
        double e = fabs(iq_to_d(r.theta[i]) - th[i]) / fabs(th[i]);
        double ed = fabs(iq_to_d(r.theta[i]) - d.th[i]);
        print_message("split rows K%d: true %.6f  iq %.6f (%.2e rel)  double %.6f (%.2e rel)\n",
                      i + 1, th[i], iq_to_d(r.theta[i]), e, d.th[i],
                      fabs(d.th[i] - th[i]) / fabs(th[i]));
        assert_true(e <= 2e-4);
        assert_true(ed <= 2e-4 * fabs(th[i]) + 2e-6);
    }
    assert_int_equal(r.sat_count, 0);
    assert_int_equal(r.pd_count, 0);
    assert_int_equal(r.n_updates, 15000);
}

/* Measurement noise: white Gaussian, sigma = 2e-3 pu on y1 and y2 (a few
 * % of |y|).  The LS estimate's covariance is sigma^2 P (P of the double
 * reference, p0 = 1e6 large enough to be negligible), so each theta_i is
 * within 4.5 sigma sqrt(P_ii) of the truth with probability 1 - 7e-6
 * (the seed is fixed: the test is deterministic).  The IQ estimate must
 * meet the same bound and stay close to the double estimate on the same
 * data: FLOAT within 0.05 sd + 2e-4 |K|; IQ within 1 sd: with P(0) = 1e6
 * the first rows are conditioned beyond the 30-bit mantissas (see
 * test_converge_huge_p0), so the first noisy samples get slightly
 * different weights, and the estimates differ by a fraction of the
 * noise-induced error itself (measured 0.02 sd, was 0.55 sd on K4 before
 * the theta update normalised the innovation). */
#if MATH_TYPE == IQ_MATH
#define NOISY_VS_DOUBLE(sd, K) (1.0 * (sd))
#else
#define NOISY_VS_DOUBLE(sd, K) (0.05 * (sd) + 2e-4 * fabs(K))
#endif
static void test_noisy(void **state)
{
    md_motor_t m;
    rls_t r;
    dls_t d;
    test_rng_t rng = {0x9e3779b97f4a7c15ull};
    const double sigma = 2e-3;
    double th[4];
    (void)state;
    md_motor(&m);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 1.0f, 0.0f, NULL), RLS_OK);
    dls_init(&d, 1e6, 0);
    for (int32_t k = 1; k <= 15000; k++) {
        feed(&r, &d, &m, k, sigma, &rng);
    }
    true_theta(&m, 0, th);
    for (int i = 0; i < 4; i++) {
        double sd = sigma * sqrt(d.P[i][i]);
        double ei = iq_to_d(r.theta[i]) - th[i];
        print_message("noisy K%d: err iq %.3g, err double %.3g, 1 sd %.3g\n", i + 1, ei,
                      d.th[i] - th[i], sd);
        assert_true(fabs(d.th[i] - th[i]) <= 4.5 * sd);
        assert_true(fabs(ei) <= 4.5 * sd);
        assert_true(fabs(iq_to_d(r.theta[i]) - d.th[i]) <= NOISY_VS_DOUBLE(sd, th[i]));
    }
}

/* The exponent bookkeeping: pe_ref the largest Pe_i, dl_i = pe_ref - Pe_i
 * (at most 31) and d_i = 2^-dl_i (Q30, 0 below 2^-30). */
static void assert_refs_consistent(const rls_t *r)
{
    int16_t m = r->Pe[0];
    for (int i = 1; i < 4; i++) { if (r->Pe[i] > m) { m = r->Pe[i]; } }
    assert_int_equal(r->pe_ref, m);
    for (int i = 0; i < 4; i++) {
        int dl = m - r->Pe[i];
        assert_int_equal(r->dl[i], dl > 31 ? 31 : dl);
        assert_true(qn_to_d(r->d[i], 30) == (dl > 30 ? 0.0 : ldexp(1.0, -dl)));
    }
}

/* Leading principal minors of Pn (double): P = D Pn D with D > 0, so P is
 * PD iff Pn is. */
static int pn_is_pd(const rls_t *r)
{
    double a[4][4];
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 4; j++) { a[i][j] = rls_pn(r, i, j); }
    }
    /* Gaussian elimination without pivoting: the pivots are the ratios of
     * consecutive leading minors; all > 0 <=> all minors > 0 */
    for (int k = 0; k < 4; k++) {
        if (!(a[k][k] > 0.0)) { return 0; }
        for (int i = k + 1; i < 4; i++) {
            double f = a[i][k] / a[k][k];
            for (int j = k; j < 4; j++) { a[i][j] -= f * a[k][j]; }
        }
    }
    return 1;
}

/* 200 000 scalar updates (100 000 samples) on random, persistently
 * exciting rows of motor-like size (|phi| <= 1, y from a fixed theta plus
 * noise), no forgetting: P falls from 1e6 to ~1e-5 (11 decades).  Every
 * 500 samples: Pn (stored once: the upper triangle) with every |Pn_ij| < 1
 * and its diagonals in [0.25, 1) (renormalised at the end of each
 * sample), all leading minors > 0, the exponent bookkeeping consistent
 * (pe_ref = max Pe_i, d_i = 2^-(pe_ref - Pe_i)); and no PD repair or
 * saturation ever happened. */
static void test_long_run_pd(void **state)
{
    rls_t r;
    test_rng_t rng = {42u};
    const double thr[4] = {-0.84, 1.16, 0.05, -0.31};
    int32_t k;
    (void)state;
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 1.0f, 0.0f, NULL), RLS_OK);
    for (k = 0; k < 100000; k++) {
        _iq phi[4];
        double y = 0.0;
        for (int row = 0; row < 2; row++) {
            for (int j = 0; j < 4; j++) {
                double v = (j == 2) ? (row == 0 ? 1.0 : 0.0) : 2.0 * test_rng_uniform(&rng) - 1.0;
                if (row == 0 && j == 3) { v = 0.0; }
                phi[j] = d_to_iq(v);
                y += thr[j] * iq_to_d(phi[j]);
            }
            y += 1e-3 * test_rng_normal(&rng);
            (void)rls_update_row(&r, phi, d_to_iq(y));
            y = 0.0;
        }
        if ((k % 500) == 499) {
            for (int i = 0; i < 4; i++) {
                double dd = rls_pn(&r, i, i);
                assert_true(dd >= 0.25 && dd < 1.0);
                for (int j = 0; j < 4; j++) {
                    if (j != i) { assert_true(fabs(rls_pn(&r, i, j)) < 1.0); }
                }
            }
            assert_true(pn_is_pd(&r));
            assert_refs_consistent(&r);
        }
    }
    print_message("after 200000 updates: P11 = %.3g, P33 = %.3g, theta = %.5f %.5f %.5f %.5f\n",
                  rls_P(&r, 0, 0), rls_P(&r, 2, 2), iq_to_d(r.theta[0]), iq_to_d(r.theta[1]),
                  iq_to_d(r.theta[2]), iq_to_d(r.theta[3]));
    assert_int_equal(r.pd_count, 0);
    assert_int_equal(r.sat_count, 0);
    assert_int_equal(r.n_updates, 200000);
    /* the estimate after 2e5 noisy rows: sd ~ 1e-3 / sqrt(1e5 / 3) ~ 6e-6 */
    for (int i = 0; i < 4; i++) {
        assert_true(fabs(iq_to_d(r.theta[i]) - thr[i]) <= 1e-4);
    }
}

static double rls_trace(const rls_t *r)
{
    double t = 0.0;
    for (int i = 0; i < 4; i++) { t += rls_P(r, i, i); }
    return t;
}

/* Forgetting (lambda = 0.99) with no excitation (zero regressors): without
 * the guard trace(P) would grow as 0.99^-k (x 2e43 after 10 000 samples).
 * With trace_max = 1e4 (P(0) = 100 I, trace 400) the trace rises to the
 * bound and stays there: trace <= trace_max (+ 1e-6 relative for the
 * rounding of the block-floating-point comparison), windup_hold set, theta
 * untouched. */
static void test_forgetting_windup_guard(void **state)
{
    rls_t r;
    const float th0[4] = {-0.5f, 1.0f, 0.1f, -0.2f};
    double tmax = 0.0;
    (void)state;
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 100.0f, 0.99f, 1e4f, th0), RLS_OK);
    r.enable = 1u;
    for (int k = 0; k < 10000; k++) {
        double t;
        r.y1 = _IQ(0.0); r.y2 = _IQ(0.0);
        r.i_mf = _IQ(0.0); r.u_mf = _IQ(0.0); r.i_tf = _IQ(0.0); r.u_tf = _IQ(0.0); r.wr_f = _IQ(0.0);
        /* the constant regressor still excites theta3 in row 1 with
         * c = 1: use rls_forget + zero rows to have NO excitation */
        rls_forget(&r);
        t = rls_trace(&r);
        if (t > tmax) { tmax = t; }
        assert_true(t <= 1e4 * (1.0 + 1e-6));
    }
    print_message("no excitation: max trace %.6g (bound 1e4), hold = %u\n", tmax, r.windup_hold);
    assert_true(tmax >= 1e4 * 0.99);      /* it did grow to the bound */
    assert_int_equal(r.windup_hold, 1u);
    for (int i = 0; i < 4; i++) {
        assert_true(fabs(iq_to_d(r.theta[i]) - (double)th0[i]) <= LSB24);
    }
}

/* Forgetting with poor excitation through rls_step: the regressors are
 * constant (steady state: only one direction per row is excited).  P
 * shrinks along the two excited directions and grows along the others
 * until the guard holds the trace; estimates stay finite, P stays PD, and
 * the prediction error on the excited directions goes to zero. */
static void test_forgetting_poor_excitation(void **state)
{
    rls_t r;
    (void)state;
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 100.0f, 0.995f, 1e4f, NULL), RLS_OK);
    r.enable = 1u;
    for (int k = 0; k < 20000; k++) {
        r.i_mf = _IQ(0.328); r.u_mf = _IQ(0.02); r.i_tf = _IQ(0.1); r.u_tf = _IQ(0.5);
        r.wr_f = _IQ(0.9);
        r.y1 = _IQ(-0.3); r.y2 = _IQ(0.25);
        rls_step(&r);
        assert_true(rls_trace(&r) <= 1e4 * (1.0 + 1e-6));
    }
    print_message("poor excitation: trace %.6g, innovations %.3g %.3g\n", rls_trace(&r),
                  iq_to_d(r.innov[0]), iq_to_d(r.innov[1]));
    assert_true(pn_is_pd(&r));
    assert_int_equal(r.pd_count, 0);
    assert_true(fabs(iq_to_d(r.innov[0])) <= 1e-5);
    assert_true(fabs(iq_to_d(r.innov[1])) <= 1e-5);
}

/* enable = 0 holds theta and P to the bit (rls_step and rls_step_row). */
static void test_enable(void **state)
{
    rls_t r, r0;
    md_motor_t m;
    (void)state;
    md_motor(&m);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 0.999f, 0.0f, NULL), RLS_OK);
    feed(&r, NULL, &m, 1, 0.0, NULL);
    r0 = r;
    r.enable = 0u;
    r.y1 = _IQ(1.0);
    rls_step(&r);
    rls_step_row(&r);
    assert_memory_equal(r.theta, r0.theta, sizeof r.theta);
    assert_memory_equal(r.Pn, r0.Pn, sizeof r.Pn);
    assert_memory_equal(r.Pe, r0.Pe, sizeof r.Pe);
    assert_int_equal(r.row_next, 0u);
}

/* rls_step_row1 then rls_step_row2 (the multi-rate ISR's two slots) do
 * what rls_step does, to the bit (every field, forgetting on: lambda =
 * 0.999), and (IQ_MATH) theta[] is published with row 2: after row 1 it
 * still holds the last completed sample's estimate.  (FLOAT_MATH: theta[]
 * is the state itself, current after every row; the regressor of the
 * paper form, the K2 "before this sample" (eq. 9), is the same in both.) */
static void test_halves_equal_step(void **state)
{
    md_motor_t m;
    rls_t a, b;
    (void)state;
    md_motor(&m);
    assert_int_equal(rls_init(&a, RLS_FORM_PAPER, 1e6f, 0.999f, 0.0f, NULL), RLS_OK);
    assert_int_equal(rls_init(&b, RLS_FORM_PAPER, 1e6f, 0.999f, 0.0f, NULL), RLS_OK);
    for (int32_t k = 1; k <= 3000; k++) {
        _iq th[4];
        feed(&a, NULL, &m, k, 0.0, NULL);      /* rls_step */
        b.y1 = a.y1; b.y2 = a.y2; b.i_mf = a.i_mf; b.u_mf = a.u_mf;
        b.i_tf = a.i_tf; b.u_tf = a.u_tf; b.wr_f = a.wr_f; b.enable = 1u;
        memcpy(th, b.theta, sizeof th);
        rls_step_row1(&b);
#if MATH_TYPE == IQ_MATH
        assert_memory_equal(b.theta, th, sizeof th);
#endif
        rls_step_row2(&b);
        assert_memory_equal(&a, &b, sizeof a);
    }
    assert_true(a.n_updates == 6000u);
}

/* A value saturated or clamped counts once per update in sat_count,
 * however many were clamped in it: here two regressors beyond +-4 and the
 * innovation beyond +-RLS_E_MAX in each of two updates. */
static void test_sat_count_once_per_update(void **state)
{
    rls_t r;
    const _iq phi[4] = {_IQ(5.0), _IQ(-6.0), _IQ(1.0), _IQ(0.0)};
    (void)state;
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1.0f, 1.0f, 0.0f, NULL), RLS_OK);
    (void)rls_update_row(&r, phi, _IQ(100.0));
    assert_int_equal(r.sat_count, 1);
    (void)rls_update_row(&r, phi, _IQ(-100.0));
    assert_int_equal(r.sat_count, 2);
    assert_int_equal(r.n_updates, 2);
    assert_int_equal(r.pd_count, 0);
}

static void test_init_rejects(void **state)
{
    rls_t r;
    const float bad_th[4] = {0.0f, 16.0f, 0.0f, 0.0f};
    (void)state;
    assert_int_equal(rls_init(&r, (rls_form_t)3, 1e6f, 1.0f, 0.0f, NULL), RLS_ERR_FORM);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 0.0f, 1.0f, 0.0f, NULL), RLS_ERR_P0);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e13f, 1.0f, 0.0f, NULL), RLS_ERR_P0);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, NAN, 1.0f, 0.0f, NULL), RLS_ERR_P0);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 0.85f, 0.0f, NULL), RLS_ERR_LAMBDA);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 1.01f, 0.0f, NULL), RLS_ERR_LAMBDA);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 0.99f, 1e5f, NULL), RLS_ERR_TRACE);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 0.99f, -1.0f, NULL), RLS_ERR_TRACE);
    assert_int_equal(rls_init(&r, RLS_FORM_CONST, 1e6f, 1.0f, 0.0f, bad_th), RLS_ERR_THETA0);
    /* a rejected instance is zeroed: enable = 0, nothing happens */
    rls_step(&r);
    assert_true(r.theta[1] == _IQ(0.0));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_converge_const),
        cmocka_unit_test(test_converge_huge_p0),
        cmocka_unit_test(test_converge_paper),
        cmocka_unit_test(test_converge_split_rows),
        cmocka_unit_test(test_converge_flux),
        cmocka_unit_test(test_noisy),
        cmocka_unit_test(test_long_run_pd),
        cmocka_unit_test(test_forgetting_windup_guard),
        cmocka_unit_test(test_forgetting_poor_excitation),
        cmocka_unit_test(test_enable),
        cmocka_unit_test(test_halves_equal_step),
        cmocka_unit_test(test_sat_count_once_per_update),
        cmocka_unit_test(test_init_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
