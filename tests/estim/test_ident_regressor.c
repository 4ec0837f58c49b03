/* estim_ident_regressor: the regression signals of method §2 through the
 * identical Butterworth filters (method §5), checked
 *   - the rotation of the voltage into M-T at the given (mid-period) angle
 *     against double,
 *   - the regression identity (eq. 3/5, method §2) on the filtered signals
 *     of a double-precision motor trajectory (estim_motor_data.h: the
 *     paper's motor, eq. 2 in pu, accelerating), i.e. that y1, y2 and the
 *     regressor rows are mutually consistent with the true K,
 *   - that filtering the products ws*i as single signals is what keeps the
 *     identity (method §7 point 2), by comparison with the product of the
 *     filtered factors,
 *   - that every signal passes an identical filter (bit-equal to a lone
 *     bw_filter with the same input),
 *   - the period-mean form's window (ident_regressor.h (a)-(c)) against its
 *     equations in double on the same inputs, window by window. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <cmocka.h>

#include "ident_regressor.h"
#include "estim_motor_data.h"
#include "estim_test_util.h"

#define WC_RAD_S (2.0f * 3.14159265f * 10.0f)

static void init_paper(ident_regressor_t *r)
{
    assert_int_equal(ident_regressor_init(r, WC_RAD_S, 10u, (float)MD_TS_S, (float)MD_W_BASE, 0u),
                     BW_FILTER_OK);
}

/* Park rotation at 64 angles and two voltage vectors: u_m, u_t within
 * 2 LSB24 of double on the same (quantised) inputs (two truncated products,
 * each in (-1, 0] LSB), and within 3 LSB24 of the unquantised vector
 * rotated by the exact angle (plus the Q24 quantisation of u and of
 * sin/cos, 1/2 LSB each, times |u| <= 0.93). */
static void test_rotation(void **state)
{
    ident_regressor_t r;
    double emax = 0.0;
    (void)state;
    init_paper(&r);
    for (int n = 0; n < 64; n++) {
        double th = 2.0 * MD_PI * (double)n / 64.0 + 0.01;
        double ua = 0.7 * cos(0.3 * n), ub = -0.6 * sin(0.7 * n);
        double um, ut;
        r.u_alpha = d_to_iq(ua);
        r.u_beta = d_to_iq(ub);
        r.sin_k = d_to_iq(sin(th));
        r.cos_k = d_to_iq(cos(th));
        ident_regressor_step(&r);
        um = iq_to_d(r.u_alpha) * iq_to_d(r.cos_k) + iq_to_d(r.u_beta) * iq_to_d(r.sin_k);
        ut = -iq_to_d(r.u_alpha) * iq_to_d(r.sin_k) + iq_to_d(r.u_beta) * iq_to_d(r.cos_k);
        if (fabs(iq_to_d(r.u_m) - um) > emax) { emax = fabs(iq_to_d(r.u_m) - um); }
        if (fabs(iq_to_d(r.u_t) - ut) > emax) { emax = fabs(iq_to_d(r.u_t) - ut); }
        /* and against the unquantised vector rotated by the exact angle */
        assert_true(fabs(iq_to_d(r.u_m) - (ua * cos(th) + ub * sin(th))) <= 3.0 * LSB24);
        assert_true(fabs(iq_to_d(r.u_t) - (-ua * sin(th) + ub * cos(th))) <= 3.0 * LSB24);
    }
    print_message("rotation: max error vs double on the same inputs %.3g LSB\n", emax / LSB24);
    assert_true(emax <= 2.0 * LSB24);
}

