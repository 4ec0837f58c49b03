/* foc_svgen: svgen_t against the classical sector / dwell-time SVPWM
 * computed here in double; reconstruction through volt_calc_t in the
 * linear range; over-modulation onto the hexagon with the angle kept;
 * compare values; the bus-fault guard; the range edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "svgen.h"
#include "volt_calc.h"
#include "foc_test_util.h"

#define SQRT3 1.73205080756887729353

/* Classical symmetric SVPWM: sector of the reference angle, dwell times of
 * the two adjacent active vectors (amplitude-invariant alpha-beta, active
 * vectors of length 2 vdc / 3)
 *     T1/Ts = sqrt(3) |u| / vdc * sin(pi/3 - th_s),
 *     T2/Ts = sqrt(3) |u| / vdc * sin(th_s),
 * the zero time T0 = Ts - T1 - T2 split equally between 000 and 111; each
 * phase's upper switch is on for T0/2 plus the active vectors in which it is
 * 1.  Outside the hexagon (T1 + T2 > Ts), T1 and T2 are scaled to sum to Ts
 * (the vector on the hexagon edge, same angle).  Returns 1 if it scaled. */
static int classic_svpwm(double ua, double ub, double vdc, double d[3])
{
    static const int sw[6][3] = {
        { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 1, 1 }, { 0, 0, 1 }, { 1, 0, 1 }
    };
    const double mag = hypot(ua, ub);
    double th = atan2(ub, ua), ths, t1, t2, t0;
    int sec, x, over = 0;
    if (th < 0.0) { th += 2.0 * FOC_PI; }
    sec = (int)floor(th / (FOC_PI / 3.0));
    if (sec > 5) { sec = 5; }
    ths = th - sec * (FOC_PI / 3.0);
    t1 = SQRT3 * mag / vdc * sin(FOC_PI / 3.0 - ths);
    t2 = SQRT3 * mag / vdc * sin(ths);
    if (t1 + t2 > 1.0) {
        const double s = t1 + t2;
        t1 /= s;
        t2 /= s;
        over = 1;
    }
    t0 = 1.0 - t1 - t2;
    for (x = 0; x < 3; x++) {
        d[x] = 0.5 * t0 + t1 * sw[sec][x] + t2 * sw[(sec + 1) % 6][x];
    }
    return over;
}

/* Bound on each duty.  IQ_MATH (svgen.h): with div = max(vdc, max - min),
 * the truncation of the product (1 LSB), the reciprocal's error (< 1 LSB)
 * times |v_x + v0| <= div/2, and the phase references' own errors
 * (truncations of ualpha/2 and sqrt3/2 ubeta, < 2 LSB each, up to 4 LSB in
 * a difference v_x - mid) divided by div: 2 + div/2 + 4/div LSB.
 * FLOAT_MATH: a handful of roundings of terms <= 1 + |v|/div: 8 FLT_EPSILON
 * times that. */
static double duty_bound(double div, double vmax_over_div)
{
    return foc_tol(2.0 + div / 2.0 + 4.0 / div, 8.0, 1.0 + vmax_over_div);
}

static double span_of(double ua, double ub)
{
    const double va = ua, vb = -0.5 * ua + 0.5 * SQRT3 * ub, vc = -0.5 * ua - 0.5 * SQRT3 * ub;
    return fmax(fmax(va, vb), vc) - fmin(fmin(va, vb), vc);
}

/* Compare value rule: CMPR = T1PR - round(d T1PR).  IQ_MATH: exactly, with
 * round() done here on the exact Q24 duty in 64-bit integers.  FLOAT_MATH:
 * within 0.5 count plus the float rounding of d * 2 T1PR (2^-24 relative,
 * < 0.01 count for T1PR <= 65535). */
static void check_compare(const svgen_t *s, _iq d, uint16_t cmpr)
{
    assert_true(cmpr <= s->t1pr);
#if MATH_TYPE == IQ_MATH
    {
        const int64_t on = ((int64_t)d * s->t1pr + ((int64_t)1 << 23)) >> 24;
        assert_int_equal(cmpr, (int64_t)s->t1pr - on);
    }
#else
    assert_true(fabs((double)(s->t1pr - cmpr) - (double)d * s->t1pr) <= 0.51);
#endif
}

