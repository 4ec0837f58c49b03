/* estim_tr_track: the scalar forgetting RLS on 1/Tr (tr_track.h).
 *
 * Data: the rotor-flux frame on the alpha axis, psi = (psi0, 0), stator
 * current i = (i_M, i_T(t)) and the slip of the rotor equation
 *     w_sl = theta_true i_T / i_M,
 * so psi.i = psi0 i_M, psi x i = psi0 i_T and
 *     y = w_sl (psi.i) = theta_true psi0 i_T = theta_true phi   (exact).
 * References, independent of the module's code:
 *  - theta_true itself (convergence, clamps);
 *  - a double-precision reimplementation of the documented algorithm
 *    (input clamps, first-order low-pass of y and phi, decimation, scalar
 *    RLS with forgetting lambda = 1 - decim Ts / memory, wind-up guard
 *    |phi| >= phi_min, phi clamped to +-2, e to +-8, theta to its range, P
 *    to [1e-6, 4], P(0) = min((1 - lambda)/phi_min^2, 4)), with its own
 *    constants computed in double from the same init arguments, fed the
 *    same (Q24-quantised) inputs;
 *  - the steady lag of a ramp through an exponentially-forgetting
 *    estimator, in closed form (test_ramp).
 * Rig (the drive's, drive_adapt.c): 15 kHz, RLS every 15 samples (1 kHz),
 * low-pass 10 Hz, memory 0.5 s, phi_min 0.02; paper motor: Tr = 6.2141 pu
 * (theta = 0.161), psi0 = Lm i_M = 0.381 pu, i_M = 0.328 pu; theta range
 * [0.25, 4] / Tr. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "tr_track.h"
#include "estim_test_util.h"

#define PI_D 3.14159265358979323846
#define TS_S (1.0f / 15000.0f)
#define DECIM 15u
#define LPF_HZ 10.0f
#define MEM_S 0.5f
#define PHI_MIN 0.02f
#define TR_PU 6.2141
#define TH_NOM (1.0 / TR_PU)
#define TH_MIN ((float)(0.25 / TR_PU))
#define TH_MAX ((float)(4.0 / TR_PU))
#define PSI0 0.381
#define I_M 0.328

/* ---- the double reference ---------------------------------------------- */
typedef struct {
    double kf, lam, pmax, p0, pmin, phimin, tmin, tmax;
    uint16_t decim;
    double th, yf, phf, p;
    uint16_t div, held;
    uint32_t n, sat;
} dref_t;

static double dclamp(double x, double lo, double hi, uint32_t *cnt)
{
    if (x > hi) { (*cnt)++; return hi; }
    if (x < lo) { (*cnt)++; return lo; }
    return x;
}

static void dref_init(dref_t *r, double ts, uint16_t decim, double lpf, double mem,
                      double phimin, double tmin, double tmax, double th0)
{
    memset(r, 0, sizeof *r);
    r->kf = 1.0 - exp(-2.0 * PI_D * lpf * ts);
    r->lam = 1.0 - (double)decim * ts / mem;
    r->pmax = 4.0;
    r->p0 = fmin((1.0 - r->lam) / (phimin * phimin), 4.0);
    r->pmin = 1e-6;
    r->phimin = phimin;
    r->tmin = tmin;
    r->tmax = tmax;
    r->decim = decim;
    r->th = th0;
    r->p = r->p0;
    r->held = 1u;
}

static void dref_step(dref_t *r, double wsl, double pa, double pb, double ia, double ib,
                      int enable)
{
    double dot, crs, y;
    wsl = dclamp(wsl, -2.0, 2.0, &r->sat);
    pa = dclamp(pa, -4.0, 4.0, &r->sat);
    pb = dclamp(pb, -4.0, 4.0, &r->sat);
    ia = dclamp(ia, -4.0, 4.0, &r->sat);
    ib = dclamp(ib, -4.0, 4.0, &r->sat);
    dot = pa * ia + pb * ib;
    crs = pa * ib - pb * ia;
    y = wsl * dot;
    r->yf += r->kf * (y - r->yf);
    r->phf += r->kf * (crs - r->phf);
    if (!enable) {
        r->div = 0u;
        return;
    }
    if (++r->div >= r->decim) {
        double phi, den, k, e;
        r->div = 0u;
        phi = dclamp(r->phf, -2.0, 2.0, &r->sat);
        if (fabs(phi) < r->phimin) {
            r->held = 1u;
            return;
        }
        r->held = 0u;
        den = r->lam + r->p * phi * phi;
        k = r->p * phi / den;
        e = dclamp(r->yf - phi * r->th, -8.0, 8.0, &r->sat);
        r->th = dclamp(r->th + k * e, r->tmin, r->tmax, &r->sat);
        r->p = fmin(fmax(r->p / den, r->pmin), r->pmax);
        r->n++;
    }
}