/* Drive the module with the motor trajectory for 0.6 s.  The voltage is
 * given in the stationary frame, rotated by the frame angle at the middle
 * of the period (theta integrated from ws), with sin/cos of that angle as
 * the mid-angle inputs, so the module must recover u_M, u_T.
 * After 0.4 s (the filters' start transient from zero state, exp(-sigma t)
 * with sigma = 44 rad/s, is then 2e-8) the residuals
 *     r1 = y1 - (K1 i_Mf + K2 u_Mf + K3),   r2 = y2 - (K1 i_Tf + K2 u_Tf + K4 wr_f)
 * must vanish up to:
 *   - the discretisation of the filter (the same discrete map applied to
 *     i and to di/dt commutes with d/dt only up to O(a^2) = 1.8e-5 of the
 *     signal's high-frequency content: |di/dt| <= 0.02 pu here -> <= 1e-6),
 *   - fixed point: each filtered signal within 40 LSB24 of its exact
 *     discrete value (test_bw_filter), times |K| <= 1.2, on 4 terms:
 *     ~ 200 LSB24 = 1.2e-5 worst case, typically far less.
 * Bound: 2e-5 pu (IQ and FLOAT), against |y| ~ 0.3 pu.
 * The same identity with the products formed from filtered factors,
 * (ws)f (i_T)f instead of (ws i_T)f, misses by the filter's distortion of
 * a product of two varying signals: it must be at least 10 x worse
 * (that is method §7 point 2). */
static void regression_identity(uint16_t decim_log2)
{
    ident_regressor_t r;
    bw_filter_t fws;          /* filtered ws alone, for the factor products */
    bw_filter_t fim;          /* a lone filter: identical to r's? */
    md_motor_t m;
    const int32_t n = (int32_t)1 << decim_log2;
    double theta = 0.0, e1 = 0.0, e2 = 0.0, f1 = 0.0, f2 = 0.0;
    double wr_sum = 0.0, ws_sum = 0.0, im_sum = 0.0;
    md_motor(&m);
    assert_int_equal(ident_regressor_init(&r, WC_RAD_S, 10u, (float)MD_TS_S, (float)MD_W_BASE,
                                          decim_log2), BW_FILTER_OK);
    assert_int_equal(bw_filter_init(&fws, WC_RAD_S, 10u, (float)(MD_TS_S * (double)n),
                                    (float)MD_W_BASE), BW_FILTER_OK);
    fim = fws;
    for (int32_t k = 1; k <= 9000; k++) {
        md_sample_t s;
        double mid, c, sn;
        md_sample(&m, k, &s);
        mid = theta + 0.5 * s.ws * MD_W_BASE * MD_TS_S;    /* angle at mid-period */
        theta += s.ws * MD_W_BASE * MD_TS_S;               /* at the sample, the period's end */
        c = cos(mid);
        sn = sin(mid);
        r.i_m = d_to_iq(s.i_m);
        r.i_t = d_to_iq(s.i_t);
        /* the voltage of the period, in the stationary frame (its M-T
         * value belongs to the middle of the period) */
        r.u_alpha = d_to_iq(s.u_m * c - s.u_t * sn);
        r.u_beta = d_to_iq(s.u_m * sn + s.u_t * c);
        /* the module gets the frame angle at the sample and the speed
         * over the period: it must find the middle itself */
        r.sin_k = d_to_iq(sin(theta));
        r.cos_k = d_to_iq(cos(theta));
        r.ws = d_to_iq(s.ws);
        ident_regressor_accumulate(&r);
        /* the window means of ws, i_M (for the lone filters) and wr (the
         * regressor takes it as its input: the QEP's window speed) */
        wr_sum += s.wr;
        ws_sum += iq_to_d(r.ws);
        im_sum += iq_to_d(r.i_m);
        if (k % n != 0) {
            continue;
        }
        r.wr = d_to_iq(wr_sum / (double)n);
        ident_regressor_filter(&r);
        fws.u = d_to_iq(ws_sum / (double)n);
        bw_filter_step(&fws);
        fim.u = d_to_iq(im_sum / (double)n);
        bw_filter_step(&fim);
        wr_sum = ws_sum = im_sum = 0.0;
        if (n == 1) {
            assert_true(fim.y == r.i_mf && fim.dy == r.f_im.dy);   /* identical filters */
        }
        if (k > 6000) {
            double imf = iq_to_d(r.i_mf), itf = iq_to_d(r.i_tf);
            double r1 = iq_to_d(r.y1) - (m.K1 * imf + m.K2 * iq_to_d(r.u_mf) + m.K3);
            double r2 = iq_to_d(r.y2) - (m.K1 * itf + m.K2 * iq_to_d(r.u_tf) + m.K4 * iq_to_d(r.wr_f));
            /* the same with products of filtered factors */
            double wsf = iq_to_d(fws.y);
            double g1 = (iq_to_d(r.f_im.dy) - wsf * itf) - (m.K1 * imf + m.K2 * iq_to_d(r.u_mf) + m.K3);
            double g2 = (iq_to_d(r.f_it.dy) + wsf * imf)
                        - (m.K1 * itf + m.K2 * iq_to_d(r.u_tf) + m.K4 * iq_to_d(r.wr_f));
            if (fabs(r1) > e1) { e1 = fabs(r1); }
            if (fabs(r2) > e2) { e2 = fabs(r2); }
            if (fabs(g1) > f1) { f1 = fabs(g1); }
            if (fabs(g2) > f2) { f2 = fabs(g2); }
        }
    }
    print_message("identity residuals (filter step every %d samples): row1 %.3g, row2 %.3g pu; "
                  "with filtered factors %.3g, %.3g pu\n", (int)n, e1, e2, f1, f2);
    assert_true(e1 <= 2e-5);
    assert_true(e2 <= 2e-5);
    assert_true(f1 + f2 >= 10.0 * (e1 + e2));
}

