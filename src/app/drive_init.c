/**
 * Drive initialisation: every per-unit constant and controller gain, derived
 * once from the SI configuration (drive_config.h).  Float is used here only;
 * nothing in this file runs in the ISR.
 *
 * Controller design (so that another motor needs only its own ratings):
 *  - current loops: PI with the zero on the stator pole, Kp = w_c sigma Ls,
 *    Ti = sigma Ls / Rs (w_c = 2 pi current_bw_Hz), plus decoupling
 *    feed-forward u_d -= w_s sigma Ls i_T, u_q += w_s (sigma Ls i_M + Lm^2/Lr i_mr);
 *  - speed loop: plant d w_e/dt = p Kt i_T / J with Kt = 1.5 p Lm^2/Lr i_M,
 *    Kp = w_sc / gain, Ti = 4 / w_sc (w_sc = 2 pi speed_bw_Hz);
 *  - indirect field orientation with Tr = Lr / Rr of the believed motor, or
 *    (orientation = 1) the rotor-flux observer with the believed Rs,
 *    sigma Ls, Lr/Lm and Tr (flux_obs.h), crossover FOBS_WC_HZ.
 */
#include "drive_adapt.h"
#include "drive_internal.h"

#include <math.h>
#include <string.h>

#define TWO_PI_F 6.28318530717958647692f
#define SQRT3_F 1.73205080756887729353f

/* Rotor-flux observer (orientation 1).  Crossover 3 Hz: the current model's
 * weight is 3 (w_c/w_e)^2, 3 % at 10 w_c (flux_obs.h), and an offset of
 * 0.2 A leaves no drift (tests/orient/test_flux_obs.c).  ws_f, used for
 * decoupling and the modulation angle, is ws low-passed at 200 Hz: the
 * current noise through sigma Ls i makes the raw angle step noisy, and
 * 200 Hz lags by 0.8 ms, 0.3 rad/s of w_s on the paper motor's 2000 r/min/s
 * ramp.  The RLS learns only above FOBS_RLS_WS_OVER_WC w_c, where a wrong
 * Tr reaches the angle at most 3 (1/10)^2 = 3 % of its current-model error. */
#define FOBS_WC_HZ 3.0f
#define FOBS_WS_LPF_HZ 200.0f
#define FOBS_RLS_WS_OVER_WC 10.0f

static const char *const k_status_names[] = {
    "ok", "per-unit bases", "motor parameters", "PWM period", "sensor scaling",
    "current loop", "speed loop", "field orientation", "voltage model",
    "identification", "identification sequence", "protection levels",
};

const char *drive_cfg_status_str(int16_t status)
{
    if (status < 0 || status >= (int16_t)(sizeof k_status_names / sizeof k_status_names[0])) {
        return "unknown";
    }
    return k_status_names[status];
}

static int16_t motor_ok(const drive_motor_t *m)
{
    return (int16_t)(m->Rs_ohm > 0.0f && m->Rr_ohm > 0.0f && m->Lm_H > 0.0f &&
                     m->Ls_H > m->Lm_H && m->Lr_H > m->Lm_H &&
                     m->magnetizing_current_A > 0.0f && m->rated_speed_rpm > 0.0f &&
                     m->rated_current_A_rms > 0.0f);
}

static int16_t init_sensing(drive_t *d, const drive_config_t *c, float Ts)
{
    if (phase_current_init(&d->cur, 1.0f, 1.0f, 1, 0.05f) != PHASE_CURRENT_OK) {
        return 1;
    }
    if (dc_bus_init(&d->bus, c->board.vdc_adc_full_scale_V, &d->base, 200.0f) != 0) {
        return 1;
    }
    /* the angle every period, the speeds in the slow FILTERS slot */
    if (qep_speed_init(&d->qep, c->board.encoder_lines, &d->base, c->control.speed_filter_Hz,
                       16u) != 0 ||
        qep_speed_set_decim(&d->qep, DRIVE_SLOTS, &d->base, c->control.speed_filter_Hz) != 0) {
        return 1;
    }
    d->k.cal_samples = (uint16_t)(0.07f / Ts);   /* ~70 ms of offset averaging (every ISR) */
    /* live estimates at 100 Hz, counted in slow periods (drive_slow.c) */
    d->k.live_period = (uint16_t)(0.01f / (Ts * (float)DRIVE_SLOTS));
    return 0;
}

