/* estim_param_extract: motor parameters from the regression estimates
 * (method §4, eq. 10 rewritten).  The method's check (K1 = -264.548 1/s,
 * K2 = 210.623 1/H, K3' = 1.47675 V, K4 = -6.15385 A, i_M = 6.5625 A give
 * Rs 1.031, Rr 0.465, Lm 0.0064, Lr 0.0092, psi_r 0.042, Tr 0.01978) in per
 * unit (I_base 20 A, V_base 60/sqrt3 V, f_base 50 Hz), both regressor
 * forms, and every rejection path. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "param_extract.h"
#include "estim_test_util.h"

#define PI_D 3.14159265358979323846

typedef struct {
    base_values_t b;
    param_limits_t lim;
    param_extract_t p;
    /* the check, SI */
    double K1, K2, K3p, K4, im;
} fx_t;

static fx_t fx;

static int setup(void **state)
{
    (void)state;
    assert_int_equal(base_values_init(&fx.b, 20.0f, 60.0f / 1.7320508f, 50.0f, 2u, 1.0f / 15000.0f),
                     BASE_OK);
    fx.lim = (param_limits_t){
        .Rs_ohm = {0.1f, 10.0f}, .Rr_ohm = {0.05f, 5.0f}, .Lm_H = {1e-3f, 0.05f},
        .Lr_H = {1e-3f, 0.06f}, .psi_Wb = {0.005f, 0.2f}, .Tr_s = {0.002f, 0.2f},
        .i_m_min_A = 0.5f};
    assert_int_equal(param_extract_init(&fx.p, &fx.b, &fx.lim), PARAM_INIT_OK);
    fx.K1 = -264.548; fx.K2 = 210.623; fx.K3p = 1.47675; fx.K4 = -6.15385; fx.im = 6.5625;
    return 0;
}

/* the check in pu: K1/w_base, K2 V_base/(I_base w_base), K3'/V_base (paper
 * form) or K3 = K2 K3' in pu = K3/(I_base w_base) (constant form),
 * K4/I_base, i_M/I_base */
static void load(param_extract_t *p, int paper, double K1, double K2, double K3p, double K4, double im)
{
    const double wb = (double)fx.b.w_base_rad_s, Ib = (double)fx.b.I_base_A, Vb = (double)fx.b.V_base_V;
    p->theta[0] = d_to_iq(K1 / wb);
    p->theta[1] = d_to_iq(K2 * Vb / (Ib * wb));
    p->theta[2] = paper ? d_to_iq(K3p / Vb) : d_to_iq(K2 * K3p / (Ib * wb));
    p->theta[3] = d_to_iq(K4 / Ib);
    p->form = paper ? (uint16_t)RLS_FORM_PAPER : (uint16_t)RLS_FORM_CONST;
    p->i_m = d_to_iq(im / Ib);
}

/* The check, both forms.  Two comparisons:
 *  (1) against the same formulas in double from the same (Q24-quantised)
 *      pu inputs: each output within 8 LSB24 + 2e-6 relative (IQ: five
 *      to seven chained Q24 operations, _IQdiv truncating < 1 LSB, _IQsqrt
 *      <= 0.5 LSB, each rounding amplified by the following quotients by
 *      at most |1/K2|, |1/i_M| ~ 3: a few LSB; the relative term covers
 *      the Q24 quantisation of the small K3' = 0.0426 pu (1.4e-6 relative)
 *      propagating into Rr and Tr; FLOAT: 24-bit float, same bound);
 *  (2) against the method's reference values in SI: within 0.1 %, the
 *      published K values and references having 4-6 significant digits
 *      (Lm 0.0064, psi_r 0.042 are given to 2: within 0.5 % of them; the
 *      formulas give 0.0064000 and 0.0420 to 5 digits). */