static void test_regression_identity(void **state)
{
    (void)state;
    regression_identity(0u);
}

/* The multi-rate path: the inputs summed every sample, the filters stepped
 * every 4th sample on the window means (the drive's schedule).  The mean
 * is one more linear filter common to every signal, so the identity must
 * hold as closely as at 15 kHz: the same bound.  (The filter's step is 4
 * times larger, a = 0.017: its discretisation term O(a^2) stays < 1e-6.) */
static void test_regression_identity_decimated(void **state)
{
    (void)state;
    regression_identity(2u);
}

/* Products and inputs beyond the filters' +-7 pu range saturate, never wrap:
 * ws = 4 pu, i = 3 pu -> ws*i = 12 pu is clamped to 7. */
static void test_saturation(void **state)
{
    ident_regressor_t r;
    (void)state;
    init_paper(&r);
    r.ws = _IQ(4.0);
    r.i_t = _IQ(3.0);
    r.i_m = _IQ(-3.0);
    r.cos_k = _IQ(1.0);
    for (int k = 0; k < 20000; k++) {
        ident_regressor_step(&r);
    }
    assert_true(fabs(iq_to_d(r.f_ws_it.y) - 7.0) <= 1e-4);
    assert_true(fabs(iq_to_d(r.f_ws_im.y) + 7.0) <= 1e-4);
    assert_true(fabs(iq_to_d(r.y1) + 7.0) <= 1e-4);
    assert_true(fabs(iq_to_d(r.y2) + 7.0) <= 1e-4);
}

/* The period-mean form (ident_regressor.h (a)-(d); regression_bias.md
 * §5.1), the drive's schedule (a filter step every 8 samples), against its
 * equations written here in double on the same Q24 inputs: smooth,
 * unrelated sinusoids for the currents, voltage, frame and rotor speeds and
 * ifo's i_mr, and K2^ = 0 (none yet), then inside, then outside the
 * nameplate's [0.5, 2] range.  Checked after every window: the ten filter
 * inputs within 8 LSB24 (each is a window mean, rounded, plus at most six
 * truncated products of factors below 8 pu, each within 1 LSB, and the
 * Q30 ripple constant's 2^-30 relative rounding), and Delta within 32
 * LSB24 (2e-6 pu; its own rounded recursion, whose +-1/2 LSB steps do not
 * decay faster than kf_N = 0.15: at most ~1/kf_N of them add up).  The
 * corrections are far above these bounds: |K2^ c| ~ 1e-4 pu, the
 * trapezoid's half step ~ 1e-4 pu, sinc 1 - 3e-5. */
