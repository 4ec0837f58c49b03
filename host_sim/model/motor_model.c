/**
 * @file motor_model.c
 * Fifth-order induction motor in the stationary frame, RK4; see
 * motor_model.h for the equations and conventions.
 */
#include "motor_model.h"

#include <complex.h>
#include <math.h>
#include <string.h>

#define MM_TWO_PI 6.283185307179586476925
#define MM_SQRT3 1.732050807568877293527

enum { X_PSA = 0, X_PSB, X_PRA, X_PRB, X_WM, X_TH, X_N };

static int mm_pos(double v) { return isfinite(v) && (v > 0.0); }

/* fmod(a, MM_TWO_PI), bit for bit, without the library's loop: the
 * remainder a - n 2pi (n = trunc(a / 2pi)) is a double exactly, so one fma
 * gives it exactly; n from the rounded quotient may be one off, which the
 * remainder's range shows.  Beyond 2^50 (n no longer exact) and for
 * non-finite a: fmod itself. */
static double mm_fmod_2pi(double a)
{
    double n, r;
    if (!(fabs(a) < 1125899906842624.0)) {
        return fmod(a, MM_TWO_PI);
    }
    n = trunc(a / MM_TWO_PI);
    r = fma(-n, MM_TWO_PI, a);
    if (a >= 0.0) {
        if (r < 0.0) {
            r = fma(-(n - 1.0), MM_TWO_PI, a);
        } else if (r >= MM_TWO_PI) {
            r = fma(-(n + 1.0), MM_TWO_PI, a);
        } else {
            /* n was right */
        }
    } else {
        if (r > 0.0) {
            r = fma(-(n + 1.0), MM_TWO_PI, a);
        } else if (r <= -MM_TWO_PI) {
            r = fma(-(n - 1.0), MM_TWO_PI, a);
        } else {
            /* n was right */
        }
    }
    return (r == 0.0) ? copysign(0.0, a) : r;   /* fmod keeps a's sign on 0 */
}

static double mm_wrap_2pi(double a)
{
    double w = mm_fmod_2pi(a);
    if (w < 0.0) {
        w += MM_TWO_PI;
    }
    if (w >= MM_TWO_PI) { /* -tiny + 2 pi rounds to 2 pi */
        w = 0.0;
    }
    return w;
}

void motor_params_default(motor_params_t *p)
{
    p->Rs_ohm = 1.031;
    p->Rr_ohm = 0.465;
    p->Lm_H = 6.4e-3;
    p->Lls_H = 2.8e-3;
    p->Llr_H = 2.8e-3;
    p->pole_pairs = 2u;
    p->J_kgm2 = 5.0e-4;
    p->B_Nm_s = 1.0e-4;
}

/* Outputs from the state (also used for a consistent initial output). */
static void mm_outputs(motor_t *m)
{
    const double *x = m->x;
    const double ia = (m->Lr_H * x[X_PSA] - m->p.Lm_H * x[X_PRA]) / m->D_H2;
    const double ib = (m->Lr_H * x[X_PSB] - m->p.Lm_H * x[X_PRB]) / m->D_H2;
    const double pp = (double)m->p.pole_pairs;

    if (m->open != 0u) {
        /* i_s = 0 by construction; avoid reporting rounding residue */
        m->i_alpha_A = 0.0;
        m->i_beta_A = 0.0;
    } else {
        m->i_alpha_A = ia;
        m->i_beta_A = ib;
    }
    /* inverse amplitude-invariant Clarke */
    m->ia_A = m->i_alpha_A;
    m->ib_A = -0.5 * m->i_alpha_A + 0.5 * MM_SQRT3 * m->i_beta_A;
    m->ic_A = -m->ia_A - m->ib_A;
    m->i_r_alpha_A = (m->Ls_H * x[X_PRA] - m->p.Lm_H * x[X_PSA]) / m->D_H2;
    m->i_r_beta_A = (m->Ls_H * x[X_PRB] - m->p.Lm_H * x[X_PSB]) / m->D_H2;
    m->psi_s_alpha_Wb = x[X_PSA];
    m->psi_s_beta_Wb = x[X_PSB];
    m->psi_r_alpha_Wb = x[X_PRA];
    m->psi_r_beta_Wb = x[X_PRB];
    m->Te_Nm = 1.5 * pp * (x[X_PSA] * m->i_beta_A - x[X_PSB] * m->i_alpha_A);
    m->w_m_rad_s = x[X_WM];
    m->w_e_rad_s = pp * x[X_WM];
    m->n_rpm = x[X_WM] * (60.0 / MM_TWO_PI);
    m->TL_Nm = load_torque_Nm(&m->load, m->t_s, x[X_WM]);
    m->theta_m_rad = x[X_TH];
    m->theta_m_wrapped_rad = mm_wrap_2pi(x[X_TH]);
    m->theta_e_wrapped_rad = mm_wrap_2pi(pp * x[X_TH]);
}

