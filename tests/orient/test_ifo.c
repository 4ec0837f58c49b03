/* ifo (indirect field orientation): the flux-lag coefficient, the imr step
 * response against the exact exponential, the slip against its formula,
 * the angle integration against the exact integral, the small-imr guard,
 * the wrap and the mid-period angle.
 *
 * Rig: the paper's motor (Tr = 19.78 ms), f_base = 50 Hz, Ts = 1/15000 s:
 * Tr = 6.214 pu time, Ts = 0.020944 pu, kf = 1 - exp(-Ts/Tr) = 0.0033647. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <math.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "base_values.h"
#include "ifo.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
static double to_d20(_iq20 x) { return ldexp((double)x, -20); }
#else
static double to_d(_iq x) { return (double)x; }
static double to_d20(_iq20 x) { return (double)x; }
#endif
#define LSB 5.9604644775390625e-8   /* 2^-24 */
#define LSB20 9.5367431640625e-7    /* 2^-20: Tr is Q20 */
#define PI 3.14159265358979323846

#define TS_S (1.0f / 15000.0f)
#define TR_S 0.01978f

static base_values_t g_b;

static int setup(void **state)
{
    (void)state;
    return (base_values_init(&g_b, 20.0f, 34.6410161513775f, 50.0f, 2u, TS_S) == BASE_OK) ? 0 : -1;
}

/* Tr in pu time, as the module receives it (the test's reference uses the
 * same float input; its own conversion error is not the module's) */
static double tr_pu_ref(void)
{
    return (double)TR_S / (double)g_b.t_base_s;
}

/* kf against 1 - exp(-Ts/Tr) for Tr from 10 Ts to 999 pu (Tr in Q20: the
 * small motors' few pu and the large ones' hundreds; the reference takes
 * the Q20 Tr the module got).  Error budget
 * (IQ): Ts truncated to Q24 (< 1 LSB) divided by Tr: < 1/Tr LSB; the
 * division truncates (< 1 LSB); Horner steps (each < 1 LSB, multiplied by
 * x <= 0.1); the last product (< 1 LSB); series remainder < x^6/720 <
 * 1.4e-9 = 0.02 LSB.  Bound (1/Tr + 4) LSB.  Float: ~6 roundings of
 * values < 1, relative 6e-8 each: within the same bound. */
static void test_kf_series(void **state)
{
    static const double tr_list[] = {0.2094395102 * 1.0001, 0.5, 1.0, 6.2141, 20.0, 99.0,
                                     150.0, 292.4, 999.0};
    ifo_t f;
    uint32_t i;
    (void)state;

    /* imr_min 0.2 so that the slip bound admits Tr down to 10 Ts */
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.2f), IFO_OK);
    for (i = 0u; i < sizeof tr_list / sizeof tr_list[0]; i++) {
        _iq20 tr = _IQ20(tr_list[i]);
        double trd = to_d20(tr);
        double want = 1.0 - exp(-(double)g_b.Ts_pu / trd);
        assert_int_equal(ifo_set_tr(&f, tr), IFO_OK);
        if (!(fabs(to_d(f.kf) - want) <= (1.0 / trd + 4.0) * LSB)) {
            print_error("Tr=%.4f kf %.10f want %.10f err %.2f LSB\n", trd, to_d(f.kf), want,
                        (to_d(f.kf) - want) / LSB);
            fail();
        }
        /* 1/Tr: division truncated, < 1 LSB (+ float rounding) */
        assert_true(fabs(to_d(f.inv_tr) - 1.0 / trd) <= 1.5 * LSB);
    }
}

/* Magnetising from 0 with i_m = 0.33 pu (6.56 A of 20 A): imr(k) against
 * i_m (1 - exp(-k Ts/Tr)) over 8 Tr (2400 samples).
 * e(k) = (1-kf) e(k-1) + r(k) + i_m (kf_q - kf) (1-kf)^(k-1):
 * rounding |r| <= 0.5 LSB accumulates to <= 0.5/kf = 149 LSB; the
 * coefficient error (<= 1/Tr + 4 = 4.2 LSB, test_kf_series) contributes
 * <= i_m |dkf| max_k k (1-kf)^(k-1) = i_m |dkf| / (e kf) = 152 LSB; the
 * Tr conversion in float (< 2e-7 relative of x) adds < 0.1 LSB of kf,
 * i.e. < 4 LSB.  Bound 310 LSB (1.8e-5 pu, 5.6e-5 relative).  Float: per
 * step 1 rounding of < 0.5 pu (<= 0.5 LSB): same budget. */
