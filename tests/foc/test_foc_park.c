/* foc_park: angle_wrap_pu, angle_sincos, park_t and ipark_t against
 * double-precision references computed here from the same quantised
 * inputs; the park -> ipark round trip; the range edges. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "angle.h"
#include "ipark.h"
#include "park.h"
#include "foc_test_util.h"

/* angle_wrap_pu: result in [0, 1) and equal to a - floor(a) (exact in
 * IQ_MATH; in FLOAT_MATH within 1 ulp of the input, FLT_EPSILON * |a|, the
 * float subtraction of the integer part being exact except for the -tiny
 * -> 0 guard). */
static void check_wrap(_iq a)
{
    const _iq w = angle_wrap_pu(a);
    const double ad = iq2d(a);
    const double ref = ad - floor(ad);
    assert_true(iq2d(w) >= 0.0);
    assert_true(iq2d(w) < 1.0);
#if MATH_TYPE == IQ_MATH
    assert_true(iq2d(w) == ref);
#else
    /* distance on the circle: -tiny may wrap to 0 instead of 1 - tiny */
    assert_true(fmin(fabs(iq2d(w) - ref), 1.0 - fabs(iq2d(w) - ref))
                <= (double)FLT_EPSILON * (fabs(ad) + 1.0));
#endif
}

static void test_wrap(void **state)
{
    static const double edges[] = {
        -128.0, -127.5, -1.0, -0.5, -1.0 / 16777216.0, -1e-9, 0.0,
        1.0 / 16777216.0, 0.5, 1.0 - 1.0 / 16777216.0, 1.0, 1.0 + 1.0 / 16777216.0,
        2.75, 127.0, 128.0 - 1.0 / 16777216.0
    };
    foc_rng_t r = { 0xBADC0DEu };
    size_t i;
    int k;
    (void)state;
    for (i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        check_wrap(d2iq(edges[i]));
    }
    for (k = 0; k < 100000; k++) {
        check_wrap(d2iq(foc_rng_uniform(&r, -128.0, 127.999)));
    }
    /* worked values: -0.25 -> 0.75, 3.25 -> 0.25, 1.0 -> 0 */
    assert_true(iq2d(angle_wrap_pu(_IQ(-0.25))) == 0.75);
    assert_true(iq2d(angle_wrap_pu(_IQ(3.25))) == 0.25);
    assert_true(iq2d(angle_wrap_pu(_IQ(1.0))) == 0.0);
}

/* angle_sincos against sin/cos(2 pi a) in double.  IQ_MATH: the host
 * _IQsinPU/_IQcosPU are within 0.51 LSB (IQmathLib.h), the wrap is exact:
 * bound 1 LSB.  FLOAT_MATH: sinf(a * 2pi) with a in [0, 1): the argument
 * carries ~2 ulp of 2 pi (rounding of a*2pi and of 2pi itself, 2^-23 * 2pi
 * absolute), sinf 1 ulp: bound 8 FLT_EPSILON. */
static void test_sincos(void **state)
{
    foc_rng_t r = { 0x5EED5EEDu };
    double worst = 0.0, worst_norm = 0.0;
    int k;
    (void)state;
    for (k = 0; k < 200000; k++) {
        /* sweep of one revolution, then random angles over +-128 rev */
        const double ad = (k < 100000) ? (double)k / 100000.0
                                       : foc_rng_uniform(&r, -128.0, 127.999);
        const _iq a = d2iq(ad);
        const double aq = iq2d(a);
        const double th = 2.0 * FOC_PI * (aq - floor(aq));
        _iq s, c;
        double es, ec, n;
        angle_sincos(a, &s, &c);
        es = fabs(iq2d(s) - sin(th));
        ec = fabs(iq2d(c) - cos(th));
        assert_true(es <= foc_tol(1.0, 8.0, 1.0));
        assert_true(ec <= foc_tol(1.0, 8.0, 1.0));
        if (es > worst) { worst = es; }
        if (ec > worst) { worst = ec; }
        /* the pair is a unit vector to 2 x 1 LSB (or 16 eps) */
        n = fabs(iq2d(s) * iq2d(s) + iq2d(c) * iq2d(c) - 1.0);
        assert_true(n <= foc_tol(2.0, 16.0, 1.0));
        if (n > worst_norm) { worst_norm = n; }
    }
    print_message("foc_park sincos: worst error %.3g pu (%.2f LSB or FLT_EPSILON), |s^2+c^2-1| <= %.3g\n",
                  worst, worst / foc_tol(1.0, 1.0, 1.0), worst_norm);
}

/* One park and one ipark step against the double formulas with the same
 * (quantised) inputs.  IQ_MATH: each output is a sum/difference of two
 * products truncated toward -inf (each in (-1, 0] LSB): park ds, qs and
 * ipark beta lie in (-2, 0] LSB, ipark alpha in (-1, 1) LSB.  FLOAT_MATH:
 * two product roundings and one sum rounding, each <= 2^-24 of
 * |alpha| + |beta|: bound 2 FLT_EPSILON * (|alpha| + |beta|). */