/* ---- rig ------------------------------------------------------------------ */
static void init_ok(tr_track_t *t, double th0)
{
    assert_int_equal(tr_track_init(t, TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX,
                                   (float)th0),
                     TR_TRACK_OK);
}

static void dref_rig(dref_t *r, double th0)
{
    /* the same float arguments the module receives, as doubles */
    dref_init(r, (double)TS_S, DECIM, (double)LPF_HZ, (double)MEM_S, (double)PHI_MIN,
              (double)TH_MIN, (double)TH_MAX, (double)(float)th0);
}

/* One sample to both: the quantised inputs to the module, their exact
 * values to the reference. */
static void feed(tr_track_t *t, dref_t *r, double wsl, double pa, double pb, double ia,
                 double ib)
{
    t->w_sl = d_to_iq(wsl);
    t->psi_alpha = d_to_iq(pa);
    t->psi_beta = d_to_iq(pb);
    t->i_alpha = d_to_iq(ia);
    t->i_beta = d_to_iq(ib);
    tr_track_step(t);
    if (r != NULL) {
        dref_step(r, iq_to_d(t->w_sl), iq_to_d(t->psi_alpha), iq_to_d(t->psi_beta),
                  iq_to_d(t->i_alpha), iq_to_d(t->i_beta), t->enable != 0u);
    }
}

/* the exact regression y = theta phi for a torque current i_t */
static void feed_motor(tr_track_t *t, dref_t *r, double theta, double i_t)
{
    feed(t, r, theta * i_t / I_M, PSI0, 0.0, I_M, i_t);
}

/* a varying torque current: 0.22 pu + a 2 Hz sinusoid + a 0.7 Hz square
 * wave, in [0.07, 0.37] pu: phi = psi0 i_T in [0.027, 0.141] > phi_min */
static double it_varying(uint32_t k)
{
    double t = (double)k * (double)TS_S;
    return 0.22 + 0.1 * sin(2.0 * PI_D * 2.0 * t) +
           ((sin(2.0 * PI_D * 0.7 * t) >= 0.0) ? 0.05 : -0.05);
}

/* (a) constant theta_true = 0.2 (Tr 20 % below the start value), a varying
 * torque current, 10 memory times (5 s).
 * Against theta_true, after 10 memory times.  Budget (IQ, LSB of theta):
 * the transient remainder 0.04 e^-10 = 30 LSB; the rounded update stops
 * once k e rounds to 0, |theta - theta_true| < 0.5 LSB / (k phi), k phi ~
 * (1 - lambda) = 0.002: a dead zone of 250 LSB; the filters' rounding
 * (a random walk, 0.29 sqrt(1/(2 kf)) = 3.2 LSB rms each) through 1/phi_rms
 * (0.08): 40 LSB per sigma, 4 sigma 160; the truncated products dot, crs, y
 * (< 2 LSB on y, phi) through 1/phi_min: 75 LSB.  Sum 515: bound 600 LSB
 * (3.6e-5 pu, 1.8e-4 relative).  FLOAT: ~1e-6 relative; same bound.
 * Against the double reference over the whole run (every RLS tick): the
 * same quantisation budget plus the transient's sensitivity, bound 600 LSB;
 * n_updates and held equal the reference's. */