static void test_imr_step_response(void **state)
{
    ifo_t f;
    uint32_t k;
    const double im = 0.33;
    double tr = tr_pu_ref();
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    f.i_m = _IQ(im);
    f.i_t = _IQ(0.0);
    for (k = 1u; k <= 2400u; k++) {
        double want;
        ifo_step(&f);
        want = to_d(f.i_m) * (1.0 - exp(-(double)k * (double)g_b.Ts_pu / tr));
        if (!(fabs(to_d(f.imr) - want) <= 310.0 * LSB)) {
            print_error("k=%u imr %.10f want %.10f err %.1f LSB\n", (unsigned)k, to_d(f.imr),
                        want, (to_d(f.imr) - want) / LSB);
            fail();
        }
    }
    /* magnetised: the guard is off */
    assert_int_equal(f.imr_low, 0);
}

/* Slip at steady flux, against w_slip = i_t / (Tr imr) (pu), for several
 * i_t, imr.  Budget: 1/Tr truncated (< 1 LSB, times |i_t| <= 1), the
 * product truncated (< 1 LSB), the division truncated (< 1 LSB) and the
 * numerator's error divided by imr (>= 0.1): < (2/0.1 + 1) = 21 LSB; plus
 * the relative error of Tr as passed (float conversion, < 2e-7, times
 * |wslip| < 2.5: < 9 LSB).  Bound 30 LSB.  ws = wr + wslip exactly. */
static void test_slip(void **state)
{
    static const double it_list[] = {0.5, -0.5, 1.0, 0.01, -1.0};
    static const double imr_list[] = {0.33, 0.1, 1.0};
    ifo_t f;
    uint32_t i, j;
    double tr = tr_pu_ref();
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    for (i = 0u; i < sizeof it_list / sizeof it_list[0]; i++) {
        for (j = 0u; j < sizeof imr_list / sizeof imr_list[0]; j++) {
            double want;
            f.i_m = _IQ(imr_list[j]);
            f.imr = f.i_m;                  /* steady flux: i_m = imr */
            f.i_t = _IQ(it_list[i]);
            f.wr = _IQ(0.8);
            ifo_step(&f);
            assert_true(f.imr == f.i_m);    /* no drift at steady state */
            want = to_d(f.i_t) / (tr * to_d(f.imr));
            if (!(fabs(to_d(f.wslip) - want) <= 30.0 * LSB)) {
                print_error("i_t=%.3f imr=%.3f wslip %.10f want %.10f\n", it_list[i],
                            imr_list[j], to_d(f.wslip), want);
                fail();
            }
            assert_true(f.ws == f.wr + f.wslip);
            assert_int_equal(f.imr_low, 0);
        }
    }
    /* rated point of the paper's motor: i_T = 5 A (0.25 pu), imr = 6.5625 A
     * (0.328 pu): w_slip = 0.25/(6.214*0.328) = 0.1226 pu = 38.5 rad/s */
    f.i_m = _IQ(6.5625 / 20.0);
    f.imr = f.i_m;
    f.i_t = _IQ(0.25);
    ifo_step(&f);
    assert_true(fabs(to_d(f.wslip) * (double)g_b.w_base_rad_s -
                     5.0 / (0.01978 * 6.5625)) <= 1e-4 * 38.5);
}

/* The multi-rate path the drive runs (ifo_update_slip_gain in the slow task,
 * ifo_step_slip_fast every sample): the same imr step response as
 * test_imr_step_response (bound 310 LSB, same budget: the fast step's
 * rounded product is ifo_step's), and at steady flux the same slip as
 * test_slip's formula w_slip = i_t / (Tr imr) (bound 30 LSB) with
 * ws = wr + wslip exactly. */
static void test_multirate_path(void **state)
{
    static const double it_list[] = {0.5, -0.5, 0.01};
    ifo_t f;
    uint32_t k, i;
    const double im = 0.33;
    double tr = tr_pu_ref();
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    f.i_m = _IQ(im);
    f.i_t = _IQ(0.0);
    f.wr = _IQ(0.0);
    for (k = 1u; k <= 2400u; k++) {
        double want;
        ifo_t g;
        if ((k & 3u) == 0u) {
            ifo_update_slip_gain(&f);   /* the slow task, every 4th sample */
        }
        /* ifo_slip_fast, the ISR's form, on a copy whose own inputs are
         * something else: the same step (so the bounds below hold for it) */
        g = f;
        g.i_m = _IQ(0.0);
        g.i_t = _IQ(1.0);
        g.wr = _IQ(-0.5);
        ifo_slip_fast(&g, f.i_m, f.i_t, f.wr);
        ifo_step_slip_fast(&f);
        assert_true(g.imr == f.imr && g.wslip == f.wslip && g.ws == f.ws &&
                    g.slip_acc == f.slip_acc && g.i_m == _IQ(0.0));
        want = to_d(f.i_m) * (1.0 - exp(-(double)k * (double)g_b.Ts_pu / tr));
        if (!(fabs(to_d(f.imr) - want) <= 310.0 * LSB)) {
            print_error("k=%u imr %.10f want %.10f err %.1f LSB\n", (unsigned)k, to_d(f.imr),
                        want, (to_d(f.imr) - want) / LSB);
            fail();
        }
    }
    for (i = 0u; i < sizeof it_list / sizeof it_list[0]; i++) {
        double want;
        f.imr = f.i_m;                  /* steady flux */
        f.i_t = _IQ(it_list[i]);
        f.wr = _IQ(0.8);
        ifo_update_slip_gain(&f);
        ifo_step_slip_fast(&f);
        want = to_d(f.i_t) / (tr * to_d(f.imr));
        if (!(fabs(to_d(f.wslip) - want) <= 30.0 * LSB)) {
            print_error("i_t=%.3f wslip %.10f want %.10f\n", it_list[i], to_d(f.wslip), want);
            fail();
        }
        assert_true(f.ws == f.wr + f.wslip);
    }
}

