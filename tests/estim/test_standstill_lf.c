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
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "estim_test_util.h"
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
                                        (float)IM, 4.0f, 3u),
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
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, (float)a, (float)IM, 1.0f, 3u),
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

/* The ramp (standstill_lf_fast): over the 8 fast periods after each slow
 * sample the injection goes linearly from the last sample's value to the
 * new one, against that interpolation in double within 8 LSB (each step
 * rounded: 1/2 LSB a period, 4 at a ramp's end, which the next ramp starts
 * from); the slow sample's own value after the 8th period within 4 LSB; 0
 * before the first sample and after the test. */
static void test_ramp(void **state)
{
    standstill_lf_t z;
    const double a = 0.25 * IM;
    double prev = 0.0, worst = 0.0, worst_end = 0.0;
    uint32_t k;
    uint16_t n;
    (void)state;
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.05f, (float)a, (float)IM, 0.2f, 3u),
                     STANDSTILL_LF_OK);
    standstill_lf_start(&z);
    assert_true(iq_to_d(standstill_lf_fast(&z)) == 0.0);
    for (k = 0u; k < standstill_lf_samples(&z); k++) {
        double next;
        standstill_lf_step(&z);
        next = iq_to_d(z.i_add);
        for (n = 1u; n <= 8u; n++) {
            const double got = iq_to_d(standstill_lf_fast(&z));
            if (z.done == 0u) {
                worst = fmax(worst, fabs(got - (prev + (next - prev) * (double)n / 8.0)));
            }
        }
        if (z.done == 0u) {
            worst_end = fmax(worst_end, fabs(iq_to_d(z.i_ref) - next));
        }
        prev = next;
    }
    assert_int_equal(z.done, 1u);
    assert_true(iq_to_d(standstill_lf_fast(&z)) == 0.0);
#if MATH_TYPE == IQ_MATH
    assert_true(worst <= 8.0 * LSB24);
    assert_true(worst_end <= 4.0 * LSB24);
#else
    assert_true(worst < 1e-6 && worst_end < 1e-6);
#endif
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.05f, (float)a, (float)IM, 0.2f, 4u),
                     STANDSTILL_LF_ERR_HOLD);
}

/* The test in its loop (why the ramp; standstill_lf.h, Hold).  The paper's
 * motor at standstill (Rs 1.031, Rr 0.465 ohm, Lm 6.4, Lls = Llr 2.8 mH:
 * sigma Ls 4.75 mH, L_M 4.45 mH, Tr 19.8 ms; bases 60/sqrt 3 V, 20 A,
 * 2 pi 50 rad/s), in double: its M axis (stator current i, the inverse-
 * Gamma branch's current i_mu) exactly discretised over a PWM period at 15
 * kHz under a held voltage (the averaged bridge), its current PI as the
 * drive designs it (500 Hz: kp = w_c sigma Ls, ki = kp Ts Rs / sigma Ls),
 * the duty computed in period k applied in period k+1, u_k the voltage of
 * the period that ends at i_k's sample; the window means of 8 u_k and 8
 * i_k (closed at slot 1), the lock-in stepped at slot 4 on the last
 * window (drive_slow.c's slots; the regression's Butterworth, one linear
 * filter on both, left out: it cancels in U/I).  The plant starts in the
 * test's periodic steady state (two fundamental periods, 25 Tr, of the
 * same injection first): no lead transient.  Against Z(jw) in closed form:
 *   - the injection ramped (standstill_lf_fast): each Z within 5e-5 of it
 *     (measured 1.2e-5 (FLOAT) / 1.6e-5 (IQ) at the 4th harmonic: the
 *     ramp's images, of order (w Ts)^3; the ZOH's own (w Ts)^2 / 24 =
 *     2e-6); the misfit below 3e-5, Tr and Lm within 0.04 % (measured
 *     1.1e-5 / 1.4e-5, -0.013 / -0.017 %, -0.007 / -0.008 %; the RLS's
 *     prior not given back (standstill_fit.h) 4.5e-5, -0.08 %, -0.07 %);
 *   - the sample's value held over the 8 periods (the drive before): the
 *     4th harmonic's Z off by more than 1e-3 (measured 1.8e-3; the model's
 *     5.25 (w Ts)^2 w_c sigma Ls / |Z| = 2.7e-3 bounds it) and the misfit
 *     above 5e-4 (measured 1.2e-3): what the ramp removes. */