static void test_converge_constant(void **state)
{
    const double th_true = 0.2;
    tr_track_t t;
    dref_t r;
    uint32_t k, n = 75000u;
    double max_dev = 0.0;
    (void)state;

    init_ok(&t, TH_NOM);
    dref_rig(&r, TH_NOM);
    t.enable = 1u;
    for (k = 1u; k <= n; k++) {
        feed_motor(&t, &r, th_true, it_varying(k));
        if (k % DECIM == 0u) {
            double dev = fabs(iq_to_d(t.theta) - r.th);
            max_dev = (dev > max_dev) ? dev : max_dev;
            assert_int_equal(t.held, r.held);
        }
    }
    print_message("constant: theta %.8f true %.8f err %.1f LSB (ref err %.2e); max |module -"
                  " ref| %.1f LSB; updates %u (ref %u); P %.6f ref %.6f\n",
                  iq_to_d(t.theta), th_true, (iq_to_d(t.theta) - th_true) / LSB24,
                  r.th - th_true, max_dev / LSB24, (unsigned)t.n_updates, (unsigned)r.n,
                  iq_to_d(t.p), r.p);
    assert_true(fabs(iq_to_d(t.theta) - th_true) <= 600.0 * LSB24);
    assert_true(max_dev <= 600.0 * LSB24);
    assert_int_equal(t.n_updates, r.n);
    /* every tick after the filters' start-up updated: 5000 ticks, the few
     * first held (phi_f rising from 0 through phi_min) */
    assert_true(t.n_updates > 4990u && t.n_updates <= n / DECIM);
    assert_int_equal(t.sat_count, 0u);
}

/* (b) A ramp of theta_true from 1/Tr to 0.5 pu (Tr -68 %) in 5 s, after 5 s
 * at 1/Tr, then held 2 s; constant i_T = 0.25 pu (phi = 0.0953).
 * 1. The whole trajectory against the double reference (every tick).
 *    Budget (IQ): each low-pass state is within 0.5/kf = 120 LSB of its
 *    exact value (rounded first-order recursion, |r| <= 0.5 LSB, gain
 *    1/kf); y ramps deterministically, so this is not averaged: through
 *    theta = y_f / phi_f, (120 + 0.5 * 120) / 0.0953 = 1900 LSB; the update's
 *    rounding, <= 0.5 LSB / (1 - lambda) = 250 LSB; truncated dot, crs, y
 *    (< 2 LSB) / phi: 20 LSB.  Bound 2200 LSB (1.3e-4 pu, 0.4 % of the
 *    lag).  FLOAT: each filter step rounds y_f relative 6e-8, gain 1/kf:
 *    1.4e-5 relative, within the same bound.
 * 2. The steady lag.  With phi constant and P at its steady value P_inf =
 *    (1 - lambda)/phi^2 the gain is k = (1 - lambda)/phi and the update is
 *    theta(n) = lambda theta(n-1) + (1 - lambda) y_f / phi: a first-order
 *    filter of the low-passed theta_true.  A ramp of slope s through it
 *    lags by s times: lambda / (1 - lambda) updates = memory - decim Ts,
 *    plus the low-pass's (1 - kf)/kf samples:
 *        L = memory - decim Ts + Ts (1 - kf)/kf = 0.5149 s
 *    (about memory_s).  P reaches P_inf as lambda^n from P(0) (10 memory
 *    times: e^-10), the ramp's transient likewise.  Checked at the end of
 *    the ramp: (theta_true - theta) / s within 1 % of L (the quantisation
 *    above: 0.4 %).  P itself: P_inf within 1e-3 relative (P(0) remainder
 *    e^-10 = 5e-5, the Q24 P of 0.22 pu: 1e-6, lambda's float and Q24
 *    rounding 6e-5 of 1 - lambda).
 * 3. After the ramp (held 2 s = 4 memory times) the error decays as two
 *    cascaded first-order stages predict (below): within 2 % + 2200 LSB. */