static void check_park_ipark(_iq al, _iq be, _iq s, _iq c, double *worst)
{
    park_t p;
    ipark_t ip;
    const double a = iq2d(al), b = iq2d(be), sd = iq2d(s), cd = iq2d(c);
    double e1, e2, e3, e4;

    park_init(&p);
    p.alpha = al;
    p.beta = be;
    p.sine = s;
    p.cosine = c;
    park_step(&p);
    e1 = iq2d(p.ds) - (a * cd + b * sd);
    e2 = iq2d(p.qs) - (-a * sd + b * cd);

    ipark_init(&ip);
    ip.ds = al;          /* reuse the pair as a d-q input */
    ip.qs = be;
    ip.sine = s;
    ip.cosine = c;
    ipark_step(&ip);
    e3 = iq2d(ip.alpha) - (a * cd - b * sd);
    e4 = iq2d(ip.beta) - (a * sd + b * cd);
    {
        /* the argument forms the ISR calls: the same values (so the bounds
         * below hold for them); park_rotate reads its arguments, not the
         * struct's alpha/beta (set to something else here) */
        park_t q;
        _iq a2, b2;
        park_init(&q);
        q.alpha = be;
        q.beta = al;
        q.sine = s;
        q.cosine = c;
        park_rotate(&q, al, be);
        assert_true(q.ds == p.ds && q.qs == p.qs);
        ipark_rotate(al, be, s, c, &a2, &b2);
        assert_true(a2 == ip.alpha && b2 == ip.beta);
    }
#if MATH_TYPE == IQ_MATH
    assert_true(e1 > -2.0 * FOC_LSB && e1 <= 0.0);
    assert_true(e2 > -1.0 * FOC_LSB && e2 < 1.0 * FOC_LSB);
    assert_true(e3 > -1.0 * FOC_LSB && e3 < 1.0 * FOC_LSB);
    assert_true(e4 > -2.0 * FOC_LSB && e4 <= 0.0);
#else
    const double mag = fabs(a) + fabs(b);
    assert_true(fabs(e1) <= foc_tol(0.0, 2.0, mag));
    assert_true(fabs(e2) <= foc_tol(0.0, 2.0, mag));
    assert_true(fabs(e3) <= foc_tol(0.0, 2.0, mag));
    assert_true(fabs(e4) <= foc_tol(0.0, 2.0, mag));
#endif
    e1 = fmax(fmax(fabs(e1), fabs(e2)), fmax(fabs(e3), fabs(e4)));
    if (e1 > *worst) { *worst = e1; }
}

/* angle_sincos_step (angle.h): sin/cos of a + d from those of a by the
 * small-angle rotation, against double sin/cos(2 pi (a + d)) for random a
 * and |d| up to the 1/32 rev limit.  Bound: the input pair's own error
 * (angle_sincos: <= 1 LSB each, test_sincos) carried through the rotation
 * (<= 1.01 x 2 LSB), the series error (cos: x^6/720 = 1.3 LSB at the
 * limit), and the 11 truncated products (< 1 LSB each on the result):
 * 6 LSB in IQ_MATH; 16 float eps in FLOAT_MATH.  Beyond the limit the
 * absolute angle is used: bit-identical to angle_sincos(a + d). */
static void test_sincos_step(void **state)
{
    foc_rng_t r = { 0x51DE5EEDu };
    double worst = 0.0;
    int k;
    (void)state;
    for (k = 0; k < 100000; k++) {
        const double ad = foc_rng_uniform(&r, 0.0, 0.999999);
        const double dd = foc_rng_uniform(&r, -ANGLE_STEP_MAX_PU, ANGLE_STEP_MAX_PU);
        const _iq a = d2iq(ad), d = d2iq(dd);
        const double th = 2.0 * FOC_PI * (iq2d(a) + iq2d(d));
        _iq s, c, s2, c2;
        double e;
        angle_sincos(a, &s, &c);
        angle_sincos_step(s, c, a, d, &s2, &c2);
        e = fmax(fabs(iq2d(s2) - sin(th)), fabs(iq2d(c2) - cos(th)));
        worst = fmax(worst, e);
        assert_true(e <= foc_tol(6.0, 16.0, 1.0));
    }
    printf("angle_sincos_step: worst error %.3g over 1e5 steps, |d| <= 1/32 rev\n", worst);
    for (k = 0; k < 1000; k++) {
        const _iq a = d2iq(foc_rng_uniform(&r, 0.0, 0.999999));
        const _iq d = d2iq((k & 1) ? foc_rng_uniform(&r, 0.032, 0.99)
                                   : -foc_rng_uniform(&r, 0.032, 0.99));
        _iq s, c, s2, c2, s3, c3;
        angle_sincos(a, &s, &c);
        angle_sincos_step(s, c, a, d, &s2, &c2);
        angle_sincos(a + d, &s3, &c3);
        assert_true(s2 == s3 && c2 == c3);
    }
}

