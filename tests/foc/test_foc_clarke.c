/* foc_clarke: clarke_t against the double-precision transform
 * alpha = as, beta = (as + 2 bs)/sqrt(3), computed here from the very same
 * (quantised) inputs, over sweeps, random inputs and the range edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "clarke.h"
#include "foc_test_util.h"

/* Error bound for beta.  IQ_MATH: two truncated Q24*Q30 -> Q24 products
 * (each within 1 LSB below the exact product) plus the quantisation of the
 * Q30 constants (_IQ30 truncates: < 2^-30 each), which costs
 * < |x| * 2^-30 pu = |x|/64 LSB per term.  So |error| < 2 + (|as| + |bs|)/64
 * LSB.  FLOAT_MATH: each product carries the constant's and the product's
 * rounding (2 x 2^-24 relative), the sum one more (2^-24 of the sum), so
 * |error| < 3 * 2^-24 * (|as|/sqrt3 + 2|bs|/sqrt3) <= 1.5 FLT_EPSILON * mag;
 * 2 FLT_EPSILON * mag is used. */
static double beta_bound(double as, double bs)
{
    return foc_tol(2.0 + (fabs(as) + fabs(bs)) / 64.0, 2.0,
                   (fabs(as) + 2.0 * fabs(bs)) / sqrt(3.0));
}

static void check_one(_iq as, _iq bs, double *worst_lsb)
{
    clarke_t c;
    double a, b, beta_ref, err;

    clarke_init(&c);
    c.as = as;
    c.bs = bs;
    clarke_step(&c);
    a = iq2d(as);
    b = iq2d(bs);
    beta_ref = (a + 2.0 * b) / sqrt(3.0);
    /* alpha is a copy: exact in both builds */
    assert_true(iq2d(c.alpha) == a);
    /* the argument form the ISR calls (clarke_beta) is the same beta, so
     * the bound below holds for it too */
    assert_true(clarke_beta(as, bs) == c.beta);
    err = fabs(iq2d(c.beta) - beta_ref);
    if (err > beta_bound(a, b)) {
        print_error("as=%.9g bs=%.9g beta=%.12g ref=%.12g err=%.3g bound=%.3g\n",
                    a, b, iq2d(c.beta), beta_ref, err, beta_bound(a, b));
    }
    assert_true(err <= beta_bound(a, b));
    if (err / foc_tol(1.0, 1.0, 1.0) > *worst_lsb) {
        *worst_lsb = err / foc_tol(1.0, 1.0, 1.0);
    }
}

/* Balanced sets ia = I cos(th), ib = I cos(th - 2 pi/3): amplitude
 * invariance, alpha + j beta = I e^(j th) (analytic), for I from 1 mA-level
 * to the edge of the valid range (I = 64 keeps |as|, |bs| <= 64). */
static void test_balanced_sweep(void **state)
{
    static const double amps[] = { 1e-3, 0.5, 1.0, 10.0, 64.0 };
    double worst = 0.0;
    size_t i;
    int k;
    (void)state;
    for (i = 0; i < sizeof amps / sizeof amps[0]; i++) {
        for (k = 0; k < 720; k++) {
            const double th = 2.0 * FOC_PI * k / 720.0;
            const double I = amps[i] * (1.0 - 1e-9);   /* stay below +64 after rounding */
            const _iq as = d2iq(I * cos(th));
            const _iq bs = d2iq(I * cos(th - 2.0 * FOC_PI / 3.0));
            clarke_t c;
            check_one(as, bs, &worst);
            /* against the analytic vector as well: the input quantisation
             * (0.5 LSB each, ~1.2 LSB in beta) plus the bound above */
            clarke_init(&c);
            c.as = as;
            c.bs = bs;
            clarke_step(&c);
            assert_true(fabs(iq2d(c.beta) - I * sin(th))
                        <= beta_bound(I, I) + foc_tol(1.5, 2.0, I));
        }
    }
    print_message("foc_clarke balanced sweep: worst beta error %.3f (LSB or FLT_EPSILON)\n", worst);
}

/* 100 000 seeded random pairs over the whole valid range +-64 pu. */
static void test_random(void **state)
{
    foc_rng_t r = { 0x12345678u };
    double worst = 0.0;
    int k;
    (void)state;
    for (k = 0; k < 100000; k++) {
        const _iq as = d2iq(foc_rng_uniform(&r, -64.0, 64.0));
        const _iq bs = d2iq(foc_rng_uniform(&r, -64.0, 64.0));
        check_one(as, bs, &worst);
    }
    print_message("foc_clarke random: worst beta error %.3f (LSB or FLT_EPSILON)\n", worst);
}

/* Corners of the valid range: the largest |beta| = 3*64/sqrt3 = 110.9 pu
 * must come out with the right sign (no wrap). */
static void test_edges(void **state)
{
    static const double v[] = { -64.0, -1.0, 0.0, 1.0, 64.0 - 1.0 / 16777216.0 };
    double worst = 0.0;
    size_t i, j;
    (void)state;
    for (i = 0; i < 5; i++) {
        for (j = 0; j < 5; j++) {
            check_one(d2iq(v[i]), d2iq(v[j]), &worst);
        }
    }
    {
        clarke_t c;
        clarke_init(&c);
        c.as = d2iq(64.0 - 1.0 / 16777216.0);
        c.bs = c.as;
        clarke_step(&c);
        assert_true(iq2d(c.beta) > 110.8);
        c.as = d2iq(-64.0);
        c.bs = c.as;
        clarke_step(&c);
        assert_true(iq2d(c.beta) < -110.8);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_balanced_sweep),
        cmocka_unit_test(test_random),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
