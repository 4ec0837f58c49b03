/* The numbers drive_init derives from the SI configuration.  See
 * drive_design.h; the controller design is described in drive_init.c. */
#include "drive_design.h"

#include <math.h>

base_status_t drive_design_bases(base_values_t *b, const drive_config_t *c)
{
    return base_values_init(b, c->board.current_full_scale_A,
                            c->board.vdc_nominal_V / DRIVE_SQRT3_F, c->motor.rated_freq_Hz,
                            c->motor.pole_pairs, 1.0f / c->board.pwm_freq_Hz);
}

void drive_design(drive_design_t *g, const drive_config_t *c, const base_values_t *b)
{
    const drive_motor_t *m = &c->motor;
    float wc = DRIVE_TWO_PI_F * c->control.current_bw_Hz;
    float wsc = DRIVE_TWO_PI_F * c->control.speed_bw_Hz;
    float kt = 1.5f * (float)m->pole_pairs * m->Lm_H * m->Lm_H / m->Lr_H *
               m->magnetizing_current_A;                            /* N m / A */
    float gain = (float)m->pole_pairs * kt * b->I_base_A /
                 (c->control.inertia_kgm2 * b->w_base_rad_s);      /* pu speed/s per pu i_T */

    g->Ts = 1.0f / c->board.pwm_freq_Hz;
    g->Ts_slow = g->Ts * (float)DRIVE_SLOTS;   /* the slow task's period (drive_slow.c) */
    g->t1pr = c->board.sysclk_Hz / (2.0f * c->board.pwm_freq_Hz);   /* up/down count */
    g->sigma = 1.0f - m->Lm_H * m->Lm_H / (m->Ls_H * m->Lr_H);
    g->sls = g->sigma * m->Ls_H;
    g->cur_kp = wc * g->sls / b->Z_base_ohm;                      /* V/A -> pu */
    g->cur_ki = g->cur_kp * g->Ts * m->Rs_ohm / g->sls;           /* Kp Ts / Ti */
    g->spd_kp = wsc / gain;
    g->spd_ki = g->spd_kp * g->Ts_slow * wsc / 4.0f;   /* the speed loop runs at Ts_slow */
    g->i_max = c->control.max_torque_current_A / b->I_base_A;
    g->ramp = c->control.speed_ramp_rpm_s / b->n_base_rpm;        /* pu per second */
    g->tr = m->Lr_H / m->Rr_ohm;
    g->im_pu = m->magnetizing_current_A / b->I_base_A;
    g->target_pu = ((c->ident.target_speed_rpm > 0.0f) ? c->ident.target_speed_rpm
                                                       : m->rated_speed_rpm) / b->n_base_rpm;
    g->didt_pu = DRIVE_SETTLE_DIDT * 1.41421356f * m->rated_current_A_rms / b->I_base_A /
                 b->w_base_rad_s;
}

/* K of the believed motor (method §2, SI -> pu as in
 * tests/estim/estim_motor_data.h) */
void drive_design_k_nominal(float k[RLS_N], const drive_config_t *c, const base_values_t *b)
{
    const drive_motor_t *m = &c->motor;
    float sigma = 1.0f - m->Lm_H * m->Lm_H / (m->Ls_H * m->Lr_H);
    float sls = sigma * m->Ls_H;
    float psi = m->Lm_H * m->magnetizing_current_A;
    float K2 = 1.0f / sls;
    float K3 = m->Lm_H * m->Rr_ohm * psi / (sls * m->Lr_H * m->Lr_H);

    k[0] = -(m->Rs_ohm / sls + m->Rr_ohm * m->Lm_H * m->Lm_H / (sls * m->Lr_H * m->Lr_H)) /
           b->w_base_rad_s;
    k[1] = K2 * b->V_base_V / (b->I_base_A * b->w_base_rad_s);
    k[2] = (c->ident.paper_regressor != 0u) ? (K3 / K2) / b->V_base_V
                                           : K3 / (b->I_base_A * b->w_base_rad_s);
    k[3] = -m->Lm_H * psi / (sls * m->Lr_H) / b->I_base_A;
}

void drive_design_param_limits(param_limits_t *lim, const drive_config_t *c,
                               const base_values_t *b)
{
    const drive_motor_t *m = &c->motor;
    float Tr = m->Lr_H / m->Rr_ohm;
    float psi = m->Lm_H * m->magnetizing_current_A;

    lim->Rs_ohm[0] = 0.25f * m->Rs_ohm;  lim->Rs_ohm[1] = 4.0f * m->Rs_ohm;
    lim->Rr_ohm[0] = 0.25f * m->Rr_ohm;  lim->Rr_ohm[1] = 4.0f * m->Rr_ohm;
    lim->Lm_H[0] = 0.25f * m->Lm_H;      lim->Lm_H[1] = 4.0f * m->Lm_H;
    lim->Lr_H[0] = 0.25f * m->Lr_H;      lim->Lr_H[1] = 4.0f * m->Lr_H;
    lim->psi_Wb[0] = 0.25f * psi;        lim->psi_Wb[1] = 4.0f * psi;
    lim->Tr_s[0] = 0.25f * Tr;           lim->Tr_s[1] = 4.0f * Tr;
    /* Q24 holds < 128 pu: keep every upper limit representable */
    lim->Tr_s[1] = fminf(lim->Tr_s[1], 120.0f * b->t_base_s);
    lim->Lm_H[1] = fminf(lim->Lm_H[1], 120.0f * b->L_base_H);
    lim->Lr_H[1] = fminf(lim->Lr_H[1], 120.0f * b->L_base_H);
    lim->Rs_ohm[1] = fminf(lim->Rs_ohm[1], 120.0f * b->Z_base_ohm);
    lim->Rr_ohm[1] = fminf(lim->Rr_ohm[1], 120.0f * b->Z_base_ohm);
    lim->i_m_min_A = 0.25f * m->magnetizing_current_A;
}
