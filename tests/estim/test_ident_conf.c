/* estim_ident_conf: the identification's confidence (ident_conf.h) against
 * an independent double-precision reference.
 *
 * Data: the paper motor's acceleration (estim_motor_data.h, exact
 * regression) with a known error added to both rows: a 37 Hz and a 53 Hz
 * sinusoid of 0.2 % of the rows' rms (what the model does not explain),
 * 0.75 s at 15 kHz, the constant-regressor RLS (P(0) = 1e5, no forgetting)
 * updated every sample, ident_conf_acc_step after each.
 *
 * Reference, computed here in double from the same rows: the batch least
 * squares with the RLS's prior (Phi'Phi + I/p0) theta = Phi'y, its
 * residual J = sum (y - Phi theta)^2, P = (Phi'Phi + I/p0)^-1, and for each
 * parameter of method §4 the Jacobian by central differences of the
 * extraction's formulas (written out again below, not ident_conf's
 * elasticity table): bound = sqrt(J g' P g) / |p|.  The firmware's J is the
 * sum of the a-posteriori residuals of each sample (not of the final
 * estimate), its P the fixed-point RLS's: bounds within 3 % of the
 * reference, the residual within 3 % (measured: +0.8 % IQ_MATH, +1.1 %
 * FLOAT_MATH: J's a-posteriori sum is the larger).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "estim_motor_data.h"
#include "estim_test_util.h"
#include "ident_conf.h"
#include "param_extract.h"
#include "rls.h"
#include "rls_cov.h"

#define N_SAMPLES 11250   /* 0.75 s */
#define P0 1e5

typedef struct {
    md_motor_t m;
    base_values_t b;
    rls_t rls;
    rls_cov_t cov;
    ident_conf_acc_t acc;
    param_extract_t end;
    /* reference */
    double G[4][4], r[4], yy, Y;   /* sum phi phi', sum phi y, sum y^2 (both rows) */
    double theta[4], J, P[4][4];
    long n;
} fx_t;

static fx_t fx;

/* the error the model does not explain: 0.2 % of the rows' scale */
static double model_error(int row, int32_t k)
{
    double t = (double)k * MD_TS_S;
    return (row == 0) ? 2.4e-4 * sin(2.0 * MD_PI * 37.0 * t)
                      : 3.0e-4 * sin(2.0 * MD_PI * 53.0 * t + 0.4);
}

static void add_row(const double phi[4], double y)
{
    int i, j;
    for (i = 0; i < 4; i++) {
        for (j = 0; j < 4; j++) {
            fx.G[i][j] += phi[i] * phi[j];
        }
        fx.r[i] += phi[i] * y;
    }
    fx.yy += y * y;
}

/* 4x4 inverse by Gauss-Jordan with partial pivoting */
static void inv4(double a[4][4], double out[4][4])
{
    double m[4][8];
    int i, j, k;
    for (i = 0; i < 4; i++) {
        for (j = 0; j < 8; j++) {
            m[i][j] = (j < 4) ? a[i][j] : (double)(j - 4 == i);
        }
    }
    for (k = 0; k < 4; k++) {
        int p = k;
        for (i = k + 1; i < 4; i++) {
            if (fabs(m[i][k]) > fabs(m[p][k])) {
                p = i;
            }
        }
        for (j = 0; j < 8; j++) {
            double t = m[k][j];
            m[k][j] = m[p][j];
            m[p][j] = t;
        }
        for (j = 7; j >= k; j--) {
            m[k][j] /= m[k][k];
        }
        for (i = 0; i < 4; i++) {
            if (i != k) {
                double f = m[i][k];
                for (j = k; j < 8; j++) {
                    m[i][j] -= f * m[k][j];
                }
            }
        }
    }
    for (i = 0; i < 4; i++) {
        for (j = 0; j < 4; j++) {
            out[i][j] = m[i][j + 4];
        }
    }
}