motor_status_t motor_init(motor_t *m, const motor_params_t *p)
{
    motor_status_t st = MOTOR_OK;

    if ((m == NULL) || (p == NULL)) {
        return MOTOR_ERR_NULL;
    }
    memset(m, 0, sizeof(*m));
    if (!mm_pos(p->Rs_ohm)) {
        st = MOTOR_ERR_RS;
    } else if (!mm_pos(p->Rr_ohm)) {
        st = MOTOR_ERR_RR;
    } else if (!mm_pos(p->Lm_H)) {
        st = MOTOR_ERR_LM;
    } else if (!mm_pos(p->Lls_H)) {
        st = MOTOR_ERR_LLS;
    } else if (!mm_pos(p->Llr_H)) {
        st = MOTOR_ERR_LLR;
    } else if (p->pole_pairs == 0u) {
        st = MOTOR_ERR_POLES;
    } else if (!mm_pos(p->J_kgm2)) {
        st = MOTOR_ERR_J;
    } else if (!isfinite(p->B_Nm_s) || (p->B_Nm_s < 0.0)) {
        st = MOTOR_ERR_B;
    } else {
        /* all valid */
    }
    if (st != MOTOR_OK) {
        return st;
    }
    m->p = *p;
    m->Ls_H = p->Lm_H + p->Lls_H;
    m->Lr_H = p->Lm_H + p->Llr_H;
    /* D = Lm (Lls + Llr) + Lls Llr: written this way it has no
     * cancellation, unlike Ls Lr - Lm^2 */
    m->D_H2 = p->Lm_H * (p->Lls_H + p->Llr_H) + p->Lls_H * p->Llr_H;
    m->Lr_D = m->Lr_H / m->D_H2;
    m->Lm_D = p->Lm_H / m->D_H2;
    m->J_inv = 1.0 / p->J_kgm2;
    (void)load_init_none(&m->load);
    mm_outputs(m);
    return MOTOR_OK;
}

void motor_set_load(motor_t *m, const load_t *l)
{
    m->load = *l;
    m->TL_Nm = load_torque_Nm(&m->load, m->t_s, m->x[X_WM]);
}

void motor_set_speed(motor_t *m, double w_m_rad_s)
{
    m->x[X_WM] = w_m_rad_s;
    mm_outputs(m);
}

void motor_set_angle(motor_t *m, double theta_m_rad)
{
    m->x[X_TH] = theta_m_rad;
    mm_outputs(m);
}

void motor_lock_speed(motor_t *m, uint16_t locked)
{
    m->speed_locked = (locked != 0u) ? 1u : 0u;
}

/* dx/dt at state x, time t, stator voltage u (ignored when open).  The
 * state and the parameters are read into locals first and dx written last:
 * the compiler then need not reload them after each store through dx (the
 * same operations in the same order as the equations: the results are
 * bit for bit those of the direct form).  x and dx must not overlap. */
