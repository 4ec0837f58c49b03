/* foc_pi: pi_ctrl_t.  Parameter checks; the open-loop ramp and the
 * closed-loop step response against their analytic discrete solutions;
 * clamping anti-windup (no wind-up during saturation, immediate recovery);
 * the integrator's own limit; run-time limits; one-step agreement with an
 * exact double-precision model over random inputs up to the range edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <string.h>

#include "pi_ctrl.h"
#include "foc_test_util.h"

static void assert_zeroed(const pi_ctrl_t *p)
{
    pi_ctrl_t z;
    memset(&z, 0, sizeof z);
    assert_memory_equal(p, &z, sizeof z);
}

static void test_init(void **state)
{
    pi_ctrl_t p;
    const float nan = nanf("");
    const float inf = INFINITY;
    (void)state;
    assert_int_equal(pi_init(&p, -0.1f, 0.1f, -1.0f, 1.0f), PI_ERR_KP);
    assert_zeroed(&p);
    assert_int_equal(pi_init(&p, nan, 0.1f, -1.0f, 1.0f), PI_ERR_KP);
    assert_int_equal(pi_init(&p, inf, 0.1f, -1.0f, 1.0f), PI_ERR_KP);
    assert_int_equal(pi_init(&p, 100.5f, 0.1f, -1.0f, 1.0f), PI_ERR_KP);
    assert_int_equal(pi_init(&p, 1.0f, -1e-6f, -1.0f, 1.0f), PI_ERR_KI);
    assert_int_equal(pi_init(&p, 1.0f, nan, -1.0f, 1.0f), PI_ERR_KI);
    assert_int_equal(pi_init(&p, 1.0f, 1.5f, -1.0f, 1.0f), PI_ERR_KI);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, 1.0f, 1.0f), PI_ERR_LIMITS);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, 1.0f, -1.0f), PI_ERR_LIMITS);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, nan, 1.0f), PI_ERR_LIMITS);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, -1.0f, nan), PI_ERR_LIMITS);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, -16.5f, 1.0f), PI_ERR_LIMITS);
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, -1.0f, 17.0f), PI_ERR_LIMITS);
    assert_zeroed(&p);
    /* the edges of the valid ranges are accepted */
    assert_int_equal(pi_init(&p, 0.0f, 0.0f, -16.0f, 16.0f), PI_OK);
    assert_int_equal(pi_init(&p, 100.0f, 1.0f, -16.0f, 16.0f), PI_OK);
    /* gains stored to within 1 LSB (_IQ truncates toward 0) */
    assert_int_equal(pi_init(&p, 3.3f, 0.0123f, -2.0f, 1.5f), PI_OK);
    assert_true(fabs(iq2d(p.kp) - (double)3.3f) <= foc_tol(1.0, 1.0, 3.3));
    assert_true(fabs(iq2d(p.ki) - (double)0.0123f) <= foc_tol(1.0, 1.0, 1.0));
    assert_true(iq2d(p.out_min) == -2.0 && iq2d(p.out_max) == 1.5);
    assert_true(iq2d(p.ui) == 0.0 && iq2d(p.out) == 0.0 && p.sat == 0u);
}

/* Open loop, constant error e: out(k) = kp e + ki e (k + 1) + ff (analytic)
 * until it reaches out_max; from then on out = out_max and the integrator
 * holds out_max - kp e - ff (it stops exactly where the output meets the
 * limit).  kp = 2.5, ki = 0.002 (not exact in Q24), e = 0.2, ff = 0.25,
 * out_max = 1: the limit is reached when 0.75 + 0.0004 (k + 1) >= 1,
 * k = 624.
 * Bound before the limit, IQ_MATH: the stored gains are within 1 LSB
 * (truncation of _IQ) and e is exact to 1 LSB (inputs rounded), so kp e is
 * off by < (1 + kp + |e|) LSB plus 1 for its truncation; each integrator
 * step by < (0.5 + ki + |e|) LSB (rounding, gain, error); after k + 1 steps
 * (k + 1) (0.5 + ki + |e|) + 2 + kp + |e| LSB.  FLOAT_MATH: each sample adds
 * one rounding of ki e and one of ui (<= 2^-24 |ui| each), the output two
 * more: (k + 3) * 2 FLT_EPSILON * max(|out|, 1). */
