/* app_current_model_check: the model-based current plausibility
 * (current_model_check.h) against double-precision references computed
 * here from the physics, not from the module's formulas:
 *   - a healthy R-L stator (the exact period-by-period solution for a
 *     voltage held over each period) leaves no residual;
 *   - a phase sensor that starts reading 0 A makes the residual jump by
 *     the current it hides (sigma Ls |i| lambda), and trips when that is
 *     above the level, not when below; the residual then decays by lambda;
 *   - a gain error on phase a of a balanced MEASURED current (what the
 *     current loop makes) puts the negative sequence of the true current's
 *     deviation into the residual: its size against the exact window
 *     integrals of that deviation through the leaky integrator, and the
 *     UNBALANCE verdict for e = 0.2 and e = 0.02;
 *   - an offset after the calibration: the DC the loop puts into the true
 *     current needs Rs times it, r settles at lambda V / (1 - lambda);
 *     OFFSET for 5 % of full scale, not for 1 %;
 *   - bad arguments are refused.
 * Rig (pu): the paper motor's Rs = 0.595, sigma Ls = 0.861 (Z_base
 * 1.732 ohm, L_base 5.513 mH), 15 kHz, 4 periods per slow step, f_base
 * 50 Hz; tau_r 5 ms, tau_seq 50 ms; levels r_max 0.2, k_neg 0.04, d_max
 * 0.025, ws_min 0.3. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <math.h>
#include <complex.h>
#include <cmocka.h>

#include "current_model_check.h"

#define PI_D 3.14159265358979323846
#define TS (1.0 / 15000.0)
#define WB (2.0 * PI_D * 50.0)
#define SLOTS 4u
#define RS 0.595
#define SLS 0.861
#define TAU_R 0.005
#define TAU_SEQ 0.05

static double to_d(_iq x) { return (double)_IQtoF(x); }
static _iq to_q(double x) { return _IQ((float)x); }

static void init(current_model_check_t *c, float r_max)
{
    assert_int_equal(current_model_check_init(c, (float)TS, SLOTS, (float)WB, (float)TAU_R,
                                              (float)TAU_SEQ, r_max, 0.04f, 0.025f, 0.3f),
                     CMC_OK);
    c->rs = to_q(RS);
    c->sigma_ls = to_q(SLS);
    c->psi_alpha = c->psi_beta = _IQ(0.0);
    c->active = 1u;
}

/* 1: step as the drive does (drive_slow.c): the residual at the window's
 * end, the sequence tests' halves in the next window's first and third
 * periods, between its accumulate calls; 0: current_model_check_step. */
static int g_split;

/* the half still due after the last window (split) */
static void finish(current_model_check_t *c)
{
    if (g_split != 0) {
        current_model_check_half(c, 0u);
        current_model_check_half(c, 1u);
    }
}

/* One slow step: n periods of voltage (alpha, beta) summed, then the
 * sample's measured current and angle. */
static void slow_step(current_model_check_t *c, const double complex *u, double complex i_meas,
                      double theta, double ws)
{
    unsigned k;
    for (k = 0; k < SLOTS; k++) {
        current_model_check_accumulate(c, to_q(creal(u[k])), to_q(cimag(u[k])), 1u);
        if (g_split != 0 && (k == 0u || k == 2u)) {
            current_model_check_half(c, (uint16_t)(k / 2u));
        }
    }
    c->i_alpha = to_q(creal(i_meas));
    c->i_beta = to_q(cimag(i_meas));
    c->sin_t = to_q(sin(theta));
    c->cos_t = to_q(cos(theta));
    c->ws = to_q(ws);
    if (g_split != 0) {
        current_model_check_residual(c);
    } else {
        current_model_check_step(c);
    }
}

static double r_current(const current_model_check_t *c)
{
    return cabs(to_d(c->r_alpha) + I * to_d(c->r_beta)) / SLS;
}

/* Healthy R-L stator at standstill, voltage changing period by period
 * (a 20 Hz sinusoid of 0.3 pu plus a step of 0.2 pu): exact solution
 * i(k+1) = a i(k) + (1 - a) u / Rs, a = exp(-Ts Rs / sigma Ls).  The
 * residual stays below 2e-3 pu of current (the trapezoid of the Rs i term
 * and Q24 rounding), far below any level. */
