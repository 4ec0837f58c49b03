/* flux_obs (closed-loop rotor-flux observer) against a double-precision
 * reference of the paper's motor (Rs 1.031 ohm, Rr 0.465 ohm, Lm 6.4 mH,
 * Ls = Lr = 9.2 mH; bases 20 A, 34.64 V, 50 Hz, 15 kHz sampling).
 *
 * References, both independent of the module's code:
 *  - steady sinusoidal operation: rotor flux, currents and the exact mean
 *    voltage over each period in closed form (rotor-flux frame phasors);
 *    the observer's steady error predicted by the continuous-time transfer
 *    functions H_c, H_e of flux_obs.h, evaluated in complex double;
 *  - an acceleration transient: the rotor flux integrated by RK4 in the
 *    stationary frame with imposed currents (indirect orientation with the
 *    controller's Tr) and an imposed speed ramp; the mean voltage over
 *    each period is exact: int(u) = delta psi_s + Rs int(i).
 * Crossover 3 Hz (w_c = 0.06 pu); rated operating point i_M = 6.5625 A
 * (0.328 pu), i_T = 5 A (0.25 pu): w_slip Tr = 0.76. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <math.h>
#include <complex.h>
#include <cmocka.h>

#include "IQmathLib.h"
#include "base_values.h"
#include "flux_obs.h"

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
static double to_d20(_iq20 x) { return ldexp((double)x, -20); }   /* Tr is Q20 */
#else
static double to_d(_iq x) { return (double)x; }
static double to_d20(_iq20 x) { return (double)x; }
#endif
#define PI 3.14159265358979323846
#define DEG (180.0 / PI)
#define J ((double complex)I)   /* I is complex float */

/* the paper's motor, SI */
#define RS_OHM 1.031f
#define RR_OHM 0.465f
#define LM_H 6.4e-3f
#define LS_H 9.2e-3f
#define LR_H 9.2e-3f
#define TR_S (LR_H / RR_OHM)
#define WC_HZ 3.0f
#define WS_LPF_HZ 200.0f
#define ID_PU (6.5625 / 20.0)
#define IQ_PU 0.25

static base_values_t g_b;

/* the true motor in pu (double, from the same float bases the module sees) */
typedef struct {
    double rs, lm, ls, lr, sls, tr, ts, wc;
} motor_pu_t;
static motor_pu_t g_m;

static int setup(void **state)
{
    double zb, lb;
    (void)state;
    if (base_values_init(&g_b, 20.0f, 34.6410161513775f, 50.0f, 2u, 1.0f / 15000.0f) != BASE_OK) {
        return -1;
    }
    zb = (double)g_b.Z_base_ohm;
    lb = (double)g_b.L_base_H;
    g_m.rs = (double)RS_OHM / zb;
    g_m.lm = (double)LM_H / lb;
    g_m.ls = (double)LS_H / lb;
    g_m.lr = (double)LR_H / lb;
    g_m.sls = g_m.ls - g_m.lm * g_m.lm / g_m.lr;
    g_m.tr = (double)TR_S / (double)g_b.t_base_s;
    g_m.ts = (double)g_b.Ts_pu;
    g_m.wc = (double)WC_HZ / (double)g_b.f_base_Hz;
    return 0;
}