/* Angle integration at constant ws: theta(N) = frac(theta0 + N ws f_base
 * Ts).  The angle is a phase accumulator of 2^32 counts per revolution
 * (angle.h).  Per sample: the increment is truncated to a count (< 2^-32
 * revolution) and the constant k_acc = f_base Ts 2^8 carries its float
 * product (< 6e-8 relative) and its Q30 truncation (2^-30 of 2^8 counts per
 * LSB: 2^-38 revolution per pu of speed), i.e. d = |ws| (2^-38 + 6e-8 f_base
 * Ts) + 2^-32; FLOAT_MATH adds the float product of the increment (two
 * roundings: 2^-23 of it).  theta is the accumulator read as Q24, rounded
 * (0.5 LSB, not accumulated).  So after k samples |error| <= 0.5 LSB + k d
 * (+ k |inc| 2^-23 in float): 0.5 LSB + 0.02 LSB at k = 20000 in IQ_MATH,
 * where the Q24 sum it replaced lost up to one LSB per sample.  Asserted at
 * every sample, k up to 20000 (about 80 revolutions, 80 wraps), both
 * directions; also theta in [0, 1) and theta_prev. */
/* The phase accumulator itself (angle.h), against double sums: f_base Ts =
 * 3/512 (exact in float and Q30: k_acc = 1.5), so the only errors are the
 * increment's truncation to a count (2^-32 revolution per sample; FLOAT_MATH
 * also its float product, 2^-23 of the increment) and the read-out's
 * rounding (0.5 LSB of Q24).  Speeds from a slip's 0.013 pu to 120 pu, whose
 * 0.70-revolution increment wraps the int32 increment (the same angle modulo
 * one revolution); both directions; 5000 samples.  Then the read-out at its
 * edges: 0x7F counts are 0, 0x80 one LSB, 2^32 - 1 wraps to 0; and
 * angle_acc_pu(angle_acc_from_pu(a)) == a on the Q24 grid. */
static void test_angle_acc(void **state)
{
    static const double w_list[] = {0.013, -0.013, 0.9, -45.3, 120.0, -120.0};
    const double fts = 3.0 / 512.0;
    const _iq30 k_acc = angle_acc_k(3.0f / 512.0f);
    uint32_t i, k;
    (void)state;

    for (i = 0u; i < 6u; i++) {
        const _iq w = _IQ(w_list[i]);
        const double inc = to_d(w) * fts;   /* revolutions per sample, exact */
        angle_acc_t acc = angle_acc_from_pu(_IQ(0.25));
        double bound;
        for (k = 1u; k <= 5000u; k++) {
            double want = 0.25 + (double)k * inc;
            double e;
            acc = angle_acc_step(acc, w, k_acc);
            want -= floor(want);
            e = to_d(angle_acc_pu(acc)) - want;
            e -= floor(e + 0.5);   /* on the circle */
            bound = 0.5 * LSB + (double)k * ldexp(1.0, -32);
#if MATH_TYPE == FLOAT_MATH
            bound += (double)k * fabs(inc) * ldexp(1.0, -23);
#endif
            if (!(fabs(e) <= bound) || !(to_d(angle_acc_pu(acc)) >= 0.0) ||
                !(to_d(angle_acc_pu(acc)) < 1.0)) {
                print_error("w=%.3f k=%u: angle %.10f want %.10f (%.2f LSB, bound %.2f)\n",
                            w_list[i], (unsigned)k, to_d(angle_acc_pu(acc)), want, e / LSB,
                            bound / LSB);
                fail();
            }
        }
    }
    assert_true(angle_acc_pu(0x7Fu) == _IQ(0.0));
    assert_true(to_d(angle_acc_pu(0x80u)) == LSB);
    assert_true(angle_acc_pu(0xFFFFFFFFu) == _IQ(0.0));
    assert_true(to_d(angle_acc_pu(0x80000000u)) == 0.5);
    {
        static const double a_list[] = {0.0, LSB, 0.5, 1.0 - LSB, 0.123456};
        for (i = 0u; i < 5u; i++) {
            const _iq a = _IQ(a_list[i]);
            assert_true(angle_acc_pu(angle_acc_from_pu(a)) == a);
        }
    }
}