static void test_period_mean_window(void **state)
{
    const uint16_t n = 3u;
    const int32_t N = 8;
    const double Ts = MD_TS_S, wb = MD_W_BASE, tr_s = 0.05, k2n = 1.2, imn = 0.5;
    const double kf = 1.0 - exp(-(double)N * Ts / tr_s);
    const double wt = wb * Ts;
    ident_regressor_t r;
    double theta = 0.0, s_im = 0.0, s_it = 0.0, s_um = 0.0, s_ut = 0.0, s_ws = 0.0;
    double s_wsit = 0.0, s_wsim = 0.0, i0m = 0.0, i0t = 0.0, dlm = 0.0, dlt = 0.0;
    double e_in = 0.0, e_dl = 0.0, dl_max = 0.0, ic_max = 0.0;
    (void)state;
    assert_int_equal(ident_regressor_init(&r, WC_RAD_S, 10u, (float)Ts, (float)wb, n),
                     BW_FILTER_OK);
    assert_int_equal(ident_regressor_set_period_mean(&r, (float)tr_s, (float)k2n, (float)imn,
                                                     (float)Ts, (float)wb), 0);
    for (int32_t k = 1; k <= 300 * N; k++) {
        const double ws = 0.8 + 0.1 * sin(k * 1.3e-3);
        const double ua = 0.9 * cos(k * 0.021 + 0.3), ub = 0.9 * sin(k * 0.021 + 0.3);
        double sk, ck;
        theta += ws * wt;
        r.i_m = d_to_iq(0.5 + 0.05 * sin(k * 2.1e-3));
        r.i_t = d_to_iq(0.3 + 0.04 * cos(k * 3.7e-3));
        r.u_alpha = d_to_iq(ua);
        r.u_beta = d_to_iq(ub);
        r.sin_k = d_to_iq(sin(theta));
        r.cos_k = d_to_iq(cos(theta));
        r.ws = d_to_iq(ws);
        ident_regressor_accumulate(&r);
        sk = iq_to_d(r.sin_k);
        ck = iq_to_d(r.cos_k);
        s_im += iq_to_d(r.i_m);
        s_it += iq_to_d(r.i_t);
        s_um += iq_to_d(r.u_alpha) * ck + iq_to_d(r.u_beta) * sk;
        s_ut += iq_to_d(r.u_beta) * ck - iq_to_d(r.u_alpha) * sk;
        s_ws += iq_to_d(r.ws);
        s_wsit += iq_to_d(r.ws) * iq_to_d(r.i_t);
        s_wsim += iq_to_d(r.ws) * iq_to_d(r.i_m);
        if (k % N != 0) {
            continue;
        }
        {
            const int32_t w = k / N;
            const double wr = 0.76 + 0.1 * sin(w * 0.011);
            const double imr = 0.49 + 0.01 * sin(w * 0.017);
            const double k2h = (w < 100) ? 0.0 : (w < 200) ? 1.25 : 3.0;   /* none, in, out */
            const double k2 = (k2h > 0.5 * k2n && k2h < 2.0 * k2n) ? k2h : k2n;
            double wsm, x, um, ut, sinc, icm, ict, hm, ht, slip, dm, dt, mm, mt, ref[10], got[10];
            r.wr = d_to_iq(wr);
            r.imr = d_to_iq(imr);
            r.k2_hat = d_to_iq(k2h);
            ident_regressor_filter_a(&r);
            /* (a) the mean voltage: back to the periods' middle, times sinc */
            wsm = s_ws / N;
            x = 0.5 * wt * wsm;
            sinc = sin(x) / x;
            um = sinc * (cos(x) * s_um / N - sin(x) * s_ut / N);
            ut = sinc * (sin(x) * s_um / N + cos(x) * s_ut / N);
            /* (b) K2^ c and the trapezoid */
            icm = -k2 * wsm * ut * wt * wt / 12.0;
            ict = k2 * wsm * um * wt * wt / 12.0;
            hm = (iq_to_d(r.i_m) - i0m) / (2.0 * N);
            ht = (iq_to_d(r.i_t) - i0t) / (2.0 * N);
            /* (c) Delta and the flux per nameplate i_M */
            dm = hm + icm;
            dt = ht + ict;
            slip = N * wt * (wsm - wr);
            {
                const double m0 = dlm, t0 = dlt;
                dlm = m0 + kf * (dm - m0) + slip * t0;
                dlt = t0 + kf * (dt - t0) - slip * m0;
            }
            mm = (imr + dlm) / imn;
            mt = dlt / imn;
            ref[0] = s_im / N + icm - hm;        got[0] = iq_to_d(r.f_im.u);
            ref[1] = s_it / N + ict - ht;        got[1] = iq_to_d(r.f_it.u);
            ref[2] = um;                         got[2] = iq_to_d(r.f_um.u);
            ref[3] = ut;                         got[3] = iq_to_d(r.f_ut.u);
            ref[4] = s_wsit / N + wsm * (ict - ht);   got[4] = iq_to_d(r.f_ws_it.u);
            ref[5] = s_wsim / N + wsm * (icm - hm);   got[5] = iq_to_d(r.f_ws_im.u);
            ref[6] = mm;                         got[6] = iq_to_d(r.f_mm.u);
            ref[7] = mt;                         got[7] = iq_to_d(r.f_mt.u);
            ref[8] = -wr * mt;                   got[8] = iq_to_d(r.f_wmt.u);
            ref[9] = wr * mm;                    got[9] = iq_to_d(r.f_wr.u);
            for (int i = 0; i < 10; i++) {
                /* Delta's own error passes into m: judged with it, below */
                double e = fabs(got[i] - ref[i]) - ((i >= 6) ? fabs(iq_to_d(r.dl_m) - dlm) / imn +
                                                                   fabs(iq_to_d(r.dl_t) - dlt) / imn
                                                             : 0.0);
                if (e > e_in) { e_in = e; }
            }
            if (fabs(iq_to_d(r.dl_m) - dlm) > e_dl) { e_dl = fabs(iq_to_d(r.dl_m) - dlm); }
            if (fabs(iq_to_d(r.dl_t) - dlt) > e_dl) { e_dl = fabs(iq_to_d(r.dl_t) - dlt); }
            if (fabs(dlm) > dl_max) { dl_max = fabs(dlm); }
            if (fabs(icm) > ic_max) { ic_max = fabs(icm); }
            i0m = iq_to_d(r.i_m);
            i0t = iq_to_d(r.i_t);
            s_im = s_it = s_um = s_ut = s_ws = s_wsit = s_wsim = 0.0;
            ident_regressor_filter_b(&r);
            ident_regressor_filter_c(&r);
        }
    }
    print_message("period-mean window: inputs within %.1f LSB24, Delta within %.1f LSB24 "
                  "(|Delta| up to %.2e pu, |K2^ c| up to %.2e pu)\n", e_in / LSB24, e_dl / LSB24,
                  dl_max, ic_max);
    assert_true(e_in <= 8.0 * LSB24);
    assert_true(e_dl <= 32.0 * LSB24);
    assert_true(dl_max >= 1e-5 && ic_max >= 1e-5);   /* the corrections are exercised */
    /* the filters' outputs reach the rows */
    assert_true(r.m_mf == r.f_mm.y && r.m_tf == r.f_mt.y && r.wm_tf == r.f_wmt.y);
    assert_true(r.wr_f == r.f_wr.y);
}

