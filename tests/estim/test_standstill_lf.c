/* estim_standstill_lf: the standstill sequence's multisine lock-in
 * (standstill_lf.h) and its fit (standstill_fit.h) on a synthesized
 * standstill motor, against the model's closed form in double.
 *
 * The motor (pu; time in pu of 1/w_base, w_base = 2 pi 50): Rs 0.04, Rr
 * 0.035, Lm 2.2, Lls = Llr 0.09 (Ls = Lr 2.29: sigma Ls 0.1765, L_M 2.1135,
 * Tr 65.43 pu = 0.208 s), i_M 0.33.  Its M-axis impedance at standstill is
 *     Z(jw) = Rs + jw sigma Ls + jw L_M / (1 + jw Tr)
 * (method §1 at w_r = 0; what the T circuit gives, exactly).  The inputs
 * are its steady state under the injection, sampled at the slow task's
 * rate (1.875 kHz): i = I0 + a sum sin(n w1 t), u = U0 + a sum |Z_n|
 * sin(n w1 t + arg Z_n); U0 = 0.05 pu (Rs I0 plus a bridge error the
 * lock-in must reject).  The believed Tr is 1.3 the true one (the lock-in's
 * frequencies follow the belief, not the truth). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <math.h>
#include <cmocka.h>

#include "standstill_fit.h"
#include "standstill_lf.h"

#define PI_D 3.14159265358979323846
#define W_BASE (2.0 * PI_D * 50.0)
#define TS_SLOW (8.0 / 15000.0)
#define RS 0.04
#define RR 0.035
#define LM 2.2
#define LL 0.09
#define IM 0.33
#define U0 0.05

typedef struct {
    double ls, lr, sls, lmm, tr;   /* pu */
} motor_t;

static rls_t g_rls;   /* the fit's work instance */

static motor_t motor(void)
{
    motor_t m;
    m.ls = LM + LL;
    m.lr = LM + LL;
    m.sls = m.ls - LM * LM / m.lr;
    m.lmm = LM * LM / m.lr;
    m.tr = m.lr / RR;
    return m;
}

/* Z at w (pu) */
static void z_of(const motor_t *m, double w, double *r, double *x)
{
    /* jw L_M / (1 + jw Tr) = w L_M (w Tr + j) / (1 + (w Tr)^2) */
    const double d = 1.0 + w * w * m->tr * m->tr;
    *r = RS + w * m->lmm * w * m->tr / d;
    *x = w * m->sls + w * m->lmm / d;
}

/* Runs the test on the synthetic motor with @p noise (pu rms, a fixed
 * pseudo-random sequence on u and i); returns the fit. */
static standstill_fit_status_t run(standstill_fit_t *f, double noise, uint32_t seed,
                                   standstill_lf_t *zo)
{
    const motor_t m = motor();
    const double tr_s = m.tr / W_BASE;
    standstill_lf_t z;
    standstill_fit_in_t in;
    double w1, a;
    uint32_t k, n_all;

    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, (float)(1.3 * tr_s), (float)(0.25 * IM),
                                        (float)IM, 4.0f),
                     STANDSTILL_LF_OK);
    w1 = 2.0 * PI_D / ((double)z.per * TS_SLOW);   /* rad/s */
    a = 0.25 * IM;
    standstill_lf_start(&z);
    n_all = standstill_lf_samples(&z);
    for (k = 0u; k < n_all; k++) {
        double u = U0, i = IM;
        int h;
        for (h = 0; h < 3; h++) {
            const double mult = (h == 0) ? 1.0 : ((h == 1) ? 2.0 : 4.0);
            const double ph = 2.0 * PI_D * mult * (double)(k % z.per) / (double)z.per;
            double r, x;
            z_of(&m, mult * w1 / W_BASE, &r, &x);
            i += a * sin(ph);
            u += a * (r * sin(ph) + x * cos(ph));   /* Im(Z a e^{j ph}) */
        }
        if (noise > 0.0) {
            /* two uniform draws (rms noise): a linear congruential sequence */
            seed = seed * 1664525u + 1013904223u;
            u += noise * 3.4641 * ((double)(seed >> 8) / 16777216.0 - 0.5);
            seed = seed * 1664525u + 1013904223u;
            i += noise * 3.4641 * ((double)(seed >> 8) / 16777216.0 - 0.5);
        }
        z.u_m = _IQ(u);
        z.i_m = _IQ(i);
        standstill_lf_step(&z);
    }
    assert_int_equal(z.done, 1u);
    in.w1_pu = (float)(w1 / W_BASE);
    in.half_ts_pu = 0.0f;
    in.sigma_ls_pu = (float)m.sls;
    in.im_pu = (float)IM;
    if (zo != NULL) {
        *zo = z;
    }
    return standstill_fit(f, &z, &in, &g_rls);
}

