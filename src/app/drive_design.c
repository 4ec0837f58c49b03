/* The numbers drive_init derives from the SI configuration.  See
 * drive_design.h; the controller design is described in drive_init.c. */
#include "drive_design.h"

#include <math.h>

#include "volt_calc.h"

base_status_t drive_design_bases(base_values_t *b, const drive_config_t *c)
{
    return base_values_init(b, c->board.current_full_scale_A,
                            c->board.vdc_nominal_V / DRIVE_SQRT3_F, c->motor.rated_freq_Hz,
                            c->motor.pole_pairs, 1.0f / c->board.pwm_freq_Hz);
}

/* The steady-state tolerances (drive_design.h).  The ripple: the bridge's
 * dead-time and drop voltage dv = vdc td f_pwm + v_drop (per unit of V_base)
 * is a square wave along each phase current, whose 5th and 7th harmonics,
 * (4/pi)(1/5 + 1/7) dv, appear at 6 w_e in the rotor-flux frame; the current
 * follows through sigma Ls, above the current loop's bandwidth by its
 * impedance, below it rejected at the loop's rate: i6 = (4/pi)(12/35) dv /
 * (sigma Ls max(6 w_e, w_c)); the regression's 2nd-order Butterworth
 * (corner w_f) passes 1/sqrt(1 + (6 w_e / w_f)^4) of it.  This is the
 * uncompensated ripple, a bound on what the compensation leaves. */
static void settle_tolerances(drive_design_t *g, const drive_config_t *c, const base_values_t *b)
{
    float dv = (c->board.vdc_nominal_V * c->board.dead_time_s * c->board.pwm_freq_Hz +
                c->board.device_drop_V) / b->V_base_V;
    float sls = g->sls / b->L_base_H;
    float w6 = 6.0f * fabsf(g->target_pu);
    float wc = c->control.current_bw_Hz / b->f_base_Hz;
    float wf = c->ident.filter_wc_rad_s / b->w_base_rad_s;
    float x = w6 / wf;
    float i6 = (4.0f / 3.14159265f) * (12.0f / 35.0f) * dv / (sls * fmaxf(w6, wc));
    g->ripple_pu = i6 / sqrtf(1.0f + x * x * x * x);
    /* at least 16 LSB of Q24 (a tolerance that rounds to 0 would never hold) */
    g->im_tol_pu = fmaxf(fmaxf(DRIVE_SETTLE_IM_FRAC * g->im_pu,
                               DRIVE_SETTLE_RIPPLE_K * g->ripple_pu), 16.0f / 16777216.0f);
    g->it_tol_pu = fmaxf(fmaxf(DRIVE_SETTLE_IT_FRAC * g->i_max,
                               DRIVE_SETTLE_RIPPLE_K * g->ripple_pu), 16.0f / 16777216.0f);
    /* one count in the QEP's window: pp / (W 4 lines Ts f_base) pu (qep_speed.h) */
    g->speed_tol_pu = fmaxf(DRIVE_SETTLE_SPEED_FRAC * fabsf(g->target_pu),
                            DRIVE_SETTLE_SPEED_COUNTS * (float)c->motor.pole_pairs /
                                ((float)DRIVE_QEP_WINDOW * 4.0f * (float)c->board.encoder_lines *
                                 g->Ts * b->f_base_Hz));
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
    g->accel_per_it = gain;
    g->tr = m->Lr_H / m->Rr_ohm;
    g->im_pu = m->magnetizing_current_A / b->I_base_A;
    g->target_pu = ((c->ident.target_speed_rpm > 0.0f) ? c->ident.target_speed_rpm
                                                       : m->rated_speed_rpm) / b->n_base_rpm;
    settle_tolerances(g, c, b);
    /* y2's w_s i_M at rated speed with the i_M reference (ident_conf.h: the
     * excitation's reference) */
    g->y_ref_pu = m->rated_speed_rpm / b->n_base_rpm * g->im_pu;
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
    /* Q24 holds < 128 pu: keep every upper limit representable; Tr is
     * Q20 (param_extract.h), bounded by what ifo and the observer accept */
    lim->Tr_s[1] = fminf(lim->Tr_s[1], IFO_TR_MAX_PU * b->t_base_s);
    lim->Lm_H[1] = fminf(lim->Lm_H[1], 120.0f * b->L_base_H);
    lim->Lr_H[1] = fminf(lim->Lr_H[1], 120.0f * b->L_base_H);
    lim->Rs_ohm[1] = fminf(lim->Rs_ohm[1], 120.0f * b->Z_base_ohm);
    lim->Rr_ohm[1] = fminf(lim->Rr_ohm[1], 120.0f * b->Z_base_ohm);
    lim->i_m_min_A = 0.25f * m->magnetizing_current_A;
}

float drive_design_volt_band_pu(const drive_config_t *c, const base_values_t *b)
{
    return (c->ident.vi_test != 0u) ? VOLT_CALC_ITH_MAX_PU
                                    : c->board.dead_time_band_A / b->I_base_A;
}

uint16_t drive_design_volt_comp(const drive_config_t *c)
{
    return (c->ident.vi_test != 0u) ? 0u : c->board.dead_time_comp;
}

int16_t drive_design_imax_ok(float i_max_pu)
{
    return (int16_t)(i_max_pu > 0.0f && i_max_pu <= 1.0f);
}

int16_t drive_design_oc_ok(const drive_board_t *bd)
{
    return (int16_t)(bd->overcurrent_A < bd->current_full_scale_A);
}