static void mm_deriv(const motor_t *m, const double *x, double t, double ua,
                     double ub, double *dx)
{
    const double Lm = m->p.Lm_H, Lr = m->Lr_H, Ls = m->Ls_H, D = m->D_H2;
    const double Rs = m->p.Rs_ohm, Rr = m->p.Rr_ohm;
    const double pp = (double)m->p.pole_pairs;
    const double psa = x[X_PSA], psb = x[X_PSB], pra = x[X_PRA], prb = x[X_PRB];
    const double wm = x[X_WM];
    const double we = pp * wm;
    double isa, isb, ira, irb, te, d_psa, d_psb, d_pra, d_prb, d_wm;

    if (m->open != 0u) {
        /* i_s = 0: i_r = psi_r / Lr, psi_s = (Lm/Lr) psi_r follows */
        ira = pra / Lr;
        irb = prb / Lr;
        d_pra = -Rr * ira - we * prb;
        d_prb = -Rr * irb + we * pra;
        d_psa = (Lm / Lr) * d_pra;
        d_psb = (Lm / Lr) * d_prb;
        te = 0.0;
    } else {
        isa = (Lr * psa - Lm * pra) / D;
        isb = (Lr * psb - Lm * prb) / D;
        ira = (Ls * pra - Lm * psa) / D;
        irb = (Ls * prb - Lm * psb) / D;
        d_psa = ua - Rs * isa;
        d_psb = ub - Rs * isb;
        /* shorted rotor seen from the stator frame: the rotor turns at w_e,
         * hence the motional term + j w_e psi_r */
        d_pra = -Rr * ira - we * prb;
        d_prb = -Rr * irb + we * pra;
        te = 1.5 * pp * (psa * isb - psb * isa);
    }
    if (m->speed_locked != 0u) {
        d_wm = 0.0;
    } else {
        d_wm = (te - load_torque_Nm(&m->load, t, wm) - m->p.B_Nm_s * wm) / m->p.J_kgm2;
    }
    dx[X_PSA] = d_psa;
    dx[X_PSB] = d_psb;
    dx[X_PRA] = d_pra;
    dx[X_PRB] = d_prb;
    dx[X_WM] = d_wm;
    dx[X_TH] = wm;
}

/* RK4 over dt_s in n_sub steps.  The state is kept in a local copy during
 * the steps (no reload through m after each stage's store). */