static void test_healthy_rl(void **state)
{
    current_model_check_t c;
    const double tp = WB * TS, a = exp(-tp * RS / SLS);
    double complex i = 0.0;
    double worst = 0.0;
    unsigned n, k;
    (void)state;
    init(&c, 0.2f);
    for (n = 0; n < 2000u; n++) {
        double complex u[SLOTS];
        for (k = 0; k < SLOTS; k++) {
            const double t = (double)(n * SLOTS + k) * TS;
            u[k] = 0.3 * cexp(I * 2.0 * PI_D * 20.0 * t) + ((n > 500u) ? 0.2 : 0.0);
            i = a * i + (1.0 - a) * u[k] / RS;
        }
        slow_step(&c, u, i, 0.0, 0.0);
        if (n > 2u && r_current(&c) > worst) {
            worst = r_current(&c);
        }
    }
    print_message("healthy R-L: largest |r| / sigma Ls = %.2e pu\n", worst);
    assert_true(worst < 2e-3);
    assert_int_equal(c.fault, 0u);
}

/* Phase b's sensor starts reading 0 A with the true current steady at
 * 0.3 pu along beta (ia = 0, ib = -ic = 0.26): the measured vector drops
 * to 0 while the voltage still drives the true 0.3.  The residual of that
 * window is lambda (sigma Ls 0.3 + Rs T (0.3 - (0.3 + 0)/2)): the current
 * that did not move, and the Rs i term, which the model takes as the
 * trapezoid of its two measured samples; it trips when that is above the
 * level.  Then each window adds Rs 0.3 T (the voltage explains a current
 * the measurement never shows) and r follows lambda (r + v). */
static void dead_phase(float r_max, uint16_t expect_trip)
{
    current_model_check_t c;
    const double complex i_true = 0.3 * I;
    const double complex u_dc = RS * i_true;   /* the steady voltage */
    const double lambda = exp(-(double)SLOTS * TS / TAU_R);
    const double tw = (double)SLOTS * WB * TS;   /* the window, pu time */
    double complex u[SLOTS];
    double r1, r1_ref;
    unsigned n;
    for (n = 0; n < SLOTS; n++) {
        u[n] = u_dc;
    }
    init(&c, r_max);
    for (n = 0; n < 20u; n++) {
        slow_step(&c, u, i_true, 0.0, 0.0);
    }
    assert_int_equal(c.fault, 0u);
    slow_step(&c, u, 0.0, 0.0, 0.0);   /* ia = 0 and ib = 0: the measured vector is 0 */
    r1 = r_current(&c);
    r1_ref = lambda * (SLS * 0.3 + RS * tw * 0.15) / SLS;
    print_message("dead phase: |r| / sigma Ls = %.5f pu (reference %.5f), level %.2f: %s\n",
                  r1, r1_ref, (double)r_max, c.fault ? "trip" : "no trip");
    assert_true(fabs(r1 - r1_ref) < 1e-3);
    assert_int_equal(c.fault, expect_trip);
    assert_int_equal(c.cause, expect_trip ? CMC_MISMATCH : 0u);
    for (n = 0; n < 10u; n++) {
        slow_step(&c, u, 0.0, 0.0, 0.0);
    }
    /* each window: v = Ts sum(u) - Rs T 0 - sigma Ls 0 */
    {
        double complex r = r1_ref * SLS * I;
        const double complex v = tw * u_dc;
        for (n = 0; n < 10u; n++) {
            r = lambda * (r + v);
        }
        print_message("after 10 more steps: |r| %.5f, reference %.5f\n",
                      r_current(&c) * SLS, cabs(r));
        assert_true(fabs(r_current(&c) * SLS - cabs(r)) < 1e-3);
    }
}

static void test_dead_phase_trips(void **state)
{
    (void)state;
    dead_phase(0.2f, 1u);
}

static void test_dead_phase_below_level(void **state)
{
    (void)state;
    dead_phase(0.35f, 0u);   /* 0.29 < 0.35 at the step; the Rs term then keeps it near
                                lambda Rs 0.3 T / ((1 - lambda) sigma Ls) = 0.32 */
}

/* A balanced measured current I e^{j w t} (the current loop's doing) and a
 * true current M^-1 of it (phase a's sensor reads (1 + e) ia; alpha = a,
 * beta = (a + 2 b)/sqrt(3)): the exact voltage of the true current through
 * the R-L stator, period by period (u = Rs i + sigma Ls di/dt averaged
 * over each period: Rs times the integral of the rotating phasors, sigma
 * Ls times the change).  The negative-sequence part D_n e^{-j w t} of the
 * deviation i_true - i_meas reaches the residual as the window integral
 * V_n = Rs int D_n + sigma Ls (change of D_n) through r(k) = lambda (r(k-1)
 * + v(k)): |r_n| = |lambda V_n / (1 - lambda e^{j w T})|. */
