/* Synthetic regression data for the estim_ tests: the paper's motor
 * (method §6: Rs 1.031, Rr 0.465 ohm, Lm 6.4, Ls = Lr 9.2 mH, psi_r 0.042
 * Wb) in per unit (I_base 20 A, V_base 60/sqrt3 V, f_base 50 Hz), through
 * an acceleration, computed in double from the model of method §1-2
 * (eq. 2 in the M-T frame, flux held constant) with analytic derivatives.
 *
 * Currents and speed are prescribed (what the current and speed loops
 * would produce: i_M at its reference with a small loop ripple, i_T the
 * accelerating torque current with ripple, wr a ramp to 1400 r/min
 * (0.933 pu) in 0.7 s, ws = wr + slip of the indirect orientation), and the
 * voltages follow from eq. 2, so the regression
 *     y1 = K1 i_M + K2 u_M + K3,   y2 = K1 i_T + K2 u_T + K4 wr
 * holds exactly. */
#ifndef ESTIM_MOTOR_DATA_H
#define ESTIM_MOTOR_DATA_H

#include <math.h>
#include <stdint.h>

#define MD_PI 3.14159265358979323846
#define MD_I_BASE 20.0
#define MD_V_BASE (60.0 / 1.7320508075688772)
#define MD_W_BASE (2.0 * MD_PI * 50.0)
#define MD_TS_S (1.0 / 15000.0)

typedef struct {
    double K1, K2, K3, K3p, K4;   /* pu */
    double i_m0;                  /* pu, steady magnetising current */
    double Tr;                    /* pu time */
    /* SI values, for the parameter checks */
    double Rs, Rr, Lm, Lr, psi;
} md_motor_t;

typedef struct {
    double i_m, i_t, u_m, u_t, ws, wr;   /* pu */
    double y1, y2;                       /* pu / pu time */
} md_sample_t;

static inline void md_motor(md_motor_t *m)
{
    const double Rs = 1.031, Rr = 0.465, Lm = 0.0064, Ls = 0.0092, Lr = 0.0092, psi = 0.042;
    double sigma = 1.0 - Lm * Lm / (Ls * Lr);
    double sls = sigma * Ls;
    double K1 = -(Rs / sls + Rr * Lm * Lm / (sls * Lr * Lr));
    double K2 = 1.0 / sls;
    double K3 = Lm * Rr * psi / (sls * Lr * Lr);
    double K4 = -Lm * psi / (sls * Lr);
    m->K1 = K1 / MD_W_BASE;
    m->K2 = K2 * MD_V_BASE / (MD_I_BASE * MD_W_BASE);
    m->K3 = K3 / (MD_I_BASE * MD_W_BASE);
    m->K3p = (K3 / K2) / MD_V_BASE;
    m->K4 = K4 / MD_I_BASE;
    m->i_m0 = psi / Lm / MD_I_BASE;
    m->Tr = Lr / Rr * MD_W_BASE;
    m->Rs = Rs; m->Rr = Rr; m->Lm = Lm; m->Lr = Lr; m->psi = psi;
}

/* Sample k (time k Ts).  Time derivatives are d/dt_pu = (1/w_base) d/dt. */
static inline void md_sample(const md_motor_t *m, int32_t k, md_sample_t *s)
{
    double t = (double)k * MD_TS_S;
    const double w1 = 2.0 * MD_PI * 11.0, w2 = 2.0 * MD_PI * 3.0, w3 = 2.0 * MD_PI * 17.0;
    double di_m, di_t;
    s->i_m = m->i_m0 + 0.01 * sin(w1 * t);
    di_m = 0.01 * w1 * cos(w1 * t) / MD_W_BASE;
    s->i_t = 0.25 + 0.05 * sin(w2 * t) + 0.03 * sin(w3 * t);
    di_t = (0.05 * w2 * cos(w2 * t) + 0.03 * w3 * cos(w3 * t)) / MD_W_BASE;
    s->wr = (t < 0.7) ? 0.9333 * t / 0.7 : 0.9333;
    s->ws = s->wr + s->i_t / (m->Tr * m->i_m0);
    s->y1 = di_m - s->ws * s->i_t;
    s->y2 = di_t + s->ws * s->i_m;
    s->u_m = (s->y1 - m->K1 * s->i_m - m->K3) / m->K2;
    s->u_t = (s->y2 - m->K1 * s->i_t - m->K4 * s->wr) / m->K2;
}

#endif /* ESTIM_MOTOR_DATA_H */