/* observer with the controller's beliefs: Rs x k_rs, Tr x k_tr */
static void obs_init(flux_obs_t *o, double k_rs, double k_tr)
{
    assert_int_equal(flux_obs_init(o, &g_b, (float)((double)RS_OHM * k_rs), LS_H, LR_H, LM_H,
                                   (float)((double)TR_S * k_tr), WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_OK);
}

static double wrap1(double x)
{
    x -= floor(x);
    return (x >= 1.0) ? 0.0 : x;
}

static void obs_feed(flux_obs_t *o, double complex i, double complex u, double th_r_rad)
{
    o->i_alpha = _IQ(creal(i));
    o->i_beta = _IQ(cimag(i));
    o->u_alpha = _IQ(creal(u));
    o->u_beta = _IQ(cimag(u));
    o->theta_r = _IQ(wrap1(th_r_rad / (2.0 * PI)));
    flux_obs_step(o);
}

static double complex obs_psi(const flux_obs_t *o)
{
    return to_d(o->psi_alpha) + J * to_d(o->psi_beta);
}

/* angle of a relative to b, degrees, in (-180, 180] */
static double ang_err_deg(double complex a, double complex b)
{
    return carg(a * conj(b)) * DEG;
}

/* ---- steady sinusoidal operation ---------------------------------------- */

typedef struct {
    double we;    /* flux (synchronous) speed, pu */
    double id;    /* i_M = psi_r / Lm, pu */
    double iq;    /* i_T, pu */
} op_t;

/* The observer's steady flux over the true one, psi^ / psi, from the
 * continuous-time blend of flux_obs.h: psi_s^ = (1 - H_c) psi_s + H_c
 * psi_s,cm + H_e dRs i, with the current model's steady flux in rotor
 * coordinates Lm i^r / (1 + j w_slip Tr') (i^r turns at w_slip). */
static double complex predict(const op_t *p, double k_rs, double k_tr)
{
    const double wc = g_m.wc;
    double complex s = J * p->we;
    double complex d = (s + wc) * (s + wc) * (s + wc);
    double complex hc = (3.0 * wc * wc * s + wc * wc * wc) / d;
    double complex he = s * (s + 3.0 * wc) / d;
    double wsl = p->iq / (g_m.tr * p->id);
    double complex i = p->id + J * p->iq;
    double complex psir = g_m.lm * p->id;
    double complex psis = g_m.ls * p->id + J * g_m.sls * p->iq;
    double complex psi_cm = g_m.lm * i / (1.0 + J * wsl * g_m.tr * k_tr);
    double complex psis_cm = (g_m.lm / g_m.lr) * psi_cm + g_m.sls * i;
    double complex psis_hat = (1.0 - hc) * psis + hc * psis_cm + he * (g_m.rs * (1.0 - k_rs)) * i;
    return (g_m.lr / g_m.lm) * (psis_hat - g_m.sls * i) / psir;
}

typedef struct {
    double err_max;    /* max |angle error|, deg, over the last 0.1 s */
    double err_mean;   /* mean angle error, deg, same window */
    double mag_mean;   /* mean |psi^| / |psi| */
    double ws_mean;    /* mean ws, pu */
    double complex uc_mean;   /* mean correction voltage u_c, pu */
} steady_res_t;

/* Run @p n samples of the closed-form operating point @p p with an extra DC
 * offset @p i0 on the measured current; statistics over the last @p m. */
static steady_res_t run_steady(flux_obs_t *o, const op_t *p, uint32_t n, uint32_t m,
                               double complex i0)
{
    const double ts = g_m.ts;
    double wsl = p->iq / (g_m.tr * p->id);
    double wr = p->we - wsl;
    double complex idq = p->id + J * p->iq;
    /* u = Rs i + j w_e psi_s in the flux frame; mean over [t - Ts, t] of
     * a phasor turning at w_e: factor (1 - e^{-j w_e Ts}) / (j w_e Ts) */
    double complex udq = g_m.rs * idq + J * p->we * (g_m.ls * p->id + J * g_m.sls * p->iq);
    double x = p->we * ts;
    double complex fm = (fabs(x) < 1e-12) ? 1.0 : (1.0 - cexp(-J * x)) / (J * x);
    steady_res_t r = {0.0, 0.0, 0.0, 0.0, 0.0};
    uint32_t k;

    for (k = 1u; k <= n; k++) {
        double t = (double)k * ts;
        double complex e = cexp(J * p->we * t);
        obs_feed(o, idq * e + i0, udq * fm * e, wr * t);
        if (k > n - m) {
            double complex psi = g_m.lm * p->id * e;
            double err = ang_err_deg(obs_psi(o), psi);
            if (fabs(err) > r.err_max) {
                r.err_max = fabs(err);
            }
            r.err_mean += err / (double)m;
            r.mag_mean += cabs(obs_psi(o)) / cabs(psi) / (double)m;
            r.ws_mean += to_d(o->ws) / (double)m;
            r.uc_mean += (to_d(o->uc_alpha) + J * to_d(o->uc_beta)) / (double)m;
        }
    }
    return r;
}

#define N_STEADY 18000u   /* 1.2 s: the triple pole at 3 Hz has settled (e^{-22.6} 22.6^2/2 < 1e-7) */
#define M_STEADY 1500u    /* last 0.1 s: 5 electrical periods at 0.93 pu */

/* Tr of the current model +-30 %, speeds from 1/3 w_c to 0.93 pu (1400
 * r/min).  Reference: the closed-form prediction.  The discrete observer
 * differs from it by the loop's one-sample delay (a phase of w_e Ts <=
 * 0.02 rad on the H_c term, i.e. <= 2 % of the predicted error), the
 * trapezoidal current integral ((w_e Ts)^2/12 = 3e-5 relative) and Q24
 * rounding (the angle to ~1e-5 deg): bound |err - pred| <= 0.03 |pred| +
 * 0.01 deg.  The requirement: above 10 w_c (0.6 pu, 30 Hz) the angle is
 * within 0.4 deg whatever the Tr error: |psi_cm - psi| / |psi| <= 0.20 at
 * the rated point for Tr +-30 %, times |H_c(10 w_c)| = 0.0296 -> 0.34 deg. */
static void test_steady_tr_error(void **state)
{
    static const double we_list[] = {0.02, 0.06, 0.2, 0.6, 0.9333, -0.9333};
    static const double ktr_list[] = {0.7, 1.0, 1.3};
    uint32_t i, j;
    (void)state;

    for (j = 0u; j < sizeof ktr_list / sizeof ktr_list[0]; j++) {
        for (i = 0u; i < sizeof we_list / sizeof we_list[0]; i++) {
            flux_obs_t o;
            op_t p = {we_list[i], ID_PU, IQ_PU};
            steady_res_t r;
            double complex pr = predict(&p, 1.0, ktr_list[j]);
            double pred = carg(pr) * DEG;

            obs_init(&o, 1.0, ktr_list[j]);
            r = run_steady(&o, &p, N_STEADY, M_STEADY, 0.0);
            print_message("Tr x%.1f w_e %+.4f pu: angle err %+.4f deg (max %.4f), predicted %+.4f;"
                          " |psi| %.5f pred %.5f; ws %.5f\n",
                          ktr_list[j], p.we, r.err_mean, r.err_max, pred, r.mag_mean, cabs(pr),
                          r.ws_mean);
            assert_int_equal(o.sat, 0);
            /* steady: the error is constant (max == |mean| within 0.01 deg) */
            assert_true(r.err_max - fabs(r.err_mean) <= 0.01);
            assert_true(fabs(r.err_mean - pred) <= 0.03 * fabs(pred) + 0.01);
            assert_true(fabs(r.mag_mean - cabs(pr)) <= 0.03 * fabs(cabs(pr) - 1.0) + 2e-4);
            if (fabs(p.we) >= 10.0 * g_m.wc) {
                assert_true(r.err_max <= 0.4);
            }
            /* the frame speed is the flux speed (angle steps, Q24 angles:
             * 2^-24 rev per step / (f_base Ts) -> 2e-5 pu) */
            assert_true(fabs(r.ws_mean - p.we) <= 1e-4);
        }
    }
}

/* The same operating points with one observer step every n = 8 samples
 * (the drive's slow task: flux_obs_set_step), fed as the drive feeds it:
 * the mean of the window's 8 period voltages and the trapezoidal mean of
 * its 9 current samples (exact sums of the closed-form signals), this
 * sample's current and rotor angle.  Against the same prediction: the
 * loop's delay is one step (n w_e Ts <= 0.16 rad of phase on the H_c
 * term: <= 16 % of the predicted error) and the forward-Euler correction
 * runs at g = w_c n Ts = 0.01; bound |err - pred| <= 0.2 |pred| + 0.02
 * deg, and the requirement above 10 w_c, 0.4 deg, holds as at n = 1. */
static void test_steady_tr_error_window(void **state)
{
    static const double we_list[] = {0.02, 0.2, 0.6, 0.9333, -0.9333};
    static const double ktr_list[] = {0.7, 1.0, 1.3};
    const uint32_t n = 8u;
    uint32_t i, j;
    (void)state;

    for (j = 0u; j < sizeof ktr_list / sizeof ktr_list[0]; j++) {
        for (i = 0u; i < sizeof we_list / sizeof we_list[0]; i++) {
            flux_obs_t o;
            op_t p = {we_list[i], ID_PU, IQ_PU};
            const double ts = g_m.ts;
            double wsl = p.iq / (g_m.tr * p.id);
            double wr = p.we - wsl;
            double complex idq = p.id + J * p.iq;
            double complex udq = g_m.rs * idq + J * p.we * (g_m.ls * p.id + J * g_m.sls * p.iq);
            double x = p.we * ts;
            double complex fm = (fabs(x) < 1e-12) ? 1.0 : (1.0 - cexp(-J * x)) / (J * x);
            double complex pr = predict(&p, 1.0, ktr_list[j]);
            double pred = carg(pr) * DEG;
            double err_mean = 0.0, err_max = 0.0;
            uint32_t k, steps = 0u, m = M_STEADY / n;

            obs_init(&o, 1.0, ktr_list[j]);
            assert_int_equal(flux_obs_set_step(&o, &g_b, (uint16_t)n, WC_HZ, WS_LPF_HZ),
                             FLUX_OBS_OK);
            for (k = n; k <= N_STEADY; k += n) {
                double complex su = 0.0, si = 0.0, e_k = cexp(J * p.we * (double)k * ts);
                uint32_t q;
                for (q = k - n + 1u; q <= k; q++) {
                    double complex e = cexp(J * p.we * (double)q * ts);
                    su += udq * fm * e;   /* the period (q-1, q]'s mean voltage */
                    si += idq * e;
                }
                /* trapezoid: the window's samples less half the change from
                 * its start sample to its end */
                si -= 0.5 * (idq * e_k - idq * cexp(J * p.we * (double)(k - n) * ts));
                o.u_alpha = _IQ(creal(su) / (double)n);
                o.u_beta = _IQ(cimag(su) / (double)n);
                o.i_mean_alpha = _IQ(creal(si) / (double)n);
                o.i_mean_beta = _IQ(cimag(si) / (double)n);
                o.i_alpha = _IQ(creal(idq * e_k));
                o.i_beta = _IQ(cimag(idq * e_k));
                o.theta_r = _IQ(wrap1(wr * (double)k * ts / (2.0 * PI)));
                flux_obs_step(&o);
                steps++;
                if (k > N_STEADY - m * n) {
                    double err = ang_err_deg(obs_psi(&o), g_m.lm * p.id * e_k);
                    err_max = fmax(err_max, fabs(err));
                    err_mean += err / (double)m;
                }
            }
            print_message("n = 8, Tr x%.1f w_e %+.4f pu: angle err %+.4f deg (max %.4f), "
                          "predicted %+.4f; ws %.5f\n", ktr_list[j], p.we, err_mean, err_max,
                          pred, to_d(o.ws));
            assert_true(steps == N_STEADY / n);
            assert_int_equal(o.sat, 0);
            assert_true(err_max - fabs(err_mean) <= 0.02);
            assert_true(fabs(err_mean - pred) <= 0.2 * fabs(pred) + 0.02);
            if (fabs(p.we) >= 10.0 * g_m.wc) {
                assert_true(err_max <= 0.4);
            }
            assert_true(fabs(to_d(o.ws) - p.we) <= 1e-3);
        }
    }
}

/* Rs of the voltage model +-10 %: no effect at DC (the current model
 * rules), an error ~ dRs |i| / w_e near and above the crossover: the
 * prediction again, same bound. */
static void test_steady_rs_error(void **state)
{
    static const double we_list[] = {0.02, 0.06, 0.2, 0.6, 0.9333};
    static const double krs_list[] = {0.9, 1.1};
    uint32_t i, j;
    (void)state;

    for (j = 0u; j < sizeof krs_list / sizeof krs_list[0]; j++) {
        for (i = 0u; i < sizeof we_list / sizeof we_list[0]; i++) {
            flux_obs_t o;
            op_t p = {we_list[i], ID_PU, IQ_PU};
            steady_res_t r;
            double complex pr = predict(&p, krs_list[j], 1.0);
            double pred = carg(pr) * DEG;

            obs_init(&o, krs_list[j], 1.0);
            r = run_steady(&o, &p, N_STEADY, M_STEADY, 0.0);
            print_message("Rs x%.1f w_e %+.4f pu: angle err %+.4f deg, predicted %+.4f;"
                          " |psi| %.5f pred %.5f\n",
                          krs_list[j], p.we, r.err_mean, pred, r.mag_mean, cabs(pr));
            assert_true(fabs(r.err_mean - pred) <= 0.03 * fabs(pred) + 0.01);
            assert_true(fabs(r.mag_mean - cabs(pr)) <= 0.03 * fabs(cabs(pr) - 1.0) + 2e-4);
        }
    }
}


/* ---- acceleration transient (RK4 reference) ------------------------------ */

/* The identification's run: magnetise at standstill for 0.15 s (i_M only,
 * ramped from 0 in 2 ms),
 * then i_T = 0.25 pu (ramped in 2 ms) and the speed ramped at 2000 r/min/s
 * to 1400 r/min (0.9333 pu, 0.7 s), held 0.3 s.  Currents are imposed in
 * the frame of an indirect orientation with the controller's Tr (x k_ctrl):
 * theta_f = theta_r + int(i_T / (Tr_ctrl i_M)); with k_ctrl != 1 the true
 * flux is mis-oriented and its magnitude swings, as in the drive today. */
typedef struct {
    double tm, tq, a, wmax, tend;   /* pu time, pu speed / pu time, pu */
    double k_ctrl;
} accel_t;

static double accel_wr(const accel_t *s, double t)
{
    double w = (t <= s->tm) ? 0.0 : s->a * (t - s->tm);
    return (w > s->wmax) ? s->wmax : w;
}

static double accel_thr(const accel_t *s, double t)
{
    double t1 = s->tm + s->wmax / s->a;   /* end of the ramp */
    if (t <= s->tm) {
        return 0.0;
    }
    if (t <= t1) {
        return 0.5 * s->a * (t - s->tm) * (t - s->tm);
    }
    return 0.5 * s->a * (t1 - s->tm) * (t1 - s->tm) + s->wmax * (t - t1);
}

static double accel_iq(const accel_t *s, double t, double *iq_int)
{
    double x = t - s->tm;
    if (x <= 0.0) {
        *iq_int = 0.0;
        return 0.0;
    }
    if (x <= s->tq) {
        *iq_int = IQ_PU * x * x / (2.0 * s->tq);
        return IQ_PU * x / s->tq;
    }
    *iq_int = IQ_PU * (0.5 * s->tq + (x - s->tq));
    return IQ_PU;
}

/* imposed stator current at t, and the controller's frame angle */
static double complex accel_i(const accel_t *s, double t, double *th_f)
{
    double iq_int;
    double iq = accel_iq(s, t, &iq_int);
    /* i_M rises from 0 in tq (the observer starts at rest: a current step
     * at t = 0 would be a flux the period's mean voltage cannot show) */
    double id = (t >= s->tq) ? ID_PU : ID_PU * t / s->tq;
    *th_f = accel_thr(s, t) + iq_int / (g_m.tr * s->k_ctrl * ID_PU);
    return (id + J * iq) * cexp(J * *th_f);
}

/* d/dt of (psi_r, int i): (Lm i - psi_r) / Tr + j w_r psi_r, i */
static void accel_deriv(const accel_t *s, double t, const double complex *x, double complex *dx)
{
    double th_f;
    double complex i = accel_i(s, t, &th_f);
    dx[0] = (g_m.lm * i - x[0]) / g_m.tr + J * accel_wr(s, t) * x[0];
    dx[1] = i;
}

typedef struct {
    double err_hi;     /* max |angle error| with w_r >= 10 w_c, deg */
    double err_mid;    /* max with 3 w_c <= w_r < 10 w_c */
    double err_lo;     /* max with w_r < 3 w_c, after 0.1 s of magnetisation */
    double err_ifo_hi; /* the controller frame's own error at w_r >= 10 w_c */
    double mag_hi;     /* max ||psi^| / |psi| - 1| at w_r >= 10 w_c */
    double swing;      /* max |psi_r| / min |psi_r| of the true flux during the ramp */
} accel_res_t;

static accel_res_t run_accel(double k_ctrl, double k_tr_obs)
{
    const double wb = (double)g_b.w_base_rad_s;
    const double ts = g_m.ts;
    const double h = ts / 4.0;
    accel_t s;
    accel_res_t r = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double complex x[2] = {0.0, 0.0};
    double psi_min = 1e9, psi_max = 0.0;
    double complex psis_prev, q_prev;
    double th_f;
    flux_obs_t o;
    uint32_t k, n;

    s.tm = 0.15 * wb;
    s.tq = 0.002 * wb;
    s.a = (2000.0 / 1500.0) / wb;     /* 2000 r/min/s, n_base = 1500 r/min */
    s.wmax = 1400.0 / 1500.0;
    s.tend = 1.15 * wb;
    s.k_ctrl = k_ctrl;
    obs_init(&o, 1.0, k_tr_obs);
    n = (uint32_t)(s.tend / ts);
    psis_prev = g_m.sls * accel_i(&s, 0.0, &th_f);
    q_prev = 0.0;
    for (k = 1u; k <= n; k++) {
        double t0 = (double)(k - 1u) * ts;
        double t = (double)k * ts;
        double complex psis, u, i, k1[2], k2[2], k3[2], k4[2], xt[2];
        double wr, err, j;
        uint32_t m, c;

        for (m = 0u; m < 4u; m++) {   /* RK4, 4 steps per period */
            double tt = t0 + (double)m * h;
            accel_deriv(&s, tt, x, k1);
            for (c = 0u; c < 2u; c++) xt[c] = x[c] + 0.5 * h * k1[c];
            accel_deriv(&s, tt + 0.5 * h, xt, k2);
            for (c = 0u; c < 2u; c++) xt[c] = x[c] + 0.5 * h * k2[c];
            accel_deriv(&s, tt + 0.5 * h, xt, k3);
            for (c = 0u; c < 2u; c++) xt[c] = x[c] + h * k3[c];
            accel_deriv(&s, tt + h, xt, k4);
            for (c = 0u; c < 2u; c++) {
                x[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
            }
        }
        i = accel_i(&s, t, &th_f);
        psis = g_m.sls * i + (g_m.lm / g_m.lr) * x[0];
        /* exact mean voltage over the period: (delta psi_s + Rs int i) / Ts */
        u = (psis - psis_prev + g_m.rs * (x[1] - q_prev)) / ts;
        psis_prev = psis;
        q_prev = x[1];
        obs_feed(&o, i, u, accel_thr(&s, t));
        assert_int_equal(o.sat, 0);

        wr = accel_wr(&s, t);
        err = fabs(ang_err_deg(obs_psi(&o), x[0]));
        if (wr >= 10.0 * g_m.wc) {
            double ifo = fabs(ang_err_deg(cexp(J * th_f), x[0]));
            j = fabs(cabs(obs_psi(&o)) / cabs(x[0]) - 1.0);
            r.err_hi = (err > r.err_hi) ? err : r.err_hi;
            r.err_ifo_hi = (ifo > r.err_ifo_hi) ? ifo : r.err_ifo_hi;
            r.mag_hi = (j > r.mag_hi) ? j : r.mag_hi;
        } else if (wr >= 3.0 * g_m.wc) {
            r.err_mid = (err > r.err_mid) ? err : r.err_mid;
        } else if (t > 0.1 * wb) {
            r.err_lo = (err > r.err_lo) ? err : r.err_lo;
        }
        if (t > s.tm) {
            double pm = cabs(x[0]);
            psi_min = (pm < psi_min) ? pm : psi_min;
            psi_max = (pm > psi_max) ? pm : psi_max;
        }
    }
    r.swing = psi_max / psi_min;
    return r;
}

/* The acceleration with Tr +-30 % in the observer's current model, the
 * controller's frame either right or wrong by the same factor (the drive
 * today: one believed Tr everywhere).  Bound at speed (w_r >= 10 w_c,
 * from 0.45 s into the ramp): 0.4 deg, the steady bound (<= 0.34 deg at
 * 10 w_c for the rated slip, test_steady_tr_error) plus margin for the
 * decay of the larger low-speed error through (s + w_c)^3; the frame error
 * of the indirect orientation itself is 7-10 deg there.  Magnitude: the
 * steady analysis gives |H_c| 0.2 = 0.6 % at 10 w_c; bound 0.6 %.  With
 * exact models the observer is exact (complementary blend): 0.01 deg
 * everywhere (measured 0.005: RK4 and Q24). */
static void test_accel_tr_error(void **state)
{
    static const double cases[][2] = {{1.0, 0.7}, {1.0, 1.3}, {0.7, 0.7}, {1.3, 1.3}, {1.0, 1.0}};
    uint32_t c;
    (void)state;

    for (c = 0u; c < sizeof cases / sizeof cases[0]; c++) {
        accel_res_t r = run_accel(cases[c][0], cases[c][1]);
        print_message("ctrl Tr x%.1f, observer Tr x%.1f: angle err max %.3f deg (w_r >= 10 w_c),"
                      " %.3f (3..10 w_c), %.3f (< 3 w_c); |psi| err %.4f; true |psi| swing"
                      " x%.3f; indirect frame err %.2f deg\n",
                      cases[c][0], cases[c][1], r.err_hi, r.err_mid, r.err_lo, r.mag_hi, r.swing,
                      r.err_ifo_hi);
        assert_true(r.err_hi <= 0.4);
        assert_true(r.mag_hi <= 0.006);
        if (cases[c][1] == 1.0) {
            assert_true(r.err_hi <= 0.01 && r.err_mid <= 0.01 && r.err_lo <= 0.01);
        }
    }
}

/* ---- drift, wind-up, parameters, bad input -------------------------------- */

/* 20 s at the rated point with a DC offset of (0.01, -0.005) pu (0.2 A,
 * 0.1 A: twenty times a trimmed sensor's) on the measured current and the
 * right parameters.  A pure integrator would drift by Rs i0 = 0.0067 pu of
 * flux per pu time, 42 pu in 20 s.  Here H_e(0) = 0: the integral state
 * takes u_c = Rs i0 and the flux does not drift.  What remains: the
 * current model's response to a DC current, Lm i0 / (1 - j w_r Tr) (a DC
 * flux vector in the stationary frame, an angle ripple at w_e), passed at
 * H_c(0) = 1: 0.0023 pu of 0.38 pu, i.e. asin(0.0060) = 0.35 deg.
 * Asserted: the angle error over the last 0.1 s is within 0.01 deg of that
 * over 1.9..2.0 s (no drift) and below the predicted ripple + 0.02 deg;
 * the mean correction voltage is Rs i0 within 2 % (the integral holds the
 * offset, far inside its bound); no state saturated. */
static void test_dc_offset_no_drift(void **state)
{
    const double complex i0 = 0.01 - 0.005 * J;
    op_t p = {0.9333, ID_PU, IQ_PU};
    double wr = p.we - p.iq / (g_m.tr * p.id);
    double ripple = asin(cabs(g_m.lm * i0 / (1.0 - J * wr * g_m.tr)) / (g_m.lm * ID_PU)) * DEG;
    flux_obs_t o;
    steady_res_t r2, r20;
    double complex uc;
    (void)state;

    /* the 2 s window from its own run (same start, same inputs) */
    obs_init(&o, 1.0, 1.0);
    r2 = run_steady(&o, &p, 30000u, M_STEADY, i0);
    obs_init(&o, 1.0, 1.0);
    r20 = run_steady(&o, &p, 300000u, M_STEADY, i0);
    uc = r20.uc_mean;   /* over 0.1 s: 4.67 electrical periods, AC part averages out */
    print_message("DC offset: angle err max %.4f deg at 2 s, %.4f at 20 s (predicted ripple %.4f);"
                  " u_c (%.6f, %.6f) vs Rs i0 (%.6f, %.6f); |psi_s| %.4f\n",
                  r2.err_max, r20.err_max, ripple, creal(uc), cimag(uc), creal(g_m.rs * i0),
                  cimag(g_m.rs * i0), cabs(to_d(o.psis_alpha) + J * to_d(o.psis_beta)));
    assert_int_equal(o.sat, 0);
    assert_true(fabs(r20.err_max - r2.err_max) <= 0.01);
    assert_true(r20.err_max <= ripple + 0.02);
    assert_true(cabs(uc - g_m.rs * i0) <= 0.02 * cabs(g_m.rs * i0));
}

/* Online parameter change: at 0.2 pu (3.3 w_c, where the current model
 * still weighs |H_c| = 0.27) with Tr x1.3 the steady error is +2.22 deg
 * (test_steady_tr_error); flux_obs_set_tr(true Tr) mid-run must bring it
 * to the exact-model error (< 0.01 deg) after the blend settles (1.2 s). */
static void test_set_tr_online(void **state)
{
    op_t p = {0.2, ID_PU, IQ_PU};
    flux_obs_t o;
    steady_res_t r;
    (void)state;

    obs_init(&o, 1.0, 1.3);
    r = run_steady(&o, &p, N_STEADY, M_STEADY, 0.0);
    assert_true(r.err_mean > 2.0);
    assert_int_equal(flux_obs_set_tr(&o, _IQ20(g_m.tr)), FLUX_OBS_OK);
    /* run_steady restarts its clock at t = 0: the inputs jump in phase,
     * which the observer has to ride through as well */
    r = run_steady(&o, &p, N_STEADY, M_STEADY, 0.0);
    print_message("after set_tr: angle err %.4f deg\n", r.err_mean);
    assert_true(r.err_max <= 0.01);
}

/* Setters: values from pu against the init's (float) values, the series kf
 * against 1 - exp(-Ts/Tr) (budget as ifo: (1/Tr + 4) LSB in Q24), and
 * rejection keeping the old values. */
static void test_setters(void **state)
{
    const double lsb = ldexp(1.0, -24);
    flux_obs_t o, ref;
    _iq20 tr;
    uint32_t i;
    (void)state;

    obs_init(&ref, 1.0, 1.0);
    obs_init(&o, 1.0, 1.0);
    /* large motors' Tr (hundreds of pu, Q20) as the paper motor's 6.2 pu */
    {
        static const double tr_list[] = {150.0, 292.4, 999.0};
        for (i = 0u; i < sizeof tr_list / sizeof tr_list[0]; i++) {
            tr = _IQ20(tr_list[i]);
            assert_int_equal(flux_obs_set_tr(&o, tr), FLUX_OBS_OK);
            assert_true(o.tr == tr);
            assert_true(fabs(to_d(o.kf) - (1.0 - exp(-to_d(o.ts) / to_d20(tr)))) <=
                        (1.0 / to_d20(tr) + 4.0) * lsb + 1e-9);
        }
    }
    tr = _IQ20(g_m.tr);
    assert_int_equal(flux_obs_set_tr(&o, tr), FLUX_OBS_OK);
    assert_true(fabs(to_d(o.kf) - (1.0 - exp(-to_d(o.ts) / to_d20(tr)))) <=
                (1.0 / to_d20(tr) + 4.0) * lsb + 1e-9);
    /* against the init's float kf: plus the Q20 Tr's truncation, kf 16 / Tr LSB */
    assert_true(fabs(to_d(o.kf) - to_d(ref.kf)) <=
                (1.0 / to_d20(tr) + 4.0 + 16.0 * to_d(o.kf) / to_d20(tr)) * lsb + 1e-9);

    /* rejected: the old values stay */
    ref = o;
    assert_int_equal(flux_obs_set_rs(&o, _IQ(-0.01)), FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_set_rs(&o, _IQ(4.5)), FLUX_OBS_ERR_RS);
    assert_true(o.rs == ref.rs);
    assert_int_equal(flux_obs_set_tr(&o, _IQtoIQ20(_IQmpy(o.ts, _IQ(5.0)))), FLUX_OBS_ERR_TR);
    assert_int_equal(flux_obs_set_tr(&o, _IQ20(FLUX_OBS_TR_MAX_PU) + _IQ20(1.0)), FLUX_OBS_ERR_TR);
    assert_int_equal(flux_obs_set_tr(&o, _IQ20(-1.0)), FLUX_OBS_ERR_TR);
    assert_true(o.kf == ref.kf && o.tr == ref.tr);
}

/* Bad arguments to init: a status naming the argument, and an inert
 * observer (zero gains: its outputs stay 0 whatever the inputs). */
static void test_init_errors(void **state)
{
    static const struct {
        float rs, ls, lr, lm, tr, wc, wf;
        flux_obs_status_t want;
    } bad[] = {
        {-0.1f, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_RS},
        {100.0f, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_RS},
        {RS_OHM, LS_H, LM_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_L},       /* Lr = Lm */
        {RS_OHM, LM_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_L},       /* Ls = Lm */
        {RS_OHM, LS_H, 5.0f * LM_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_L},
        {RS_OHM, LS_H, LR_H, 0.0f, TR_S, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_L},
        {RS_OHM, LS_H, LR_H, LM_H, 1e-4f, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_TR},    /* < 10 Ts */
        {RS_OHM, LS_H, LR_H, LM_H, 3.5f, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_TR},     /* > 1000 pu */
        {RS_OHM, LS_H, LR_H, LM_H, TR_S, 0.0f, WS_LPF_HZ, FLUX_OBS_ERR_WC},
        {RS_OHM, LS_H, LR_H, LM_H, TR_S, 60.0f, WS_LPF_HZ, FLUX_OBS_ERR_WC},     /* > f_base */
        {RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, 0.0f, FLUX_OBS_ERR_WS_LPF},
        {RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, 5000.0f, FLUX_OBS_ERR_WS_LPF},
    };
    flux_obs_t o;
    uint32_t c, k;
    (void)state;

    assert_int_equal(flux_obs_init(&o, NULL, RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_ERR_BASE);
    assert_int_equal(flux_obs_init(&o, &g_b, NAN, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_init(&o, &g_b, RS_OHM, LS_H, LR_H, LM_H, NAN, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_ERR_TR);
    for (c = 0u; c < sizeof bad / sizeof bad[0]; c++) {
        flux_obs_status_t st = flux_obs_init(&o, &g_b, bad[c].rs, bad[c].ls, bad[c].lr, bad[c].lm,
                                             bad[c].tr, bad[c].wc, bad[c].wf);
        if (st != bad[c].want) {
            print_error("case %u: status %d want %d\n", (unsigned)c, (int)st, (int)bad[c].want);
            fail();
        }
        for (k = 0u; k < 100u; k++) {
            o.i_alpha = _IQ(0.5);
            o.i_beta = _IQ(-0.3);
            o.u_alpha = _IQ(0.7);
            o.u_beta = _IQ(0.2);
            o.theta_r = _IQ(0.25);
            flux_obs_step(&o);
        }
        assert_true(o.psi_alpha == _IQ(0.0) && o.psi_beta == _IQ(0.0));
        assert_true(o.psi_mag == _IQ(0.0) && o.ws == _IQ(0.0));
    }
}

/* flux_obs_check and flux_obs_step_check, the configuration table's tests:
 * flux_obs_init's and flux_obs_set_step's verdicts at bounds of flux_obs.h
 * (bases 50 Hz, 15 kHz: Ts = 0.020944 pu).  Init: w_c at most
 * FLUX_OBS_WC_MAX_PU (50 Hz), the ws low-pass 2 pi f Ts <= 1 (2387.3 Hz),
 * Rs at most FLUX_OBS_RS_MAX (4 Z_base = 6.93 ohm).  The step of 8
 * samples: w_c 8 Ts <= FLUX_OBS_G_MAX (14.92 Hz), 2 pi f 8 Ts <= 1
 * (298.4 Hz), the float of the Q20 Tr at least 10 steps (to the LSB);
 * set_step names each refusal FLUX_OBS_ERR_BASE. */
static void test_check(void **state)
{
    static const struct {
        float rs, wc, wf;
        flux_obs_status_t want;
    } c_init[] = {
        {RS_OHM, 50.0f, WS_LPF_HZ, FLUX_OBS_OK},
        {RS_OHM, 50.01f, WS_LPF_HZ, FLUX_OBS_ERR_WC},
        {RS_OHM, WC_HZ, 2387.0f, FLUX_OBS_OK},
        {RS_OHM, WC_HZ, 2388.0f, FLUX_OBS_ERR_WS_LPF},
        {4.0f * 1.7320508f * 0.9999f, WC_HZ, WS_LPF_HZ, FLUX_OBS_OK},
        {4.0f * 1.7320508f * 1.0001f, WC_HZ, WS_LPF_HZ, FLUX_OBS_ERR_RS},
    };
    static const struct {
        float wc, wf;
        flux_obs_status_t want;
    } c_step[] = {
        {14.9f, WS_LPF_HZ, FLUX_OBS_OK},
        {15.0f, WS_LPF_HZ, FLUX_OBS_ERR_WC},
        {WC_HZ, 298.0f, FLUX_OBS_OK},
        {WC_HZ, 299.0f, FLUX_OBS_ERR_WS_LPF},
    };
    flux_obs_t o;
    _iq20 tr_lo, tr_below;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof c_init / sizeof c_init[0]; i++) {
        assert_int_equal(flux_obs_check(&g_b, c_init[i].rs, LS_H, LR_H, LM_H, TR_S, c_init[i].wc,
                                        c_init[i].wf),
                         c_init[i].want);
        assert_int_equal(flux_obs_init(&o, &g_b, c_init[i].rs, LS_H, LR_H, LM_H, TR_S,
                                       c_init[i].wc, c_init[i].wf),
                         c_init[i].want);
    }
    assert_int_equal(flux_obs_check(NULL, RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_ERR_BASE);
    for (i = 0; i < sizeof c_step / sizeof c_step[0]; i++) {
        assert_int_equal(flux_obs_init(&o, &g_b, RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ,
                                       WS_LPF_HZ),
                         FLUX_OBS_OK);
        assert_int_equal(flux_obs_step_check(&g_b, 8u, c_step[i].wc, c_step[i].wf, o.tr),
                         c_step[i].want);
        assert_int_equal(flux_obs_set_step(&o, &g_b, 8u, c_step[i].wc, c_step[i].wf),
                         (c_step[i].want == FLUX_OBS_OK) ? FLUX_OBS_OK : FLUX_OBS_ERR_BASE);
    }
    /* the least Tr: the first Q20 value whose float reaches 10 steps (the
     * truncated conversion of the bound itself falls short: set_step's kf
     * design refused it) */
    tr_lo = _IQ20(FLUX_OBS_TR_MIN_SAMPLES * (g_b.Ts_pu * 8.0f));
#if MATH_TYPE == IQ_MATH
    if (_IQ20toF(tr_lo) < FLUX_OBS_TR_MIN_SAMPLES * (g_b.Ts_pu * 8.0f)) {
        tr_lo++;
    }
    tr_below = tr_lo - 1;
#else
    tr_below = nextafterf(tr_lo, 0.0f);
#endif
    assert_int_equal(flux_obs_step_check(&g_b, 8u, WC_HZ, WS_LPF_HZ, tr_lo), FLUX_OBS_OK);
    assert_int_equal(flux_obs_step_check(&g_b, 8u, WC_HZ, WS_LPF_HZ, tr_below), FLUX_OBS_ERR_TR);
    /* set_step on an observer holding each: the same verdicts */
    assert_int_equal(flux_obs_init(&o, &g_b, RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_OK);
    o.tr = tr_lo;
    assert_int_equal(flux_obs_set_step(&o, &g_b, 8u, WC_HZ, WS_LPF_HZ), FLUX_OBS_OK);
    assert_int_equal(flux_obs_init(&o, &g_b, RS_OHM, LS_H, LR_H, LM_H, TR_S, WC_HZ, WS_LPF_HZ),
                     FLUX_OBS_OK);
    o.tr = tr_below;
    assert_true(flux_obs_set_step(&o, &g_b, 8u, WC_HZ, WS_LPF_HZ) != FLUX_OBS_OK);
    assert_int_equal(flux_obs_step_check(&g_b, 3u, WC_HZ, WS_LPF_HZ, o.tr), FLUX_OBS_ERR_BASE);
    assert_int_equal(flux_obs_step_check(NULL, 8u, WC_HZ, WS_LPF_HZ, o.tr), FLUX_OBS_ERR_BASE);
}

/* Inputs at the ends of Q24 (+-127 pu, a broken sensor or a wrong scale)
 * for 2 s with a turning rotor angle: saturation, reported in sat, every
 * state within its bound (UBSan would flag an overflow), and after a
 * reset the observer is back at rest. */
static void test_extreme_inputs(void **state)
{
    flux_obs_t o;
    uint32_t k;
    uint16_t any_sat = 0u;
    (void)state;

    obs_init(&o, 1.0, 1.0);
    for (k = 0u; k < 30000u; k++) {
        _iq big = ((k / 700u) % 2u == 0u) ? _IQ(127.0) : _IQ(-127.0);
        o.i_alpha = big;
        o.i_beta = -big;
        o.u_alpha = -big;
        o.u_beta = big;
        o.theta_r = _IQ(wrap1((double)k * 0.0011));
        flux_obs_step(&o);
        any_sat |= o.sat;
        assert_true(_IQabs(o.psis_alpha) <= _IQ(FLUX_OBS_PSI_MAX));
        assert_true(_IQabs(o.psis_beta) <= _IQ(FLUX_OBS_PSI_MAX));
        assert_true(_IQabs(o.z_alpha) <= _IQ(FLUX_OBS_Z_MAX) && _IQabs(o.y_beta) <= _IQ(FLUX_OBS_Y_MAX));
        assert_true(o.theta >= _IQ(0.0) && o.theta < _IQ(1.0));
    }
    assert_int_equal(any_sat, 1);
    flux_obs_reset(&o);
    assert_true(o.psis_alpha == _IQ(0.0) && o.z_beta == _IQ(0.0) && o.psirr_d == _IQ(0.0));
}

/* The flux angle jumping +0.3 rev per sample for 300 samples, then -0.3 rev
 * (the flux vanishing when the bridge turns off makes such jumps): ws hits
 * its limit +-FLUX_OBS_WS_MAX and the low-pass ws_f follows it from one
 * limit to the other.  ws - ws_f must stay inside Q24 (it reached -200 pu,
 * a signed overflow, with the former 100 pu limit); ws_f never leaves
 * [-50, 50] pu (a wrapped sum would flip its sign).  The angle is imposed
 * through the stator-flux state, with zero current and voltage. */
static void test_angle_jumps_bounded(void **state)
{
    flux_obs_t o;
    uint32_t k;
    const _iq lim = _IQ(FLUX_OBS_WS_MAX);
    const _iq tol = _IQ((double)FLUX_OBS_WS_MAX * 1e-4);   /* truncation of the angle step */
    double th = 0.0;
    _iq ws_f_max = _IQ(0.0), ws_f_min = _IQ(0.0);
    (void)state;

    obs_init(&o, 1.0, 1.0);
    for (k = 0u; k < 600u; k++) {
        th = wrap1(th + ((k < 300u) ? 0.3 : -0.3));
        o.psis_alpha = _IQ(0.5 * cos(2.0 * PI * th));
        o.psis_beta = _IQ(0.5 * sin(2.0 * PI * th));
        obs_feed(&o, 0.0, 0.0, 0.0);
        assert_true(_IQabs(o.ws) <= lim + tol);
        assert_true(_IQabs(o.ws_f) <= lim + tol);
        if (o.ws_f > ws_f_max) { ws_f_max = o.ws_f; }
        if (o.ws_f < ws_f_min) { ws_f_min = o.ws_f; }
    }
    /* both limits were reached: the test exercised the worst difference */
    assert_true(ws_f_max > lim - _IQ(1.0) && ws_f_min < -lim + _IQ(1.0));
}

/* ---- DC re-seat (flux_obs_set_rs_dc) -------------------------------------- */

/* Standstill magnetisation with the believed Rs 30 % high: a constant
 * current of 0.328 pu at 30 deg (both axes), u = Rs_true i, the rotor at
 * 0.3 rev, for 0.3 s (15 Tr: the current model is at Lm i within e^-15 =
 * 3e-7), while the voltage model's error -0.3 Rs i pulls psi_s off (the
 * blend removes it only as e^{-w_c t} (w_c t)^2: still visible at 0.3 s).
 * Then flux_obs_set_rs_dc(true Rs, u, i):
 *  - at once: psi (output) = psi_cm, exactly (IQ: the same integers; the
 *    doc: "the output continues from the re-seated flux (= the current
 *    model's rotor flux)"), |psi| by _IQmag (0.5 LSB), theta by
 *    _IQatan2PU (0.52 LSB), theta_prev = theta, ws = ws_f = 0; psi_cm
 *    against Lm i in double: the rounded current-model recursion settles
 *    within 0.5/kf = 149 LSB on each rotor axis (211 LSB in magnitude),
 *    Lm i and the rotation back to the stationary frame truncated (< 4
 *    LSB), the inputs quantised (< 1), e^-15 Lm |i| = 2 LSB: bound 220 LSB
 *    (the angle: 220 LSB / (2 pi |psi|) = 92 LSB of a revolution, + 1);
 *  - the re-seated states: psi_s = (Lm/Lr) psi_cm + sigma Ls i (2 products,
 *    2 LSB), y = (Rs i - u)/w_c, z = 3 y: here Rs i - u is only the Q24
 *    rounding of u and of Rs i (< 2 LSB), so |y| <= 2 LSB / w_c + 1 =
 *    35 LSB and |u_c| <= 3 LSB;
 *  - continuing at DC with the true Rs for 2000 samples (1.3 crossover
 *    time constants past the peak below), the flux stays put: what moves
 *    it is the truncation of Ts e (-0.5 LSB per sample, a voltage of 0.5
 *    LSB / Ts_pu = 24 LSB that the old integral state had compensated and
 *    the re-seat discarded) plus the 2 LSB residual of u_c, through
 *    H_e/s: the flux error of a voltage step eps is eps t (1 + w_c t)
 *    e^{-w_c t}, at most 0.84 eps / w_c, times Lr/Lm = 1.44 for psi_r:
 *    0.84 * 26 / 0.06 * 1.44 = 524 LSB; bound 600 LSB (1e-4 of |psi|).
 *    FLOAT: no truncation bias; within the same bound.
 * Rejected Rs (< 0, > 4): nothing changes (the whole struct). */
static void test_set_rs_dc(void **state)
{
    const double lsb = ldexp(1.0, -24);
    const double im = ID_PU, ang = PI / 6.0;
    const double complex i = im * cexp(J * ang);
    const double complex u = g_m.rs * i;
    flux_obs_t o, before;
    double complex psi_cm, psi0, drift_before;
    double max_move = 0.0;
    uint32_t k;
    _iq rs_true = _IQ(g_m.rs);
    (void)state;

    obs_init(&o, 1.3, 1.0);
    for (k = 1u; k <= 4500u; k++) {
        obs_feed(&o, i, u, 0.3 * 2.0 * PI);
    }
    psi_cm = to_d(o.psi_cm_alpha) + J * to_d(o.psi_cm_beta);
    drift_before = obs_psi(&o) - psi_cm;

    /* rejected: nothing changes */
    before = o;
    assert_int_equal(flux_obs_set_rs_dc(&o, _IQ(-0.01), o.u_alpha, o.u_beta, o.i_alpha, o.i_beta),
                     FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_set_rs_dc(&o, _IQ(4.01), o.u_alpha, o.u_beta, o.i_alpha, o.i_beta),
                     FLUX_OBS_ERR_RS);
    assert_memory_equal(&o, &before, sizeof o);

    assert_int_equal(flux_obs_set_rs_dc(&o, rs_true, o.u_alpha, o.u_beta, o.i_alpha, o.i_beta),
                     FLUX_OBS_OK);
    print_message("set_rs_dc: before |psi - psi_cm| %.4f pu; psi_cm err vs Lm i %.1f LSB;"
                  " y (%.1f, %.1f) LSB, u_c (%.1f, %.1f) LSB\n",
                  cabs(drift_before), cabs(psi_cm - g_m.lm * i) / lsb, to_d(o.y_alpha) / lsb,
                  to_d(o.y_beta) / lsb, to_d(o.uc_alpha) / lsb, to_d(o.uc_beta) / lsb);
    /* the voltage model had drifted (the reason for the re-seat) */
    assert_true(cabs(drift_before) > 0.01);
    assert_true(o.rs == rs_true);
    assert_int_equal(o.sat, 0);
    assert_true(o.psi_alpha == o.psi_cm_alpha && o.psi_beta == o.psi_cm_beta);
    assert_true(fabs(to_d(o.psi_mag) - cabs(psi_cm)) <= 0.5 * lsb + 1e-7);
    assert_true(fabs(to_d(o.theta) - to_d(_IQatan2PU(o.psi_cm_beta, o.psi_cm_alpha))) <= 0.0);
    assert_true(o.theta_prev == o.theta);
    assert_true(o.ws == _IQ(0.0) && o.ws_f == _IQ(0.0));
    /* independent: the current model at DC is Lm i, its angle that of i */
    assert_true(cabs(psi_cm - g_m.lm * i) <= 220.0 * lsb);
    assert_true(fabs(to_d(o.theta) - ang / (2.0 * PI)) <= (220.0 / (2.0 * PI * cabs(g_m.lm * i)) + 1.0) * lsb);
    /* the re-seated states */
    assert_true(cabs(to_d(o.psis_alpha) + J * to_d(o.psis_beta) -
                     ((g_m.lm / g_m.lr) * psi_cm + g_m.sls * i)) <= 4.0 * lsb + 1e-6 * cabs(psi_cm));
    assert_true(fabs(to_d(o.y_alpha)) <= 35.0 * lsb && fabs(to_d(o.y_beta)) <= 35.0 * lsb);
    assert_true(fabs(to_d(o.z_alpha) - 3.0 * to_d(o.y_alpha)) <= lsb);
    assert_true(fabs(to_d(o.z_beta) - 3.0 * to_d(o.y_beta)) <= lsb);
    assert_true(fabs(to_d(o.uc_alpha)) <= 3.0 * lsb && fabs(to_d(o.uc_beta)) <= 3.0 * lsb);

    /* continue at DC with the true Rs: the flux stays put */
    psi0 = obs_psi(&o);
    for (k = 1u; k <= 2000u; k++) {
        double mv;
        obs_feed(&o, i, u, 0.3 * 2.0 * PI);
        mv = cabs(obs_psi(&o) - psi0);
        max_move = (mv > max_move) ? mv : max_move;
        assert_int_equal(o.sat, 0);
    }
    print_message("set_rs_dc: flux moved at most %.1f LSB over 2000 samples; ws %.2e\n",
                  max_move / lsb, to_d(o.ws));
    assert_true(max_move <= 600.0 * lsb);
    assert_true(fabs(to_d(o.ws_f)) <= 1e-4);

    /* saturation: a DC voltage far off (u 10 pu, clamped to 4): Rs i - u
     * clamped to 1 pu, y = 1/w_c = 16.7 -> 10 (Y_MAX), z = 30 (Z_MAX), sat */
    assert_int_equal(flux_obs_set_rs_dc(&o, rs_true, _IQ(-10.0), _IQ(0.0), o.i_alpha, o.i_beta),
                     FLUX_OBS_OK);
    assert_int_equal(o.sat, 1);
    assert_true(o.y_alpha == _IQ(FLUX_OBS_Y_MAX) && o.z_alpha == _IQ(FLUX_OBS_Z_MAX));
}

/* flux_obs_design: the model's constants in float, what the drive's
 * background computes for a new set (drive_adapt_bg.c) and what
 * flux_obs_init computes from SI.
 *  - from the pu floats flux_obs_init derives from the same SI values:
 *    every constant equal to the initialised observer's (one code path);
 *  - against double references: Rs, Lm, Tr within 1 LSB (the _IQ
 *    truncation) + 1e-7 relative (float rounding of the pu value);
 *    Lr/Lm, Lm/Lr: 1 LSB + 2e-7 relative (a float quotient of two rounded
 *    floats); sigma Ls = Ls - Lm^2/Lr: 1 LSB + 4 float ulps of Ls (the
 *    difference of two rounded terms of size Ls), 4e-7 x 1.37 pu = 9 LSB;
 *    kf = 1 - exp(-Ts/Tr): 1 LSB + 3e-7 relative (series 1.4e-9 and a few
 *    float roundings of x ~ 3.4e-3);
 *  - against the fixed-point setter of Tr (flux_obs_set_tr): the sum of
 *    the two budgets (the setter's kf (1/Tr + 4) LSB);
 *  - a refused group leaves its members as they were (NaN too). */
static void test_design(void **state)
{
    const double lsb = ldexp(1.0, -24);
    flux_obs_t o, fx;
    flux_obs_model_t m, keep;
    const float rs = RS_OHM / g_b.Z_base_ohm, lm = LM_H / g_b.L_base_H;
    const float lr = LR_H / g_b.L_base_H, ls = LS_H / g_b.L_base_H;
    const float tr = TR_S / g_b.t_base_s;
    (void)state;

    obs_init(&o, 1.0, 1.0);
    assert_int_equal(flux_obs_design(&m, g_b.Ts_pu, rs, lm, lr, ls, tr), FLUX_OBS_OK);
    assert_true(m.rs == o.rs && m.lm == o.lm && m.sigma_ls == o.sigma_ls &&
                m.lr_lm == o.lr_lm && m.lm_lr == o.lm_lr && m.tr == o.tr && m.kf == o.kf);

    assert_true(fabs(to_d(m.rs) - g_m.rs) <= lsb + 1e-7 * g_m.rs);
    assert_true(fabs(to_d(m.lm) - g_m.lm) <= lsb + 1e-7 * g_m.lm);
    assert_true(fabs(to_d20(m.tr) - g_m.tr) <= 16.0 * lsb + 1e-7 * g_m.tr);   /* Q20 */
    assert_true(fabs(to_d(m.lr_lm) - g_m.lr / g_m.lm) <= lsb + 2e-7 * g_m.lr / g_m.lm);
    assert_true(fabs(to_d(m.lm_lr) - g_m.lm / g_m.lr) <= lsb + 2e-7);
    print_message("design: sigma Ls %.2f LSB, kf %.2f LSB from double\n",
                  (to_d(m.sigma_ls) - g_m.sls) / lsb,
                  (to_d(m.kf) - (1.0 - exp(-g_m.ts / g_m.tr))) / lsb);
    assert_true(fabs(to_d(m.sigma_ls) - g_m.sls) <= lsb + 4.0 * 1.2e-7 * g_m.ls);
    assert_true(fabs(to_d(m.kf) - (1.0 - exp(-g_m.ts / g_m.tr))) <= lsb + 3e-7 * to_d(m.kf));

    /* the fixed-point setter of Tr from the same Q20 value */
    fx = o;
    assert_int_equal(flux_obs_set_tr(&fx, m.tr), FLUX_OBS_OK);
    assert_true(fabs(to_d(fx.kf) - to_d(m.kf)) <= (1.0 / g_m.tr + 6.0) * lsb);
    /* a large motor's Tr (292 pu: 0.93 s at 50 Hz) against double */
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, 292.4f), FLUX_OBS_OK);
    assert_true(fabs(to_d20(m.tr) - 292.4) <= 16.0 * lsb + 1e-7 * 292.4);
    assert_true(fabs(to_d(m.kf) - (1.0 - exp(-(double)g_b.Ts_pu / 292.4))) <= lsb + 3e-7 * to_d(m.kf));
    assert_int_equal(flux_obs_set_tr(&fx, m.tr), FLUX_OBS_OK);
    assert_true(fabs(to_d(fx.kf) - to_d(m.kf)) <= (1.0 / 292.4 + 6.0) * lsb);
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, tr), FLUX_OBS_OK);

    /* refusals: each group keeps its members */
    keep = m;
    assert_int_equal(flux_obs_design_rs(&m, -0.01f), FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_design_rs(&m, 4.01f), FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_design_rs(&m, NAN), FLUX_OBS_ERR_RS);
    assert_int_equal(flux_obs_design_l(&m, 1.0f, 0.9f, 1.1f), FLUX_OBS_ERR_L);    /* Lr < Lm */
    assert_int_equal(flux_obs_design_l(&m, 1.0f, 1.1f, 1.0f), FLUX_OBS_ERR_L);    /* Ls = Lm */
    assert_int_equal(flux_obs_design_l(&m, 1.0f, 4.5f, 4.5f), FLUX_OBS_ERR_L);    /* Lr > 4 Lm */
    assert_int_equal(flux_obs_design_l(&m, 1.0f, 1.1f, 6.0f), FLUX_OBS_ERR_L);    /* sigma Ls > 4 */
    assert_int_equal(flux_obs_design_l(&m, NAN, 1.1f, 1.2f), FLUX_OBS_ERR_L);
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, 5.0f * g_b.Ts_pu), FLUX_OBS_ERR_TR);
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, 1001.0f), FLUX_OBS_ERR_TR);
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, NAN), FLUX_OBS_ERR_TR);
    assert_memory_equal(&m, &keep, sizeof m);
    /* a refused group does not stop the others being written alone */
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, 2.0f * tr), FLUX_OBS_OK);
    assert_true(m.tr != keep.tr && m.kf < keep.kf && m.rs == keep.rs && m.lm == keep.lm);
    /* the edges are accepted: Tr = 10 Ts, Rs = 0 and 4 */
    assert_int_equal(flux_obs_design_tr(&m, g_b.Ts_pu, 10.0f * g_b.Ts_pu), FLUX_OBS_OK);
    assert_true(fabs(to_d(m.kf) - (1.0 - exp(-0.1))) <= lsb + 3e-7 * 0.1);
    assert_int_equal(flux_obs_design_rs(&m, 0.0f), FLUX_OBS_OK);
    assert_int_equal(flux_obs_design_rs(&m, 4.0f), FLUX_OBS_OK);

    /* apply_model copies the seven constants and nothing else */
    fx = o;
    flux_obs_apply_model(&fx, &keep);
    assert_memory_equal(&fx, &o, sizeof o);
    flux_obs_apply_model(&fx, &m);
    assert_true(fx.tr == m.tr && fx.kf == m.kf && fx.rs == m.rs);
    assert_true(fx.ts == o.ts && fx.wc == o.wc && fx.psis_alpha == o.psis_alpha);
}