#define CL_F_PWM 15000.0
#define CL_RS 1.031
#define CL_RR 0.465
#define CL_LM 6.4e-3
#define CL_LL 2.8e-3
#define CL_IM 6.5625
#define CL_BW_HZ 500.0
#define CL_V_BASE (60.0 / 1.7320508075688772)
#define CL_I_BASE 20.0

typedef struct {
    double ad[2][2], bd[2];   /* the period's map under a held voltage */
    double x[2];              /* i, i_mu (A) */
    double kp, ki, ui;        /* the PI (V/A, V/A per period, V) */
    double v_next, v_now;     /* the voltages computed one and two periods ago */
    double su, si;            /* the window's sums */
} cl_loop_t;

/* e^{M h} of the 3x3 [A B; 0 0] by scaling and squaring (Taylor to 20 terms) */
static void cl_discretise(cl_loop_t *c, double sls, double lmm, double rrr, double ts)
{
    double m[3][3] = {{-(CL_RS + rrr) / sls, rrr / sls, 1.0 / sls},
                      {rrr / lmm, -rrr / lmm, 0.0},
                      {0.0, 0.0, 0.0}};
    double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double t[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int i, j, k, n, sq = 10;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            m[i][j] *= ts / 1024.0;
        }
    }
    for (n = 1; n <= 20; n++) {
        double u[3][3];
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                u[i][j] = 0.0;
                for (k = 0; k < 3; k++) {
                    u[i][j] += t[i][k] * m[k][j] / (double)n;
                }
            }
        }
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                t[i][j] = u[i][j];
                e[i][j] += u[i][j];
            }
        }
    }
    while (sq-- > 0) {
        double u[3][3];
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                u[i][j] = 0.0;
                for (k = 0; k < 3; k++) {
                    u[i][j] += e[i][k] * e[k][j];
                }
            }
        }
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                e[i][j] = u[i][j];
            }
        }
    }
    for (i = 0; i < 2; i++) {
        c->ad[i][0] = e[i][0];
        c->ad[i][1] = e[i][1];
        c->bd[i] = e[i][2];
    }
}

/* One PWM period: sample, the window's sums, the PI on the reference
 * i_M + inj (A), the plant over the period under the voltage computed
 * one period ago. */
static void cl_period(cl_loop_t *c, double inj)
{
    const double i = c->x[0];
    const double e = CL_IM + inj - i;
    const double v = c->v_next;
    double x0, x1;
    c->su += c->v_now;   /* the voltage of the period that just ended */
    c->si += i;
    c->ui += c->ki * e;
    c->v_now = c->v_next;
    c->v_next = c->kp * e + c->ui;
    x0 = c->ad[0][0] * c->x[0] + c->ad[0][1] * c->x[1] + c->bd[0] * v;
    x1 = c->ad[1][0] * c->x[0] + c->ad[1][1] * c->x[1] + c->bd[1] * v;
    c->x[0] = x0;
    c->x[1] = x1;
}

/* @p n slow samples of @p z in the loop: 8 periods each, the window closed
 * after slot 1, the lock-in stepped after slot 4; the injection ramped
 * (@p ramp) or the sample's value held. */