static void test_ramp(void **state)
{
    const double th0 = TH_NOM, th1 = 0.5, t_ramp = 5.0, i_t = 0.25;
    const double slope = (th1 - th0) / t_ramp;
    const double ts = (double)TS_S, kf = 1.0 - exp(-2.0 * PI_D * (double)LPF_HZ * ts);
    const double lag = (double)MEM_S - (double)DECIM * ts + ts * (1.0 - kf) / kf;
    const uint32_t n0 = 75000u, n1 = 150000u, n2 = 180000u;
    tr_track_t t;
    dref_t r;
    uint32_t k;
    double max_dev = 0.0, lag_meas = 0.0, lag_ref = 0.0, p_end = 0.0;
    (void)state;

    init_ok(&t, th0);
    dref_rig(&r, th0);
    t.enable = 1u;
    for (k = 1u; k <= n2; k++) {
        double tt = (double)k * ts;
        double th = (k <= n0) ? th0 : ((k <= n1) ? th0 + slope * (tt - (double)n0 * ts) : th1);
        feed_motor(&t, &r, th, i_t);
        if (k % DECIM == 0u) {
            double dev = fabs(iq_to_d(t.theta) - r.th);
            max_dev = (dev > max_dev) ? dev : max_dev;
        }
        if (k == n1) {
            lag_meas = (th - iq_to_d(t.theta)) / slope;
            lag_ref = (th - r.th) / slope;
            p_end = iq_to_d(t.p);
        }
    }
    {
        double phi = PSI0 * i_t;
        double p_inf = (1.0 - r.lam) / (phi * phi);
        double rest = fabs(th1 - iq_to_d(t.theta));
        double rest_ref = fabs(th1 - r.th);
        /* two first-order stages (time constants tau1 of the RLS, tau2 of
         * the low-pass): the ramp's error decays after the stop as
         * s tau1^2 / (tau1 - tau2) e^{-t/tau1} (+ the tau2 term, e^-126) */
        double tau1 = -(double)DECIM * ts / log(r.lam), tau2 = -ts / log(1.0 - kf);
        double rest_want = slope * tau1 * tau1 / (tau1 - tau2) * exp(-2.0 / tau1);
        print_message("ramp: lag %.5f s (ref %.5f, analytic %.5f, rel err %+.2e); max |module -"
                      " ref| %.1f LSB; P %.6f (P_inf %.6f); after 2 s: %.3e (ref %.3e, decay %.3e)\n",
                      lag_meas, lag_ref, lag, lag_meas / lag - 1.0, max_dev / LSB24, p_end, p_inf,
                      rest, rest_ref, rest_want);
        assert_true(max_dev <= 2200.0 * LSB24);
        assert_true(fabs(lag_meas / lag - 1.0) <= 0.01);
        assert_true(fabs(lag_ref / lag - 1.0) <= 0.001);   /* the reference: e^-10 remainders */
        assert_true(fabs(p_end / p_inf - 1.0) <= 1e-3);
        assert_true(fabs(rest_ref / rest_want - 1.0) <= 0.02);
        assert_true(fabs(rest - rest_want) <= 0.02 * rest_want + 2200.0 * LSB24);
    }
    assert_int_equal(t.sat_count, 0u);
}

/* (c) Wind-up guard.  Learn for 1 s, then no torque current (i_T = 0, a
 * slip of garbage 0.05 pu: y != 0 with phi -> 0).  phi_f decays with the
 * 10 Hz low-pass; from the first RLS tick at which |phi_f| < phi_min
 * (predicted from phi_f itself) on, theta, P and n_updates hold exactly
 * and held = 1, for 2 s.  Then enable = 0 with informative data (theta
 * true 0.3): theta, P, n_updates hold exactly, the filters still run.
 * Then enable = 1: the updates resume. */