static void test_open_loop_ramp(void **state)
{
    const double kp = 2.5, ki = 0.002, e = 0.2, ff = 0.25;
    pi_ctrl_t p;
    int k;
    (void)state;
    assert_int_equal(pi_init(&p, (float)kp, (float)ki, -1.0f, 1.0f), PI_OK);
    p.ref = d2iq(0.3);
    p.fbk = d2iq(0.1);
    p.ff = d2iq(ff);
    for (k = 0; k < 624; k++) {
        const double ref = kp * e + ki * e * (k + 1) + ff;
        pi_step(&p);
        assert_true(fabs(iq2d(p.out) - ref)
                    <= foc_tol((k + 1) * (0.5 + ki + e) + 2.0 + kp + e, (k + 3) * 2.0, ref));
        assert_int_equal(p.sat, 0u);
    }
    for (; k < 2000; k++) {
        pi_step(&p);
        assert_true(iq2d(p.out) == 1.0);
        assert_int_equal(p.sat, 1u);
        /* held at out_max - up - ff: within the bound on up (kp e) */
        assert_true(fabs(iq2d(p.ui) - (1.0 - kp * e - ff)) <= foc_tol(2.0 + kp + e, 8.0, 1.0));
    }
}

/* Closed loop with a first-order plant y(k+1) = a y(k) + b u(k) (the R-L
 * current loop: a = exp(-Ts R/L), b = (1 - a)/R), the PI zero placed on the
 * plant pole (kp/(kp + ki) = a, the usual current-loop design).  The loop
 * gain is then g/(z - 1), g = b (kp + ki), and the unit step response is
 * exactly y(k) = 1 - (1 - g)^k.  kp = 0.25, ki = 2^-8, a = 64/65, b = 0.5:
 * gains exact in Q24 and float, g = 0.126953125.
 *
 * Bound: the controller differs from the exact one by bounded errors
 * injected at three points: the feedback quantisation n (IQ: 0.5 LSB;
 * float: 1 FLT_EPSILON), the proportional path and the output sums dp
 * (IQ: truncation, 1 LSB; float: 3 roundings, 3 FLT_EPSILON) and the
 * integrator input di (IQ: rounding, 0.5 LSB; float: 2 FLT_EPSILON).  The
 * effect on y is at most the l1 norm of the impulse response from each
 * point to y times its bound; the norms are computed here by simulating the
 * exact (double) closed loop with a unit impulse at that point. */
typedef struct { double a, b, kp, ki; } loop_t;

static double loop_l1(const loop_t *L, int where)
{
    double y = 0.0, ui = 0.0, sum = 0.0;
    int k;
    for (k = 0; k < 2000; k++) {
        const double imp = (k == 0) ? 1.0 : 0.0;
        const double e = 0.0 - (y + ((where == 0) ? imp : 0.0));
        const double up = L->kp * e + ((where == 1) ? imp : 0.0);
        double u;
        ui += L->ki * e + ((where == 2) ? imp : 0.0);
        u = up + ui;
        y = L->a * y + L->b * u;
        sum += fabs(y);
    }
    return sum;
}