static void test_angle_integration(void **state)
{
    static const double ws_list[] = {1.2, -0.7};
    ifo_t f;
    uint32_t i, k;
    (void)state;

    for (i = 0u; i < 2u; i++) {
        double ws = ws_list[i];
        double inc = ws * 50.0 * (double)TS_S;
        double d = fabs(ws) * (ldexp(1.0, -38) + 6e-8 * 50.0 * (double)TS_S) + ldexp(1.0, -32);
        _iq prev;
        assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
        ifo_reset(&f, _IQ(0.9));
        f.wr = _IQ(ws);                /* i_t = 0: no slip */
        for (k = 1u; k <= 20000u; k++) {
            double want = fmod(to_d(_IQ(0.9)) + (double)k * to_d(f.wr) / ws * inc, 1.0);
            double e;
            double d_k;
            if (want < 0.0) {
                want += 1.0;
            }
            prev = f.theta;
            ifo_step(&f);
            assert_true(f.theta_prev == prev);
            assert_true(to_d(f.theta) >= 0.0 && to_d(f.theta) < 1.0);
            e = to_d(f.theta) - want;
            e -= floor(e + 0.5);       /* compare on the circle */
#if MATH_TYPE == FLOAT_MATH
            d_k = (double)k * (d + fabs(inc) * ldexp(1.0, -23));
#else
            d_k = (double)k * d;
#endif
            if (!(fabs(e) <= 0.5 * LSB + d_k)) {
                print_error("ws=%.2f k=%u theta %.10f want %.10f err %.1f LSB\n", ws,
                            (unsigned)k, to_d(f.theta), want, e / LSB);
                fail();
            }
        }
        assert_true(to_d(f.ws) == to_d(f.wr));
    }
}

/* Below imr_min the slip is 0 (no division by a vanishing flux) and the
 * flag is set; it clears on the sample imr crosses imr_min. */
static void test_small_imr_guard(void **state)
{
    ifo_t f;
    uint32_t k;
    double tr = tr_pu_ref();
    /* imr crosses 0.05 when 0.33 (1 - exp(-k Ts/Tr)) = 0.05: k = 48.9 */
    double k_cross = -log(1.0 - 0.05 / 0.33) * tr / (double)g_b.Ts_pu;
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    assert_int_equal(f.imr_low, 1);
    f.i_m = _IQ(0.33);
    f.i_t = _IQ(1.0);                  /* full torque current, no flux yet */
    f.wr = _IQ(0.1);
    for (k = 1u; k <= 100u; k++) {
        ifo_step(&f);
        if ((double)k < k_cross - 0.5) {
            assert_int_equal(f.imr_low, 1);
            assert_true(to_d(f.wslip) == 0.0);
            assert_true(f.ws == f.wr);
        } else if ((double)k > k_cross + 0.5) {
            assert_int_equal(f.imr_low, 0);
            /* finite, and the formula's value (Tr imr >= 0.31: < 3 pu) */
            assert_true(to_d(f.wslip) > 0.0 && to_d(f.wslip) < 3.3);
        }
    }
    /* zero flux, negative torque current: still 0, no overflow */
    ifo_reset(&f, _IQ(0.0));
    f.i_m = _IQ(0.0);
    f.i_t = _IQ(-1.0);
    ifo_step(&f);
    assert_true(to_d(f.wslip) == 0.0);
    assert_int_equal(f.imr_low, 1);
}

/* ifo_theta_mid: midpoint along the shorter arc, across the wrap both
 * ways.  Exact in IQ to 1 LSB (the halving floors). */
static void test_theta_mid(void **state)
{
    static const double cases[][3] = {
        /* theta_prev, theta, mid */
        {0.30, 0.31, 0.305},
        {0.998, 0.004, 0.001},        /* forwards through the wrap */
        {0.002, 0.996, 0.999},        /* backwards through the wrap */
        {0.999, 0.001, 0.0},          /* mid exactly on the wrap */
        {0.7, 0.6, 0.65},
    };
    ifo_t f;
    uint32_t i;
    (void)state;
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    for (i = 0u; i < sizeof cases / sizeof cases[0]; i++) {
        double m, e;
        f.theta_prev = _IQ(cases[i][0]);
        f.theta = _IQ(cases[i][1]);
        m = to_d(ifo_theta_mid(&f));
        assert_true(m >= 0.0 && m < 1.0);
        e = m - cases[i][2];
        e -= floor(e + 0.5);
        assert_true(fabs(e) <= 2.0 * LSB);
    }
    /* after a real step, the mid angle is theta_prev + ws f_base Ts / 2 */
    ifo_reset(&f, _IQ(0.9995));
    f.wr = _IQ(1.0);
    ifo_step(&f);
    {
        double e = to_d(ifo_theta_mid(&f)) - fmod(0.9995 + 0.5 * 50.0 * (double)TS_S, 1.0);
        e -= floor(e + 0.5);
        assert_true(fabs(e) <= 3.0 * LSB);
    }
}