static void mm_integrate(motor_t *m, double ua, double ub, double dt_s,
                         uint16_t n_sub)
{
    double k1[X_N], k2[X_N], k3[X_N], k4[X_N], xt[X_N], x[X_N];
    const uint16_t n = (n_sub == 0u) ? 1u : n_sub;
    const double h = dt_s / (double)n;
    const double h2 = 0.5 * h, h6 = h / 6.0;
    const double t0 = m->t_s;
    uint16_t s;
    int i;

    for (i = 0; i < X_N; i++) {
        x[i] = m->x[i];
    }
    for (s = 0u; s < n; s++) {
        /* time from the start of the call, not accumulated, so that long
         * runs do not drift */
        const double t = t0 + h * (double)s;
        mm_deriv(m, x, t, ua, ub, k1);
        for (i = 0; i < X_N; i++) {
            xt[i] = x[i] + h2 * k1[i];
        }
        mm_deriv(m, xt, t + h2, ua, ub, k2);
        for (i = 0; i < X_N; i++) {
            xt[i] = x[i] + h2 * k2[i];
        }
        mm_deriv(m, xt, t + h2, ua, ub, k3);
        for (i = 0; i < X_N; i++) {
            xt[i] = x[i] + h * k3[i];
        }
        mm_deriv(m, xt, t + h, ua, ub, k4);
        for (i = 0; i < X_N; i++) {
            x[i] += h6 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    for (i = 0; i < X_N; i++) {
        m->x[i] = x[i];
    }
    m->t_s = t0 + dt_s;
}

void motor_step(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s,
                uint16_t n_sub)
{
    if (!isfinite(dt_s) || !(dt_s > 0.0)) {
        return;
    }
    m->open = 0u;
    m->u_alpha_V = u_alpha_V;
    m->u_beta_V = u_beta_V;
    mm_integrate(m, u_alpha_V, u_beta_V, dt_s, n_sub);
    mm_outputs(m);
}

void motor_step_abc(motor_t *m, double ua_V, double ub_V, double uc_V,
                    double dt_s, uint16_t n_sub)
{
    /* amplitude-invariant Clarke; (2ua - ub - uc)/3 removes the
     * zero-sequence part */
    const double ual = (2.0 * ua_V - ub_V - uc_V) / 3.0;
    const double ube = (ub_V - uc_V) / MM_SQRT3;
    motor_step(m, ual, ube, dt_s, n_sub);
}

/* The start of an open-stator step of @p dt_s: 0 for no step (dt_s <= 0 or
 * not finite), else 1 with the motor in open mode (entering it sets
 * psi_s = (Lm/Lr) psi_r, i_s = 0). */
static int mm_open_begin(motor_t *m, double dt_s)
{
    if (!isfinite(dt_s) || !(dt_s > 0.0)) {
        return 0;
    }
    if (m->open == 0u) {
        m->open = 1u;
        m->x[X_PSA] = (m->p.Lm_H / m->Lr_H) * m->x[X_PRA];
        m->x[X_PSB] = (m->p.Lm_H / m->Lr_H) * m->x[X_PRB];
    }
    return 1;
}

void motor_step_open(motor_t *m, double dt_s, uint16_t n_sub)
{
    double dx[X_N];

    if (mm_open_begin(m, dt_s) == 0) {
        return;
    }
    mm_integrate(m, 0.0, 0.0, dt_s, n_sub);
    /* terminal voltage of the open stator: u_s = dpsi_s/dt (i_s = 0) */
    mm_deriv(m, m->x, m->t_s, 0.0, 0.0, dx);
    m->u_alpha_V = dx[X_PSA];
    m->u_beta_V = dx[X_PSB];
    mm_outputs(m);
}

/* ------------------------------------------------------------------------
 * The exact electrical step (motor_step_exact). */

typedef double complex mm_cx;

#ifndef CMPLX /* C11's; in C99 from the imaginary unit (the values here are finite) */
#define CMPLX(x, y) ((double)(x) + (double)(y) * (mm_cx)I)
#endif

static void mm_cx_put(double *v, size_t k, mm_cx z)
{
    v[2u * k] = creal(z);
    v[2u * k + 1u] = cimag(z);
}

/* cos x and sin x; for |x| < 0.1 (the angles a PWM period turns through)
 * by their Taylor series to x^12 and x^13 (the next terms below 1e-22)
 * rather than the library's argument reduction */
static void mm_cos_sin(double x, double *c, double *s)
{
    if (fabs(x) < 0.1) {
        const double x2 = x * x;
        *s = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 *
                 (1.0 - x2 / 72.0 * (1.0 - x2 / 110.0 * (1.0 - x2 / 156.0))))));
        *c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0 *
                 (1.0 - x2 / 90.0 * (1.0 - x2 / 132.0)))));
    } else {
        *c = cos(x);
        *s = sin(x);
    }
}

/* z w without C's check of the product for NaN (the values here are finite) */
static mm_cx mm_cmul(mm_cx z, mm_cx w)
{
    return CMPLX(creal(z) * creal(w) - cimag(z) * cimag(w),
                 creal(z) * cimag(w) + cimag(z) * creal(w));
}

/* 1/z (no checks: z finite and not 0 here; the library's division scales
 * against overflow, which these magnitudes never approach) */
static mm_cx mm_cinv(mm_cx z)
{
    const double n = creal(z) * creal(z) + cimag(z) * cimag(z);
    return CMPLX(creal(z) / n, -cimag(z) / n);
}

