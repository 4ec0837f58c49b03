/* estim_standstill_z: the lock-in measurement of sigma Ls at standstill
 * (standstill_z.h) on a synthesized R-L branch, against its closed-form
 * discrete-time answer.
 *
 * The branch (pu; time in pu, Ts_pu = 2 pi f_base Ts):
 *     i(t) = I0 + A sin(w t + phi),   w Ts_pu = 2 pi / P   (P = per_period)
 *     u(k) = the exact mean of R i + L di/dt over [t(k-1), t(k)]
 *          = R (mean of i over the period) + L (i(k) - i(k-1)) / Ts_pu.
 * With x = w Ts_pu / 2 = pi / P and m = t(k) - Ts_pu/2 (mid-period):
 *     mean of i    = I0 + A (sin x / x) sin(w m + phi)
 *     i(k) - i(k-1) = 2 A sin x cos(w m + phi)
 *     i_mid = (i(k) + i(k-1)) / 2 = I0 + A cos x sin(w m + phi)
 * The module pairs u(k) with i_mid (same instant m); as phasors at m:
 *     U = A [R sin x / x + j (2 L / Ts_pu) sin x],   I = A cos x
 *     Z = U / I = R tan(x)/x + j (2 L / Ts_pu) tan x
 * so, exactly (no approximation in x):
 *     X = Im Z = (2 L / Ts_pu) tan x,   X / w = L tan(x) / x   (w = 2x/Ts_pu)
 *     r = Re Z = R (sin x / x) / cos x = R tan(x) / x.
 * The DC part I0 and R I0 is orthogonal to the sine/cosine over whole
 * periods, so it drops out (up to the rounding below).
 *
 * Rig: 15 kHz, f_base 50 Hz, f_inj 300 Hz (P = 50, x = 0.0628, tan(x)/x =
 * 1.00132), 20 periods, I0 = 0.328 pu (the paper motor's i_M), A = 0.15 I0,
 * R = 0.595 pu (1.031 ohm), L = 0.861 pu (sigma Ls 4.75 mH). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "standstill_z.h"
#include "estim_test_util.h"

#define PI_D 3.14159265358979323846
#define TS_S (1.0f / 15000.0f)
#define FB_HZ 50.0f
#define F_INJ 300.0f
#define CYCLES 20u
#define I0_PU 0.328
#define A_PU (0.15 * I0_PU)
#define R_PU 0.595
#define L_PU 0.861

typedef struct {
    double sigma_ls, r, x;   /* module results, pu */
    uint16_t valid, done;
    uint32_t steps;          /* steps until done */
    double i_add_err;        /* max |i_add - A sin(2 pi (k mod P)/P)|, pu */
    uint16_t i_add_after;    /* i_add != 0 after done (count) */
} run_t;

/* i(t) at sample k and the exact mean of R i + L di/dt over the period
 * k-1 -> k. */
static double branch_i(double k, double P, double phi)
{
    return I0_PU + A_PU * sin(2.0 * PI_D * k / P + phi);
}

static double branch_u(double k, double P, double phi, double ts_pu)
{
    const double th1 = 2.0 * PI_D * k / P + phi, th0 = 2.0 * PI_D * (k - 1.0) / P + phi;
    const double wts = 2.0 * PI_D / P;   /* w Ts_pu, rad per sample */
    double mean_i = I0_PU + A_PU * (cos(th0) - cos(th1)) / wts;
    return R_PU * mean_i + L_PU * (branch_i(k, P, phi) - branch_i(k - 1.0, P, phi)) / ts_pu;
}

/* Run the module on the branch (amplitude scale @p a_scale of A: 0 = no
 * current), a few samples past done. */