static void test_closed_loop_step(void **state)
{
    const loop_t L = { 64.0 / 65.0, 0.5, 0.25, 1.0 / 256.0 };
    const double g = L.b * (L.kp + L.ki);
    const double l1n = loop_l1(&L, 0), l1p = loop_l1(&L, 1), l1i = loop_l1(&L, 2);
    const double bound = foc_tol(0.5 * l1n + 1.0 * l1p + 0.5 * l1i, 1.0 * l1n + 3.0 * l1p + 2.0 * l1i, 1.0);
    double y = 0.0, worst = 0.0;
    pi_ctrl_t p;
    int k;
    (void)state;
    assert_true(fabs(L.kp / (L.kp + L.ki) - L.a) < 1e-15);   /* the design */
    assert_int_equal(pi_init(&p, (float)L.kp, (float)L.ki, -2.0f, 2.0f), PI_OK);
    p.ref = _IQ(1.0);
    for (k = 0; k < 300; k++) {
        const double yref = 1.0 - pow(1.0 - g, k);
        const double err = fabs(y - yref);
        if (err > worst) { worst = err; }
        assert_true(err <= bound);
        p.fbk = d2iq(y);
        pi_step(&p);
        assert_int_equal(p.sat, 0u);
        y = L.a * y + L.b * iq2d(p.out);
    }
    print_message("foc_pi closed loop: l1 norms n %.2f p %.2f i %.2f, bound %.3g pu, worst %.3g pu\n",
                  l1n, l1p, l1i, bound, worst);
}

/* Anti-windup.  kp = 0.5, ki = 0.05, limits +-1, ff = 0, e = 1.5:
 * up = 0.75, the integrator steps 0.075, 0.15, 0.225 and then stops at
 * exactly 0.25 (out_max - up), where the output meets the limit (k = 3).
 * Without anti-windup it would reach 0.075 * 1000 = 75 pu in 1000 samples
 * (or the 1 pu integrator limit) and need thousands of samples to unwind.
 * Here it holds 0.25, and when the error drops to 0.5 the output leaves the
 * limit in the very first sample: out = 0.5*0.5 + 0.25 + 0.05*0.5 = 0.525.
 * ki = 0.05 is not exact: stored within 1 LSB, each integrator step
 * ki e is then within 0.5 (rounding) + |e| LSB, so after n steps the
 * integrator is within n (0.5 + |e|) LSB: 2 (k + 1) LSB during the ramp
 * (e = 1.5), 1 LSB after the first recovery step (e = 0.5) and 3 LSB after
 * the reversal (e = -1); FLOAT_MATH: a few FLT_EPSILON.  up and the held
 * value 0.25 = 1 - 0.75 are exact in both builds. */
static void test_anti_windup(void **state)
{
    pi_ctrl_t p;
    int k;
    (void)state;
    assert_int_equal(pi_init(&p, 0.5f, 0.05f, -1.0f, 1.0f), PI_OK);
    p.ref = _IQ(1.5);
    p.fbk = _IQ(0.0);
    for (k = 0; k < 3; k++) {
        pi_step(&p);
        assert_true(fabs(iq2d(p.out) - (0.75 + 0.075 * (k + 1))) <= foc_tol(2.0 * (k + 1), 4.0, 1.0));
        assert_int_equal(p.sat, 0u);
    }
    for (; k < 1000; k++) {
        pi_step(&p);
        assert_true(iq2d(p.out) == 1.0);
        assert_int_equal(p.sat, 1u);
        assert_true(iq2d(p.ui) == 0.25);     /* held, exactly */
    }
    /* error drops: out of saturation at once */
    p.ref = _IQ(0.5);
    pi_step(&p);
    assert_int_equal(p.sat, 0u);
    assert_true(fabs(iq2d(p.out) - 0.525) <= foc_tol(1.0, 2.0, 1.0));
    /* error reverses: the integrator moves down at once */
    p.ref = _IQ(-1.0);
    pi_step(&p);
    assert_true(fabs(iq2d(p.ui) - (0.275 - 0.05)) <= foc_tol(3.0, 4.0, 1.0));
    assert_true(fabs(iq2d(p.out) - (-0.5 + 0.225)) <= foc_tol(3.0, 4.0, 1.0));
    /* saturation by the proportional term alone (up = 5): the integrator
     * neither grows nor unwinds */
    {
        const _iq ui0 = p.ui;
        p.ref = _IQ(10.0);
        for (k = 0; k < 100; k++) {
            pi_step(&p);
            assert_true(p.ui == ui0);
            assert_true(iq2d(p.out) == 1.0);
            assert_int_equal(p.sat, 1u);
        }
        /* and symmetrically at the lower limit */
        p.ref = _IQ(-10.0);
        for (k = 0; k < 100; k++) {
            pi_step(&p);
            assert_true(p.ui == ui0);
            assert_true(iq2d(p.out) == -1.0);
            assert_int_equal(p.sat, 1u);
        }
    }
}