static int16_t init_current_loops(drive_t *d, const drive_config_t *c, float Ts)
{
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;
    float sigma = 1.0f - m->Lm_H * m->Lm_H / (m->Ls_H * m->Lr_H);
    float sls = sigma * m->Ls_H;
    float wc = TWO_PI_F * c->control.current_bw_Hz;
    float kp = wc * sls / b->Z_base_ohm;          /* V/A -> pu */
    float ki = kp * Ts * m->Rs_ohm / sls;         /* Kp Ts / Ti */

    d->k.sigma_ls = _IQ(sls / b->L_base_H);
    d->k.lm2_lr = _IQ(m->Lm_H * m->Lm_H / m->Lr_H / b->L_base_H);
    if (pi_init(&d->pi_id, kp, ki, -1.0f, 1.0f) != 0 ||
        pi_init(&d->pi_iq, kp, ki, -1.0f, 1.0f) != 0) {
        return 1;
    }
    return 0;
}

/* The speed loop runs in the slow task (drive_slow.c): Ts is its period. */
static int16_t init_speed_loop(drive_t *d, const drive_config_t *c, float Ts)
{
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;
    float kt = 1.5f * (float)m->pole_pairs * m->Lm_H * m->Lm_H / m->Lr_H *
               m->magnetizing_current_A;                            /* N m / A */
    float gain = (float)m->pole_pairs * kt * b->I_base_A /
                 (c->control.inertia_kgm2 * b->w_base_rad_s);      /* pu speed/s per pu i_T */
    float wsc = TWO_PI_F * c->control.speed_bw_Hz;
    float kp = wsc / gain;
    float ki = kp * Ts * wsc / 4.0f;
    float imax = c->control.max_torque_current_A / b->I_base_A;
    float ramp = c->control.speed_ramp_rpm_s / b->n_base_rpm;      /* pu per second */

    if (!(c->control.inertia_kgm2 > 0.0f) || !(imax > 0.0f) || imax > 1.0f) {
        return 1;
    }
    d->k.i_max = _IQ(imax);
    if (pi_init(&d->pi_speed, kp, ki, -imax, imax) != 0) {
        return 1;
    }
    if (ramp_gen_init(&d->speed_ramp, ramp, Ts, -2.0f, 2.0f) != 0) {
        return 1;
    }
    return 0;
}

rls_status_t drive_rls_start(drive_t *d)
{
    const drive_ident_t *id = &d->ident_cfg;
    rls_status_t st = rls_init(&d->rls, (id->paper_regressor != 0u) ? RLS_FORM_PAPER
                                                                    : RLS_FORM_CONST,
                               id->rls_p0, id->forgetting, 0.0f, NULL);
    d->rls_start = d->rls;   /* each further pass starts from this copy */
    return st;
}

/* The regression's filters, the RLS and the sequence run in the slow task
 * (drive_slow.c), once every DRIVE_SLOTS periods Ts; the regression's
 * inputs are summed every period (ident_regressor.h). */