/* exp(M dt/2) and its response to a unit stator voltage, for w_e.  For a
 * 2x2 M with mean eigenvalue mu = tr M / 2 and delta^2 = ((a - d)/2)^2 + b c:
 *   exp(M h) = e^(mu h) [cosh(delta h) I + sinh(delta h)/delta (M - mu I)];
 * the voltage's response over h, integral of exp(M s) (1, 0) ds, is
 * M^-1 (exp(M h) - I) (1, 0) (M is regular: det M = Rs Rr / D - j w_e Rs Lr / D,
 * not 0 for Rs, Rr > 0). */
static void mm_ex_prepare(motor_t *m, double we, double dt)
{
    const double Lm = m->p.Lm_H, Lr = m->Lr_H, Ls = m->Ls_H, D = m->D_H2;
    const double Rs = m->p.Rs_ohm, Rr = m->p.Rr_ohm;
    const double h = 0.5 * dt;
    const double a = -Rs * Lr / D, b = Rs * Lm / D, c = Rr * Lm / D;
    const mm_cx d = CMPLX(-Rr * Ls / D, we);
    const mm_cx hd = 0.5 * (a - d);
    const mm_cx w2 = mm_cmul(hd, hd) + b * c;
    const mm_cx zz = w2 * (h * h);   /* (delta h)^2 */
    mm_cx ch, sh_over_delta, e_mu, p11, p12, p21, p22, inv_det, dm1;
    if (creal(zz) * creal(zz) + cimag(zz) * cimag(zz) < 1e-4) {
        /* |delta h| < 0.1 (the common case: a period is short against the
         * motor's time constants and turn): cosh z and sinh(z)/z, even in z,
         * as series in z^2 = (delta h)^2 (to z^10: the next terms below
         * 1e-20), no root, division or transcendental function */
        ch = 1.0 + mm_cmul(zz * (1.0 / 2.0), 1.0 + mm_cmul(zz * (1.0 / 12.0),
             1.0 + mm_cmul(zz * (1.0 / 30.0), 1.0 + mm_cmul(zz * (1.0 / 56.0),
             1.0 + zz * (1.0 / 90.0)))));
        sh_over_delta = h * (1.0 + mm_cmul(zz * (1.0 / 6.0), 1.0 + mm_cmul(zz * (1.0 / 20.0),
                        1.0 + mm_cmul(zz * (1.0 / 42.0), 1.0 + mm_cmul(zz * (1.0 / 72.0),
                        1.0 + zz * (1.0 / 110.0))))));
    } else {
        /* delta = a square root of w2 (either: cosh and sinh(x)/x are even) */
        mm_cx delta, z;
        const double p = creal(w2), q = cimag(w2);
        const double r = sqrt(p * p + q * q);
        if (p >= 0.0) {
            const double sq = sqrt(0.5 * (r + p));
            delta = CMPLX(sq, q / (2.0 * sq));
        } else {
            const double t = sqrt(0.5 * (r - p));
            delta = CMPLX(q / (2.0 * t), t);
        }
        z = delta * h;
        {
            /* cosh and sinh of x + j y from e^x - 1 (no cancellation for a
             * small x): sinh x = (em + em/ex)/2, cosh x = 1 + em^2/(2 ex) */
            const double em = expm1(creal(z)), ex = 1.0 + em;
            const double shx = 0.5 * (em + em / ex), chx = 1.0 + 0.5 * em * em / ex;
            double cy, sy;
            mm_cos_sin(cimag(z), &cy, &sy);
            ch = CMPLX(chx * cy, shx * sy);
            sh_over_delta = mm_cmul(CMPLX(shx * cy, chx * sy), mm_cinv(delta));
        }
    }
    /* e^(mu h), mu = (a + d)/2: its modulus depends on dt and the resistances */
    if (!(m->ex_dt == dt && m->ex_Rs == Rs && m->ex_Rr == Rr)) {
        m->ex_emu_mod = exp(0.5 * (a + creal(d)) * h);
    }
    {
        const double r = m->ex_emu_mod;
        double ca, sa;
        mm_cos_sin(0.5 * we * h, &ca, &sa);
        e_mu = CMPLX(r * ca, r * sa);
    }
    sh_over_delta = mm_cmul(e_mu, sh_over_delta);
    ch = mm_cmul(e_mu, ch);
    p11 = ch + mm_cmul(sh_over_delta, hd);
    p22 = ch - mm_cmul(sh_over_delta, hd);
    p12 = sh_over_delta * b;
    p21 = sh_over_delta * c;
    mm_cx_put(m->ex_phi, 0, p11);
    mm_cx_put(m->ex_phi, 1, p12);
    mm_cx_put(m->ex_phi, 2, p21);
    mm_cx_put(m->ex_phi, 3, p22);
    /* M^-1 = [d -b; -c a] / det applied to (p11 - 1, p21) */
    inv_det = mm_cinv(a * d - b * c);
    dm1 = p11 - 1.0;
    mm_cx_put(m->ex_gam, 0, mm_cmul(mm_cmul(d, dm1) - b * p21, inv_det));
    mm_cx_put(m->ex_gam, 1, mm_cmul(-c * dm1 + a * p21, inv_det));
    m->ex_we = we;
    m->ex_dt = dt;
    m->ex_Rs = Rs;
    m->ex_Rr = Rr;
}