static void cl_run(cl_loop_t *c, standstill_lf_t *z, uint32_t n, int ramp)
{
    uint32_t k;
    uint16_t slot;
    for (k = 0u; k < n; k++) {
        for (slot = 0u; slot < 8u; slot++) {
            const double inj = ramp ? iq_to_d(standstill_lf_fast(z)) : iq_to_d(z->i_add);
            cl_period(c, inj * CL_I_BASE);
            if (slot == 1u) {
                z->u_m = d_to_iq(c->su / 8.0 / CL_V_BASE);
                z->i_m = d_to_iq(c->si / 8.0 / CL_I_BASE);
                c->su = c->si = 0.0;
            } else if (slot == 4u) {
                standstill_lf_step(z);
            }
        }
    }
}

static void closed_loop(int ramp, double err[3], standstill_fit_t *f)
{
    static const double k_nu_d[3] = {1.0, 2.0, 4.0};
    const double ts = 1.0 / CL_F_PWM, w_base = 2.0 * PI_D * 50.0;
    const double ls = CL_LM + CL_LL, lmm = CL_LM * CL_LM / ls, sls = ls - lmm, tr = ls / CL_RR;
    const double z_base = CL_V_BASE / CL_I_BASE, l_base = z_base / w_base;
    const double ampl = 0.25 * CL_IM / CL_I_BASE, im = CL_IM / CL_I_BASE;
    static cl_loop_t c;
    static standstill_lf_t pre, z;
    standstill_fit_in_t in;
    double w1;
    int n;

    memset(&c, 0, sizeof c);
    cl_discretise(&c, sls, lmm, lmm / tr, ts);
    c.kp = 2.0 * PI_D * CL_BW_HZ * sls;
    c.ki = c.kp * ts * CL_RS / sls;
    c.x[0] = c.x[1] = CL_IM;
    c.ui = c.v_next = c.v_now = CL_RS * CL_IM;
    assert_int_equal(standstill_lf_init(&pre, (float)(8.0 * ts), (float)tr, (float)ampl, (float)im,
                                        1.0f, 3u), STANDSTILL_LF_OK);
    z = pre;
    /* two fundamental periods (25 Tr) of the injection: the periodic steady
     * state; then the test, its ramp continuing where this one is */
    standstill_lf_start(&pre);
    cl_run(&c, &pre, 2u * pre.per, ramp);
    standstill_lf_start(&z);
    z.i_ref = pre.i_ref;
    z.i_add = pre.i_add;
    cl_run(&c, &z, standstill_lf_samples(&z), ramp);
    assert_int_equal(z.done, 1u);
    w1 = 2.0 * PI_D / ((double)z.per * 8.0 * ts);
    in.w1_pu = (float)(w1 / w_base);
    in.half_ts_pu = (float)(0.5 * ts * w_base);
    in.sigma_ls_pu = (float)(sls / l_base);
    in.im_pu = (float)im;
    assert_int_equal(standstill_fit(f, &z, &in, &g_rls), STANDSTILL_FIT_OK);
    for (n = 0; n < 3; n++) {
        const double w = k_nu_d[n] * w1;
        const double d = 1.0 + w * w * tr * tr;
        const double r = (CL_RS + w * lmm * w * tr / d) / z_base;
        const double x = (w * sls + w * lmm / d) / z_base;
        const double rm = (double)f->r[n];
        const double xm = (double)f->x[n] + (w / w_base) * (sls / l_base);   /* X_r + w sigma Ls */
        err[n] = sqrt(((rm - r) * (rm - r) + (xm - x) * (xm - x)) / (r * r + x * x));
    }
}