static run_t run_branch(standstill_z_t *z, double phi, double a_scale)
{
    const double ts_pu = 2.0 * PI_D * (double)FB_HZ * (double)TS_S;
    const double P = (double)z->per_period;
    const double ampl = iq_to_d(z->ampl);
    run_t r = {0.0, 0.0, 0.0, 0u, 0u, 0u, 0.0, 0u};
    uint32_t k;

    standstill_z_start(z);
    for (k = 0u; k < (uint32_t)standstill_z_samples(z) + 10u; k++) {
        double i = I0_PU + a_scale * (branch_i((double)k, P, phi) - I0_PU);
        double u = R_PU * I0_PU + a_scale * (branch_u((double)k, P, phi, ts_pu) - R_PU * I0_PU);
        uint16_t was_done = z->done;
        z->i_m = d_to_iq(i);
        z->u_m = d_to_iq(u);
        standstill_z_step(z);
        if (was_done == 0u) {
            /* the injection of this sample: A sin(2 pi (k mod P) / P) from
             * the test's own counter; the last sample (done now) has 0 */
            double want = (z->done != 0u) ? 0.0
                                          : ampl * sin(2.0 * PI_D * (double)(k % z->per_period) / P);
            double e = fabs(iq_to_d(z->i_add) - want);
            r.i_add_err = (e > r.i_add_err) ? e : r.i_add_err;
            if (z->done != 0u) {
                r.steps = k + 1u;
            }
        } else if (z->i_add != _IQ(0.0)) {
            r.i_add_after++;
        }
    }
    /* the window ends without a result (the step divides nothing: it runs
     * in the ISR); standstill_z_finish computes it from the sums */
    assert_int_equal(z->valid, 0);
    assert_true(z->x == _IQ(0.0) && z->r == _IQ(0.0) && z->sigma_ls == _IQ(0.0));
    standstill_z_finish(z);
    r.sigma_ls = iq_to_d(z->sigma_ls);
    r.r = iq_to_d(z->r);
    r.x = iq_to_d(z->x);
    r.valid = z->valid;
    r.done = z->done;
    return r;
}

static void init_ok(standstill_z_t *z, float corr)
{
    assert_int_equal(standstill_z_init(z, TS_S, FB_HZ, F_INJ, CYCLES, (float)A_PU, corr),
                     STANDSTILL_Z_OK);
}

/* sigma Ls = L tan(x)/x and Re Z = R tan(x)/x (file comment), over 12
 * phases of the branch against the module's reference (0 .. 2 pi).
 * Budget (IQ), relative to X.  The module weighs each sample by 16/N
 * (standstill_z.c, SUM_GAIN), so |I| = 16 A cos(x)/2 = 0.39 pu = 6.6e6 LSB
 * and |U| = |Z| |I| = 3.4e7 LSB:
 *  - the products u w, i w are rounded (+-0.5 LSB each).  The data are
 *    exactly periodic in P samples, so the rounding errors repeat every
 *    period and add coherently over the 20 periods: per sum an error of
 *    cycles * (sum of P uniform +-0.5) = 41 LSB rms, 6e-6 of I per sigma,
 *    1.2e-6 of U.  Over 12 phases and 4 sums: 4 sigma, 2.5e-5 (with noisy
 *    data it would be the header's sqrt(N)/2 LSB);
 *  - the weights themselves (Q24, a pattern repeating every period):
 *    rounded, their DC weight over the window (the leak of I0 = 0.328 and
 *    R I0 into the phasors) is of the same size and included above (a
 *    truncated, biased weight leaked I0 N/2 LSB: +8e-4 measured, the bug
 *    this test found);
 *  - finish: |I|^2 = 0.15 pu^2 = 2.6e6 LSB; its truncated products bias it
 *    by 2 LSB (8e-7), the numerator alike;
 *  - inputs quantised to Q24 (1e-6), rev_step truncated (an exactly periodic
 *    reference: no effect on the ratio), 1/w (4e-7).
 * Bound on sigma Ls: 2.5e-5 + 2e-6, doubled: 5e-5.  Re Z: an error dI/I
 * rotates Z (dZ = -Z dI/I), which is |Z|/R = 8.7 times larger relative to
 * Re Z (X = 5.17, R = 0.595): 2.5e-5 |Z|/R + 1e-5, doubled.
 * FLOAT: N accumulations rounded to 24 bits (relative 6e-8 each, < 6e-5
 * in the worst case), unbiased weights, a float quotient: 1e-4 on sigma
 * Ls, 1e-4 |Z|/R on Re Z. */