/* flux_obs_l_check, the one test of the inductances (flux_obs_design_l and
 * the table of limits): each refusal named at its own edge, the edge itself
 * accepted and the next float refused; the tests in their stated order (an
 * Lr and an Ls both out: LR); flux_obs_design_l refuses exactly what the
 * check refuses, over a log-uniform sweep that crosses every edge. */
static void test_l_check(void **state)
{
    static const struct {
        float lm, lr, ls;
        flux_obs_l_fault_t want;
    } c[] = {
        {16.0f, 17.0f, 19.0f, FLUX_OBS_L_OK},                  /* Lm at its top; sigma Ls 3.94 */
        {0.0f, 1.1f, 1.2f, FLUX_OBS_L_LM},
        {-1.0f, 1.1f, 1.2f, FLUX_OBS_L_LM},
        {NAN, 1.1f, 1.2f, FLUX_OBS_L_LM},
        {1.0f, 4.0f, 1.5f, FLUX_OBS_L_OK},                     /* Lr = 4 Lm */
        {1.0f, 1.0f, 1.5f, FLUX_OBS_L_LR},                     /* Lr = Lm */
        {1.0f, NAN, 1.5f, FLUX_OBS_L_LR},
        {1.0f, 5.0f, 1.0f, FLUX_OBS_L_LR},                     /* Lr first, Ls too */
        {1.0f, 1.1f, 1.0f, FLUX_OBS_L_LS},                     /* Ls = Lm */
        {1.0f, 1.1f, NAN, FLUX_OBS_L_LS},
        {16.0f, 17.0f, 32.0f, FLUX_OBS_L_SLS},                 /* Ls at its top; sigma Ls 16.9 */
        {2.0f, 4.0f, 5.0f, FLUX_OBS_L_OK},                     /* sigma Ls = 4 exactly */
    };
    flux_obs_model_t m;
    uint32_t i, seed = 12345u, n_bad[5] = {0u, 0u, 0u, 0u, 0u};
    (void)state;

    for (i = 0u; i < sizeof c / sizeof c[0]; i++) {
        if (flux_obs_l_check(c[i].lm, c[i].lr, c[i].ls) != c[i].want) {
            fail_msg("case %u: %d, want %d", (unsigned)i,
                     (int)flux_obs_l_check(c[i].lm, c[i].lr, c[i].ls), (int)c[i].want);
        }
    }
    /* one float beyond each upper edge */
    assert_int_equal(flux_obs_l_check(nextafterf(16.0f, 32.0f), 17.0f, 19.0f), FLUX_OBS_L_LM);
    assert_int_equal(flux_obs_l_check(1.0f, nextafterf(4.0f, 8.0f), 1.5f), FLUX_OBS_L_LR);
    assert_int_equal(flux_obs_l_check(16.0f, 17.0f, nextafterf(32.0f, 64.0f)), FLUX_OBS_L_LS);
    assert_int_equal(flux_obs_l_check(2.0f, 4.0f, nextafterf(5.0f, 8.0f)), FLUX_OBS_L_SLS);
    /* one float above each lower edge: accepted */
    assert_int_equal(flux_obs_l_check(1.0f, nextafterf(1.0f, 2.0f), 1.5f), FLUX_OBS_L_OK);
    assert_int_equal(flux_obs_l_check(1.0f, 1.1f, nextafterf(1.0f, 2.0f)), FLUX_OBS_L_OK);
    /* nonzero in Q24: an Lm or a sigma Ls below one LSB is 0 in the model */
#if MATH_TYPE == IQ_MATH
    assert_int_equal(flux_obs_l_check(0x1p-25f, 0x1p-24f, 0x1p-24f), FLUX_OBS_L_LM);
    assert_int_equal(flux_obs_l_check(1e-3f, nextafterf(1e-3f, 1.0f), nextafterf(1e-3f, 1.0f)), FLUX_OBS_L_SLS);
#else
    assert_int_equal(flux_obs_l_check(0x1p-25f, 0x1p-24f, 0x1p-24f), FLUX_OBS_L_OK);
#endif
    /* flux_obs_design_l: refused exactly when the check refuses, the model
     * then kept; Lm, Lr/Lm and Ls/Lm log-uniform across their edges */
    for (i = 0u; i < 20000u; i++) {
        float lm, lr, ls;
        flux_obs_l_fault_t lf;
        flux_obs_status_t st;
        flux_obs_model_t keep;
        seed = seed * 1664525u + 1013904223u;
        lm = (float)pow(2.0, -26.0 + 31.0 * (double)(seed >> 8) / 16777216.0);   /* 2^-26..32 */
        seed = seed * 1664525u + 1013904223u;
        lr = lm * (float)pow(2.0, -0.5 + 3.0 * (double)(seed >> 8) / 16777216.0);   /* 0.7..5.7 Lm */
        seed = seed * 1664525u + 1013904223u;
        ls = lm * (float)pow(2.0, -0.5 + 4.0 * (double)(seed >> 8) / 16777216.0);
        memset(&m, 0x5a, sizeof m);
        keep = m;
        lf = flux_obs_l_check(lm, lr, ls);
        st = flux_obs_design_l(&m, lm, lr, ls);
        n_bad[lf]++;
        if ((st == FLUX_OBS_OK) != (lf == FLUX_OBS_L_OK) ||
            (st != FLUX_OBS_OK && memcmp(&m, &keep, sizeof m) != 0)) {
            fail_msg("Lm %.9g Lr %.9g Ls %.9g: check %d, design %d", (double)lm, (double)lr,
                     (double)ls, (int)lf, (int)st);
        }
    }
    print_message("sweep: ok %u, Lm %u, Lr %u, Ls %u, sigma Ls %u\n", (unsigned)n_bad[0],
                  (unsigned)n_bad[1], (unsigned)n_bad[2], (unsigned)n_bad[3], (unsigned)n_bad[4]);
    for (i = 0u; i < 5u; i++) {
        assert_true(n_bad[i] > 100u);   /* every verdict reached */
    }
}