static void test_windup_guard(void **state)
{
    tr_track_t t;
    uint32_t k, first_hold = 0u;
    _iq th_h = 0, p_h = 0;
    uint32_t n_h = 0u;
    (void)state;

    init_ok(&t, TH_NOM);
    t.enable = 1u;
    for (k = 1u; k <= 15000u; k++) {
        feed_motor(&t, NULL, 0.2, it_varying(k));
    }
    assert_int_equal(t.held, 0);
    {
        /* the first sample with |phi_f| < phi_min: phi_f(k) = phi_f(0)
         * (1 - kf)^k, k_c = ln(phi_f(0) / phi_min) / -ln(1 - kf); the hold
         * starts at the first RLS tick from k_c on (within DECIM samples) */
        const double kf = 1.0 - exp(-2.0 * PI_D * (double)LPF_HZ * (double)TS_S);
        const double phi0 = iq_to_d(t.phi_f);
        const double k_c = log(phi0 / (double)PHI_MIN) / -log(1.0 - kf);
        for (k = 1u; k <= 30000u; k++) {
            uint32_t n_before = t.n_updates;
            feed(&t, NULL, 0.05, PSI0, 0.0, I_M, 0.0);
            if (t.div == 0u) {   /* an RLS tick happened in this sample */
                int below = fabs(iq_to_d(t.phi_f)) < (double)PHI_MIN;
                assert_int_equal(t.held, below ? 1 : 0);
                assert_int_equal(t.n_updates, n_before + (below ? 0u : 1u));
                if (below && first_hold == 0u) {
                    first_hold = k;
                    th_h = t.theta;
                    p_h = t.p;
                    n_h = t.n_updates;
                }
            }
            if (first_hold != 0u) {
                assert_true(t.theta == th_h && t.p == p_h);
                assert_int_equal(t.n_updates, n_h);
                assert_int_equal(t.held, 1);
            }
        }
        print_message("guard: phi_f %.4f -> held from sample %u after i_T -> 0 (phi_f below"
                      " phi_min from %.1f)\n",
                      phi0, (unsigned)first_hold, k_c);
        /* 1 sample of margin for the Q24 filter's rounding */
        assert_true((double)first_hold >= k_c - 1.0 && (double)first_hold <= k_c + (double)DECIM + 1.0);
    }
    /* enable = 0: informative data, nothing learnt; the filters run */
    t.enable = 0u;
    for (k = 1u; k <= 15000u; k++) {
        feed_motor(&t, NULL, 0.3, 0.25);
        assert_true(t.theta == th_h && t.p == p_h);
        assert_int_equal(t.n_updates, n_h);
        assert_int_equal(t.div, 0u);
    }
    assert_true(fabs(iq_to_d(t.phi_f) - PSI0 * 0.25) <= 1e-4);
    /* enable = 1: the updates resume on the next tick, theta moves to 0.3 */
    t.enable = 1u;
    for (k = 1u; k <= DECIM; k++) {
        feed_motor(&t, NULL, 0.3, 0.25);
    }
    assert_int_equal(t.n_updates, n_h + 1u);
    assert_int_equal(t.held, 0);
    assert_true(t.theta > th_h);
}

/* (d) Clamps.  (1) Only the input clamps: enable = 0 and all five inputs
 * beyond their limits: sat_count grows by exactly 5 per sample.  (2) A
 * consistent regression with theta_true = 3 theta_max: theta reaches
 * theta_max and stays there, each tick from then on adds exactly one
 * clamp.  (3) theta_true < 0 (a reversed slip): theta_min, likewise.
 * (4) Absurd inputs with learning on (Q24 extremes, alternating signs):
 * theta always in range, counted.  (5) restart clamps theta0 into the
 * range and zeroes the counters and filters; the counters saturate. */