#if MATH_TYPE == IQ_MATH
#define BR_LS 5e-5
#define BR_R(zr) (5e-5 * (zr) + 2e-5)
#else
#define BR_LS 1e-4
#define BR_R(zr) (1e-4 * (zr))
#endif
static void test_rl_branch(void **state)
{
    standstill_z_t z;
    uint32_t c;
    double max_ls = 0.0, max_r = 0.0;
    const double x = PI_D / 50.0;
    const double want_ls = L_PU * tan(x) / x;
    const double want_r = R_PU * tan(x) / x;
    const double zr = hypot(R_PU * tan(x) / x, 6.0 * want_ls) / R_PU;   /* |Z| / R */
    (void)state;

    init_ok(&z, 0.0f);
    assert_int_equal(z.per_period, 50u);
    for (c = 0u; c < 12u; c++) {
        const double phi = -0.7 + 2.0 * PI_D * (double)c / 12.0;
        run_t r = run_branch(&z, phi, 1.0);
        double e_ls = r.sigma_ls / want_ls - 1.0;
        double e_r = r.r / want_r - 1.0;
        print_message("phi %+.3f: sigma Ls %.7f want %.7f (rel %+.2e); Re Z %.7f want %.7f"
                      " (rel %+.2e)\n",
                      phi, r.sigma_ls, want_ls, e_ls, r.r, want_r, e_r);
        assert_int_equal(r.done, 1);
        assert_int_equal(r.valid, 1);
        assert_int_equal(r.steps, (uint32_t)standstill_z_samples(&z));
        max_ls = fmax(max_ls, fabs(e_ls));
        max_r = fmax(max_r, fabs(e_r));
    }
    print_message("max |rel err|: sigma Ls %.2e (bound %.2e), Re Z %.2e (bound %.2e)\n", max_ls,
                  BR_LS, max_r, BR_R(zr));
    assert_true(max_ls <= BR_LS);
    assert_true(max_r <= BR_R(zr));
}

/* corr > 0: the result is X/w - corr, so against the corr = 0 run on the
 * same data the difference is exactly _IQ(corr) (IQ: an integer
 * subtraction; FLOAT: one rounding of a value < 1, <= 0.5 ulp = 2^-24). */
static void test_corr_shift(void **state)
{
    standstill_z_t z0, z1;
    run_t r0, r1;
    const float corr = 0.0123f;
    (void)state;

    init_ok(&z0, 0.0f);
    init_ok(&z1, corr);
    r0 = run_branch(&z0, -0.7, 1.0);
    r1 = run_branch(&z1, -0.7, 1.0);
    assert_int_equal(r1.valid, 1);
    assert_true(z1.x == z0.x && z1.r == z0.r);
    print_message("corr %.4f: sigma Ls %.7f -> %.7f (shift %.9f)\n", (double)corr, r0.sigma_ls,
                  r1.sigma_ls, r0.sigma_ls - r1.sigma_ls);
#if MATH_TYPE == IQ_MATH
    assert_true(z0.sigma_ls - z1.sigma_ls == _IQ(corr));
#else
    assert_true(fabs((r0.sigma_ls - r1.sigma_ls) - (double)corr) <= LSB24);
#endif
    /* standstill_z_corr: the rotor-branch term of the header's model,
     * (Lm^2/Lr)/(1 + (w Tr)^2) / L_base, in double (paper motor, 300 Hz,
     * L_base 5.513 mH): float evaluation, relative 1e-6 */
    {
        const double lm = 6.4e-3, lr = 9.2e-3, rr = 0.465, lb = 5.5133e-3;
        double wtr = 2.0 * PI_D * 300.0 * lr / rr;
        double want = (lm * lm / lr) / (1.0 + wtr * wtr) / lb;
        double got = (double)standstill_z_corr(300.0f, (float)lm, (float)lr, (float)rr, (float)lb);
        assert_true(fabs(got / want - 1.0) <= 1e-6);
    }
}

/* The injection: i_add = A sin(2 pi (k mod P) / P) while running (from the
 * test's own sample counter), 0 from the sample that completes the window
 * on.  Bound: rev_step = 1/P truncated (< 1 LSB per step, < P LSB of a
 * revolution at the end of a period: 2 pi P A LSB in i_add), _IQsinPU
 * (0.52 LSB) times A, the product (1 LSB): A (2 pi P + 1) + 1 LSB. */
static void test_injection(void **state)
{
    standstill_z_t z;
    run_t r;
    (void)state;

    init_ok(&z, 0.0f);
    /* before start: not running, no injection, nothing done, no result */
    standstill_z_step(&z);
    assert_true(z.i_add == _IQ(0.0));
    assert_int_equal(z.done, 0);
    standstill_z_finish(&z);
    assert_int_equal(z.valid, 0);
    assert_true(z.x == _IQ(0.0) && z.sigma_ls == _IQ(0.0));
    r = run_branch(&z, -0.7, 1.0);
    print_message("i_add max err %.2f LSB\n", r.i_add_err / LSB24);
    assert_true(r.i_add_err <= (A_PU * (2.0 * PI_D * 50.0 + 1.0) + 1.0) * LSB24);
    assert_int_equal(r.i_add_after, 0);
    /* after done: further steps change nothing */
    {
        standstill_z_t before = z;
        z.i_m = _IQ(1.0);
        z.u_m = _IQ(-1.0);
        standstill_z_step(&z);
        assert_true(z.sigma_ls == before.sigma_ls && z.x == before.x && z.r == before.r);
        assert_true(z.us == before.us && z.is == before.is && z.k == before.k);
        assert_int_equal(z.done, 1);
        assert_true(z.i_add == _IQ(0.0));
    }
    /* a new start clears the result */
    standstill_z_start(&z);
    assert_int_equal(z.done, 0);
    assert_int_equal(z.valid, 0);
    assert_true(z.sigma_ls == _IQ(0.0));
}