/* e = (psi_sa, psi_sb, psi_ra, psi_rb) <- exp(M dt/2) e + gam u, in real
 * arithmetic (C's complex product checks every result for NaN) */
static void mm_ex_half(const motor_t *m, double ua, double ub, double e[4])
{
    const double *f = m->ex_phi, *g = m->ex_gam;
    const double sr = e[0], si = e[1], rr = e[2], ri = e[3];
    e[0] = f[0] * sr - f[1] * si + f[2] * rr - f[3] * ri + g[0] * ua - g[1] * ub;
    e[1] = f[0] * si + f[1] * sr + f[2] * ri + f[3] * rr + g[0] * ub + g[1] * ua;
    e[2] = f[4] * sr - f[5] * si + f[6] * rr - f[7] * ri + g[2] * ua - g[3] * ub;
    e[3] = f[4] * si + f[5] * sr + f[6] * ri + f[7] * rr + g[2] * ub + g[3] * ua;
}

/* T_e = 1.5 p (psi_sa i_sb - psi_sb i_sa) */
static double mm_ex_torque(const motor_t *m, const double e[4])
{
    /* the stator current by the gains Lr/D and Lm/D */
    const double isa = m->Lr_D * e[0] - m->Lm_D * e[2];
    const double isb = m->Lr_D * e[1] - m->Lm_D * e[3];
    return 1.5 * (double)m->p.pole_pairs * (e[0] * isb - e[1] * isa);
}

/* dw_m/dt at time t, speed w, electrical torque te */
static double mm_ex_accel(const motor_t *m, double t, double w, double te)
{
    if (m->speed_locked != 0u) {
        return 0.0;
    }
    /* a constant load (the plant's, held over each period) without the call */
    const double tl = (m->load.kind == LOAD_CONSTANT) ? m->load.T0_Nm
                                                       : load_torque_Nm(&m->load, t, w);
    return (te - tl - m->p.B_Nm_s * w) * m->J_inv;
}

/* The speed the electrical part sees over a step from the present state:
 * the predicted mid-step speed. */
static double mm_ex_mid_speed(const motor_t *m, double te0, double dt)
{
    const double w0 = m->x[X_WM];
    return w0 + 0.5 * dt * mm_ex_accel(m, m->t_s, w0, te0);
}

/* The mechanics over the step by RK4 with the torque given at its start,
 * middle and end; sets x[X_WM], x[X_TH], t_s. */