static double run_case(svgen_t *s, double ua, double ub, double vdc, double *worst)
{
    double d[3], err = 0.0, div, sp;
    int over, x;
    const _iq *out[3];
    s->ualpha = d2iq(ua);
    s->ubeta = d2iq(ub);
    s->vdc = d2iq(vdc);
    svgen_step(s);
    /* the reference sees exactly the quantised inputs */
    ua = iq2d(s->ualpha);
    ub = iq2d(s->ubeta);
    vdc = iq2d(s->vdc);
    over = classic_svpwm(ua, ub, vdc, d);
    sp = span_of(ua, ub);
    div = fmax(vdc, sp);
    out[0] = &s->da;
    out[1] = &s->db;
    out[2] = &s->dc;
    for (x = 0; x < 3; x++) {
        const double e = fabs(iq2d(*out[x]) - d[x]);
        if (e > duty_bound(div, hypot(ua, ub) / div)) {
            print_error("u=(%.9g, %.9g) vdc=%.9g phase %d: d=%.12f classic=%.12f err %.3g bound %.3g\n",
                        ua, ub, vdc, x, iq2d(*out[x]), d[x], e, duty_bound(div, hypot(ua, ub) / div));
        }
        assert_true(e <= duty_bound(div, hypot(ua, ub) / div));
        assert_true(iq2d(*out[x]) >= 0.0 && iq2d(*out[x]) <= 1.0);
        check_compare(s, *out[x], s->cmpr[x]);
        if (e > err) { err = e; }
    }
    /* the flag follows the geometry, except within the duty bound of the
     * hexagon edge, where either answer is right */
    if (fabs(sp - vdc) > 1e-6 * vdc) {
        assert_int_equal(s->overmod, (uint16_t)over);
    }
    assert_int_equal(s->vdc_fault, 0u);
    if (err > *worst) { *worst = err; }
    return err;
}

static void test_init(void **state)
{
    svgen_t s;
    (void)state;
    assert_int_equal(svgen_init(&s, 0u), SVGEN_ERR_PERIOD);
    assert_int_equal(svgen_init(&s, 5000u), SVGEN_OK);
    assert_true(iq2d(s.da) == 0.5 && iq2d(s.db) == 0.5 && iq2d(s.dc) == 0.5);
    assert_int_equal(s.cmpr[0], 2500u);
    assert_int_equal(s.cmpr[2], 2500u);
}

/* Sweep of the angle (1/4 degree) at magnitudes from 0 to 1.3 times the
 * hexagon vertex (2 vdc / 3), nominal bus sqrt(3) pu, T1PR = 5000. */
static void test_classic_sweep(void **state)
{
    static const double rel[] = { 0.0, 0.01, 0.3, 0.5, 0.577, 0.57735, 0.6, 0.65, 0.6666, 0.8, 1.3 };
    svgen_t s;
    double worst = 0.0;
    size_t i;
    int k;
    (void)state;
    assert_int_equal(svgen_init(&s, 5000u), SVGEN_OK);
    for (i = 0; i < sizeof rel / sizeof rel[0]; i++) {
        for (k = 0; k < 1440; k++) {
            const double th = 2.0 * FOC_PI * k / 1440.0, m = rel[i] * SQRT3;
            run_case(&s, m * cos(th), m * sin(th), SQRT3, &worst);
        }
    }
    print_message("foc_svgen classic sweep: worst duty error %.3g (%.2f LSB or FLT_EPSILON)\n",
                  worst, worst / foc_tol(1.0, 1.0, 1.0));
}

/* Seeded random references over the whole valid range (|u| <= 32) and
 * buses from the fault guard to 100 pu, with T1PR random. */