static void test_clamps(void **state)
{
    tr_track_t t;
    uint32_t k, sat0;
    (void)state;

    init_ok(&t, TH_NOM);
    t.enable = 0u;
    for (k = 1u; k <= 100u; k++) {
        feed(&t, NULL, 3.0, 5.0, -5.0, -6.0, 7.0);
    }
    assert_int_equal(t.sat_count, 500u);

    /* (2) theta_true = 3 theta_max */
    tr_track_restart(&t, _IQ(TH_NOM));
    t.enable = 1u;
    for (k = 1u; k <= 30000u; k++) {
        feed_motor(&t, NULL, 3.0 * (double)TH_MAX, 0.25);
        assert_true(t.theta >= _IQ(TH_MIN) && t.theta <= _IQ(TH_MAX));
    }
    assert_true(t.theta == _IQ(TH_MAX));
    sat0 = t.sat_count;
    for (k = 1u; k <= 150u; k++) {
        feed_motor(&t, NULL, 3.0 * (double)TH_MAX, 0.25);
    }
    assert_int_equal(t.sat_count, sat0 + 10u);   /* 10 ticks, one theta clamp each */
    assert_true(t.theta == _IQ(TH_MAX));

    /* (3) reversed slip */
    tr_track_restart(&t, _IQ(TH_NOM));
    for (k = 1u; k <= 30000u; k++) {
        feed_motor(&t, NULL, -0.3, 0.25);
    }
    assert_true(t.theta == _IQ(TH_MIN));
    sat0 = t.sat_count;
    for (k = 1u; k <= 150u; k++) {
        feed_motor(&t, NULL, -0.3, 0.25);
    }
    assert_int_equal(t.sat_count, sat0 + 10u);

    /* (4) absurd inputs, learning on: w_sl, psi_alpha, i_alpha, i_beta at
     * the ends of Q24 (clamped to 2, 4, 4, 4: 4 counts per sample), psi_beta
     * 2 pu: dot = -8, y = -16, psi x i = -24 (phi_f clamped to -2 at the
     * ticks), e = y_f - phi theta clamped to -8 */
    tr_track_restart(&t, _IQ(TH_NOM));
    for (k = 1u; k <= 30000u; k++) {
        double sg = ((k / 700u) % 2u == 0u) ? 1.0 : -1.0;
        t.w_sl = d_to_iq(127.0 * sg);
        t.psi_alpha = d_to_iq(-127.0 * sg);
        t.psi_beta = d_to_iq(2.0);
        t.i_alpha = d_to_iq(127.0);
        t.i_beta = d_to_iq(127.0 * sg);
        tr_track_step(&t);
        assert_true(t.theta >= _IQ(TH_MIN) && t.theta <= _IQ(TH_MAX));
        assert_true(t.p >= _IQ(0.0) && t.p <= _IQ(TR_TRACK_P_MAX));
        assert_true(_IQabs(t.y_f) <= _IQ(64.0) && _IQabs(t.phi_f) <= _IQ(32.0));
    }
    print_message("absurd: theta %.6f, sat_count %u, updates %u\n", iq_to_d(t.theta),
                  (unsigned)t.sat_count, (unsigned)t.n_updates);
    assert_true(t.sat_count >= 4u * 30000u);
    assert_true(t.n_updates > 1900u);

    /* (5) restart: theta0 clamped, state cleared */
    tr_track_restart(&t, _IQ(100.0));
    assert_true(t.theta == _IQ(TH_MAX));
    assert_true(t.y_f == _IQ(0.0) && t.phi_f == _IQ(0.0) && t.p == t.p0);
    assert_int_equal(t.n_updates, 0u);
    assert_int_equal(t.sat_count, 0u);
    tr_track_restart(&t, _IQ(-1.0));
    assert_true(t.theta == _IQ(TH_MIN));
    t.sat_count = 0xFFFFFFFEu;
    t.enable = 0u;
    feed(&t, NULL, 3.0, 5.0, 0.0, 0.0, 0.0);
    assert_true(t.sat_count == 0xFFFFFFFFu);
    feed(&t, NULL, 3.0, 5.0, 0.0, 0.0, 0.0);
    assert_true(t.sat_count == 0xFFFFFFFFu);
}

/* The covariance floor P >= 1e-6: it binds when the forgetting RLS's steady
 * state (1 - lambda) / phi^2 falls below it.  Accepted but extreme: 15 kHz,
 * an update every sample, memory 20 s (1 - lambda = 3.3e-6, 56 LSB), phi at
 * its clamp 2 (psi x i = 2.5): the steady state ~14 LSB, below the floor's
 * 16.  P must stop at the floor (the drive's rig, 1 kHz and 0.5 s, keeps P
 * near 5e-4, far above it). */
static void test_p_floor(void **state)
{
    tr_track_t t;
    uint32_t k;
    const double wsl = TH_NOM * 2.5 / I_M;
    (void)state;

    assert_int_equal(tr_track_init(&t, TS_S, 1u, LPF_HZ, 20.0f, 1.0f, TH_MIN, TH_MAX,
                                   (float)TH_NOM),
                     TR_TRACK_OK);
    t.enable = 1u;
    /* IQ_MATH: _IQdiv's truncation takes P down ~1 LSB per update (the
     * floor within ~300 samples); FLOAT_MATH: 1/P approaches phi^2 / (1 -
     * lambda) with a time constant of 1 / (1 - lambda) = 3e5 updates */
    for (k = 1u; k <= 2000000u && (t.n_updates < 1000u || t.p != _IQ(1.0e-6)); k++) {
        feed(&t, NULL, wsl, 1.0, 0.0, I_M, 2.5);
        assert_true(t.p >= _IQ(1.0e-6) && t.p <= _IQ(TR_TRACK_P_MAX));
    }
    print_message("floor: P %.3g after %u updates\n", iq_to_d(t.p), (unsigned)t.n_updates);
    assert_true(t.p == _IQ(1.0e-6));   /* the floor reached */
    for (k = 1u; k <= 1000u; k++) {
        feed(&t, NULL, wsl, 1.0, 0.0, I_M, 2.5);
        assert_true(t.p == _IQ(1.0e-6));   /* and held */
    }
}