static void check_reference(int paper)
{
    param_extract_t *p = &fx.p;
    const double wb = (double)fx.b.w_base_rad_s;
    double K1, K2, K3p, K4, im, a, Lr, Lm, psi, Rr, Rs, Tr;
    load(p, paper, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    param_extract_step(p);
    assert_int_equal(p->status, PARAM_OK);
    assert_int_equal(p->valid, 1);
    /* (1) double formulas on the quantised inputs */
    K1 = iq_to_d(p->theta[0]); K2 = iq_to_d(p->theta[1]); K4 = iq_to_d(p->theta[3]);
    K3p = paper ? iq_to_d(p->theta[2]) : iq_to_d(p->theta[2]) / K2;
    im = iq_to_d(p->i_m);
    a = -K4 / (K2 * im);
    Lr = 1.0 / K2 + a;
    Lm = sqrt(a * Lr);
    psi = Lm * im;
    Rr = K3p * Lr / (a * im);
    Rs = -K1 / K2 - K3p / im;
    Tr = -K4 / (K2 * K3p);
    print_message("%s: Rs %.7f/%.7f Rr %.7f/%.7f Lm %.7f/%.7f Lr %.7f/%.7f psi %.7f/%.7f Tr %.6f/%.6f pu\n",
                  paper ? "paper" : "const", iq_to_d(p->Rs), Rs, iq_to_d(p->Rr), Rr, iq_to_d(p->Lm), Lm,
                  iq_to_d(p->Lr), Lr, iq_to_d(p->psi_r), psi, qn_to_d(p->Tr, 20), Tr);
#define NEAR(x, ref) assert_true(fabs(iq_to_d(x) - (ref)) <= 8.0 * LSB24 + 2e-6 * fabs(ref))
    NEAR(p->Rs, Rs); NEAR(p->Rr, Rr); NEAR(p->Lm, Lm); NEAR(p->Lr, Lr); NEAR(p->psi_r, psi);
#undef NEAR
    /* Tr is Q20: its truncation (< 1 LSB20) on top */
    assert_true(fabs(qn_to_d(p->Tr, 20) - Tr) <= LSB20 + 8.0 * LSB24 + 2e-6 * Tr);
    /* (2) the method's reference values, SI */
#define REL(x, base, ref, tol) assert_true(fabs(iq_to_d(x) * (double)(base) / (ref) - 1.0) <= (tol))
    REL(p->Rs, fx.b.Z_base_ohm, 1.031, 1e-3);
    REL(p->Rr, fx.b.Z_base_ohm, 0.465, 1e-3);
    REL(p->Lm, fx.b.L_base_H, 0.0064, 5e-3);
    REL(p->Lr, fx.b.L_base_H, 0.0092, 1e-3);
    REL(p->psi_r, fx.b.psi_base_Wb, 0.042, 5e-3);
#undef REL
    assert_true(fabs(qn_to_d(p->Tr, 20) / wb / 0.01978 - 1.0) <= 1e-3);
}

static void test_reference_paper_form(void **state)
{
    (void)state;
    check_reference(1);
}

static void test_reference_const_form(void **state)
{
    (void)state;
    check_reference(0);
}

/* The flux form (RLS_FORM_FLUX): theta3, theta4 are K3, K4 at the
 * nameplate's i_M, here 10 % above the flux current i_m the run had
 * (theta = K x 1.1); with inv_im_nom = 1/(1.1 i_m) the extraction must give
 * the constant form's parameters: within 16 LSB24 + 4e-6 relative of them
 * (the constant form's own bound, doubled for the two rounded products
 * that bring theta3, theta4 to the flux: m_M / i_M,nom and K x that), and
 * the method's SI values as check_reference. */
static void test_reference_flux_form(void **state)
{
    param_extract_t c, f;
    const double wb = (double)fx.b.w_base_rad_s, Ib = (double)fx.b.I_base_A;
    (void)state;
    c = fx.p;
    load(&c, 0, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    param_extract_step(&c);
    assert_int_equal(c.status, PARAM_OK);
    f = c;
    f.form = (uint16_t)RLS_FORM_FLUX;
    f.theta[2] = d_to_iq(iq_to_d(c.theta[2]) * 1.1);
    f.theta[3] = d_to_iq(iq_to_d(c.theta[3]) * 1.1);
    f.inv_im_nom = d_to_iq(Ib / (1.1 * fx.im));
    param_extract_step(&f);
    assert_int_equal(f.status, PARAM_OK);
    assert_int_equal(f.valid, 1);
#define SAME(x) assert_true(fabs(iq_to_d(f.x) - iq_to_d(c.x)) <= 16.0 * LSB24 + 4e-6 * fabs(iq_to_d(c.x)))
    SAME(Rs); SAME(Rr); SAME(Lm); SAME(Lr); SAME(psi_r); SAME(K3p);
#undef SAME
    assert_true(fabs(qn_to_d(f.Tr, 20) - qn_to_d(c.Tr, 20)) <=
                2.0 * LSB20 + 4e-6 * qn_to_d(c.Tr, 20));
    assert_true(fabs(iq_to_d(f.Rr) * (double)fx.b.Z_base_ohm / 0.465 - 1.0) <= 1e-3);
    assert_true(fabs(qn_to_d(f.Tr, 20) / wb / 0.01978 - 1.0) <= 1e-3);
    /* the same theta read as the constant form would be 10 % off: the
     * flux unit matters */
    f.form = (uint16_t)RLS_FORM_CONST;
    param_extract_step(&f);
    assert_true(fabs(iq_to_d(f.Lr) / iq_to_d(c.Lr) - 1.0) > 0.01);
}

/* Each rejection: status, valid = 0. */
static void expect(param_status_t st)
{
    param_extract_step(&fx.p);
    assert_int_equal(fx.p.status, st);
    assert_int_equal(fx.p.valid, 0);
}

static void test_rejections(void **state)
{
    param_extract_t *p = &fx.p;
    (void)state;
    /* i_M below its minimum (0.5 A) */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, 0.4);
    expect(PARAM_ERR_IM);
    /* K2 <= 0, and K2 ~ 0 (1/K2 beyond Q24) */
    load(p, 1, fx.K1, -fx.K2, fx.K3p, fx.K4, fx.im);
    expect(PARAM_ERR_K2);
    load(p, 1, fx.K1, 0.0, fx.K3p, fx.K4, fx.im);
    expect(PARAM_ERR_K2);
    p->theta[1] = d_to_iq(1e-3);             /* 1/K2 = 1000 pu > 127 */
    expect(PARAM_ERR_K2);
    /* constant form: K3/K2 with K2 tiny but 1/K2 representable: K3/K2 too big */
    load(p, 0, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    p->theta[1] = d_to_iq(0.02);
    p->theta[2] = d_to_iq(3.0);              /* K3/K2 = 150 > 127 */
    expect(PARAM_ERR_DIV);
    /* K3' <= 0 */
    load(p, 1, fx.K1, fx.K2, -fx.K3p, fx.K4, fx.im);
    expect(PARAM_ERR_K3);
    /* negative square-root argument: K4 > 0 makes a = Lm^2/Lr < 0 */
    load(p, 1, fx.K1, fx.K2, fx.K3p, -fx.K4, fx.im);
    expect(PARAM_ERR_SQRT);
    /* K4 = 0: a = 0, Lm = 0 (no magnetising inductance): rejected */
    load(p, 1, fx.K1, fx.K2, fx.K3p, 0.0, fx.im);
    expect(PARAM_ERR_SQRT);
    /* a = -K4/(K2 i_M) with K2 i_M tiny: division by ~0 */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    p->theta[1] = d_to_iq(0.0100);           /* 1/K2 = 100 pu: representable */
    p->theta[3] = d_to_iq(-2.0);             /* a = 2/(0.01*0.328) = 610 pu */
    expect(PARAM_ERR_DIV);
    /* a product beyond Q24: K3' Lr = 2 x 112 with a = 12, 1/K2 = 100 (Lm^2 =
     * a Lr = 1344 is not formed: Lm = sqrt(a) sqrt(Lr) = 36.7 pu) */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    p->theta[1] = d_to_iq(0.0100);
    p->theta[2] = d_to_iq(2.0);              /* K3' = 2 pu (paper form) */
    p->theta[3] = d_to_iq(-0.01 * 0.328125 * 12.0);
    expect(PARAM_ERR_OVERFLOW);
    /* results outside their ranges (one at a time, from the check):
     * Rs: K1 larger in magnitude -> Rs = -K1/K2 - K3'/i_M above 10 ohm */
    load(p, 1, fx.K1 * 20.0, fx.K2, fx.K3p, fx.K4, fx.im);
    expect(PARAM_ERR_RS);
    /* Rr: K3' x 20 -> Rr 9.3 ohm > 5 (K1 x 5 keeps Rs = 1.8 ohm in range:
     * Rs is checked first) */
    load(p, 1, fx.K1 * 5.0, fx.K2, fx.K3p * 20.0, fx.K4, fx.im);
    expect(PARAM_ERR_RR);
    /* Lm: K4 / 100 -> a / 100, Lm 0.46 mH < 1 mH (K3' / 100 keeps Rr at
     * 0.24 ohm, in range: Rr is checked before Lm) */
    load(p, 1, fx.K1, fx.K2, fx.K3p / 100.0, fx.K4 / 100.0, fx.im);
    expect(PARAM_ERR_LM);
    /* Lr: K2 / 20 -> Lr 0.0994 H > 0.06 (K1, K4 / 20 keep -K1/K2 and a;
     * K3' / 2 keeps Rr = 2.5 ohm in range; Lm 0.021 H, Tr 40 ms in range) */
    load(p, 1, fx.K1 / 20.0, fx.K2 / 20.0, fx.K3p / 2.0, fx.K4 / 20.0, fx.im);
    expect(PARAM_ERR_LR);
    /* psi: i_M x 12 -> psi_r 0.5 Wb > 0.2 (K4, K3' x 12 keep a, Lr, Lm,
     * Rr, Rs and Tr unchanged) */
    load(p, 1, fx.K1, fx.K2, fx.K3p * 12.0, fx.K4 * 12.0, fx.im * 12.0);
    expect(PARAM_ERR_PSI);
    /* Tr: narrow the Tr range with a fresh init so that 19.8 ms is outside */
    {
        param_limits_t l = fx.lim;
        param_extract_t q;
        l.Tr_s[0] = 0.025f;
        l.Tr_s[1] = 0.2f;
        assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_OK);
        load(&q, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
        param_extract_step(&q);
        assert_int_equal(q.status, PARAM_ERR_TR);
        assert_int_equal(q.valid, 0);
    }
    /* and back to valid */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    param_extract_step(p);
    assert_int_equal(p->valid, 1);
}

/* A large motor's Tr (tens of kW: Tr 0.3 to 1 s, ~100 to 300 pu, beyond
 * Q24's 128): pu model Rs 0.02, Rr 0.01, Lm 3.0, Ls = Lr 3.1, i_M 0.3, so
 * Tr = Lr/Rr = 310 pu; its K values from method §4 (K2 = 1/(sigma Ls),
 * a = Lm^2/Lr, K4 = -a K2 i_M, K3' = Lm^2 Rr i_M / Lr^2, K1 = -K2 (Rs +
 * K3'/i_M)), both forms.  Tr against the formula in double on the quantised
 * inputs: 1 LSB20 (the Q20 quotient's truncation) + 3e-5 relative (the
 * constant form's K3' = theta3/K2 = 0.0028 pu truncated to Q24: < 1 LSB24,
 * 2.1e-5; K2 K3' = 0.014 pu rounded to 0.5 LSB24: 2.1e-6; the paper form
 * measures 2e-8);
 * and against the model's 310 within 0.01 % (the K values' quantisation).
 * A Tr above the range is PARAM_ERR_TR, a quotient beyond Q20 PARAM_ERR_DIV. */
static void test_large_tr(void **state)
{
    const double rs = 0.02, rr = 0.01, lm = 3.0, lr = 3.1, im = 0.3;
    const double a = lm * lm / lr, k2 = 1.0 / (lr - a);
    const double k3p = lm * lm * rr * im / (lr * lr);
    param_limits_t l = fx.lim;
    param_extract_t q;
    int paper;
    (void)state;

    l.Rs_ohm[0] = 0.001f; l.Rr_ohm[0] = 0.001f;
    l.Tr_s[0] = 0.1f; l.Tr_s[1] = 3.0f;       /* 31 to 942 pu */
    for (paper = 0; paper <= 1; paper++) {
        double K2, K3p, K4, Tr;
        assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_OK);
        q.theta[0] = d_to_iq(-k2 * (rs + k3p / im));
        q.theta[1] = d_to_iq(k2);
        q.theta[2] = paper ? d_to_iq(k3p) : d_to_iq(k2 * k3p);
        q.theta[3] = d_to_iq(-a * k2 * im);
        q.form = paper ? (uint16_t)RLS_FORM_PAPER : (uint16_t)RLS_FORM_CONST;
        q.i_m = d_to_iq(im);
        param_extract_step(&q);
        assert_int_equal(q.status, PARAM_OK);
        K2 = iq_to_d(q.theta[1]); K4 = iq_to_d(q.theta[3]);
        K3p = paper ? iq_to_d(q.theta[2]) : iq_to_d(q.theta[2]) / K2;
        Tr = -K4 / (K2 * K3p);
        print_message("%s: Tr %.6f / %.6f pu (model 310)\n", paper ? "paper" : "const",
                      qn_to_d(q.Tr, 20), Tr);
        assert_true(fabs(qn_to_d(q.Tr, 20) - Tr) <= LSB20 + 3e-5 * Tr);
        assert_true(fabs(qn_to_d(q.Tr, 20) / 310.0 - 1.0) <= 1e-4);
        assert_true(fabs(iq_to_d(q.Rr) / rr - 1.0) <= 1e-3);
    }
    /* Tr 310 pu above a range ending at 0.5 s = 157 pu */
    l.Tr_s[1] = 0.5f;
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_OK);
    q.theta[0] = d_to_iq(-k2 * (rs + k3p / im));
    q.theta[1] = d_to_iq(k2);
    q.theta[2] = d_to_iq(k3p);
    q.theta[3] = d_to_iq(-a * k2 * im);
    q.form = (uint16_t)RLS_FORM_PAPER;
    q.i_m = d_to_iq(im);
    param_extract_step(&q);
    assert_int_equal(q.status, PARAM_ERR_TR);
    assert_int_equal(q.valid, 0);
    /* K3' 1/1000 of it: Tr 310000 pu, beyond Q20 (the division's status
     * comes before any range check) */
    q.theta[2] = d_to_iq(k3p / 1000.0);
    param_extract_step(&q);
    assert_int_equal(q.status, PARAM_ERR_DIV);
    assert_int_equal(q.valid, 0);
}