static void mm_ex_mechanics(motor_t *m, double dt, double te0, double te_mid, double te1)
{
    const double t0 = m->t_s, w0 = m->x[X_WM];
    const double h2 = 0.5 * dt;
    const double k1 = mm_ex_accel(m, t0, w0, te0);
    const double w2 = w0 + h2 * k1;
    const double k2 = mm_ex_accel(m, t0 + h2, w2, te_mid);
    const double w3 = w0 + h2 * k2;
    const double k3 = mm_ex_accel(m, t0 + h2, w3, te_mid);
    const double w4 = w0 + dt * k3;
    const double k4 = mm_ex_accel(m, t0 + dt, w4, te1);
    m->x[X_WM] = w0 + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    m->x[X_TH] += (dt / 6.0) * (w0 + 2.0 * w2 + 2.0 * w3 + w4);
    m->t_s = t0 + dt;
}

/* Electrical state at the start into @p e and the transition for this
 * step; returns the start torque. */
static double mm_ex_begin(motor_t *m, double dt, double e[4])
{
    double we, te0;
    e[0] = m->x[X_PSA];
    e[1] = m->x[X_PSB];
    e[2] = m->x[X_PRA];
    e[3] = m->x[X_PRB];
    te0 = (m->open != 0u) ? 0.0 : mm_ex_torque(m, e);
    we = (double)m->p.pole_pairs * mm_ex_mid_speed(m, te0, dt);
    if (!(m->ex_dt == dt && m->ex_we == we && m->ex_Rs == m->p.Rs_ohm &&
          m->ex_Rr == m->p.Rr_ohm)) {
        mm_ex_prepare(m, we, dt);
    }
    return te0;
}

void motor_predict_current(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s,
                           double *i_alpha_A, double *i_beta_A)
{
    double e[4];
    const uint16_t open = m->open;
    m->open = 0u;   /* the start torque as motor_step_exact will see it */
    (void)mm_ex_begin(m, dt_s, e);
    m->open = open;
    mm_ex_half(m, u_alpha_V, u_beta_V, e);
    mm_ex_half(m, u_alpha_V, u_beta_V, e);
    /* as mm_outputs will have it after the step */
    *i_alpha_A = (m->Lr_H * e[0] - m->p.Lm_H * e[2]) / m->D_H2;
    *i_beta_A = (m->Lr_H * e[1] - m->p.Lm_H * e[3]) / m->D_H2;
}

void motor_step_exact(motor_t *m, double u_alpha_V, double u_beta_V, double dt_s)
{
    double e[4];
    double te0, te_mid, te1;
    if (!isfinite(dt_s) || !(dt_s > 0.0)) {
        return;
    }
    m->open = 0u;
    m->u_alpha_V = u_alpha_V;
    m->u_beta_V = u_beta_V;
    te0 = mm_ex_begin(m, dt_s, e);
    mm_ex_half(m, u_alpha_V, u_beta_V, e);
    te_mid = mm_ex_torque(m, e);
    mm_ex_half(m, u_alpha_V, u_beta_V, e);
    te1 = mm_ex_torque(m, e);
    m->x[X_PSA] = e[0];
    m->x[X_PSB] = e[1];
    m->x[X_PRA] = e[2];
    m->x[X_PRB] = e[3];
    mm_ex_mechanics(m, dt_s, te0, te_mid, te1);
    mm_outputs(m);
}