static void test_park_ipark_random(void **state)
{
    foc_rng_t r = { 0xC0FFEEu };
    double worst = 0.0;
    int k;
    (void)state;
    for (k = 0; k < 100000; k++) {
        const _iq al = d2iq(foc_rng_uniform(&r, -64.0, 64.0));
        const _iq be = d2iq(foc_rng_uniform(&r, -64.0, 64.0));
        _iq s, c;
        angle_sincos(d2iq(foc_rng_uniform(&r, -2.0, 2.0)), &s, &c);
        check_park_ipark(al, be, s, c, &worst);
    }
    print_message("foc_park park/ipark random: worst error %.3g pu (%.2f LSB or FLT_EPSILON)\n",
                  worst, worst / foc_tol(1.0, 1.0, 1.0));
}

/* Edges: |alpha|, |beta| = 64 at the angles where a product or a sum is
 * largest (45 deg: |ds| = 90.5 pu), with sine/cosine exactly +-1 and 0. */
static void test_park_edges(void **state)
{
    static const double v[] = { -64.0, 64.0 - 1.0 / 16777216.0 };
    static const double ang[] = { 0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875 };
    double worst = 0.0;
    size_t i, j, k;
    (void)state;
    for (k = 0; k < sizeof ang / sizeof ang[0]; k++) {
        _iq s, c;
        angle_sincos(d2iq(ang[k]), &s, &c);
        for (i = 0; i < 2; i++) {
            for (j = 0; j < 2; j++) {
                check_park_ipark(d2iq(v[i]), d2iq(v[j]), s, c, &worst);
            }
        }
    }
    check_park_ipark(d2iq(64.0 - 1.0 / 16777216.0), d2iq(-64.0), _IQ(1.0), _IQ(0.0), &worst);
    check_park_ipark(d2iq(-64.0), d2iq(-64.0), _IQ(0.0), _IQ(-1.0), &worst);
}

/* Physics: the rotating vector I e^(j th) seen in the frame at th is
 * (I, 0); ipark(park(x)) = x.  Round-trip bound from the error model above:
 * alpha' - alpha = alpha (s^2 + c^2 - 1) + eps_d c - eps_q s + eps_3 and
 * beta' - beta = beta (s^2 + c^2 - 1) + eps_d s + eps_q c + eps_4, with
 * |eps_d|, |eps_4| < 2 LSB and |eps_q|, |eps_3| < 1 LSB (see above), so
 * |error| <= |x| |s^2 + c^2 - 1| + 2 (|s| + |c|) + 2 LSB (IQ_MATH), with the
 * actual s, c of each sample; FLOAT_MATH: 12 FLT_EPSILON * |x| (two stages
 * of 2 FLT_EPSILON * (|u| + |v|) <= 2.8 FLT_EPSILON |x| each, plus
 * |s^2 + c^2 - 1| <= 4 FLT_EPSILON, rounded up).  The (I, 0) check adds the
 * sincos error (1 LSB or 8 FLT_EPSILON per factor, times I (|s| + |c|) <=
 * 1.42 I, i.e. 0.73 I LSB) and the input quantisation (0.5 LSB per
 * component, 0.71 LSB) to the park bound: 3 + I LSB, or 16 FLT_EPSILON * I. */
static void test_rotation_and_round_trip(void **state)
{
    foc_rng_t r = { 0xFEEDu };
    int k;
    (void)state;
    for (k = 0; k < 20000; k++) {
        const double I = foc_rng_uniform(&r, 0.0, 64.0);
        const double ad = foc_rng_uniform(&r, 0.0, 1.0);
        const _iq a = d2iq(ad);
        const double th = 2.0 * FOC_PI * iq2d(a);
        park_t p;
        ipark_t ip;
        _iq s, c;
        double sd, cd, n, bound;

        angle_sincos(a, &s, &c);
        sd = iq2d(s);
        cd = iq2d(c);
        park_init(&p);
        p.alpha = d2iq(I * cos(th));
        p.beta = d2iq(I * sin(th));
        p.sine = s;
        p.cosine = c;
        park_step(&p);
        assert_true(fabs(iq2d(p.ds) - I) <= foc_tol(3.0 + I, 16.0, I));
        assert_true(fabs(iq2d(p.qs)) <= foc_tol(3.0 + I, 16.0, I));

        ipark_init(&ip);
        ip.ds = p.ds;
        ip.qs = p.qs;
        ip.sine = s;
        ip.cosine = c;
        ipark_step(&ip);
#if MATH_TYPE == IQ_MATH
        n = fabs(sd * sd + cd * cd - 1.0);
        bound = (I * n / FOC_LSB + 2.0 * (fabs(sd) + fabs(cd)) + 2.0) * FOC_LSB;
#else
        (void)n;
        (void)sd;
        (void)cd;
        bound = 12.0 * (double)FLT_EPSILON * (I > 1.0 ? I : 1.0);
#endif
        assert_true(fabs(iq2d(ip.alpha) - iq2d(p.alpha)) <= bound);
        assert_true(fabs(iq2d(ip.beta) - iq2d(p.beta)) <= bound);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_sincos_step),
        cmocka_unit_test(test_park_ipark_random),
        cmocka_unit_test(test_park_edges),
        cmocka_unit_test(test_rotation_and_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