static void unbalance_allow(double e, double allow, double *neg_meas, double *neg_ref,
                            uint16_t *fault)
{
    current_model_check_t c;
    const double iamp = 0.5, w = 0.8;            /* pu current, pu speed */
    const double wr = w * WB;                    /* rad/s */
    const double T = (double)SLOTS * TS;         /* s */
    const double lambda = exp(-T / TAU_R);
    /* M^-1 for M = [[1+e, 0], [e/sqrt3, 1]] in complex form: x -> p x + q conj(x) */
    const double m11 = 1.0 / (1.0 + e), m21 = -(e / sqrt(3.0)) / (1.0 + e);
    const double complex p = 0.5 * ((m11 + 1.0) + I * (m21 - 0.0));
    const double complex q = 0.5 * ((m11 - 1.0) + I * (m21 + 0.0));
    /* i_true = p i_m + q conj(i_m); deviation d = (p - 1) i_m + q conj(i_m): its
     * negative sequence D_n = q iamp */
    const double complex dn = q * iamp;
    unsigned n, k;
    init(&c, 0.9f);
    /* the bridge allowance as E = allow / tau_r (pu), k_bridge 1 */
    assert_int_equal(current_model_check_set_bridge(&c, (float)(allow / (TAU_R * WB)), 1.0f,
                                                    (float)TAU_R, (float)WB), CMC_OK);
    for (n = 0; n < 3000u; n++) {
        double complex u[SLOTS];
        double t1 = 0.0;
        for (k = 0; k < SLOTS; k++) {
            const double t0 = (double)(n * SLOTS + k) * TS;
            const double complex e0 = cexp(I * wr * t0), e1 = cexp(I * wr * (t0 + TS));
            /* true current phasors: p iamp e^{jwt} + q iamp e^{-jwt} */
            const double complex int_pos = p * iamp * (e1 - e0) / (I * wr);
            const double complex int_neg = q * iamp * (conj(e1) - conj(e0)) / (-I * wr);
            const double complex di = p * iamp * (e1 - e0) + q * iamp * (conj(e1) - conj(e0));
            /* pu: Rs [pu ohm] x mean current; sigma Ls [pu] x di / (w_base Ts) */
            u[k] = RS * (int_pos + int_neg) / TS + SLS * di / (WB * TS);
            t1 = t0 + TS;
        }
        slow_step(&c, u, iamp * cexp(I * wr * t1), wr * t1, w);
    }
    finish(&c);
    {
        const double complex vn = RS * WB * dn * (cexp(-I * wr * T) - 1.0) / (-I * wr) +
                                  SLS * dn * (cexp(-I * wr * T) - 1.0);
        *neg_ref = cabs(lambda * vn / (1.0 - lambda * cexp(I * wr * T))) / SLS;
    }
    *neg_meas = sqrt(to_d(c.neg2)) / SLS;
    *fault = (uint16_t)((c.cause & CMC_UNBALANCE) != 0u);
}

static void unbalance(double e, double *neg_meas, double *neg_ref, uint16_t *fault)
{
    unbalance_allow(e, 0.0, neg_meas, neg_ref, fault);
}

/* The bridge allowance (current_model_check_set_bridge): k E tau_r in pu
 * flux, refused (kept) outside [0, CMC_BRIDGE_ALLOW_MAX] or NaN; added to
 * UNBALANCE's and OFFSET's levels: the 0.2 gain error's negative sequence
 * (|r_n| 0.042 pu flux here), and a 0.05 pu offset's DC part, still trip
 * with an allowance of half of it and not with one of twice it. */
static void offset_allow(double d, double allow, double *dc_meas, double *dc_ref,
                         uint16_t *fault);

