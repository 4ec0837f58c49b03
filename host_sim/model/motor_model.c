/**
 * @file motor_model.c
 * Fifth-order induction motor in the stationary frame, RK4; see
 * motor_model.h for the equations and conventions.
 */
#include "motor_model.h"

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

void motor_step_open(motor_t *m, double dt_s, uint16_t n_sub)
{
    double dx[X_N];

    if (!isfinite(dt_s) || !(dt_s > 0.0)) {
        return;
    }
    if (m->open == 0u) {
        m->open = 1u;
        m->x[X_PSA] = (m->p.Lm_H / m->Lr_H) * m->x[X_PRA];
        m->x[X_PSB] = (m->p.Lm_H / m->Lr_H) * m->x[X_PRB];
    }
    mm_integrate(m, 0.0, 0.0, dt_s, n_sub);
    /* terminal voltage of the open stator: u_s = dpsi_s/dt (i_s = 0) */
    mm_deriv(m, m->x, m->t_s, 0.0, 0.0, dx);
    m->u_alpha_V = dx[X_PSA];
    m->u_beta_V = dx[X_PSB];
    mm_outputs(m);
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