static void expect_near(double got, double want, double rel, const char *what)
{
    double e = fabs(got / want - 1.0);
    if (e > rel) {
        fail_msg("%s: %.6g against %.6g (%.4f %% > %.4f %%)", what, got, want, 100.0 * e,
                 100.0 * rel);
    }
}

/* Noiseless: every parameter within 0.05 % of the motor's.  What is left
 * is fixed point: the sums' rounding (about sqrt(N)/2 LSB of a sum of
 * ~0.3e7 LSB: 1e-5) and the RLS's Q24 rows and Q26 state, through the
 * fit's conditioning (measured: below 0.01 %; 0.05 % leaves 5x). */
static void test_exact_motor(void **state)
{
    const motor_t m = motor();
    standstill_fit_t f;
    (void)state;
    assert_int_equal(run(&f, 0.0, 1u, NULL), STANDSTILL_FIT_OK);
    expect_near(f.p[SSFIT_RS], RS, 5e-4, "Rs");
    expect_near(f.p[SSFIT_TR], m.tr, 5e-4, "Tr");
    expect_near(f.p[SSFIT_RR], RR, 5e-4, "Rr");
    expect_near(f.p[SSFIT_LM], LM, 5e-4, "Lm");
    expect_near(f.p[SSFIT_LR], m.lr, 5e-4, "Lr");
    expect_near(f.p[SSFIT_PSI], LM * IM, 5e-4, "psi_r");
    /* a model the data fit: the residual and the halves' spread tiny */
    assert_true(f.residual < 1e-4f);
    assert_true(f.conf[SSFIT_RR] < STANDSTILL_FIT_CONF_FLOOR + 1e-3f);
}

/* With noise (2e-4 pu rms on u and i in every slow sample, unfiltered:
 * the drive's signals pass the regression's 10 Hz filter first): each
 * result within its own confidence figure, and every figure below 3 % (the
 * publication's limit). */
static void test_noise_within_confidence(void **state)
{
    const motor_t m = motor();
    const double want[SSFIT_NP] = {RS, RR, LM, m.lr, LM * IM, m.tr};
    standstill_fit_t f;
    uint16_t j;
    (void)state;
    assert_int_equal(run(&f, 2e-4, 12345u, NULL), STANDSTILL_FIT_OK);
    for (j = 0u; j < SSFIT_NP; j++) {
        const double e = fabs((double)f.p[j] / want[j] - 1.0);
        if (!(e <= (double)f.conf[j]) || !(f.conf[j] < 0.03f)) {
            fail_msg("parameter %u: error %.4f %%, confidence %.4f %%", j, 100.0 * e,
                     100.0 * (double)f.conf[j]);
        }
    }
}

/* The fit's standard deviations are the results' own: over 40 noise
 * sequences (5e-4 pu rms) the spread of each parameter against the mean
 * of its predicted standard deviation, within 35 % (the sample standard
 * deviation of 40 draws is within +-22 % of the true one at 95 %; the
 * predicted one rests on three degrees of freedom per run, averaged). */