/* method §4 in double, constant form (theta3 = K3 = K2 K3'): p[6] */
static void params_d(const double th[4], double im, double p[6])
{
    double K1 = th[0], K2 = th[1], K3p = th[2] / th[1], K4 = th[3];
    double a = -K4 / (K2 * im), Lr = 1.0 / K2 + a, Lm = sqrt(a * Lr);
    p[IDENT_P_RS] = -K1 / K2 - K3p / im;
    p[IDENT_P_RR] = K3p * Lr / (a * im);
    p[IDENT_P_LM] = Lm;
    p[IDENT_P_LR] = Lr;
    p[IDENT_P_PSI] = Lm * im;
    p[IDENT_P_TR] = -K4 / (K2 * K3p);
}

static int setup(void **state)
{
    param_limits_t lim = {.Rs_ohm = {0.1f, 10.0f}, .Rr_ohm = {0.05f, 5.0f},
                          .Lm_H = {1e-3f, 0.05f}, .Lr_H = {1e-3f, 0.06f},
                          .psi_Wb = {0.005f, 0.2f}, .Tr_s = {0.002f, 0.2f}, .i_m_min_A = 0.5f};
    double A[4][4];
    int32_t k;
    int i, j;
    (void)state;
    memset(&fx, 0, sizeof fx);
    md_motor(&fx.m);
    assert_int_equal(base_values_init(&fx.b, 20.0f, 60.0f / 1.7320508f, 50.0f, 2u, 1.0f / 15000.0f),
                     BASE_OK);
    assert_int_equal(rls_init(&fx.rls, RLS_FORM_CONST, (float)P0, 1.0f, 0.0f, NULL), RLS_OK);
    ident_conf_acc_reset(&fx.acc);
    for (k = 0; k < N_SAMPLES; k++) {
        md_sample_t s;
        double y1, y2, phi1[4], phi2[4];
        md_sample(&fx.m, k, &s);
        y1 = s.y1 + model_error(0, k);
        y2 = s.y2 + model_error(1, k);
        fx.rls.y1 = d_to_iq(y1);
        fx.rls.y2 = d_to_iq(y2);
        fx.rls.i_mf = d_to_iq(s.i_m);
        fx.rls.u_mf = d_to_iq(s.u_m);
        fx.rls.i_tf = d_to_iq(s.i_t);
        fx.rls.u_tf = d_to_iq(s.u_t);
        fx.rls.wr_f = d_to_iq(s.wr);
        fx.rls.enable = 1u;
        rls_step(&fx.rls);
        ident_conf_acc_step(&fx.acc, &fx.rls);
        /* the reference sees the Q24 values the RLS saw */
        phi1[0] = iq_to_d(fx.rls.i_mf); phi1[1] = iq_to_d(fx.rls.u_mf); phi1[2] = 1.0; phi1[3] = 0.0;
        phi2[0] = iq_to_d(fx.rls.i_tf); phi2[1] = iq_to_d(fx.rls.u_tf); phi2[2] = 0.0;
        phi2[3] = iq_to_d(fx.rls.wr_f);
        add_row(phi1, iq_to_d(fx.rls.y1));
        add_row(phi2, iq_to_d(fx.rls.y2));
        fx.n++;
    }
    rls_cov_save(&fx.cov, &fx.rls);
    /* the batch fit with the RLS's prior and its residual (the prior's term
     * theta' theta / p0 is below 1e-5 of J here) */
    for (i = 0; i < 4; i++) {
        for (j = 0; j < 4; j++) {
            A[i][j] = fx.G[i][j] + ((i == j) ? 1.0 / P0 : 0.0);
        }
    }
    inv4(A, fx.P);
    for (i = 0; i < 4; i++) {
        fx.theta[i] = 0.0;
        for (j = 0; j < 4; j++) {
            fx.theta[i] += fx.P[i][j] * fx.r[j];
        }
    }
    fx.J = fx.yy;
    for (i = 0; i < 4; i++) {
        fx.J -= 2.0 * fx.theta[i] * fx.r[i];
        for (j = 0; j < 4; j++) {
            fx.J += fx.theta[i] * fx.G[i][j] * fx.theta[j];
        }
    }
    fx.Y = fx.yy;
    /* the extraction of the RLS's final estimate */
    assert_int_equal(param_extract_init(&fx.end, &fx.b, &lim), PARAM_INIT_OK);
    for (i = 0; i < 4; i++) {
        fx.end.theta[i] = fx.rls.theta[i];
    }
    fx.end.form = (uint16_t)RLS_FORM_CONST;
    fx.end.i_m = d_to_iq(fx.m.i_m0);
    param_extract_step(&fx.end);
    assert_int_equal(fx.end.valid, 1u);
    return 0;
}