/* The integrator's own limit.  kp = 0, ki = 0.1, limits +-1, e = 1 and a
 * feed-forward of -3 pu: the output is pinned at -1 while the integrator
 * moves up (away from that limit, so it may) and stops at out_max = 1 after
 * 10 samples instead of growing without bound. */
static void test_integrator_limit(void **state)
{
    pi_ctrl_t p;
    int k;
    (void)state;
    assert_int_equal(pi_init(&p, 0.0f, 0.1f, -1.0f, 1.0f), PI_OK);
    p.ref = _IQ(1.0);
    p.ff = _IQ(-3.0);
    for (k = 0; k < 200; k++) {
        pi_step(&p);
        assert_true(iq2d(p.out) == -1.0);
        assert_int_equal(p.sat, 1u);
        assert_true(iq2d(p.ui) <= 1.0);
        if (k < 9) {
            assert_true(fabs(iq2d(p.ui) - 0.1 * (k + 1)) <= foc_tol(k + 2.0, k + 2.0, 1.0));
        } else if (k >= 10) {
            assert_true(iq2d(p.ui) == 1.0);
        }
    }
    /* pi_reset clears state and outputs, keeps the parameters */
    pi_reset(&p);
    assert_true(iq2d(p.ui) == 0.0 && iq2d(p.out) == 0.0 && p.sat == 0u);
    assert_true(fabs(iq2d(p.ki) - 0.1) <= foc_tol(1.0, 1.0, 1.0));
}

/* Run-time limits: rejected requests change nothing; an accepted one
 * clamps the integrator at once and bounds the next output. */
static void test_set_limits(void **state)
{
    pi_ctrl_t p, before;
    (void)state;
    assert_int_equal(pi_init(&p, 1.0f, 0.1f, -2.0f, 2.0f), PI_OK);
    p.ref = _IQ(1.0);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);
    pi_step(&p);                           /* ui = 0.8 */
    assert_true(fabs(iq2d(p.ui) - 0.8) <= foc_tol(8.0, 8.0, 1.0));
    before = p;
    assert_int_equal(pi_set_limits(&p, _IQ(0.5), _IQ(0.5)), PI_ERR_LIMITS);
    assert_int_equal(pi_set_limits(&p, _IQ(0.6), _IQ(0.5)), PI_ERR_LIMITS);
    assert_int_equal(pi_set_limits(&p, _IQ(-17.0), _IQ(0.5)), PI_ERR_LIMITS);
    assert_int_equal(pi_set_limits(&p, _IQ(-0.5), _IQ(16.5)), PI_ERR_LIMITS);
    assert_memory_equal(&p, &before, sizeof p);
    assert_int_equal(pi_set_limits(&p, _IQ(-0.5), _IQ(0.5)), PI_OK);
    assert_true(iq2d(p.ui) == 0.5);
    p.ref = _IQ(0.0);                      /* e = 0: out = ui = 0.5, at the limit */
    pi_step(&p);
    assert_true(iq2d(p.out) == 0.5);
    assert_int_equal(p.sat, 1u);
    assert_int_equal(pi_set_limits(&p, _IQ(-16.0), _IQ(16.0)), PI_OK);
    assert_true(iq2d(p.ui) == 0.5);        /* widening leaves ui alone */
}

/* Exact (double) model of one step of the specified controller, with the
 * stored gains and the same state; no clamp of e (the implementation's
 * clamp must not be visible). */