/* ident_regressor_set_period_mean refuses what it cannot represent and
 * changes nothing then. */
static void test_period_mean_rejects(void **state)
{
    ident_regressor_t r;
    (void)state;
    init_paper(&r);
    assert_int_equal(ident_regressor_set_period_mean(&r, 1e-5f, 1.0f, 0.5f, (float)MD_TS_S,
                                                     (float)MD_W_BASE), 1);   /* Tr < Ts */
    assert_int_equal(ident_regressor_set_period_mean(&r, 0.05f, 0.0f, 0.5f, (float)MD_TS_S,
                                                     (float)MD_W_BASE), 1);   /* K2 <= 0 */
    assert_int_equal(ident_regressor_set_period_mean(&r, 0.05f, 16.0f, 0.5f, (float)MD_TS_S,
                                                     (float)MD_W_BASE), 1);   /* K2 beyond the RLS */
    assert_int_equal(ident_regressor_set_period_mean(&r, 0.05f, 1.0f, 0.01f, (float)MD_TS_S,
                                                     (float)MD_W_BASE), 1);   /* i_M too small */
    assert_int_equal(r.period_mean, 0);
    assert_true(r.k_inv_im == _IQ(0.0));
    assert_int_equal(ident_regressor_set_period_mean(&r, 0.05f, 1.0f, 0.5f, (float)MD_TS_S,
                                                     (float)MD_W_BASE), 0);
    assert_int_equal(r.period_mean, 1);
}