/* rls_cov_factor against sqrt(P_ii) and P_ij / sqrt(P_ii P_jj) computed in
 * double from the copy's mantissas and exponents (P_ij = 2^(Pe_i + Pe_j)
 * Pn_ij / w, rls.h): within 8 LSB30 (IQ_MATH: _IQ30sqrt and _IQ30div, each
 * within 1 LSB, twice for the deviation's 0.5 / sqrt(w) factor), 1e-6 in FLOAT_MATH (float's 6e-8, a few operations). */
#if MATH_TYPE == IQ_MATH
#define COV_TOL 8e-9
#else
#define COV_TOL 1e-6
#endif
static void test_cov_factor(void **state)
{
    _iq30 sd_m[RLS_N], rho[RLS_N][RLS_N];
    int16_t sd_e[RLS_N];
    int i, j;
    (void)state;
    rls_cov_factor(&fx.cov, sd_m, sd_e, rho);
    for (i = 0; i < RLS_N; i++) {
        double pii = ldexp(qn_to_d(fx.cov.Pn[i][i], 30), 2 * fx.cov.Pe[i]) /
                     qn_to_d(fx.cov.w, 30);
        double sd = ldexp(qn_to_d(sd_m[i], 30), sd_e[i]);
        assert_true(fabs(sd / sqrt(pii) - 1.0) < COV_TOL);
        for (j = 0; j < RLS_N; j++) {
            double pij = ldexp(qn_to_d(fx.cov.Pn[i][j], 30), fx.cov.Pe[i] + fx.cov.Pe[j]) /
                         qn_to_d(fx.cov.w, 30);
            double pjj = ldexp(qn_to_d(fx.cov.Pn[j][j], 30), 2 * fx.cov.Pe[j]) /
                         qn_to_d(fx.cov.w, 30);
            assert_true(fabs(qn_to_d(rho[i][j], 30) - pij / sqrt(pii * pjj)) < COV_TOL);
        }
    }
    /* and the RLS's P is the batch fit's (P(0) forgotten): diagonals within 2 % */
    for (i = 0; i < RLS_N; i++) {
        double pii = ldexp(qn_to_d(fx.cov.Pn[i][i], 30), 2 * fx.cov.Pe[i]) /
                     qn_to_d(fx.cov.w, 30);
        assert_true(fabs(pii / fx.P[i][i] - 1.0) < 0.02);
    }
}

/* The residual, the excitation and every parameter's bound against the
 * reference (file comment). */
static void test_bounds_against_reference(void **state)
{
    ident_conf_t c;
    const double y_ref = 0.9333 * fx.m.i_m0;
    double res_ref = sqrt(fx.J / fx.Y), exc_ref = sqrt(fx.Y / (2.0 * (double)fx.n)) / y_ref;
    double th[4], p0[6];
    int i, j, q;
    (void)state;
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, (float)y_ref), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, NULL);
    printf("residual %.4e (reference %.4e), excitation %.4f (%.4f), n %u\n",
           iq_to_d(c.residual), res_ref, iq_to_d(c.excitation), exc_ref, (unsigned)fx.acc.n);
    assert_int_equal(fx.acc.n, (uint32_t)N_SAMPLES);
    assert_true(res_ref > 5e-4 && res_ref < 5e-3);    /* the error added is there */
    assert_true(fabs(iq_to_d(c.residual) / res_ref - 1.0) < 0.03);
    assert_true(fabs(iq_to_d(c.excitation) / exc_ref - 1.0) < 0.01);
    for (i = 0; i < 4; i++) {
        th[i] = iq_to_d(fx.rls.theta[i]);
    }
    params_d(th, iq_to_d(fx.end.i_m), p0);
    for (q = 0; q < (int)IDENT_NP; q++) {
        double g[4], var = 0.0, ref, got = 100.0 * iq_to_d(c.bound[q]);
        for (i = 0; i < 4; i++) {
            double hp[4], hm[4], pp[6], pm[6], h = 1e-6 * fabs(th[i]);
            memcpy(hp, th, sizeof th);
            memcpy(hm, th, sizeof th);
            hp[i] += h;
            hm[i] -= h;
            params_d(hp, iq_to_d(fx.end.i_m), pp);
            params_d(hm, iq_to_d(fx.end.i_m), pm);
            g[i] = (pp[q] - pm[q]) / (2.0 * h);
        }
        for (i = 0; i < 4; i++) {
            for (j = 0; j < 4; j++) {
                var += g[i] * fx.P[i][j] * g[j];
            }
        }
        ref = 100.0 * sqrt(fx.J * var) / fabs(p0[q]);
        printf("  parameter %d: bound %.4f %% (reference %.4f %%), confidence %.4f %%\n", q, got,
               ref, 100.0 * iq_to_d(c.conf[q]));
        assert_true(fabs(got / ref - 1.0) < 0.03);
        /* no mid-window estimate: the confidence is the bound */
        assert_true(c.conf[q] == c.bound[q]);
        assert_true(c.drift[q] == _IQ(0.0));
    }
    /* a residual of 0.1 % of the signal bounds Tr to 2.0 % (amplification 20):
     * within 3 %, published */
    assert_int_equal(c.verdict, IDENT_CONF_OK);
}