static void model_step(double kp, double ki, double omin, double omax, double ref,
                       double fbk, double ff, double *ui, double *out)
{
    const double e = ref - fbk, up = kp * e, di = ki * e;
    const double hi = omax - up - ff, lo = omin - up - ff;
    double u = *ui + di, v;
    if (di > 0.0 && u > hi) {
        u = fmax(hi, *ui);
    } else if (di < 0.0 && u < lo) {
        u = fmin(lo, *ui);
    }
    u = fmin(fmax(u, omin), omax);
    v = up + u + ff;
    *ui = u;
    *out = fmin(fmax(v, omin), omax);
}

/* 200 000 random single steps over the whole valid range (|ref|, |fbk|
 * <= 32, |ff| <= 16, kp in [0, 100], ki in [0, 1], limits in [-16, 16],
 * ui anywhere inside them), plus the corners.  The model is continuous in
 * its inputs, so the implementation may differ only by its arithmetic:
 * IQ_MATH: up truncated (1 LSB) enters hi/lo and the output, di rounded
 * (0.5 LSB): ui within 1.5 LSB, out within 2.5 LSB.  FLOAT_MATH: each of
 * the <= 4 roundings is <= 2^-24 of the largest operand (|kp e| + 32):
 * 4 FLT_EPSILON of it.  Without the clamp of e in the implementation, the
 * corners (kp e up to 6400 pu) would wrap in Q24. */
static void check_step(foc_rng_t *r, double kp, double ki, double omin, double omax,
                       double ref, double fbk, double ff, double ui0)
{
    pi_ctrl_t p;
    double ui, out, mag;
    (void)r;
    assert_int_equal(pi_init(&p, (float)kp, (float)ki, (float)omin, (float)omax), PI_OK);
    p.ui = d2iq(ui0);
    p.ui = _IQsat(p.ui, p.out_max, p.out_min);
    p.ref = d2iq(ref);
    p.fbk = d2iq(fbk);
    p.ff = d2iq(ff);
    ui = iq2d(p.ui);
    model_step(iq2d(p.kp), iq2d(p.ki), iq2d(p.out_min), iq2d(p.out_max), iq2d(p.ref),
               iq2d(p.fbk), iq2d(p.ff), &ui, &out);
    {
        /* pi_step_in, the current loops' form, on a copy whose own fbk and
         * ff are something else: the same step as pi_step of p (so the
         * model's bounds below hold for it), its fbk and ff untouched */
        pi_ctrl_t q = p;
        q.fbk = p.ff;
        q.ff = p.fbk;
        pi_step_in(&q, p.fbk, p.ff);
        pi_step(&p);
        assert_true(q.ui == p.ui && q.out == p.out && q.sat == p.sat);
        assert_true(q.fbk == p.ff && q.ff == p.fbk);
    }
    mag = fabs(iq2d(p.kp) * (iq2d(p.ref) - iq2d(p.fbk))) + 32.0;
    assert_true(fabs(iq2d(p.ui) - ui) <= foc_tol(1.5, 4.0, mag));
    assert_true(fabs(iq2d(p.out) - out) <= foc_tol(2.5, 4.0, mag));
    assert_true(iq2d(p.out) >= iq2d(p.out_min) && iq2d(p.out) <= iq2d(p.out_max));
    assert_true(iq2d(p.ui) >= iq2d(p.out_min) && iq2d(p.ui) <= iq2d(p.out_max));
}