static void test_classic_random(void **state)
{
    static const double buses[] = { 0.05, 0.3, SQRT3, 2.5, 16.0, 100.0 };
    foc_rng_t r = { 0x5A5A5A5Au };
    svgen_t s;
    double worst = 0.0;
    int k;
    (void)state;
    for (k = 0; k < 60000; k++) {
        const double vdc = (k % 7 == 6) ? foc_rng_uniform(&r, 0.05, 100.0) : buses[k % 6];
        /* half the cases inside 1.5 x the hexagon, half anywhere in range */
        const double lim = (k % 2 == 0) ? fmin(vdc, 32.0) : 32.0;
        assert_int_equal(svgen_init(&s, (uint16_t)(1u + foc_rng_u32(&r) % 65535u)), SVGEN_OK);
        run_case(&s, foc_rng_uniform(&r, -lim, lim), foc_rng_uniform(&r, -lim, lim), vdc, &worst);
    }
    /* corners of the valid range */
    assert_int_equal(svgen_init(&s, 65535u), SVGEN_OK);
    run_case(&s, 32.0, 32.0, 0.05, &worst);
    run_case(&s, -32.0, 32.0, 100.0, &worst);
    run_case(&s, -32.0, -32.0, 127.0, &worst);
    run_case(&s, 0.0, -32.0, SQRT3, &worst);
    print_message("foc_svgen classic random: worst duty error %.3g\n", worst);
}

/* Linear range, |u| <= vdc/sqrt(3) (and up to the hexagon edge): the
 * voltages volt_calc_t reconstructs from the duties and the same bus are the
 * reference.  Bound: va = vdc (da - mean(d)) carries vdc * 4/3 of the duty
 * error, vbeta = (vb - vc)/sqrt(3) vdc * 2/sqrt(3) of it; plus volt_calc's
 * own arithmetic (volt_calc.h: 3 and 4 LSB).  So 1.34 vdc eps_d + 4 LSB
 * (FLOAT_MATH: the same with eps_d in float, plus 8 FLT_EPSILON vdc). */
static void test_linear_reconstruction(void **state)
{
    static const double buses[] = { 0.5, SQRT3, 4.0, 16.0 };
    foc_rng_t r = { 0x77777u };
    svgen_t s;
    volt_calc_t v;
    double worst = 0.0;
    size_t b;
    int k;
    (void)state;
    assert_int_equal(svgen_init(&s, 5000u), SVGEN_OK);
    assert_int_equal(volt_calc_init(&v, 0.0f, 1.0f / 15000.0f, 0.0f, 0.05f, 0u), VOLT_CALC_OK);
    for (b = 0; b < sizeof buses / sizeof buses[0]; b++) {
        const double vdc = buses[b];
        for (k = 0; k < 20000; k++) {
            /* radius up to the inscribed circle, or (every 4th) up to the
             * hexagon edge in that direction */
            const double th = foc_rng_uniform(&r, 0.0, 2.0 * FOC_PI);
            const double ths = fmod(th, FOC_PI / 3.0);
            const double rmax = (k % 4 == 3) ? vdc / SQRT3 / cos(ths - FOC_PI / 6.0) : vdc / SQRT3;
            const double m = foc_rng_uniform(&r, 0.0, rmax * (1.0 - 1e-6));
            double ua, ub, eps_d, bound;
            s.ualpha = d2iq(m * cos(th));
            s.ubeta = d2iq(m * sin(th));
            s.vdc = d2iq(vdc);
            svgen_step(&s);
            assert_int_equal(s.overmod, 0u);
            ua = iq2d(s.ualpha);
            ub = iq2d(s.ubeta);
            v.da = s.da;
            v.db = s.db;
            v.dc = s.dc;
            v.vdc = s.vdc;
            volt_calc_step(&v);
            eps_d = duty_bound(vdc, m / vdc);
            bound = 1.34 * vdc * eps_d + foc_tol(4.0, 8.0, vdc);
            assert_true(fabs(iq2d(v.valpha) - ua) <= bound);
            assert_true(fabs(iq2d(v.vbeta) - ub) <= bound);
            if (fabs(iq2d(v.valpha) - ua) > worst) { worst = fabs(iq2d(v.valpha) - ua); }
            if (fabs(iq2d(v.vbeta) - ub) > worst) { worst = fabs(iq2d(v.vbeta) - ub); }
        }
    }
    print_message("foc_svgen linear reconstruction: worst %.3g pu (%.2f LSB or FLT_EPSILON)\n",
                  worst, worst / foc_tol(1.0, 1.0, 1.0));
}