static void test_closed_loop_ramp(void **state)
{
    const double ls = CL_LM + CL_LL, tr = ls / CL_RR;
    const double w_base = 2.0 * PI_D * 50.0;
    double err[3], err_held[3];
    standstill_fit_t f, fh;
    (void)state;
    closed_loop(1, err, &f);
    closed_loop(0, err_held, &fh);
    printf("closed loop, Z error at nu = 1, 2, 4: ramp %.2e %.2e %.2e (misfit %.2e), held "
           "%.2e %.2e %.2e (misfit %.2e); ramp Tr %+.4f %%, Lm %+.4f %%\n",
           err[0], err[1], err[2], (double)f.residual, err_held[0], err_held[1], err_held[2],
           (double)fh.residual, 100.0 * ((double)f.p[SSFIT_TR] / (tr * w_base) - 1.0),
           100.0 * ((double)f.p[SSFIT_LM] * CL_V_BASE / CL_I_BASE / w_base / CL_LM - 1.0));
    assert_true(err[0] < 5e-5 && err[1] < 5e-5 && err[2] < 5e-5);
    assert_true(f.residual < 3e-5f);
    expect_near((double)f.p[SSFIT_TR], tr * w_base, 4e-4, "Tr");
    expect_near((double)f.p[SSFIT_LM] * CL_V_BASE / CL_I_BASE / w_base, CL_LM, 4e-4, "Lm");
    assert_true(err_held[2] > 1e-3);
    assert_true(fh.residual > 5e-4f);
}

/* The fit is the batch least-squares fit of its rows (standstill_fit.h:
 * the RLS's prior given back), where the prior would pull most: the paper
 * motor's points (pu, as test_closed_loop_ramp's; lambda_min of the
 * rows 1.5e-3), each Z turned by a misfit the model cannot take (a
 * relative e_n = 1e-3 (nu/4)^2 (-2 + j), the held injection's shape).
 * The reference: the same six rows (R = Rs + (w1 Tr)(nu X_r), X_r =
 * -(w1 Tr)(nu R) + w1 (L_M + Tr Rs) nu) solved by the normal equations in
 * double (Cramer).  Rs, Tr, Lm within 2e-5 of it, the misfit within 2 %
 * (measured 6e-6 IQ / 6e-7 FLOAT: the rows' Q24 / float entries through
 * the conditioning; from P(0) = 1e6 without the give-back Tr was 4e-4 /
 * 1.1e-3 off, with it 3e-4 / 4e-4: the RLS's own rounding). */