static void test_random_steps(void **state)
{
    static const double gains[][2] = { { 100.0, 1.0 }, { 0.0, 1.0 }, { 100.0, 0.0 }, { 1.0, 0.5 } };
    static const double sig[] = { -32.0, 32.0 - 1.0 / 16777216.0 };
    static const double ffs[] = { -16.0, 0.0, 16.0 };
    foc_rng_t r = { 0xA11CEu };
    size_t g, i, j, f;
    int k;
    (void)state;
    for (g = 0; g < 4; g++) {
        for (i = 0; i < 2; i++) {
            for (j = 0; j < 2; j++) {
                for (f = 0; f < 3; f++) {
                    check_step(&r, gains[g][0], gains[g][1], -16.0, 16.0, sig[i], sig[j], ffs[f], 0.0);
                    check_step(&r, gains[g][0], gains[g][1], -16.0, 16.0, sig[i], sig[j], ffs[f], 16.0);
                    check_step(&r, gains[g][0], gains[g][1], -16.0, 16.0, sig[i], sig[j], ffs[f], -16.0);
                }
            }
        }
    }
    for (k = 0; k < 200000; k++) {
        const double kp = (k % 4 == 0) ? foc_rng_uniform(&r, 0.0, 100.0) : foc_rng_uniform(&r, 0.0, 3.0);
        const double ki = (k % 4 == 1) ? foc_rng_uniform(&r, 0.0, 1.0) : foc_rng_uniform(&r, 0.0, 0.05);
        const double a = foc_rng_uniform(&r, -16.0, 16.0), b = foc_rng_uniform(&r, -16.0, 16.0);
        const double omin = fmin(a, b), omax = fmax(a, b);
        const double sc = (k % 2 == 0) ? 32.0 : 2.0;
        if (omax - omin < 1e-3) { continue; }
        check_step(&r, kp, ki, omin, omax, foc_rng_uniform(&r, -sc, sc), foc_rng_uniform(&r, -sc, sc),
                   foc_rng_uniform(&r, -sc / 2.0, sc / 2.0), foc_rng_uniform(&r, omin, omax));
    }
}

/* pi_set_gains: e_max = min(64, 64/kp) by _IQdiv, as pi_init computes it
 * in float; the integrator kept (bumpless); rejections change nothing.
 * e_max against the exact 64 / kp of the stored (Q24) kp: _IQdiv
 * truncates, < 1 LSB (FLOAT: one division, 0.5 ulp of 64/kp <= 2^-18, i.e.
 * 4 FLT_EPSILON relative).  Against pi_init's e_max for the same float
 * gain: pi_init divides the float kp in float (0.5 ulp of 64/kp: up to
 * 64/kp * 2^-24 pu = e_max LSB) and truncates to Q24 (1 LSB), and the two
 * see kp differing by the Q24 truncation of kp (< 1 LSB: 64/kp^2 LSB in
 * e_max): bound (e_max + 64/kp^2 + 2) LSB.  For kp a power of two (2, 4,
 * 64) every step is exact: the two agree within 1 LSB. */