/* No current follows the injection (A = 0: i = I0, u = R I0): done but
 * invalid.  The threshold: the current's amplitude at least a quarter of
 * the commanded one (the phasor sums hold half the amplitude: |I|^2 >
 * (ampl/8)^2). */
static void test_invalid(void **state)
{
    standstill_z_t z;
    run_t r;
    (void)state;

    init_ok(&z, 0.0f);
    r = run_branch(&z, -0.7, 0.0);
    assert_int_equal(r.done, 1);
    assert_int_equal(r.valid, 0);
    /* a fifth of the commanded amplitude: below the quarter */
    r = run_branch(&z, -0.7, 0.2);
    assert_int_equal(r.done, 1);
    assert_int_equal(r.valid, 0);
    /* 0.3 of it, above the quarter: valid, the same sigma Ls (the ratio
     * does not depend on the amplitude; the rounding is relative to a
     * phasor 3.3x smaller, |I|^2 11x smaller: test_rl_branch's 4e-4 / 0.3
     * + 2e-4 / 0.09 + 4e-5 / 0.3 = 3.7e-3) */
    r = run_branch(&z, -0.7, 0.3);
    assert_int_equal(r.valid, 1);
    {
        const double x = PI_D / 50.0;
        assert_true(fabs(r.sigma_ls / (L_PU * tan(x) / x) - 1.0) <= 3.7e-3);
    }
}

/* Frequency rounding: a whole number of samples per period,
 * P = round(1 / (f Ts)); the frequency used 1/(P Ts); samples = lead
 * (one period) + window (cycles periods). */
static void test_freq_rounding(void **state)
{
    static const struct {
        float f;
        uint16_t per;
    } cases[] = {
        {300.0f, 50u},   /* exact */
        {310.0f, 48u},   /* 48.39 -> 48 */
        {290.0f, 52u},   /* 51.72 -> 52 */
        {410.0f, 37u},   /* 36.59 -> 37 */
        {1400.0f, 11u},  /* 10.71 -> 11 (w = 27.3 pu, below the 30 pu limit) */
    };
    standstill_z_t z;
    uint32_t c;
    (void)state;

    for (c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        double want_f = 15000.0 / (double)cases[c].per;
        assert_int_equal(standstill_z_init(&z, TS_S, FB_HZ, cases[c].f, CYCLES, (float)A_PU, 0.0f),
                         STANDSTILL_Z_OK);
        assert_int_equal(z.per_period, cases[c].per);
        assert_int_equal(z.lead, cases[c].per);
        assert_int_equal(z.window, CYCLES * cases[c].per);
        assert_int_equal(standstill_z_samples(&z), (CYCLES + 1u) * cases[c].per);
        /* float: 1/(P Ts) to 1e-6 relative */
        assert_true(fabs((double)standstill_z_freq_Hz(&z, TS_S) / want_f - 1.0) <= 1e-6);
        /* w in pu of the rounded frequency, 1/w: Q24 (IQ: 1 LSB + float) */
        assert_true(fabs(iq_to_d(z.w) - want_f / 50.0) <= 2.0 * LSB24 + 1e-6 * want_f / 50.0);
    }
    /* not initialised: 0 Hz */
    assert_int_equal(standstill_z_init(&z, TS_S, FB_HZ, 0.0f, CYCLES, (float)A_PU, 0.0f),
                     STANDSTILL_Z_ERR_FREQ);
    assert_true(standstill_z_freq_Hz(&z, TS_S) == 0.0f);
    assert_int_equal(standstill_z_samples(&z), 0u);
}