/* The drift: the same extraction of another estimate (K3 +2 %, K4 -1 %):
 * |p_end - p_mid| / |p_end| to 1e-5 of the double formulas; the confidence
 * the sum of bound and drift; with Tr's drift (3 %) the set is refused,
 * not converged (the drift is the larger part). */
static void test_drift(void **state)
{
    ident_conf_t c;
    param_extract_t mid = fx.end;
    double th_e[4], th_m[4], pe[6], pm[6];
    int i, q;
    (void)state;
    mid.theta[2] = _IQmpy(fx.end.theta[2], _IQ(1.02));
    mid.theta[3] = _IQmpy(fx.end.theta[3], _IQ(0.99));
    param_extract_step(&mid);
    assert_int_equal(mid.valid, 1u);
    for (i = 0; i < 4; i++) {
        th_e[i] = iq_to_d(fx.end.theta[i]);
        th_m[i] = iq_to_d(mid.theta[i]);
    }
    params_d(th_e, iq_to_d(fx.end.i_m), pe);
    params_d(th_m, iq_to_d(fx.end.i_m), pm);
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, &mid);
    for (q = 0; q < (int)IDENT_NP; q++) {
        double ref = fabs(pe[q] - pm[q]) / fabs(pe[q]);
        assert_true(fabs(iq_to_d(c.drift[q]) - ref) < 1e-5 + 1e-4 * ref);
        assert_true(c.conf[q] == c.bound[q] + c.drift[q]);
    }
    assert_true(iq_to_d(c.drift[IDENT_P_TR]) > 0.029);   /* Tr = |K4|/K3: 0.99/1.02 */
    assert_int_equal(c.verdict, IDENT_CONF_NOT_CONVERGED);
    assert_int_equal(c.worst, IDENT_P_TR);
    /* a mid estimate that is not plausible: the largest drift */
    mid.valid = 0u;
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, &mid);
    assert_true(c.drift[IDENT_P_RS] == _IQ(IDENT_CONF_MAX));
    assert_int_equal(c.verdict, IDENT_CONF_NOT_CONVERGED);
}

/* Why a set is refused, in order: no data; low excitation; high residual;
 * not converged; low confidence.  The same data under other limits. */