/* Constants: kf, lambda, P(0), the range, against their formulas in
 * double (IQ: _IQ truncates, < 1 LSB, after a float evaluation, relative
 * 1.2e-7: bound 1 LSB + 2e-7 relative). */
static void test_constants(void **state)
{
    tr_track_t t;
    dref_t r;
    (void)state;

    init_ok(&t, TH_NOM);
    dref_rig(&r, TH_NOM);
#define NEAR(a, b) assert_true(fabs(iq_to_d(a) - (b)) <= LSB24 + 2e-7 * fabs(b))
    NEAR(t.kf, r.kf);
    NEAR(t.lambda, r.lam);
    NEAR(t.p0, r.p0);
    NEAR(t.phi_min, r.phimin);
    NEAR(t.theta_min, r.tmin);
    NEAR(t.theta_max, r.tmax);
    NEAR(t.theta, r.th);
#undef NEAR
    assert_true(t.p == t.p0 && t.p_max == _IQ(TR_TRACK_P_MAX));
    assert_int_equal(t.decim, DECIM);
    assert_int_equal(t.held, 1);
    assert_int_equal(t.n_updates, 0u);
    /* here (1 - lambda) / phi_min^2 = 5: P(0) at its bound 4.  With
     * phi_min = 0.05, 0.8: 1 - lambda computed in float carries lambda's
     * rounding (6e-8 of 0.002: 3e-5 relative) */
    assert_true(t.p0 == _IQ(TR_TRACK_P_MAX));
    assert_int_equal(tr_track_init(&t, TS_S, DECIM, LPF_HZ, MEM_S, 0.05f, TH_MIN, TH_MAX,
                                   (float)TH_NOM),
                     TR_TRACK_OK);
    assert_true(fabs(iq_to_d(t.p0) / ((1.0 - r.lam) / ((double)0.05f * (double)0.05f)) - 1.0) <= 5e-5);
}

/* (f) tr_track_settle_s: 3 Tr + 2 memories; 0 for a bad argument.  And
 * what the memories part claims: after a step of the data (the end of a
 * start transient, theta_true 0.3 -> 1/Tr with the estimate settled on 0.3
 * for 10 memories), the estimate still holds exp(-2) of the step after
 * 2 memories.  Reference: the two first-order stages of test_ramp (the RLS
 * at steady P, time constant tau1 ~ memory; the low-pass tau2), whose step
 * response leaves (tau1 e^{-t/tau1} - tau2 e^{-t/tau2}) / (tau1 - tau2) of
 * the step: 14.8 % here.  Bound: 2 % of it (test_ramp's) + 2200 LSB; the
 * double reference within 0.5 %. */
static void test_settle(void **state)
{
    const double th_a = 0.3, th_b = TH_NOM, i_t = 0.25;
    const double ts = (double)TS_S, kf = 1.0 - exp(-2.0 * PI_D * (double)LPF_HZ * ts);
    const float settle = tr_track_settle_s(MEM_S, 0.0001f) - 3.0f * 0.0001f;
    const uint32_t n0 = 75000u, n1 = n0 + (uint32_t)((double)settle / ts + 0.5);
    const float inf = 1.0e30f * 1.0e30f;
    tr_track_t t;
    dref_t r;
    uint32_t k;
    (void)state;

    assert_true(fabsf(tr_track_settle_s(0.5f, 0.1f) - 1.3f) <= 1e-6f);
    assert_true(fabsf(tr_track_settle_s(1.0f, 0.6f) - 3.8f) <= 1e-6f);
    assert_true(tr_track_settle_s(0.0f, 0.1f) == 0.0f);
    assert_true(tr_track_settle_s(1.0f, -0.1f) == 0.0f);
    assert_true(tr_track_settle_s(inf - inf, 0.1f) == 0.0f);   /* NaN */
    assert_true(tr_track_settle_s(inf, 0.1f) == 0.0f);
    assert_true(tr_track_settle_s(1.0f, inf) == 0.0f);

    init_ok(&t, th_a);
    dref_rig(&r, th_a);
    t.enable = 1u;
    for (k = 1u; k <= n1; k++) {
        feed_motor(&t, &r, (k <= n0) ? th_a : th_b, i_t);
    }
    {
        double tau1 = -(double)DECIM * ts / log(r.lam), tau2 = -ts / log(1.0 - kf);
        double tt = (double)(n1 - n0) * ts;
        double want = (tau1 * exp(-tt / tau1) - tau2 * exp(-tt / tau2)) / (tau1 - tau2);
        double rest = (iq_to_d(t.theta) - th_b) / (th_a - th_b);
        double rest_ref = (r.th - th_b) / (th_a - th_b);
        print_message("settle: %.3f s after the step the estimate holds %.4f of it (ref %.4f,"
                      " two stages %.4f, exp(-2) %.4f)\n", tt, rest, rest_ref, want, exp(-2.0));
        assert_true(fabs(rest_ref / want - 1.0) <= 0.005);
        assert_true(fabs(rest - want) <= 0.02 * want + 2200.0 * LSB24 / fabs(th_a - th_b));
        assert_true(rest < 0.16);   /* e^-2 and the low-pass's 16 ms */
    }
}