static int16_t init_identification(drive_t *d, const drive_config_t *c, float Ts)
{
    const float Ts_slow = Ts * (float)DRIVE_SLOTS;
    const drive_motor_t *m = &c->motor;
    const drive_ident_t *id = &c->ident;
    const base_values_t *b = &d->base;
    float im_pu = m->magnetizing_current_A / b->I_base_A;
    float target_rpm = (id->target_speed_rpm > 0.0f) ? id->target_speed_rpm : m->rated_speed_rpm;
    float target_pu = target_rpm / b->n_base_rpm;
    /* steady-state: filtered di/dt below 5 % of the rated peak current per
     * second.  The speed loop's answer to encoder quantisation keeps the
     * filtered d(i_T)/dt of the paper motor at up to 1.8 %/s in steady
     * state (measured), so a 2 % threshold was reset by noise alone. */
    float didt_pu = 0.05f * 1.41421356f * m->rated_current_A_rms / b->I_base_A / b->w_base_rad_s;

    if (ident_regressor_init(&d->reg, id->filter_wc_rad_s, id->euler_passes, Ts,
                             b->w_base_rad_s, DRIVE_SLOTS_LOG2) != 0) {
        return 1;
    }
    d->ident_cfg = *id;
    if (drive_rls_start(d) != RLS_OK) {
        return 1;
    }
    /* plausibility: a factor of 4 either way of what the controller believes */
    {
        param_limits_t lim;
        float Tr = m->Lr_H / m->Rr_ohm;
        float psi = m->Lm_H * m->magnetizing_current_A;
        lim.Rs_ohm[0] = 0.25f * m->Rs_ohm;  lim.Rs_ohm[1] = 4.0f * m->Rs_ohm;
        lim.Rr_ohm[0] = 0.25f * m->Rr_ohm;  lim.Rr_ohm[1] = 4.0f * m->Rr_ohm;
        lim.Lm_H[0] = 0.25f * m->Lm_H;      lim.Lm_H[1] = 4.0f * m->Lm_H;
        lim.Lr_H[0] = 0.25f * m->Lr_H;      lim.Lr_H[1] = 4.0f * m->Lr_H;
        lim.psi_Wb[0] = 0.25f * psi;        lim.psi_Wb[1] = 4.0f * psi;
        lim.Tr_s[0] = 0.25f * Tr;           lim.Tr_s[1] = 4.0f * Tr;
        /* Q24 holds < 128 pu: keep every upper limit representable */
        lim.Tr_s[1] = fminf(lim.Tr_s[1], 120.0f * b->t_base_s);
        lim.Lm_H[1] = fminf(lim.Lm_H[1], 120.0f * b->L_base_H);
        lim.Lr_H[1] = fminf(lim.Lr_H[1], 120.0f * b->L_base_H);
        lim.Rs_ohm[1] = fminf(lim.Rs_ohm[1], 120.0f * b->Z_base_ohm);
        lim.Rr_ohm[1] = fminf(lim.Rr_ohm[1], 120.0f * b->Z_base_ohm);
        lim.i_m_min_A = 0.25f * m->magnetizing_current_A;
        if (param_extract_init(&d->pex, b, &lim) != PARAM_INIT_OK) {
            return 1;
        }
    }
    d->live = d->pex;
    /* estimator safeguard: K of the believed motor (method §2, SI -> pu as
     * in tests/estim/estim_motor_data.h), accepted within a factor 8 */
    {
        float sigma = 1.0f - m->Lm_H * m->Lm_H / (m->Ls_H * m->Lr_H);
        float sls = sigma * m->Ls_H;
        float psi = m->Lm_H * m->magnetizing_current_A;
        float K2 = 1.0f / sls;
        float K3 = m->Lm_H * m->Rr_ohm * psi / (sls * m->Lr_H * m->Lr_H);
        float k_nom[RLS_N];
        k_nom[0] = -(m->Rs_ohm / sls + m->Rr_ohm * m->Lm_H * m->Lm_H / (sls * m->Lr_H * m->Lr_H)) /
                   b->w_base_rad_s;
        k_nom[1] = K2 * b->V_base_V / (b->I_base_A * b->w_base_rad_s);
        k_nom[2] = (id->paper_regressor != 0u) ? (K3 / K2) / b->V_base_V
                                              : K3 / (b->I_base_A * b->w_base_rad_s);
        k_nom[3] = -m->Lm_H * psi / (sls * m->Lr_H) / b->I_base_A;
        if (theta_guard_init(&d->guard, k_nom, 8.0f) != THETA_GUARD_OK) {
            return 1;
        }
    }
    d->k.speed_tol = _IQ(0.005f * target_pu);
    if (id_sequence_init(&d->seq, Ts_slow, id->magnetize_time_s, 0.2f, 0.2f, 3.0f, id->rls_tail_s,
                         d->k.speed_tol,
                         _IQ(didt_pu), _IQ(im_pu), _IQ(target_pu)) != 0) {
        return 2;
    }
    return 0;
}