static void test_verdict_order(void **state)
{
    ident_conf_t c;
    ident_conf_acc_t none;
    (void)state;
    ident_conf_acc_reset(&none);
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &none, 0u, &fx.end, NULL);
    assert_int_equal(c.verdict, IDENT_CONF_NO_DATA);
    /* every bound above 0.01 %: refused; why depends on the references */
    assert_int_equal(ident_conf_init(&c, 0.0001f, 0.02f, 50.0f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, NULL);
    assert_int_equal(c.verdict, IDENT_CONF_LOW_EXCITATION);
    assert_int_equal(ident_conf_init(&c, 0.0001f, 0.0005f, 0.01f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, NULL);
    assert_int_equal(c.verdict, IDENT_CONF_HIGH_RESIDUAL);
    assert_int_equal(ident_conf_init(&c, 0.0001f, 0.5f, 0.01f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, NULL);
    assert_int_equal(c.verdict, IDENT_CONF_LOW_CONFIDENCE);
    /* the magnetic part alone: Lm, Lr, psi_r judged (bounds below 0.5 %) */
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, 0.3f), IDENT_CONF_INIT_OK);
    c.mask = IDENT_MASK_MAGNETIC;
    ident_conf_eval(&c, &fx.cov, &fx.acc, 0u, &fx.end, NULL);
    assert_true(c.conf[IDENT_P_RS] == _IQ(0.0) && c.conf[IDENT_P_TR] == _IQ(0.0));
    assert_true(c.conf[IDENT_P_LM] > _IQ(0.0) && c.conf[IDENT_P_LM] < _IQ(0.005));
    assert_int_equal(c.verdict, IDENT_CONF_OK);
    /* bad limits */
    assert_int_equal(ident_conf_init(&c, 0.0f, 0.02f, 0.2f, 0.3f), IDENT_CONF_INIT_ERR_LIMIT);
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, 0.0f), IDENT_CONF_INIT_ERR_LIMIT);
}

/* A covariance the RLS had to repair (rls_t.pd_count) says nothing: every
 * bound at its saturation, refused. */
static void test_repaired_covariance_refuses(void **state)
{
    ident_conf_t c;
    int q;
    (void)state;
    assert_int_equal(ident_conf_init(&c, 0.03f, 0.02f, 0.2f, 0.3f), IDENT_CONF_INIT_OK);
    ident_conf_eval(&c, &fx.cov, &fx.acc, 1u, &fx.end, NULL);
    for (q = 0; q < (int)IDENT_NP; q++) {
        assert_true(c.bound[q] == _IQ(IDENT_CONF_MAX));
    }
    assert_int_not_equal(c.verdict, IDENT_CONF_OK);
}

/* The one-parameter fit (the tracker's): y = 0.8 phi + e with e known:
 * sqrt(sum e^2 / sum (0.8 phi)^2) within 1e-4 relative; no signal: the
 * saturation.  rel_change: |a - b| / |a|, saturated. */
static void test_fit_and_rel_change(void **state)
{
    ident_conf_fit_t f;
    double se = 0.0, ss = 0.0;
    int k;
    (void)state;
    ident_conf_fit_reset(&f);
    assert_true(ident_conf_fit_bound(&f) == _IQ(IDENT_CONF_MAX));
    for (k = 0; k < 2000; k++) {
        double phi = 0.3 + 0.1 * sin(0.01 * k), e = 0.004 * sin(0.37 * k);
        _iq phq = d_to_iq(phi), yq = d_to_iq(0.8 * phi + e), thq = _IQ(0.8);
        double p = iq_to_d(_IQmpy(thq, phq)), r = iq_to_d(yq) - p;
        ident_conf_fit_add(&f, yq, phq, thq);
        se += r * r;
        ss += p * p;
    }
    assert_true(fabs(iq_to_d(ident_conf_fit_bound(&f)) / sqrt(se / ss) - 1.0) < 1e-4);
    assert_true(fabs(iq_to_d(ident_conf_rel_change(_IQ(2.0), _IQ(1.9))) - 0.05) < 1e-6);
    assert_true(fabs(iq_to_d(ident_conf_rel_change(_IQ(0.5), _IQ(0.51))) - 0.02) < 1e-6);
    assert_true(ident_conf_rel_change(_IQ(0.0), _IQ(1.0)) == _IQ(IDENT_CONF_MAX));
    assert_true(ident_conf_rel_change(_IQ(0.001), _IQ(0.5)) == _IQ(IDENT_CONF_MAX));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cov_factor),
        cmocka_unit_test(test_bounds_against_reference),
        cmocka_unit_test(test_drift),
        cmocka_unit_test(test_verdict_order),
        cmocka_unit_test(test_repaired_covariance_refuses),
        cmocka_unit_test(test_fit_and_rel_change),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