static void test_init_errors(void **state)
{
    ifo_t f;
    base_values_t slow;
    (void)state;
    assert_int_equal(ifo_init(&f, TR_S, NULL, 0.05f), IFO_ERR_BASE);
    /* Ts = 10 ms at 50 Hz: f_base Ts = 0.5 >= 1/128 */
    assert_int_equal(base_values_init(&slow, 20.0f, 34.6f, 50.0f, 2u, 0.01f), BASE_OK);
    assert_int_equal(ifo_init(&f, TR_S, &slow, 0.05f), IFO_ERR_BASE);
    {
        /* 1/(f_base Ts) beyond its Q20 range: 1 Hz base at 15 kHz (15000) */
        base_values_t fine;
        assert_int_equal(base_values_init(&fine, 20.0f, 34.64f, 1.0f, 2u, TS_S), BASE_OK);
        assert_int_equal(ifo_init(&f, 0.05f, &fine, 0.05f), IFO_ERR_BASE);
    }
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.0f), IFO_ERR_IMR_MIN);
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 1.5f), IFO_ERR_IMR_MIN);
    assert_int_equal(ifo_init(&f, TR_S, &g_b, NAN), IFO_ERR_IMR_MIN);
    /* Tr = 5 Ts */
    assert_int_equal(ifo_init(&f, 5.0f * TS_S, &g_b, 0.05f), IFO_ERR_TR);
    assert_int_equal(ifo_init(&f, 0.0f, &g_b, 0.05f), IFO_ERR_TR);
    assert_int_equal(ifo_init(&f, NAN, &g_b, 0.05f), IFO_ERR_TR);
    /* 0.5 s = 157 pu and 3 s = 942 pu: accepted (Q20); 3.2 s = 1005 pu > 1000 */
    assert_int_equal(ifo_init(&f, 0.5f, &g_b, 0.05f), IFO_OK);
    assert_int_equal(ifo_init(&f, 3.0f, &g_b, 0.05f), IFO_OK);
    assert_true(fabs(to_d20(f.tr) - 3.0 / (double)g_b.t_base_s) <= LSB20 + 1e-7 * 942.5);
    assert_int_equal(ifo_init(&f, 3.2f, &g_b, 0.05f), IFO_ERR_TR);
    /* slip bound: 2 / (6.21 * 0.004) = 80 > 64 */
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.004f), IFO_ERR_IMR_MIN);

    /* online change: a rejected Tr keeps the old constants */
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    {
        _iq kf = f.kf, inv = f.inv_tr;
        _iq20 tr = f.tr;
        assert_int_equal(ifo_set_tr(&f, _IQ20(0.1)), IFO_ERR_TR);      /* < 10 Ts */
        assert_int_equal(ifo_set_tr(&f, _IQ20(IFO_TR_MAX_PU) + _IQ20(1.0)), IFO_ERR_TR);
        assert_int_equal(ifo_set_tr(&f, _IQ20(2047.0)), IFO_ERR_TR);
        assert_int_equal(ifo_set_tr(&f, _IQ20(-6.0)), IFO_ERR_TR);
        assert_true(f.kf == kf && f.inv_tr == inv && f.tr == tr);
        /* Tr +10 %: kf and 1/Tr move accordingly */
        assert_int_equal(ifo_set_tr(&f, _IQ20(6.2141 * 1.1)), IFO_OK);
        assert_true(fabs(to_d(f.inv_tr) - 1.0 / to_d20(f.tr)) <= 1.5 * LSB);
        assert_true(to_d(f.kf) < to_d(kf));
    }
}

/* One step of the representation below / above a Q value (a float in
 * FLOAT_MATH). */
#if MATH_TYPE == IQ_MATH
#define Q_BELOW(x) ((x) - 1)
#define Q_ABOVE(x) ((x) + 1)
#else
#define Q_BELOW(x) nextafterf((x), -INFINITY)
#define Q_ABOVE(x) nextafterf((x), INFINITY)
#endif

/* ifo_check and ifo_tr_check, the configuration table's tests: ifo_init's
 * and ifo_set_tr's verdicts at each bound of ifo.h.  ifo_check: imr_min in
 * (0, 1], Tr at most IFO_TR_MAX_PU, f_base Ts in (1/2000, 1/128) (at
 * 15 kHz a base of 7.5 .. 117.19 Hz); Tr's lower bound is ifo_design_tr's.
 * ifo_tr_check on the Q20 Tr: [10 Ts, IFO_TR_MAX_PU] to the LSB, and
 * Tr imr_min >= 2/64. */