/* flux_obs_seat_dc + flux_obs_apply_seat (the background computes, the ISR
 * copies) is flux_obs_set_rs_dc bit for bit; the re-seat follows the model
 * it is given (not the one in the observer): psi_s = (Lm/Lr) psi_cm +
 * sigma Ls i of that model (bound as test_set_rs_dc: 4 LSB + 1e-6 |psi|);
 * the observer itself is not touched; a refused Rs writes nothing. */
static void test_seat_dc(void **state)
{
    const double lsb = ldexp(1.0, -24);
    const double complex i = ID_PU * cexp(J * PI / 6.0);
    const double complex u = g_m.rs * i;
    flux_obs_t o, ref, before;
    flux_obs_model_t m;
    flux_obs_seat_t s, s0;
    double complex psi_cm;
    uint32_t k;
    (void)state;

    obs_init(&o, 1.3, 1.0);
    for (k = 1u; k <= 4500u; k++) {
        obs_feed(&o, i, u, 0.3 * 2.0 * PI);
    }
    ref = o;
    assert_int_equal(flux_obs_set_rs_dc(&ref, _IQ(g_m.rs), o.u_alpha, o.u_beta, o.i_alpha,
                                        o.i_beta),
                     FLUX_OBS_OK);
    before = o;
    m.rs = _IQ(g_m.rs);
    m.lm = o.lm;
    m.sigma_ls = o.sigma_ls;
    m.lr_lm = o.lr_lm;
    m.lm_lr = o.lm_lr;
    m.tr = o.tr;
    m.kf = o.kf;
    assert_int_equal(flux_obs_seat_dc(&o, &m, o.psi_cm_alpha, o.psi_cm_beta, o.u_alpha,
                                      o.u_beta, o.i_alpha, o.i_beta, &s),
                     FLUX_OBS_OK);
    assert_memory_equal(&o, &before, sizeof o);
    o.rs = m.rs;
    flux_obs_apply_seat(&o, &s);
    assert_memory_equal(&o, &ref, sizeof o);

    /* another model: sigma Ls 10 % lower, Lm/Lr 5 % higher */
    m.sigma_ls = _IQmpy(o.sigma_ls, _IQ(0.9));
    m.lm_lr = _IQmpy(o.lm_lr, _IQ(1.05));
    assert_int_equal(flux_obs_seat_dc(&o, &m, o.psi_cm_alpha, o.psi_cm_beta, o.u_alpha,
                                      o.u_beta, o.i_alpha, o.i_beta, &s),
                     FLUX_OBS_OK);
    psi_cm = to_d(o.psi_cm_alpha) + J * to_d(o.psi_cm_beta);
    assert_true(cabs(to_d(s.psis_alpha) + J * to_d(s.psis_beta) -
                     (to_d(m.lm_lr) * psi_cm + to_d(m.sigma_ls) * i)) <=
                4.0 * lsb + 1e-6 * cabs(psi_cm));

    /* refused: nothing written */
    s0 = s;
    m.rs = _IQ(-0.01);
    assert_int_equal(flux_obs_seat_dc(&o, &m, o.psi_cm_alpha, o.psi_cm_beta, o.u_alpha,
                                      o.u_beta, o.i_alpha, o.i_beta, &s),
                     FLUX_OBS_ERR_RS);
    m.rs = _IQ(4.01);
    assert_int_equal(flux_obs_seat_dc(&o, &m, o.psi_cm_alpha, o.psi_cm_beta, o.u_alpha,
                                      o.u_beta, o.i_alpha, o.i_beta, &s),
                     FLUX_OBS_ERR_RS);
    assert_memory_equal(&s, &s0, sizeof s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_steady_tr_error),
        cmocka_unit_test(test_steady_tr_error_window),
        cmocka_unit_test(test_steady_rs_error),
        cmocka_unit_test(test_accel_tr_error),
        cmocka_unit_test(test_dc_offset_no_drift),
        cmocka_unit_test(test_set_tr_online),
        cmocka_unit_test(test_setters),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_extreme_inputs),
        cmocka_unit_test(test_angle_jumps_bounded),
        cmocka_unit_test(test_set_rs_dc),
        cmocka_unit_test(test_design),
        cmocka_unit_test(test_l_check),
        cmocka_unit_test(test_seat_dc),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