static void test_init_rejects(void **state)
{
    param_extract_t q;
    param_limits_t l = fx.lim;
    base_values_t zero = {0};
    (void)state;
    assert_int_equal(param_extract_init(&q, &zero, &l), PARAM_INIT_ERR_BASES);
    l.Rs_ohm[0] = -0.1f;
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_ERR_RANGE);
    l = fx.lim;
    l.Lm_H[0] = 0.06f;                        /* min > max */
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_ERR_RANGE);
    l = fx.lim;
    l.Tr_s[1] = 1.0f;                         /* 314 pu: Q20 (a 55 kW motor's 0.93 s is 292) */
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_OK);
    assert_true(fabs(qn_to_d(q.Tr_lim[1], 20) - 1.0 * (double)fx.b.w_base_rad_s) <=
                LSB20 + 1e-7 * 314.2);
    l.Tr_s[1] = 7.0f;                         /* 2199 pu: not representable in Q20 */
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_ERR_RANGE);
    l = fx.lim;
    l.i_m_min_A = 0.0f;
    assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_ERR_IM);
    assert_int_equal(q.valid, 0);
}

/* param_extract_check, the configuration table's test: param_extract_init's
 * verdict, naming the first range refused.  Each range's top just below
 * and just above PARAM_EXTRACT_PU_MAX (Tr: 2047) of its base, in turn;
 * a minimum below 0; two ranges refused at once name the first in
 * param_limits_t's order; i_m_min_A not > 0. */