static void test_check(void **state)
{
    const float t1000 = 1000.0f * g_b.t_base_s;
    const float tr[] = {TR_S, TR_S, TR_S, 0.9999f * t1000, 1.0001f * t1000};
    const float imr[] = {1.0f, nextafterf(1.0f, 2.0f), 0.0f, 0.05f, 0.05f};
    const ifo_status_t want[] = {IFO_OK, IFO_ERR_IMR_MIN, IFO_ERR_IMR_MIN, IFO_OK, IFO_ERR_TR};
    const float fb[] = {117.0f, 118.0f, 7.6f, 7.4f};
    const ifo_status_t want_fb[] = {IFO_OK, IFO_ERR_BASE, IFO_OK, IFO_ERR_BASE};
    ifo_t f;
    _iq20 lo, hi;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(ifo_check(tr[i], &g_b, imr[i]), want[i]);
        assert_int_equal(ifo_init(&f, tr[i], &g_b, imr[i]), want[i]);
    }
    for (i = 0; i < sizeof want_fb / sizeof want_fb[0]; i++) {
        base_values_t b;
        assert_int_equal(base_values_init(&b, 20.0f, 34.64f, fb[i], 2u, TS_S), BASE_OK);
        assert_int_equal(ifo_check(0.05f, &b, 0.05f), want_fb[i]);
        assert_int_equal(ifo_init(&f, 0.05f, &b, 0.05f), want_fb[i]);
    }
    /* below 10 Ts: ifo_design_tr's refusal, not ifo_check's */
    assert_int_equal(ifo_check(5.0f * TS_S, &g_b, 0.05f), IFO_OK);
    assert_int_equal(ifo_check(TR_S, NULL, 0.05f), IFO_ERR_BASE);

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 1.0f), IFO_OK);   /* no slip bound at 10 Ts */
    lo = _IQtoIQ20(_IQmpy(f.ts, _IQ(IFO_TR_MIN_SAMPLES)));
    hi = _IQ20(IFO_TR_MAX_PU);
    assert_int_equal(ifo_tr_check(f.ts, f.imr_min, lo), IFO_OK);
    assert_int_equal(ifo_tr_check(f.ts, f.imr_min, Q_BELOW(lo)), IFO_ERR_TR);
    assert_int_equal(ifo_set_tr(&f, Q_BELOW(lo)), IFO_ERR_TR);
    assert_int_equal(ifo_tr_check(f.ts, f.imr_min, hi), IFO_OK);
    assert_int_equal(ifo_tr_check(f.ts, f.imr_min, Q_ABOVE(hi)), IFO_ERR_TR);
    assert_int_equal(ifo_set_tr(&f, Q_ABOVE(hi)), IFO_ERR_TR);
    assert_int_equal(ifo_tr_check(f.ts, _IQ(0.03125), _IQ20(1.0)), IFO_OK);
    assert_int_equal(ifo_tr_check(f.ts, Q_BELOW(_IQ(0.03125)), _IQ20(1.0)), IFO_ERR_IMR_MIN);
    assert_int_equal(ifo_set_tr(&f, lo), IFO_OK);
}

/* ifo_design_tr: the Tr constants in float, what ifo_init computes and the
 * drive's background posts to the ISR.  From the pu floats ifo_init
 * derives: equal to the initialised module's.  Against double: Tr within
 * 1 LSB + 1e-7 relative (_IQ truncation, float rounding of the pu value),
 * 1/Tr within 1 LSB + 1.2e-7 relative (one more float rounding), kf =
 * 1 - exp(-Ts/Tr) within 1 LSB + 3e-7 relative (series 1.4e-9, a few
 * float roundings), over Tr from 10 Ts to 999 pu (Tr in Q20: its LSB is
 * 2^-20); against ifo_set_tr (the fixed-point path) the sum of both
 * budgets.  Refusals (Tr < 10 Ts, > IFO_TR_MAX_PU, NaN; the slip bound)
 * leave the set as it was. */