/* (e) Every init error code, the other arguments valid. */
static void test_init_errors(void **state)
{
    static const struct {
        float ts;
        uint16_t decim;
        float lpf, mem, phimin, tmin, tmax, th0;
        tr_track_status_t want;
    } bad[] = {
        {0.0f, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {NAN, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {TS_S, 0u, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {TS_S, 65u, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {TS_S, DECIM, 0.0f, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {TS_S, DECIM, 1200.0f, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},   /* 2 pi f Ts = 0.503 */
        {TS_S, DECIM, NAN, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_RATE},
        {TS_S, DECIM, LPF_HZ, 0.19f, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_MEMORY},
        {TS_S, DECIM, LPF_HZ, 20.5f, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_MEMORY},
        {TS_S, DECIM, LPF_HZ, NAN, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_MEMORY},
        /* lambda = 1 - 64 ms / 0.5 s = 0.872 < 0.9 */
        {1e-3f, 64u, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_MEMORY},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, 0.0f, TH_MAX, 0.161f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, 0.3f, 0.3f, 0.3f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, 31.0f, 0.161f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.02f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, TH_MIN, TH_MAX, 0.7f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, PHI_MIN, NAN, TH_MAX, 0.161f, TR_TRACK_ERR_RANGE},
        {TS_S, DECIM, LPF_HZ, MEM_S, 0.0f, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_PHI},
        {TS_S, DECIM, LPF_HZ, MEM_S, 1.01f, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_PHI},
        {TS_S, DECIM, LPF_HZ, MEM_S, NAN, TH_MIN, TH_MAX, 0.161f, TR_TRACK_ERR_PHI},
    };
    tr_track_t t;
    uint32_t c;
    (void)state;

    for (c = 0u; c < sizeof bad / sizeof bad[0]; c++) {
        tr_track_status_t st = tr_track_init(&t, bad[c].ts, bad[c].decim, bad[c].lpf, bad[c].mem,
                                             bad[c].phimin, bad[c].tmin, bad[c].tmax, bad[c].th0);
        if (st != bad[c].want) {
            print_error("case %u: status %d want %d\n", (unsigned)c, (int)st, (int)bad[c].want);
            fail();
        }
    }
    /* the edges are accepted: decim 1 and 64, memory 0.2 and 20 s, theta_max
     * 30, phi_min 1, theta0 at either end */
    assert_int_equal(tr_track_init(&t, TS_S, 1u, LPF_HZ, 0.2f, PHI_MIN, TH_MIN, TH_MAX, TH_MIN),
                     TR_TRACK_OK);
    assert_int_equal(tr_track_init(&t, TS_S, 64u, LPF_HZ, 20.0f, 1.0f, TH_MIN, 30.0f, 30.0f),
                     TR_TRACK_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_converge_constant),
        cmocka_unit_test(test_ramp),
        cmocka_unit_test(test_windup_guard),
        cmocka_unit_test(test_clamps),
        cmocka_unit_test(test_p_floor),
        cmocka_unit_test(test_constants),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_settle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