static void test_set_gains(void **state)
{
    static const double kps[] = { 0.0, 0.5, 1.0, 1.0001, 2.0, 3.3, 4.0, 17.7, 64.0, 99.9, 100.0 };
    pi_ctrl_t p, q, before;
    size_t i;
    double max_diff = 0.0;
    (void)state;
    for (i = 0; i < sizeof kps / sizeof kps[0]; i++) {
        const double kp = kps[i];
        double em, want, tol_init;
        assert_int_equal(pi_init(&p, (float)kp, 0.01f, -1.0f, 1.0f), PI_OK);
        assert_int_equal(pi_init(&q, 1.0f, 0.5f, -1.0f, 1.0f), PI_OK);
        assert_int_equal(pi_set_gains(&q, p.kp, p.ki), PI_OK);
        assert_true(q.kp == p.kp && q.ki == p.ki);
        em = iq2d(q.e_max);
        want = (iq2d(p.kp) <= 1.0) ? 64.0 : 64.0 / iq2d(p.kp);
#if MATH_TYPE == IQ_MATH
        assert_true(em <= want && want - em < FOC_LSB);
#else
        assert_true(fabs(em - want) <= 4.0 * (double)FLT_EPSILON * want);
#endif
        tol_init = (kp == 2.0 || kp == 4.0 || kp == 64.0 || kp <= 1.0)
                       ? foc_tol(1.0, 1.0, 1.0)
                       : foc_tol(want + 64.0 / (kp * kp) + 2.0, 4.0, want);
        if (!(fabs(em - iq2d(p.e_max)) <= tol_init)) {
            print_error("kp %.4f: e_max %.9f (set_gains) %.9f (init), diff %.2f LSB\n", kp, em,
                        iq2d(p.e_max), (em - iq2d(p.e_max)) * 16777216.0);
            fail();
        }
        max_diff = fmax(max_diff, fabs(em - iq2d(p.e_max)));
    }
    print_message("set_gains: e_max vs pi_init's, max |diff| %.3g pu (%.1f LSB24)\n", max_diff,
                  max_diff * 16777216.0);

    /* bumpless: build up the integrator, change the gains, the integrator
     * and the output stay; the next step is the analytic kp' e + ui + ki' e
     * + ff (unsaturated; IQ: kp e truncated 1 LSB, ki e rounded 0.5 LSB;
     * FLOAT: 3 roundings of values < 1) */
    assert_int_equal(pi_init(&p, 2.0f, 0.01f, -2.0f, 2.0f), PI_OK);
    p.ref = d2iq(0.3);
    p.fbk = d2iq(0.1);
    p.ff = d2iq(0.05);
    {
        int k;
        double ui, e, want;
        for (k = 0; k < 50; k++) {
            pi_step(&p);
        }
        before = p;
        assert_int_equal(pi_set_gains(&p, d2iq(1.5), d2iq(0.02)), PI_OK);
        assert_true(p.ui == before.ui && p.out == before.out && p.sat == before.sat);
        assert_true(p.out_min == before.out_min && p.out_max == before.out_max);
        ui = iq2d(p.ui);
        e = iq2d(p.ref) - iq2d(p.fbk);
        pi_step(&p);
        want = iq2d(p.kp) * e + ui + iq2d(p.ki) * e + iq2d(p.ff);
        assert_true(fabs(iq2d(p.out) - want) <= foc_tol(1.5, 3.0, 1.0));
        assert_true(fabs(iq2d(p.ui) - (ui + iq2d(p.ki) * e)) <= foc_tol(0.5, 2.0, 1.0));
    }

    /* rejected: kp outside [0, 100], ki outside [0, 1]; nothing changes */
    before = p;
    assert_int_equal(pi_set_gains(&p, d2iq(-1e-6), d2iq(0.01)), PI_ERR_KP);
    assert_int_equal(pi_set_gains(&p, d2iq(100.0001), d2iq(0.01)), PI_ERR_KP);
    assert_int_equal(pi_set_gains(&p, d2iq(1.0), d2iq(-1e-6)), PI_ERR_KI);
    assert_int_equal(pi_set_gains(&p, d2iq(1.0), d2iq(1.0001)), PI_ERR_KI);
    assert_int_equal(pi_set_gains(&p, d2iq(101.0), d2iq(2.0)), PI_ERR_KP);   /* kp checked first */
    assert_memory_equal(&p, &before, sizeof p);
    /* the edges are accepted */
    assert_int_equal(pi_set_gains(&p, d2iq(100.0), d2iq(1.0)), PI_OK);
    assert_true(fabs(iq2d(p.e_max) - 0.64) <= foc_tol(1.0, 4.0, 1.0));
    assert_int_equal(pi_set_gains(&p, d2iq(0.0), d2iq(0.0)), PI_OK);
    assert_true(iq2d(p.e_max) == 64.0);
}

/* pi_design_gains: the gains as pi_init sets them (the drive's background
 * posts a set, the ISR copies it with pi_apply_gains): equal to pi_init's
 * for the same floats; e_max against the exact 64/kp of the float kp:
 * one float division (half an ulp: 64/kp x 2^-24 pu, i.e. 64/kp LSB) and
 * the Q24 truncation (1 LSB); refusals (kp first) leave the set as it was; apply copies the three
 * words and keeps the integrator. */