static void test_design_tr(void **state)
{
    static const double tr_list[] = {0.2094395102 * 1.0001, 0.5, 1.0, 6.2141, 20.0, 99.0,
                                     150.0, 292.4, 999.0};
    ifo_t f, g;
    ifo_tr_t t, keep;
    uint32_t i;
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.2f), IFO_OK);
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, TR_S / g_b.t_base_s, 0.2f), IFO_OK);
    assert_true(t.tr == f.tr && t.inv_tr == f.inv_tr && t.kf == f.kf);
    g = f;
    for (i = 0u; i < sizeof tr_list / sizeof tr_list[0]; i++) {
        const double trd = tr_list[i];
        const double want = 1.0 - exp(-(double)g_b.Ts_pu / trd);
        assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, (float)trd, 0.2f), IFO_OK);
        assert_true(fabs(to_d20(t.tr) - trd) <= LSB20 + 1e-7 * trd);
        assert_true(fabs(to_d(t.inv_tr) - 1.0 / trd) <= LSB + 1.2e-7 / trd);
        if (!(fabs(to_d(t.kf) - want) <= LSB + 3e-7 * want)) {
            print_error("Tr=%.4f kf %.10f want %.10f err %.2f LSB\n", trd, to_d(t.kf), want,
                        (to_d(t.kf) - want) / LSB);
            fail();
        }
        assert_int_equal(ifo_set_tr(&g, t.tr), IFO_OK);
        /* plus the Q20 Tr's truncation (< 1 LSB20 = 16 LSB of Q24, relative
         * 16 LSB / Tr): kf moves by kf 16 / Tr LSB (7.6 at 10 Ts), 1/Tr by
         * 16 / Tr^2 LSB (0.8 at the paper motor's 6.2 pu, 365 at 10 Ts =
         * 0.21 pu: 4.5e-6 relative, still far below 0.01 %) */
        assert_true(fabs(to_d(g.kf) - to_d(t.kf)) <=
                    (1.0 / trd + 6.0 + 16.0 * to_d(t.kf) / trd) * LSB);
        assert_true(fabs(to_d(g.inv_tr) - to_d(t.inv_tr)) <=
                    (3.0 + 16.0 / (trd * trd)) * LSB + 1.2e-7 / trd);
    }
    /* apply copies the three words */
    ifo_apply_tr(&f, &t);
    assert_true(f.tr == t.tr && f.inv_tr == t.inv_tr && f.kf == t.kf);

    keep = t;
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, 5.0f * g_b.Ts_pu, 0.2f), IFO_ERR_TR);
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, 1001.0f, 0.2f), IFO_ERR_TR);
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, 3000.0f, 0.2f), IFO_ERR_TR);
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, NAN, 0.2f), IFO_ERR_TR);
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, -6.0f, 0.2f), IFO_ERR_TR);
    /* slip bound 2 / (Tr imr_min) <= 64: 6.21 x 0.004 = 0.025 < 1/32 */
    assert_int_equal(ifo_design_tr(&t, g_b.Ts_pu, 6.2141f, 0.004f), IFO_ERR_IMR_MIN);
    assert_memory_equal(&t, &keep, sizeof t);
}

/* Encoder-angle mode: theta(k) = theta_r(k) + sum of w_slip f_base Ts, and
 * ws_frame = the frame's angle step / (f_base Ts).  A rotor turning at a
 * constant 0.9 pu with a constant slip command: after n samples the angle is
 * the exact sum (reference in double from the module's own constants), and
 * ws_frame equals w_r + w_slip up to the truncation of the two angle terms.
 * Bounds: the slip angle accumulates one truncation (<= 1 LSB) per sample,
 * so n LSB after n samples; ws_frame is a difference of two angles, each
 * within 1 LSB of exact, times 1/(f_base Ts) = 300: 2 * 300 + 2 LSB. */
static void test_encoder_angle_mode(void **state)
{
    ifo_t f;
    const double wr = 0.9, k = 50.0 * (1.0 / 15000.0);
    double slip_ref = 0.0, wslip = 0.0;
    int n;
    (void)state;
    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    ifo_reset(&f, _IQ(0.0));
    f.imr = _IQ(0.33);        /* magnetised: the slip is active */
    f.i_m = _IQ(0.33);
    f.i_t = _IQ(0.25);
    f.wr = _IQ(0.9);
    for (n = 1; n <= 3000; n++) {
        double th_r = fmod(wr * k * n, 1.0);
        double th_ref;
        double d;
        f.theta_r = _IQ(th_r);
        ifo_frame_from_rotor(&f);
        th_ref = fmod(th_r + slip_ref, 1.0);
        d = fabs(to_d(f.theta) - th_ref);
        d = fmin(d, 1.0 - d);                       /* across the wrap */
        assert_true(d <= (double)(n + 2) * LSB);
        if (n > 1) {
            /* frame speed over the last sample: w_r + the previous w_slip */
            assert_true(fabs(to_d(f.ws_frame) - (wr + wslip)) <= 602.0 * LSB + 1e-6 * 300.0);
        }
        ifo_step_slip(&f);
        wslip = to_d(f.wslip);
        slip_ref = fmod(slip_ref + wslip * k, 1.0);
        assert_true(to_d(angle_acc_pu(f.slip_acc)) >= 0.0 && to_d(angle_acc_pu(f.slip_acc)) < 1.0);
    }
    assert_true(fabs(to_d(f.ws) - (wr + wslip)) <= 2.0 * LSB);
}

/* ifo_align: taking over from another frame (the flux observer's) in
 * encoder-angle mode.  With theta_r set, ifo_align(theta_frame, imr) and
 * then ifo_frame_from_rotor() on the same sample give theta = theta_frame
 * (IQ: exactly, integer wraps; FLOAT: the difference theta_frame -
 * theta_r, the sum theta_r + slip and their +-1 wraps each round to 24
 * bits of a value below 2: 4 * 2^-24), theta_prev = theta, ws_frame = 0.
 * imr is set, clamped to [0, 4], and imr_low follows it.  Cases across the
 * 0/1 wrap both ways.  Afterwards the slip integrates as before
 * (test_encoder_angle_mode's reference and bound, started from the
 * aligned slip theta_frame - theta_r). */