static void test_fit_is_batch(void **state)
{
    static const double nu[3] = {1.0, 2.0, 4.0};
    const double w_base = 2.0 * PI_D * 50.0, z_base = CL_V_BASE / CL_I_BASE;
    const double l_base = z_base / w_base;
    const double ls = (CL_LM + CL_LL) / l_base, lmm = CL_LM * CL_LM / (CL_LM + CL_LL) / l_base;
    const double sls = ls - lmm, tr = ls / (CL_RR / z_base), rs = CL_RS / z_base;
    const double w1 = 0.0804721;   /* pu: w1 Tr = 0.5 */
    double a[3][3] = {{0}}, b[3] = {0}, th[3], det, rr[3], xr[3], e2 = 0.0, y2 = 0.0;
    standstill_lf_t z;
    standstill_fit_in_t in;
    standstill_fit_t f;
    int n, i, j;
    (void)state;
    memset(&z, 0, sizeof z);
    z.done = 1u;   /* the sums below, both halves alike; half = 0: no bias to give back */
    for (n = 0; n < 3; n++) {
        const double w = nu[n] * w1, d = 1.0 + w * w * tr * tr;
        const double er = -2e-3 * (nu[n] / 4.0) * (nu[n] / 4.0), ei = 1e-3 * (nu[n] / 4.0) * (nu[n] / 4.0);
        const double r0 = rs + w * lmm * w * tr / d, x0 = w * sls + w * lmm / d;
        const double r = r0 * (1.0 + er) - x0 * ei, x = x0 * (1.0 + er) + r0 * ei;
        int h;
        rr[n] = r;
        xr[n] = x - w * sls;
        for (h = 0; h < 2; h++) {
            /* I = 1 (sum_c), U = Z: sum_c = Re U, sum_s = -Im U */
            z.sum[h][n][SSLF_UC] = d_to_iq(0.5 * r);
            z.sum[h][n][SSLF_US] = d_to_iq(-0.5 * x);
            z.sum[h][n][SSLF_IC] = d_to_iq(0.5);
            z.sum[h][n][SSLF_IS] = d_to_iq(0.0);
        }
    }
    in.w1_pu = (float)w1;
    in.half_ts_pu = 0.0f;
    in.sigma_ls_pu = (float)sls;
    in.im_pu = 0.33f;
    assert_int_equal(standstill_fit(&f, &z, &in, &g_rls), STANDSTILL_FIT_OK);
    /* the reference: theta = [Rs, w1 Tr, w1 (L_M + Tr Rs)] from the rows */
    for (n = 0; n < 3; n++) {
        const double p1[3] = {1.0, nu[n] * xr[n], 0.0}, p2[3] = {0.0, -nu[n] * rr[n], nu[n]};
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                a[i][j] += p1[i] * p1[j] + p2[i] * p2[j];
            }
            b[i] += p1[i] * rr[n] + p2[i] * xr[n];
        }
    }
    det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
          a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
          a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (i = 0; i < 3; i++) {
        double m[3][3];
        int k;
        for (j = 0; j < 3; j++) {
            for (k = 0; k < 3; k++) {
                m[j][k] = (k == i) ? b[j] : a[j][k];
            }
        }
        th[i] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
    }
    for (n = 0; n < 3; n++) {
        const double e1 = rr[n] - (th[0] + th[1] * nu[n] * xr[n]);
        const double e2r = xr[n] - (-th[1] * nu[n] * rr[n] + th[2] * nu[n]);
        e2 += e1 * e1 + e2r * e2r;
        y2 += rr[n] * rr[n] + xr[n] * xr[n];
    }
    {
        const double tr_ls = th[1] / w1, lmm_ls = th[2] / w1 - tr_ls * th[0];
        const double lm_ls = sqrt(lmm_ls * (sls + lmm_ls));
        expect_near((double)f.p[SSFIT_RS], th[0], 2e-5, "Rs");
        expect_near((double)f.p[SSFIT_TR], tr_ls, 2e-5, "Tr");
        expect_near((double)f.p[SSFIT_LM], lm_ls, 2e-5, "Lm");
        expect_near((double)f.residual, sqrt(e2 / y2), 2e-2, "misfit");
        /* the misfit is the perturbation's, not nothing: the test sees the fit move */
        assert_true(sqrt(e2 / y2) > 1e-4);
    }
}

static void test_init_errors(void **state)
{
    standstill_lf_t z;
    standstill_fit_t f;
    standstill_fit_in_t in = {0.01f, 0.0f, 0.0f, 0.3f};   /* sigma Ls 0 */
    (void)state;
    assert_int_equal(standstill_lf_init(&z, 0.0f, 0.2f, 0.05f, 0.3f, 1.0f, 3u),
                     STANDSTILL_LF_ERR_TIME);
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 1e-3f, 0.05f, 0.3f, 1.0f, 3u),
                     STANDSTILL_LF_ERR_TIME);   /* 12 samples per period */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.1f, 0.3f, 1.0f, 3u),
                     STANDSTILL_LF_ERR_AMPL);   /* 0.1 > 0.3 i_M */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.05f, 0.3f, 1e6f, 3u),
                     STANDSTILL_LF_ERR_WINDOW);
    assert_int_equal(z.per, 0u);
    standstill_lf_start(&z);
    assert_int_equal(z.running, 0u);   /* an init that failed never runs */
    assert_int_equal(standstill_lf_init(&z, (float)TS_SLOW, 0.2f, 0.05f, 0.3f, 1.0f, 3u),
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
        cmocka_unit_test(test_ramp),
        cmocka_unit_test(test_closed_loop_ramp),
        cmocka_unit_test(test_fit_is_batch),
        cmocka_unit_test(test_init_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