static void test_init_rejects(void **state)
{
    ident_regressor_t r;
    (void)state;
    assert_int_equal(ident_regressor_init(&r, 0.0f, 10u, 1e-4f, 314.0f, 0u), BW_FILTER_ERR_WC);
    assert_int_equal(ident_regressor_init(&r, 62.8f, 0u, 1e-4f, 314.0f, 0u), BW_FILTER_ERR_N);
    assert_true(r.f_wr.d12 == _IQ30(0.0));     /* zeroed on error */
    init_paper(&r);
    r.i_m = _IQ(0.5);
    ident_regressor_step(&r);
    ident_regressor_reset(&r);
    assert_true(r.f_im.x1 == _IQ27(0.0) && r.f_im.z2 == _IQ27(0.0));
}

/* ident_regressor_check, the configuration table's test:
 * ident_regressor_init's verdict at its bounds: the decimation up to
 * IDENT_REGRESSOR_DECIM_LOG2_MAX, the filters' step Wc Ts 2^decim_log2 at
 * most BW_FILTER_A_MAX (Ts = 2^-15 s, 8 samples a step: Wc = 0.3 x 4096,
 * exact products). */
static void test_check(void **state)
{
    const float ts = 3.0517578125e-5f;
    const float wa = BW_FILTER_A_MAX * 4096.0f;
    const float wc[] = {wa, nextafterf(wa, 1e4f), WC_RAD_S, WC_RAD_S};
    const uint16_t dl[] = {3u, 3u, IDENT_REGRESSOR_DECIM_LOG2_MAX,
                           IDENT_REGRESSOR_DECIM_LOG2_MAX + 1u};
    const bw_filter_status_t want[] = {BW_FILTER_OK, BW_FILTER_ERR_STEP, BW_FILTER_OK,
                                       BW_FILTER_ERR_TS};
    ident_regressor_t r;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof want / sizeof want[0]; i++) {
        assert_int_equal(ident_regressor_check(wc[i], 10u, ts, 512.0f, dl[i]), want[i]);
        assert_int_equal(ident_regressor_init(&r, wc[i], 10u, ts, 512.0f, dl[i]), want[i]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rotation),
        cmocka_unit_test(test_regression_identity),
        cmocka_unit_test(test_regression_identity_decimated),
        cmocka_unit_test(test_saturation),
        cmocka_unit_test(test_period_mean_window),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_period_mean_rejects),
        cmocka_unit_test(test_init_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