static void test_deviation_matches_spread(void **state)
{
    const motor_t m = motor();
    const double want[SSFIT_NP] = {RS, RR, LM, m.lr, LM * IM, m.tr};
    double s1[SSFIT_NP] = {0}, s2[SSFIT_NP] = {0}, pred[SSFIT_NP] = {0};
    standstill_fit_t f;
    uint32_t q;
    uint16_t j;
    (void)state;
    for (q = 0u; q < 40u; q++) {
        assert_int_equal(run(&f, 5e-4, 1000u + 7919u * q, NULL), STANDSTILL_FIT_OK);
        for (j = 0u; j < SSFIT_NP; j++) {
            const double e = (double)f.p[j] / want[j] - 1.0;
            s1[j] += e;
            s2[j] += e * e;
            pred[j] += (double)f.sd[j] / 40.0;
        }
    }
    for (j = 0u; j < SSFIT_NP; j++) {
        const double mean = s1[j] / 40.0;
        const double sd = sqrt(s2[j] / 40.0 - mean * mean);
        if (fabs(pred[j] / sd - 1.0) > 0.35) {
            fail_msg("parameter %u: spread %.4f %%, predicted %.4f %%", j, 100.0 * sd,
                     100.0 * pred[j]);
        }
    }
}

/* The injection: a sum sin(2 pi n ph / per) for n = 1, 2, 4, to Q24's
 * sine within 4 LSB per harmonic; 0 after the test. */
static void test_injection(void **state)
{
    standstill_lf_t z;
    uint32_t k;
    double a = 0.25 * IM, worst = 0.0;
    (void)state;
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, (float)a, (float)IM, 1.0f),
                     STANDSTILL_LF_OK);
    standstill_lf_start(&z);
    for (k = 0u; k < standstill_lf_samples(&z); k++) {
        const double ph = 2.0 * PI_D * (double)(k % z.per) / (double)z.per;
        const double want = a * (sin(ph) + sin(2.0 * ph) + sin(4.0 * ph));
        standstill_lf_step(&z);
        if (z.done == 0u) {
            worst = fmax(worst, fabs((double)_IQtoF(z.i_add) - want));
        }
    }
    assert_int_equal(z.done, 1u);
    assert_true(_IQtoF(z.i_add) == 0.0f);
    assert_true(worst < 12.0 / 16777216.0 + 1e-6);
    standstill_lf_step(&z);   /* done: nothing more */
    assert_true(_IQtoF(z.i_add) == 0.0f);
}

static void test_init_errors(void **state)
{
    standstill_lf_t z;
    standstill_fit_t f;
    standstill_fit_in_t in = {0.01f, 0.0f, 0.0f, 0.3f};   /* sigma Ls 0 */
    (void)state;
    assert_int_equal(standstill_lf_init(&z, 0.0f, 0.2f, 0.05f, 0.3f, 1.0f),
                     STANDSTILL_LF_ERR_TIME);
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 1e-3f, 0.05f, 0.3f, 1.0f),
                     STANDSTILL_LF_ERR_TIME);   /* 12 samples per period */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.1f, 0.3f, 1.0f),
                     STANDSTILL_LF_ERR_AMPL);   /* 0.1 > 0.3 i_M */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.05f, 0.3f, 1e6f),
                     STANDSTILL_LF_ERR_WINDOW);
    assert_int_equal(z.per, 0u);
    standstill_lf_start(&z);
    assert_int_equal(z.running, 0u);   /* an init that failed never runs */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.05f, 0.3f, 1.0f),
                     STANDSTILL_LF_OK);
    assert_int_equal(standstill_fit(&f, &z, &in, &g_rls), STANDSTILL_FIT_ERR_INPUT);
    in.sigma_ls_pu = 0.2f;
    /* never run: every current phasor zero */
    assert_int_equal(standstill_fit(&f, &z, &in, &g_rls), STANDSTILL_FIT_ERR_CURRENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_motor),
        cmocka_unit_test(test_noise_within_confidence),
        cmocka_unit_test(test_deviation_matches_spread),
        cmocka_unit_test(test_injection),
        cmocka_unit_test(test_init_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