int16_t drive_init(drive_t *d, const drive_config_t *c)
{
    const drive_motor_t *m = &c->motor;
    float Ts, t1pr, Tr;

    memset(d, 0, sizeof *d);
    d->telemetry.fault = FAULT_CONFIG;   /* until init completes */
    d->config_status = DRIVE_CFG_BASES;
    if (!(c->board.pwm_freq_Hz > 0.0f) || !(c->board.sysclk_Hz > 0.0f)) {
        return DRIVE_CFG_BASES;
    }
    Ts = 1.0f / c->board.pwm_freq_Hz;
    if (base_values_init(&d->base, c->board.current_full_scale_A,
                         c->board.vdc_nominal_V / SQRT3_F, m->rated_freq_Hz, m->pole_pairs,
                         Ts) != BASE_OK) {
        return DRIVE_CFG_BASES;
    }
    d->config_status = DRIVE_CFG_MOTOR;
    if (!motor_ok(m)) {
        return DRIVE_CFG_MOTOR;
    }
    d->config_status = DRIVE_CFG_PWM;
    t1pr = c->board.sysclk_Hz / (2.0f * c->board.pwm_freq_Hz);   /* up/down count */
    if (!(t1pr >= 100.0f && t1pr <= 65535.0f)) {
        return DRIVE_CFG_PWM;
    }
    d->t1pr = (uint16_t)(t1pr + 0.5f);
    if (svgen_init(&d->svgen, d->t1pr) != 0) {
        return DRIVE_CFG_PWM;
    }
    d->config_status = DRIVE_CFG_SENSORS;
    if (init_sensing(d, c, Ts) != 0) {
        return DRIVE_CFG_SENSORS;
    }
    d->config_status = DRIVE_CFG_CURRENT_LOOP;
    if (init_current_loops(d, c, Ts) != 0) {
        return DRIVE_CFG_CURRENT_LOOP;
    }
    d->config_status = DRIVE_CFG_SPEED_LOOP;
    if (init_speed_loop(d, c, Ts * (float)DRIVE_SLOTS) != 0) {
        return DRIVE_CFG_SPEED_LOOP;
    }
    d->config_status = DRIVE_CFG_ORIENTATION;
    Tr = m->Lr_H / m->Rr_ohm;
    if (ifo_init(&d->ifo, Tr, &d->base, 0.2f * m->magnetizing_current_A / d->base.I_base_A) != 0) {
        return DRIVE_CFG_ORIENTATION;
    }
    d->k.three_half_step = _IQ(1.5f * d->base.f_base_Hz * Ts);
    d->k.orientation = c->control.orientation;
    drive_set_run_ifo(d, 0u);   /* the control frame: ifo's in mode 0, the observer's in 1 */
    if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
        if (flux_obs_init(&d->fobs, &d->base, m->Rs_ohm, m->Ls_H, m->Lr_H, m->Lm_H, Tr,
                          FOBS_WC_HZ, FOBS_WS_LPF_HZ) != FLUX_OBS_OK) {
            return DRIVE_CFG_ORIENTATION;
        }
        d->k.rls_ws_min = _IQ(FOBS_RLS_WS_OVER_WC * FOBS_WC_HZ / d->base.f_base_Hz);
        /* as ifo's imr_min: 20 % of the believed rated flux Lm i_M */
        d->k.psi_min = _IQ(0.2f * (m->Lm_H / d->base.L_base_H) *
                           (m->magnetizing_current_A / d->base.I_base_A));
    } else if (d->k.orientation != DRIVE_ORIENT_IFO) {
        return DRIVE_CFG_ORIENTATION;
    }
    d->config_status = DRIVE_CFG_VOLTAGE_MODEL;
    if (volt_calc_init(&d->volt, c->board.dead_time_s, Ts,
                       c->board.device_drop_V / d->base.V_base_V,
                       c->board.dead_time_band_A / d->base.I_base_A,
                       c->board.dead_time_comp) != 0) {
        return DRIVE_CFG_VOLTAGE_MODEL;
    }
    d->config_status = DRIVE_CFG_IDENT;
    {
        int16_t r = init_identification(d, c, Ts);
        if (r == 2) {
            d->config_status = DRIVE_CFG_SEQUENCE;
            return DRIVE_CFG_SEQUENCE;
        }
        if (r != 0) {
            return DRIVE_CFG_IDENT;
        }
        if (drive_adapt_init(d, c, Ts) != 0) {
            return DRIVE_CFG_IDENT;
        }
    }
    d->config_status = DRIVE_CFG_PROTECTION;
    if (protect_init(&d->prot, _IQ(c->board.overcurrent_A / d->base.I_base_A),
                     _IQ(c->board.vdc_max_V / d->base.V_base_V),
                     _IQ(c->board.vdc_min_V / d->base.V_base_V)) != 0 ||
        !(c->board.overcurrent_A < c->board.current_full_scale_A)) {
        return DRIVE_CFG_PROTECTION;
    }
    /* encoder plausibility (encoder_check.h): counts frozen for 50 ms with
     * |i_T| above 30 % of its limit, or a speed above 4 pu in one sample */
    if (encoder_check_init(&d->enc_chk, Ts, 0.05f,
                           0.3f * c->control.max_torque_current_A / d->base.I_base_A, 4.0f,
                           d->base.f_base_Hz, c->board.encoder_lines,
                           m->pole_pairs) != ENCODER_CHECK_OK ||
        encoder_check_set_rate(&d->enc_chk, DRIVE_SLOTS) != 0) {
        return DRIVE_CFG_PROTECTION;
    }
    /* current feedback (current_check.h): tau 2 ms, trip at 0.15 pu of
     * filtered |e_M| + |e_T|.  Measured (tests/fault): the worst healthy
     * value is the magnetising step, 0.073 pu (paper motor; 1.1 kW 0.035);
     * a phase-b sensor lost at the zero-current level trips in 8-10 samples,
     * before the true current reaches the trip level. */
    if (current_check_init(&d->cur_chk, Ts * (float)DRIVE_SLOTS, 0.002f, 0.15f) !=
            CURRENT_CHECK_OK) {
        return DRIVE_CFG_PROTECTION;
    }
    isr_monitor_init(&d->ovr);
    clarke_init(&d->clarke);
    park_init(&d->park);
    ipark_init(&d->ipark);
    d->duty_next[0] = d->duty_next[1] = d->duty_next[2] = _IQ(0.5);
    d->duty_last[0] = d->duty_last[1] = d->duty_last[2] = _IQ(0.5);
    d->config_status = DRIVE_CFG_OK;
    d->telemetry.fault = FAULT_NONE;
    return DRIVE_CFG_OK;
}