/* The rotation recurrence of the phase's sine and cosine (standstill_z.h)
 * against double: the pair each step uses, (0, 1) at a period's start, else
 * the pair the last step turned, against (sin, cos)(2 pi ph / P), over the
 * whole test of the longest period the init allows (P = 4096 at 3.66 Hz,
 * 14 periods, the most that fit 65535 samples with the lead) and of the
 * rig's 50.  Bound (header), LSB of Q30: sqrt(2) a step from the truncated
 * products (after the sum's +1), 0.5 from the rotation's cos rounded to
 * Q30, and its float sine's 2^-22 relative (2 pi 2^-22 rad a period, 1 608
 * LSB): 2 (P - 1) + 1 608.  And the
 * recurrence must not hide a bias in it: the DC of the weights each sample
 * uses (16/N sin rounded to Q24, summed over a period: exactly 0 for the
 * exact sine) within P (0.5 LSB of Q24 + 16/N the drift).  FLOAT: no
 * recurrence, the float sine and cosine of the float phase (its rounding,
 * 2 pi 6e-8 rad, and 1 ulp): 1e-6, and the weights' DC P 16/N 1e-6. */
static void test_weight_recurrence(void **state)
{
    static const struct {
        float f;
        uint16_t cycles, per;
    } cases[] = {{15000.0f / 4096.0f, 14u, 4096u}, {F_INJ, CYCLES, 50u}};
    uint32_t c;
    (void)state;

    for (c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        standstill_z_t z;
        const double P = (double)cases[c].per;
        double w, max_e = 0.0, max_dc = 0.0, dc = 0.0, bound, bound_dc;
        uint32_t k;
        assert_int_equal(standstill_z_init(&z, TS_S, FB_HZ, cases[c].f, cases[c].cycles,
                                           (float)A_PU, 0.0f),
                         STANDSTILL_Z_OK);
        assert_int_equal(z.per_period, cases[c].per);
        w = iq_to_d(z.inv_n);
#if MATH_TYPE == IQ_MATH
        bound = (2.0 * (P - 1.0) + 1608.0) / 1073741824.0;
        bound_dc = P * (0.5 * LSB24 + w * bound);
#else
        bound = 1e-6;
        bound_dc = P * w * bound;
#endif
        standstill_z_start(&z);
        z.i_m = _IQ(0.3);
        z.u_m = _IQ(0.2);
        for (k = 0u; z.running != 0u; k++) {
            const uint16_t ph = z.ph;
#if MATH_TYPE == IQ_MATH
            const double sv = (ph == 0u) ? 0.0 : qn_to_d(z.s, 30);
            const double cv = (ph == 0u) ? 1.0 : qn_to_d(z.c, 30);
#else
            const double sv = (double)_IQsinPU(z.rev_step * (float)ph);
            const double cv = (double)_IQcosPU(z.rev_step * (float)ph);
#endif
            const double a = 2.0 * PI_D * (double)ph / P;
            double e = fmax(fabs(sv - sin(a)), fabs(cv - cos(a)));
            assert_int_equal(ph, k % cases[c].per);
            max_e = fmax(max_e, e);
            /* the Q24 weight 16/N sin used: Q30 * Q24 -> Q30, rounded to
             * Q24 (IQ); the product (FLOAT) */
#if MATH_TYPE == IQ_MATH
            dc += (double)(((int32_t)(((int64_t)((ph == 0u) ? 0 : z.s) * z.inv_n) >> 24) + 32) >>
                           6) *
                  LSB24;
#else
            dc += sv * w;
#endif
            if (ph == cases[c].per - 1u) {
                max_dc = fmax(max_dc, fabs(dc));
                dc = 0.0;
            }
            standstill_z_step(&z);
        }
        assert_int_equal(k, (uint32_t)standstill_z_samples(&z));
        print_message("P %4.0f: sin, cos max drift %.1f LSB30 (bound %.1f); the weight's DC per "
                      "period %.2f LSB24 (bound %.1f)\n",
                      P, max_e * 1073741824.0, bound * 1073741824.0, max_dc / LSB24,
                      bound_dc / LSB24);
        assert_true(max_e <= bound);
        assert_true(max_dc <= bound_dc);
    }
}

/* Every init error, the others valid; on error the module does not run
 * (done stays 0, no injection). */