static void test_bridge_allowance(void **state)
{
    current_model_check_t c;
    double m, r;
    uint16_t f;
    const double tw = TAU_R * WB;
    (void)state;
    init(&c, 0.9f);
    assert_true(c.bridge_allow == _IQ(0.0));
    assert_int_equal(current_model_check_set_bridge(&c, 0.1f, 0.01f, (float)TAU_R, (float)WB),
                     CMC_OK);
    assert_true(fabs(to_d(c.bridge_allow) - 0.01 * 0.1 * tw) < 1e-6);
    assert_int_equal(current_model_check_set_bridge(&c, -0.1f, 0.01f, (float)TAU_R, (float)WB),
                     CMC_ERR_ARG);
    assert_int_equal(current_model_check_set_bridge(&c, nanf(""), 0.01f, (float)TAU_R,
                                                    (float)WB), CMC_ERR_ARG);
    assert_int_equal(current_model_check_set_bridge(&c, (float)(0.51 / tw), 1.0f, (float)TAU_R,
                                                    (float)WB), CMC_ERR_ARG);
    assert_true(fabs(to_d(c.bridge_allow) - 0.01 * 0.1 * tw) < 1e-6);   /* kept */

    unbalance(0.2, &m, &r, &f);
    assert_int_equal(f, 1u);
    unbalance_allow(0.2, 0.5 * m * SLS, &m, &r, &f);
    print_message("gain error 0.20, allowance half its negative sequence: %s\n",
                  f ? "UNBALANCE" : "no trip");
    assert_int_equal(f, 1u);
    unbalance_allow(0.2, 2.0 * m * SLS, &m, &r, &f);
    print_message("gain error 0.20, allowance twice its negative sequence: %s\n",
                  f ? "UNBALANCE" : "no trip");
    assert_int_equal(f, 0u);

    /* OFFSET's level takes the same allowance (offset_allow: dc in units of
     * Rs tau_r w_base, the level's unit for the allowance) */
    offset_allow(0.05, 0.0, &m, &r, &f);
    assert_int_equal(f, 1u);
    offset_allow(0.05, 0.5 * m * RS * TAU_R * WB, &m, &r, &f);
    print_message("offset 0.05 pu, allowance half its DC part: %s\n", f ? "OFFSET" : "no trip");
    assert_int_equal(f, 1u);
    offset_allow(0.05, 2.0 * m * RS * TAU_R * WB, &m, &r, &f);
    print_message("offset 0.05 pu, allowance twice its DC part: %s\n", f ? "OFFSET" : "no trip");
    assert_int_equal(f, 0u);
}

static void test_unbalance(void **state)
{
    double m, r;
    uint16_t f;
    (void)state;
    unbalance(0.2, &m, &r, &f);
    print_message("gain error 0.20: negative sequence %.5f pu (reference %.5f, %+.1f %%), %s\n",
                  m, r, 100.0 * (m / r - 1.0), f ? "UNBALANCE" : "no trip");
    assert_true(fabs(m / r - 1.0) < 0.1);
    assert_int_equal(f, 1u);
    unbalance(0.02, &m, &r, &f);
    print_message("gain error 0.02: negative sequence %.5f pu (reference %.5f, %+.1f %%), %s\n",
                  m, r, 100.0 * (m / r - 1.0), f ? "UNBALANCE" : "no trip");
    assert_true(fabs(m / r - 1.0) < 0.1);
    assert_int_equal(f, 0u);
}

/* An offset d on phase a after the calibration: the loop keeps the
 * measured current a balanced I e^{jwt}, the true one is that minus
 * (d, d/sqrt3), whose DC needs Rs times it: v = -Rs (d, d/sqrt3) T per
 * step, r_dc = lambda V / (1 - lambda). */
static void offset_allow(double d, double allow, double *dc_meas, double *dc_ref,
                         uint16_t *fault)
{
    current_model_check_t c;
    const double iamp = 0.5, w = 0.8, wr = w * WB, T = (double)SLOTS * TS;
    const double lambda = exp(-T / TAU_R);
    const double complex dv = d + I * d / sqrt(3.0);
    unsigned n, k;
    init(&c, 0.9f);
    /* the bridge allowance as E = allow / tau_r (pu), k_bridge 1 */
    assert_int_equal(current_model_check_set_bridge(&c, (float)(allow / (TAU_R * WB)), 1.0f,
                                                    (float)TAU_R, (float)WB), CMC_OK);
    for (n = 0; n < 3000u; n++) {
        double complex u[SLOTS];
        double t1 = 0.0;
        for (k = 0; k < SLOTS; k++) {
            const double t0 = (double)(n * SLOTS + k) * TS;
            const double complex e0 = cexp(I * wr * t0), e1 = cexp(I * wr * (t0 + TS));
            const double complex int_i = iamp * (e1 - e0) / (I * wr) - dv * TS;
            u[k] = RS * int_i / TS + SLS * iamp * (e1 - e0) / (WB * TS);
            t1 = t0 + TS;
        }
        slow_step(&c, u, iamp * cexp(I * wr * t1), wr * t1, w);
    }
    finish(&c);
    *dc_ref = cabs(lambda * RS * dv * WB * T / (1.0 - lambda)) / (RS * TAU_R * WB);
    *dc_meas = sqrt(to_d(c.dc2)) / (RS * TAU_R * WB);
    *fault = (uint16_t)((c.cause & CMC_OFFSET) != 0u);
}

static void offset(double d, double *dc_meas, double *dc_ref, uint16_t *fault)
{
    offset_allow(d, 0.0, dc_meas, dc_ref, fault);
}