static void test_align(void **state)
{
    static const double cases[][2] = {
        /* theta_r, theta_frame */
        {0.37, 0.81}, {0.81, 0.37}, {0.999, 0.001}, {0.001, 0.999}, {0.0, 0.0},
        {0.5, 0.5}, {0.99999994, 0.0}, {0.0, 0.99999994}, {0.25, 0.7500001},
    };
#if MATH_TYPE == IQ_MATH
    const double tol = 0.0;
#else
    const double tol = 4.0 * LSB;
#endif
    ifo_t f;
    uint32_t c;
    double d_max = 0.0;
    (void)state;

    assert_int_equal(ifo_init(&f, TR_S, &g_b, 0.05f), IFO_OK);
    for (c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        double d;
        /* some history first: a magnetised frame turning with slip */
        ifo_reset(&f, _IQ(0.0));
        f.imr = _IQ(0.33);
        f.i_m = _IQ(0.33);
        f.i_t = _IQ(0.25);
        f.wr = _IQ(0.5);
        for (int n = 1; n <= 100; n++) {
            f.theta_r = _IQ(fmod(0.5 * 50.0 * (double)TS_S * n, 1.0));
            ifo_frame_from_rotor(&f);
            ifo_step_slip(&f);
        }
        f.theta_r = _IQ(cases[c][0]);
        ifo_align(&f, _IQ(cases[c][1]), _IQ(0.3));
        assert_true(f.theta == _IQ(cases[c][1]) && f.theta_prev == f.theta);
        assert_true(f.ws_frame == _IQ(0.0));
        assert_true(to_d(angle_acc_pu(f.slip_acc)) >= 0.0 && to_d(angle_acc_pu(f.slip_acc)) < 1.0);
        ifo_frame_from_rotor(&f);
        d = fabs(to_d(f.theta) - to_d(_IQ(cases[c][1])));
        d = fmin(d, 1.0 - d);
        if (!(d <= tol)) {
            print_error("theta_r %.8f frame %.8f: theta %.8f (%.2f LSB off)\n", cases[c][0],
                        cases[c][1], to_d(f.theta), d / LSB);
            fail();
        }
        d_max = fmax(d_max, d);
        assert_true(to_d(f.theta) >= 0.0 && to_d(f.theta) < 1.0);
        assert_true(fabs(to_d(f.ws_frame)) <= tol * 300.0 + 1e-12);
        assert_true(f.imr == _IQ(0.3));
        assert_int_equal(f.imr_low, 0);
    }

    print_message("align: max |theta - theta_frame| after frame_from_rotor %.2f LSB\n", d_max / LSB);

    /* imr clamped to [0, 4]; imr_low follows imr_min (0.05) */
    f.theta_r = _IQ(0.2);
    ifo_align(&f, _IQ(0.4), _IQ(5.0));
    assert_true(f.imr == _IQ(4.0));
    assert_int_equal(f.imr_low, 0);
    ifo_align(&f, _IQ(0.4), _IQ(-0.2));
    assert_true(f.imr == _IQ(0.0));
    assert_int_equal(f.imr_low, 1);
    ifo_align(&f, _IQ(0.4), _IQ(0.03));
    assert_true(f.imr == _IQ(0.03));
    assert_int_equal(f.imr_low, 1);

    /* then the slip integrates as before: rotor at 0.9 pu, i_T 0.25 */
    {
        const double wr = 0.9, k = 50.0 * (double)TS_S;
        double slip_ref, wslip = 0.0;
        int n;
        ifo_align(&f, _IQ(0.95), _IQ(0.33));
        slip_ref = fmod(to_d(_IQ(0.95)) - to_d(_IQ(0.2)) + 1.0, 1.0);
        f.i_m = _IQ(0.33);
        f.i_t = _IQ(0.25);
        f.wr = _IQ(wr);
        for (n = 0; n <= 3000; n++) {
            double th_r = fmod(0.2 + wr * k * n, 1.0);
            double d;
            f.theta_r = _IQ(th_r);
            ifo_frame_from_rotor(&f);
            d = fabs(to_d(f.theta) - fmod(to_d(f.theta_r) + slip_ref, 1.0));
            d = fmin(d, 1.0 - d);
            assert_true(d <= (double)(n + 2) * LSB + tol);
            ifo_step_slip(&f);
            wslip = to_d(f.wslip);
            slip_ref = fmod(slip_ref + wslip * k, 1.0);
        }
        /* and the flux model ran from the aligned imr (steady: i_m = imr) */
        assert_true(fabs(to_d(f.imr) - 0.33) <= 2.0 * LSB);
        assert_true(wslip > 0.12 && wslip < 0.125);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kf_series),
        cmocka_unit_test(test_design_tr),
        cmocka_unit_test(test_imr_step_response),
        cmocka_unit_test(test_slip),
        cmocka_unit_test(test_multirate_path),
        cmocka_unit_test(test_angle_integration),
        cmocka_unit_test(test_angle_acc),
        cmocka_unit_test(test_small_imr_guard),
        cmocka_unit_test(test_theta_mid),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_encoder_angle_mode),
        cmocka_unit_test(test_align),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