static void test_init_errors(void **state)
{
    static const struct {
        float ts, fb, f;
        uint16_t cycles;
        float ampl, corr;
        standstill_z_status_t want;
    } bad[] = {
        {0.0f, FB_HZ, F_INJ, CYCLES, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},
        {TS_S, 0.0f, F_INJ, CYCLES, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},
        {TS_S, FB_HZ, -300.0f, CYCLES, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},
        {TS_S, FB_HZ, 2100.0f, CYCLES, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},   /* 7.1 -> 7 samples */
        {TS_S, FB_HZ, 3.0f, 4u, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},           /* 5000 samples */
        {TS_S, 5000.0f, 40.0f, CYCLES, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},    /* w = 0.008 pu */
        {TS_S, 1.0f, 40.0f, 4u, 0.05f, 0.0f, STANDSTILL_Z_ERR_FREQ},           /* w = 40 pu */
        {TS_S, FB_HZ, F_INJ, 3u, 0.05f, 0.0f, STANDSTILL_Z_ERR_CYCLES},
        {TS_S, FB_HZ, F_INJ, 201u, 0.05f, 0.0f, STANDSTILL_Z_ERR_CYCLES},
        {TS_S, FB_HZ, 8.0f, 200u, 0.05f, 0.0f, STANDSTILL_Z_ERR_CYCLES},      /* 1875 x 201 > 65535 */
        {TS_S, FB_HZ, F_INJ, CYCLES, 0.0f, 0.0f, STANDSTILL_Z_ERR_AMPL},
        {TS_S, FB_HZ, F_INJ, CYCLES, 0.51f, 0.0f, STANDSTILL_Z_ERR_AMPL},
        {TS_S, FB_HZ, F_INJ, CYCLES, NAN, 0.0f, STANDSTILL_Z_ERR_AMPL},
        {TS_S, FB_HZ, F_INJ, CYCLES, 0.05f, -0.01f, STANDSTILL_Z_ERR_CORR},
        {TS_S, FB_HZ, F_INJ, CYCLES, 0.05f, 1.01f, STANDSTILL_Z_ERR_CORR},
        {TS_S, FB_HZ, F_INJ, CYCLES, 0.05f, NAN, STANDSTILL_Z_ERR_CORR},
    };
    standstill_z_t z;
    uint32_t c;
    (void)state;

    for (c = 0u; c < sizeof bad / sizeof bad[0]; c++) {
        standstill_z_status_t st = standstill_z_init(&z, bad[c].ts, bad[c].fb, bad[c].f,
                                                     bad[c].cycles, bad[c].ampl, bad[c].corr);
        if (st != bad[c].want) {
            print_error("case %u: status %d want %d\n", (unsigned)c, (int)st, (int)bad[c].want);
            fail();
        }
        standstill_z_start(&z);
        z.i_m = _IQ(0.3);
        z.u_m = _IQ(0.2);
        standstill_z_step(&z);
        assert_int_equal(z.done, 0);
        assert_true(z.i_add == _IQ(0.0));
    }
    /* the edges are accepted: 8 samples (f_base 100 Hz: w = 18.75 pu), 4
     * and 200 periods, amplitude 0.5, corr 1 */
    assert_int_equal(standstill_z_init(&z, TS_S, 100.0f, 1875.0f, 4u, 0.5f, 1.0f), STANDSTILL_Z_OK);
    assert_int_equal(z.per_period, 8u);
    assert_int_equal(standstill_z_init(&z, TS_S, FB_HZ, F_INJ, 200u, 0.05f, 0.0f), STANDSTILL_Z_OK);
}

/* standstill_z_finish on sums far larger than the drive's (a current
 * phasor of 2, |I|^2 = 4): the plausibility bound |num| < 100 |I|^2 is
 * evaluated as |num| / 100 < |I|^2, inside Q24 (100 |I|^2 = 400 is not).
 * U = (R + jX) I with R 0.6, X 3: x and r exact to 1 LSB (the products of
 * the exact Q24 sums are exact, one truncating _IQdiv). */
static void test_finish_large_sums(void **state)
{
    standstill_z_t z;
    (void)state;
    init_ok(&z, 0.0f);
    z.done = 1u;
    z.is = _IQ(2.0);
    z.ic = _IQ(0.0);
    z.us = _IQ(1.2);
    z.uc = _IQ(6.0);
    standstill_z_finish(&z);
    assert_int_equal(z.valid, 1);
    assert_true(fabs(iq_to_d(z.x) - 3.0) <= LSB24);
    assert_true(fabs(iq_to_d(z.r) - 0.6) <= 2.0 * LSB24);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rl_branch),
        cmocka_unit_test(test_corr_shift),
        cmocka_unit_test(test_injection),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_finish_large_sums),
        cmocka_unit_test(test_freq_rounding),
        cmocka_unit_test(test_weight_recurrence),
        cmocka_unit_test(test_init_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