static void test_design_gains(void **state)
{
    static const double kps[] = { 0.0, 0.5, 1.0, 1.0001, 2.0, 3.3, 17.7, 99.9, 100.0 };
    pi_ctrl_t p, q;
    pi_gains_t g, keep;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof kps / sizeof kps[0]; i++) {
        const float kp = (float)kps[i];
        double want;
        assert_int_equal(pi_init(&p, kp, 0.01f, -1.0f, 1.0f), PI_OK);
        assert_int_equal(pi_design_gains(&g, kp, 0.01f), PI_OK);
        assert_true(g.kp == p.kp && g.ki == p.ki && g.e_max == p.e_max);
        want = ((double)kp <= 1.0) ? 64.0 : 64.0 / (double)kp;
        assert_true(fabs(iq2d(g.e_max) - want) <= foc_tol(1.0 + want, 4.0, want));
    }
    assert_int_equal(pi_init(&q, 2.0f, 0.01f, -2.0f, 2.0f), PI_OK);
    q.ref = d2iq(0.3);
    q.fbk = d2iq(0.1);
    for (i = 0; i < 20; i++) {
        pi_step(&q);
    }
    p = q;
    assert_int_equal(pi_design_gains(&g, 1.5f, 0.02f), PI_OK);
    pi_apply_gains(&q, &g);
    assert_true(q.kp == g.kp && q.ki == g.ki && q.e_max == g.e_max);
    assert_true(q.ui == p.ui && q.out == p.out && q.out_min == p.out_min);

    keep = g;
    assert_int_equal(pi_design_gains(&g, -1e-6f, 0.01f), PI_ERR_KP);
    assert_int_equal(pi_design_gains(&g, 100.001f, 0.01f), PI_ERR_KP);
    assert_int_equal(pi_design_gains(&g, NAN, 0.01f), PI_ERR_KP);
    assert_int_equal(pi_design_gains(&g, 1.0f, -1e-6f), PI_ERR_KI);
    assert_int_equal(pi_design_gains(&g, 1.0f, 1.0001f), PI_ERR_KI);
    assert_int_equal(pi_design_gains(&g, 101.0f, 2.0f), PI_ERR_KP);
    assert_memory_equal(&g, &keep, sizeof g);
}

/* pi_check, the configuration table's test: pi_init's verdict at each bound
 * of pi_ctrl.h (kp in [0, PI_KP_MAX], ki in [0, PI_KI_MAX], the limits
 * within +-PI_OUT_MAX_PU, out_min < out_max), kp judged first. */
static void test_check(void **state)
{
    const float kp[] = {PI_KP_MAX, nextafterf(PI_KP_MAX, 200.0f), 0.0f, -0.0f,
                        nextafterf(0.0f, -1.0f), 1.0f, 1.0f, 1.0f, 1.0f,
                        1.0f, 200.0f};
    const float ki[] = {0.1f, 0.1f, 0.1f, 0.1f, 0.1f, PI_KI_MAX, nextafterf(PI_KI_MAX, 2.0f),
                        0.1f, 0.1f, 0.0f, 2.0f};
    const float hi[] = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, PI_OUT_MAX_PU,
                        nextafterf(PI_OUT_MAX_PU, 100.0f), -1.0f, 1.0f};
    const pi_status_t want[] = {PI_OK, PI_ERR_KP, PI_OK, PI_OK, PI_ERR_KP, PI_OK, PI_ERR_KI,
                                PI_OK, PI_ERR_LIMITS, PI_ERR_LIMITS, PI_ERR_KP};
    pi_ctrl_t p;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(pi_check(kp[i], ki[i], -1.0f, hi[i]), want[i]);
        assert_int_equal(pi_init(&p, kp[i], ki[i], -1.0f, hi[i]), want[i]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_open_loop_ramp),
        cmocka_unit_test(test_closed_loop_step),
        cmocka_unit_test(test_anti_windup),
        cmocka_unit_test(test_integrator_limit),
        cmocka_unit_test(test_set_limits),
        cmocka_unit_test(test_random_steps),
        cmocka_unit_test(test_set_gains),
        cmocka_unit_test(test_design_gains),
        cmocka_unit_test(test_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