/* Over-modulation: references outside the hexagon come out on its edge,
 * r_hex(th) = (vdc / sqrt3) / cos(th_s - pi/6), in their own direction,
 * with one duty at 1 and one at 0.  The output vector is reconstructed here
 * in double from the duties (va = vdc (da - mean d), vbeta = (vb - vc)/sqrt3
 * ); its error is at most 1.34 vdc eps_d per component, so the angle error
 * is at most 2 * 1.34 vdc eps_d / r_hex rad. */
static void test_overmodulation(void **state)
{
    static const double buses[] = { 0.2, SQRT3, 10.0 };
    svgen_t s;
    size_t b;
    int k;
    double worst_ang = 0.0;
    (void)state;
    assert_int_equal(svgen_init(&s, 5000u), SVGEN_OK);
    for (b = 0; b < sizeof buses / sizeof buses[0]; b++) {
        const double vdc = buses[b];
        for (k = 0; k < 3600; k++) {
            const double th = 2.0 * FOC_PI * (k + 0.5) / 3600.0;
            const double ths = fmod(th, FOC_PI / 3.0);
            const double rhex = vdc / SQRT3 / cos(ths - FOC_PI / 6.0);
            const double m = fmin(rhex * (1.05 + 2.0 * (k % 10)), 32.0);
            double ua, ub, da, db, dc, mean, va, vb, vc, ob, mag, dang, eps_d;
            s.ualpha = d2iq(m * cos(th));
            s.ubeta = d2iq(m * sin(th));
            s.vdc = d2iq(vdc);
            svgen_step(&s);
            assert_int_equal(s.overmod, 1u);
            ua = iq2d(s.ualpha);
            ub = iq2d(s.ubeta);
            da = iq2d(s.da);
            db = iq2d(s.db);
            dc = iq2d(s.dc);
            eps_d = duty_bound(span_of(ua, ub), 1.0);
            assert_true(fabs(fmax(fmax(da, db), dc) - 1.0) <= eps_d);
            assert_true(fabs(fmin(fmin(da, db), dc)) <= eps_d);
            mean = (da + db + dc) / 3.0;
            va = vdc * (da - mean);
            vb = vdc * (db - mean);
            vc = vdc * (dc - mean);
            ob = (vb - vc) / SQRT3;
            mag = hypot(va, ob);
            dang = fabs(remainder(atan2(ob, va) - atan2(ub, ua), 2.0 * FOC_PI));
            assert_true(fabs(mag - rhex) <= 2.0 * 1.34 * vdc * eps_d + foc_tol(1.0, 8.0, vdc));
            assert_true(dang <= 2.0 * 1.34 * vdc * eps_d / rhex + foc_tol(1.0, 8.0, 1.0) / rhex);
            if (dang > worst_ang) { worst_ang = dang; }
        }
    }
    print_message("foc_svgen overmodulation: worst angle error %.3g rad\n", worst_ang);
}

/* Bus fault: vdc below SVGEN_VDC_MIN_PU (0.05) -> 50 % on every phase and
 * vdc_fault; at the guard it runs normally. */