static void test_check(void **state)
{
    const param_status_t names[] = {PARAM_ERR_RS, PARAM_ERR_RR, PARAM_ERR_LM, PARAM_ERR_LR,
                                    PARAM_ERR_PSI, PARAM_ERR_TR};
    const float base[] = {fx.b.Z_base_ohm, fx.b.Z_base_ohm, fx.b.L_base_H, fx.b.L_base_H,
                          fx.b.psi_base_Wb, fx.b.t_base_s};
    param_extract_t q;
    param_status_t bad;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof names / sizeof names[0]; i++) {
        param_limits_t l = fx.lim;
        float *hi[] = {&l.Rs_ohm[1], &l.Rr_ohm[1], &l.Lm_H[1], &l.Lr_H[1], &l.psi_Wb[1],
                       &l.Tr_s[1]};
        const float top = ((i == 5u) ? 2047.0f : PARAM_EXTRACT_PU_MAX) * base[i];
        *hi[i] = top * 0.9999f;
        assert_int_equal(param_extract_check(&fx.b, &l, &bad), PARAM_INIT_OK);
        assert_int_equal(bad, PARAM_OK);
        assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_OK);
        *hi[i] = top * 1.0001f;
        assert_int_equal(param_extract_check(&fx.b, &l, &bad), PARAM_INIT_ERR_RANGE);
        assert_int_equal(bad, names[i]);
        assert_int_equal(param_extract_init(&q, &fx.b, &l), PARAM_INIT_ERR_RANGE);
    }
    {
        param_limits_t l = fx.lim;
        l.Rr_ohm[0] = nextafterf(0.0f, -1.0f);
        l.Lr_H[0] = -1.0f;
        assert_int_equal(param_extract_check(&fx.b, &l, &bad), PARAM_INIT_ERR_RANGE);
        assert_int_equal(bad, PARAM_ERR_RR);
        l = fx.lim;
        l.i_m_min_A = 0.0f;
        assert_int_equal(param_extract_check(&fx.b, &l, NULL), PARAM_INIT_ERR_IM);
    }
}