static void test_offset(void **state)
{
    double m, r;
    uint16_t f;
    (void)state;
    offset(0.05, &m, &r, &f);
    print_message("offset 0.05 pu: DC part %.5f pu of offset (reference %.5f, %+.1f %%), %s\n",
                  m, r, 100.0 * (m / r - 1.0), f ? "OFFSET" : "no trip");
    assert_true(fabs(m / r - 1.0) < 0.05);
    assert_int_equal(f, 1u);
    offset(0.01, &m, &r, &f);
    print_message("offset 0.01 pu: DC part %.5f pu of offset (reference %.5f, %+.1f %%), %s\n",
                  m, r, 100.0 * (m / r - 1.0), f ? "OFFSET" : "no trip");
    assert_true(fabs(m / r - 1.0) < 0.05);
    assert_int_equal(f, 0u);
}

/* Arguments; a window with the bridge off re-arms; reset clears. */
/* The drive's split (residual, then each half in its own ISR of the next
 * window) is the whole step, bit for bit: the same sequence components and
 * verdicts as above, against the same references. */
static void test_split_as_drive(void **state)
{
    double m0, m1, r;
    uint16_t f0, f1;
    (void)state;
    g_split = 0;
    unbalance(0.2, &m0, &r, &f0);
    g_split = 1;
    unbalance(0.2, &m1, &r, &f1);
    print_message("split, gain error 0.20: negative sequence %.5f pu (whole step %.5f)\n", m1, m0);
    assert_true(m1 == m0);
    assert_true(fabs(m1 / r - 1.0) < 0.1);
    assert_int_equal(f1, 1u);
    g_split = 0;
    offset(0.05, &m0, &r, &f0);
    g_split = 1;
    offset(0.05, &m1, &r, &f1);
    g_split = 0;
    print_message("split, offset 5 %%: DC %.5f (whole step %.5f, reference %.5f)\n", m1, m0, r);
    assert_true(m1 == m0);
    assert_true(fabs(m1 / r - 1.0) < 0.1);
    assert_int_equal(f1, f0);
    assert_int_equal(f1, 1u);
}

static void test_args_and_rearm(void **state)
{
    current_model_check_t c;
    double complex u[SLOTS] = {0.0, 0.0, 0.0, 0.0};
    (void)state;
    assert_int_equal(current_model_check_init(&c, 0.0f, 4u, (float)WB, 0.005f, 0.05f, 0.2f,
                                              0.04f, 0.025f, 0.3f), CMC_ERR_ARG);
    assert_int_equal(c.fault, 1u);
    assert_int_equal(current_model_check_init(&c, (float)TS, 9u, (float)WB, 0.005f, 0.05f,
                                              0.2f, 0.04f, 0.025f, 0.3f), CMC_ERR_ARG);
    assert_int_equal(current_model_check_init(&c, (float)TS, 4u, (float)WB, 1e-5f, 0.05f, 0.2f,
                                              0.04f, 0.025f, 0.3f), CMC_ERR_ARG);
    assert_int_equal(current_model_check_init(&c, (float)TS, 4u, (float)WB, 0.005f, 0.05f,
                                              1.0f, 0.04f, 0.025f, 0.3f), CMC_ERR_ARG);
    init(&c, 0.2f);
    slow_step(&c, u, 0.0, 0.0, 0.0);
    slow_step(&c, u, 0.9, 0.0, 0.0);   /* a jump no voltage explains */
    assert_int_equal(c.fault, 1u);
    current_model_check_reset(&c);
    assert_int_equal(c.fault, 0u);
    assert_int_equal(c.cause, 0u);
    /* a window with a period off: no judgement, the next one starts there */
    current_model_check_accumulate(&c, 0, 0, 0u);
    c.i_alpha = _IQ(0.5);
    current_model_check_step(&c);
    assert_int_equal(c.fault, 0u);
    slow_step(&c, u, 0.5, 0.0, 0.0);   /* 0.5 pu steady with no voltage: Rs 0.5 T unexplained */
    assert_true(fabs(r_current(&c) -
                     exp(-(double)SLOTS * TS / TAU_R) * RS * 0.5 * SLOTS * WB * TS / SLS) < 1e-3);
    assert_int_equal(c.fault, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_healthy_rl),
        cmocka_unit_test(test_dead_phase_trips),
        cmocka_unit_test(test_dead_phase_below_level),
        cmocka_unit_test(test_unbalance),
        cmocka_unit_test(test_bridge_allowance),
        cmocka_unit_test(test_offset),
        cmocka_unit_test(test_split_as_drive),
        cmocka_unit_test(test_args_and_rearm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