static void test_vdc_guard(void **state)
{
    static const double bad[] = { 0.0, -1.0, -128.0, 0.0499, 1.0 / 16777216.0 };
    svgen_t s;
    size_t i;
    double worst = 0.0;
    (void)state;
    assert_int_equal(svgen_init(&s, 4999u), SVGEN_OK);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s.ualpha = _IQ(0.7);
        s.ubeta = _IQ(-0.3);
        s.vdc = d2iq(bad[i]);
        svgen_step(&s);
        assert_int_equal(s.vdc_fault, 1u);
        assert_int_equal(s.overmod, 0u);
        assert_true(iq2d(s.da) == 0.5 && iq2d(s.db) == 0.5 && iq2d(s.dc) == 0.5);
        /* round(0.5 * 4999) = round(2499.5) = 2500 -> CMPR 2499 */
        assert_int_equal(s.cmpr[0], 2499u);
        assert_int_equal(s.cmpr[1], 2499u);
        assert_int_equal(s.cmpr[2], 2499u);
    }
    run_case(&s, 0.01, 0.02, 0.05, &worst);
    assert_int_equal(s.vdc_fault, 0u);
}

/* svgen_set_vdc: the same outputs as the bus set directly (bit for bit),
 * its reciprocal taken at the set, so that a step with that bus does not
 * divide again; a bus below the minimum is stored, not inverted (the step's
 * bus fault as before). */
static void test_set_vdc(void **state)
{
    static const double buses[] = { 1.732, 1.5, 0.9, 1.732 };
    svgen_t a, b;
    size_t i;
    (void)state;
    assert_int_equal(svgen_init(&a, 5000u), SVGEN_OK);
    assert_int_equal(svgen_init(&b, 5000u), SVGEN_OK);
    for (i = 0; i < sizeof buses / sizeof buses[0]; i++) {
        const _iq v = d2iq(buses[i]);
        svgen_set_vdc(&a, v);
        assert_true(a.vdc == v && a.vdc_seen == v);
        /* Q24 reciprocal as _IQdiv gives it */
        assert_true(a.inv_vdc == _IQdiv(_IQ(1.0), v));
        b.vdc = v;
        a.ualpha = b.ualpha = _IQ(0.6);
        a.ubeta = b.ubeta = _IQ(-0.25);
        svgen_step(&a);
        svgen_step(&b);
        assert_int_equal(a.cmpr[0], b.cmpr[0]);
        assert_int_equal(a.cmpr[1], b.cmpr[1]);
        assert_int_equal(a.cmpr[2], b.cmpr[2]);
        assert_true(a.da == b.da && a.db == b.db && a.dc == b.dc);
    }
    svgen_set_vdc(&a, d2iq(0.01));   /* below SVGEN_VDC_MIN_PU */
    assert_true(a.vdc == d2iq(0.01) && a.vdc_seen == d2iq(1.732));
    svgen_step(&a);
    assert_int_equal(a.vdc_fault, 1u);
}

/* Compare values at the duty extremes, T1PR from 1 to 65535: always within
 * [0, T1PR]; d = 1 -> 0, d = 0 -> T1PR. */
static void test_compare_edges(void **state)
{
    static const uint16_t prs[] = { 1u, 2u, 3u, 5000u, 65535u };
    svgen_t s;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof prs / sizeof prs[0]; i++) {
        assert_int_equal(svgen_init(&s, prs[i]), SVGEN_OK);
        s.ualpha = _IQ(32.0 - 1.0 / 16777216.0);    /* far outside: phase a at 1, b and c at 0 */
        s.ubeta = _IQ(0.0);
        s.vdc = _IQ(1.0);
        svgen_step(&s);
        assert_int_equal(s.overmod, 1u);
        /* within the duty bound of 1 (the reciprocal is truncated), which
         * is far below half a count even at T1PR = 65535 */
        assert_true(fabs(iq2d(s.da) - 1.0) <= duty_bound(1.5 * 32.0, 1.0));
        assert_int_equal(s.cmpr[0], 0u);
        assert_true(s.cmpr[1] == prs[i] && s.cmpr[2] == prs[i]);
        check_compare(&s, s.db, s.cmpr[1]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_classic_sweep),
        cmocka_unit_test(test_classic_random),
        cmocka_unit_test(test_linear_reconstruction),
        cmocka_unit_test(test_overmodulation),
        cmocka_unit_test(test_vdc_guard),
        cmocka_unit_test(test_set_vdc),
        cmocka_unit_test(test_compare_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