/* param_extract_magnetic (fused mode): Lm, Lr, psi_r from K2, K4, i_M only.
 * (1) For the check (both forms) it gives what param_extract_step gives:
 *     the same a = -K4/(K2 i_M), Lr = 1/K2 + a, Lm = sqrt(a Lr), psi = Lm
 *     i_M, so the same values within 1 LSB (IQ: the same operations in the
 *     same order, bit-identical; FLOAT too); Rs, Rr, Tr and K3p are 0 even
 *     when the struct held a previous result.  Against the formulas in
 *     double on the quantised inputs: 8 LSB + 2e-6 relative
 *     (check_reference's budget, fewer operations here).
 * (2) A theta that param_extract_step rejects for K1 or K3 (K3' < 0: Tr
 *     undefined; K1 20x: Rs out of range) is valid here, with the same
 *     Lm, Lr, psi_r as (1) (K1, theta3 are not used: bit-identical).
 * (3) Each of its status codes, valid = 0. */
static void test_magnetic(void **state)
{
    param_extract_t *p = &fx.p;
    param_extract_t q;
    int paper;
    (void)state;

    for (paper = 0; paper <= 1; paper++) {
        double K2, K4, im, a, Lr, Lm, psi;
        load(p, paper, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
        param_extract_step(p);
        assert_int_equal(p->valid, 1);
        q = *p;                                  /* holds step's Rs, Rr, Tr, K3p */
        param_extract_magnetic(&q);
        assert_int_equal(q.status, PARAM_OK);
        assert_int_equal(q.valid, 1);
#define SAME(x) assert_true(fabs(iq_to_d(q.x) - iq_to_d(p->x)) <= LSB24)
        SAME(Lm); SAME(Lr); SAME(psi_r);
#undef SAME
        assert_true(q.Rs == _IQ(0.0) && q.Rr == _IQ(0.0) && q.Tr == _IQ20(0.0) && q.K3p == _IQ(0.0));
        K2 = iq_to_d(q.theta[1]); K4 = iq_to_d(q.theta[3]); im = iq_to_d(q.i_m);
        a = -K4 / (K2 * im);
        Lr = 1.0 / K2 + a;
        Lm = sqrt(a * Lr);
        psi = Lm * im;
#define NEAR(x, ref) assert_true(fabs(iq_to_d(x) - (ref)) <= 8.0 * LSB24 + 2e-6 * fabs(ref))
        NEAR(q.Lm, Lm); NEAR(q.Lr, Lr); NEAR(q.psi_r, psi);
#undef NEAR
        print_message("magnetic (%s): Lm %.7f Lr %.7f psi %.7f pu (double %.7f %.7f %.7f)\n",
                      paper ? "paper" : "const", iq_to_d(q.Lm), iq_to_d(q.Lr), iq_to_d(q.psi_r),
                      Lm, Lr, psi);

        /* (2) K3' < 0: step invalid (K3), magnetic valid and unchanged */
        load(&q, paper, fx.K1, fx.K2, -fx.K3p, fx.K4, fx.im);
        param_extract_step(&q);
        assert_int_equal(q.status, PARAM_ERR_K3);
        assert_int_equal(q.valid, 0);
        param_extract_magnetic(&q);
        assert_int_equal(q.status, PARAM_OK);
        assert_int_equal(q.valid, 1);
        assert_true(q.Lm == p->Lm && q.Lr == p->Lr && q.psi_r == p->psi_r);
        /* K1 20x: step's Rs out of range, magnetic valid */
        load(&q, paper, fx.K1 * 20.0, fx.K2, fx.K3p, fx.K4, fx.im);
        param_extract_step(&q);
        assert_int_equal(q.status, PARAM_ERR_RS);
        param_extract_magnetic(&q);
        assert_int_equal(q.valid, 1);
        assert_true(q.Lm == p->Lm && q.Lr == p->Lr && q.psi_r == p->psi_r);
    }

    /* (3) the status codes */
#define EXPECT_MAG(st)                                                         \
    do {                                                                       \
        param_extract_magnetic(p);                                             \
        assert_int_equal(p->status, (st));                                     \
        assert_int_equal(p->valid, 0);                                         \
    } while (0)
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, 0.4);                 /* i_M < 0.5 A */
    EXPECT_MAG(PARAM_ERR_IM);
    load(p, 1, fx.K1, -fx.K2, fx.K3p, fx.K4, fx.im);
    EXPECT_MAG(PARAM_ERR_K2);
    load(p, 1, fx.K1, 0.0, fx.K3p, fx.K4, fx.im);
    EXPECT_MAG(PARAM_ERR_K2);
    p->theta[1] = d_to_iq(1e-3);                                  /* 1/K2 = 1000 pu */
    EXPECT_MAG(PARAM_ERR_K2);
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    p->theta[1] = d_to_iq(0.0100);                                /* a = 610 pu */
    p->theta[3] = d_to_iq(-2.0);
    EXPECT_MAG(PARAM_ERR_DIV);
    load(p, 1, fx.K1, fx.K2, fx.K3p, -fx.K4, fx.im);              /* a < 0 */
    EXPECT_MAG(PARAM_ERR_SQRT);
    load(p, 1, fx.K1, fx.K2, fx.K3p, 0.0, fx.im);                 /* a = 0 */
    EXPECT_MAG(PARAM_ERR_SQRT);
    /* a Lr = 12 x 112 = 1344 is beyond Q24, but Lm = sqrt(a) sqrt(Lr) = 36.7 pu
     * is formed without it (a small motor on a high bus: Lm 11.8 pu) and is
     * then outside its range */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    p->theta[1] = d_to_iq(0.0100);
    p->theta[3] = d_to_iq(-0.01 * 0.328125 * 12.0);
    EXPECT_MAG(PARAM_ERR_LM);
    /* K4 / 100: Lm 0.46 mH < 1 mH (Lr 4.8 mH in range; K3' irrelevant) */
    load(p, 1, fx.K1, fx.K2, -1.0, fx.K4 / 100.0, fx.im);
    EXPECT_MAG(PARAM_ERR_LM);
    /* K2, K4 / 20: Lr 0.0994 H > 0.06 (Lm 0.021 H in range) */
    load(p, 1, fx.K1, fx.K2 / 20.0, fx.K3p, fx.K4 / 20.0, fx.im);
    EXPECT_MAG(PARAM_ERR_LR);
    /* i_M, K4 x 12: a, Lr, Lm unchanged, psi_r 0.5 Wb > 0.2 */
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4 * 12.0, fx.im * 12.0);
    EXPECT_MAG(PARAM_ERR_PSI);
#undef EXPECT_MAG
    load(p, 1, fx.K1, fx.K2, fx.K3p, fx.K4, fx.im);
    param_extract_magnetic(p);
    assert_int_equal(p->valid, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_paper_form),
        cmocka_unit_test(test_reference_const_form),
        cmocka_unit_test(test_reference_flux_form),
        cmocka_unit_test(test_rejections),
        cmocka_unit_test(test_init_rejects),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_large_tr),
        cmocka_unit_test(test_magnetic),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