void motor_step_open_exact(motor_t *m, double dt_s)
{
    double dx[X_N];
    double we, ra, rb;
    if (mm_open_begin(m, dt_s) == 0) {
        return;
    }
    we = (double)m->p.pole_pairs * mm_ex_mid_speed(m, 0.0, dt_s);
    if (!(m->ex_open_dt == dt_s && m->ex_open_we == we && m->ex_open_Rr == m->p.Rr_ohm)) {
        /* e^((-Rr/Lr + j w_e) dt) */
        const double r = exp(-m->p.Rr_ohm / m->Lr_H * dt_s);
        m->ex_open[0] = r * cos(we * dt_s);
        m->ex_open[1] = r * sin(we * dt_s);
        m->ex_open_we = we;
        m->ex_open_dt = dt_s;
        m->ex_open_Rr = m->p.Rr_ohm;
    }
    ra = m->ex_open[0] * m->x[X_PRA] - m->ex_open[1] * m->x[X_PRB];
    rb = m->ex_open[0] * m->x[X_PRB] + m->ex_open[1] * m->x[X_PRA];
    m->x[X_PRA] = ra;
    m->x[X_PRB] = rb;
    m->x[X_PSA] = (m->p.Lm_H / m->Lr_H) * ra;
    m->x[X_PSB] = (m->p.Lm_H / m->Lr_H) * rb;
    mm_ex_mechanics(m, dt_s, 0.0, 0.0, 0.0);
    mm_deriv(m, m->x, m->t_s, 0.0, 0.0, dx);
    m->u_alpha_V = dx[X_PSA];
    m->u_beta_V = dx[X_PSB];
    mm_outputs(m);
}

void motor_save(const motor_t *m, motor_state_t *s)
{
    memcpy(s->x, m->x, sizeof s->x);
    s->t_s = m->t_s;
    s->u_alpha_V = m->u_alpha_V;
    s->u_beta_V = m->u_beta_V;
    s->open = m->open;
}

void motor_restore(motor_t *m, const motor_state_t *s)
{
    memcpy(m->x, s->x, sizeof m->x);
    m->t_s = s->t_s;
    m->u_alpha_V = s->u_alpha_V;
    m->u_beta_V = s->u_beta_V;
    m->open = s->open;
    mm_outputs(m);
}

void motor_set_load_constant(motor_t *m, double T_Nm)
{
    if ((m->load.kind == LOAD_CONSTANT) && isfinite(T_Nm)) {
        m->load.T0_Nm = T_Nm;
    } else {
        (void)load_init_constant(&m->load, T_Nm);   /* not finite: no load, as it says */
    }
    m->TL_Nm = load_torque_Nm(&m->load, m->t_s, m->x[X_WM]);
}

void motor_rotor_flux_dq(const motor_t *m, double theta_rad, double *psi_d_Wb,
                         double *psi_q_Wb)
{
    /* Park rotation by -theta */
    const double c = cos(theta_rad);
    const double s = sin(theta_rad);
    *psi_d_Wb = c * m->x[X_PRA] + s * m->x[X_PRB];
    *psi_q_Wb = -s * m->x[X_PRA] + c * m->x[X_PRB];
}

void motor_time_constants(const motor_params_t *p, double psi_r_Wb, double dTL_dw_Nm_s,
                          double *tau_e_s, double *tau_m_s)
{
    const double Ls = p->Lm_H + p->Lls_H, Lr = p->Lm_H + p->Llr_H;
    /* D = Ls Lr - Lm^2 without the cancellation (as motor_init) */
    const double D = p->Lm_H * (p->Lls_H + p->Llr_H) + p->Lls_H * p->Llr_H;
    const double b = p->Rs_ohm * Lr + p->Rr_ohm * Ls;
    /* b^2 - 4 D Rs Rr = (Rs Lr - Rr Ls)^2 + 4 Lm^2 Rs Rr >= 0: two real roots */
    const double d = p->Rs_ohm * Lr - p->Rr_ohm * Ls;
    const double disc = d * d + 4.0 * p->Lm_H * p->Lm_H * p->Rs_ohm * p->Rr_ohm;
    const double pp = (double)p->pole_pairs;
    const double slope = 1.5 * pp * pp * psi_r_Wb * psi_r_Wb / p->Rr_ohm + p->B_Nm_s +
                         dTL_dw_Nm_s;
    *tau_e_s = 2.0 * D / (b + sqrt(disc));
    *tau_m_s = (slope > 0.0) ? p->J_kgm2 / slope : HUGE_VAL;
}
