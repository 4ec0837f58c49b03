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
#include "drive_design.h"
#include "drive_internal.h"
#include "drive_limits.h"
#include "drive_safety.h"
#include "drive_target.h"
#include "drive_vi.h"

#include <math.h>
#include <string.h>

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

static int16_t init_sensing(drive_t *d, const drive_config_t *c, float Ts)
{
    if (phase_current_init(&d->sense.phase, 1.0f, 1.0f, 1, 0.05f) != PHASE_CURRENT_OK) {
        return 1;
    }
    if (dc_bus_init(&d->sense.bus, c->board.vdc_adc_full_scale_V, &d->base,
                    DRIVE_VDC_FILTER_HZ) != 0) {
        return 1;
    }
    /* the angle every period, the speeds in the slow FILTERS slot */
    if (qep_speed_init(&d->sense.qep, c->board.encoder_lines, &d->base, c->control.speed_filter_Hz,
                       DRIVE_QEP_WINDOW) != 0 ||
        qep_speed_set_decim(&d->sense.qep, DRIVE_SLOTS, &d->base, c->control.speed_filter_Hz) != 0) {
        return 1;
    }
    d->k.cal_samples = (uint16_t)(0.07f / Ts);   /* ~70 ms of offset averaging (every ISR) */
    /* its mean a multiply and a shift in the ISR that ends it, not a division
     * (a run-time-library call from flash on the C28x); a count it cannot do
     * exactly divides (phase_current_cal_design) */
    if (phase_current_cal_design(&d->sense.phase, d->k.cal_samples) != PHASE_CURRENT_OK) {
        return 1;
    }
    /* live estimates at 100 Hz, counted in slow periods (drive_slow.c) */
    d->k.live_period = (uint16_t)(0.01f / (Ts * (float)DRIVE_SLOTS));
    return 0;
}

static int16_t init_current_loops(drive_t *d, const drive_config_t *c, const drive_design_t *g)
{
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;

    d->k.sigma_ls = _IQ(g->sls / b->L_base_H);
    d->k.lm2_lr = _IQ(m->Lm_H * m->Lm_H / m->Lr_H / b->L_base_H);
    if (pi_init(&d->loop.pi_id, g->cur_kp, g->cur_ki, -DRIVE_CUR_PI_OUT_MAX,
                DRIVE_CUR_PI_OUT_MAX) != 0 ||
        pi_init(&d->loop.pi_iq, g->cur_kp, g->cur_ki, -DRIVE_CUR_PI_OUT_MAX,
                DRIVE_CUR_PI_OUT_MAX) != 0) {
        return 1;
    }
    return 0;
}

/* The speed loop runs in the slow task (drive_slow.c): its gains and ramp
 * are for the slow period (drive_design: spd_ki, Ts_slow). */
static int16_t init_speed_loop(drive_t *d, const drive_config_t *c, const drive_design_t *g)
{
    float imax = g->i_max;

    if (!(c->control.inertia_kgm2 > 0.0f) || drive_design_imax_ok(imax) == 0) {
        return 1;
    }
    d->k.i_max = _IQ(imax);
    if (pi_init(&d->loop.pi_speed, g->spd_kp, g->spd_ki, -imax, imax) != 0) {
        return 1;
    }
    if (ramp_gen_init(&d->loop.speed_ramp, g->ramp, g->Ts_slow, -DRIVE_SPEED_REF_MAX_PU,
                      DRIVE_SPEED_REF_MAX_PU) != 0) {
        return 1;
    }
    /* the excitation's ramp (drive_adapt.h): DRIVE_EXCITE_OF_IMAX of the
     * torque current's acceleration, at most 1 pu a slow period */
    d->k.ramp_step = d->loop.speed_ramp.step;
    d->k.excite_step = _IQ(fminf(fmaxf(g->ramp, DRIVE_EXCITE_OF_IMAX * imax * g->accel_per_it) *
                                     g->Ts_slow, 1.0f));
    return 0;
}

rls_status_t drive_rls_start(drive_t *d)
{
    const drive_ident_t *id = &d->id.cfg;
    rls_form_t form = (id->paper_regressor != 0u) ? RLS_FORM_PAPER : RLS_FORM_CONST;
    if (id->period_mean != 0u) {
        form = RLS_FORM_FLUX;
    }
    return rls_init(&d->id.rls, form, id->rls_p0, id->forgetting, 0.0f, NULL);
}

/* The regression's filters, the RLS and the sequence run in the slow task
 * (drive_slow.c), once every DRIVE_SLOTS periods Ts; the regression's
 * inputs are summed every period (ident_regressor.h). */
static int16_t init_identification(drive_t *d, const drive_config_t *c, const drive_design_t *g)
{
    const drive_ident_t *id = &c->ident;
    const base_values_t *b = &d->base;
    float Ts = g->Ts;

    if (ident_regressor_init(&d->id.reg, id->filter_wc_rad_s, id->euler_passes, Ts,
                             b->w_base_rad_s, DRIVE_SLOTS_LOG2) != 0) {
        return 1;
    }
    if (id->period_mean != 0u) {
        /* the period-mean rows on ifo's flux (ident_regressor.h): its Tr, the
         * nameplate's K2 for the ripple term until the RLS has one */
        float k_nom[RLS_N];
        drive_design_k_nominal(k_nom, c, b);
        if (ident_regressor_set_period_mean(&d->id.reg, g->tr, k_nom[1], g->im_pu, Ts,
                                            b->w_base_rad_s) != 0) {
            return 1;
        }
    }
    d->id.cfg = *id;
    if (drive_rls_start(d) != RLS_OK) {
        return 1;
    }
    /* plausibility: a factor of 4 either way of what the controller believes */
    {
        param_limits_t lim;
        drive_design_param_limits(&lim, c, b);
        if (param_extract_init(&d->id.pex, b, &lim) != PARAM_INIT_OK) {
            return 1;
        }
        /* the period-mean rows' flux unit (rls.h RLS_FORM_FLUX); 0 otherwise */
        d->id.pex.inv_im_nom = (id->period_mean != 0u) ? _IQ(1.0f / g->im_pu) : _IQ(0.0);
    }
    d->id.live = d->id.pex;
    /* estimator safeguard: K of the believed motor, accepted within a factor 8 */
    {
        float k_nom[RLS_N];
        drive_design_k_nominal(k_nom, c, b);
        if (theta_guard_init(&d->id.guard, k_nom, DRIVE_THETA_GUARD_SPAN) != THETA_GUARD_OK) {
            return 1;
        }
    }
    /* the publication's verdict (ident_conf.h; drive_design.h: the limits) */
    if (ident_conf_init(&d->verdict.conf, DRIVE_CONF_MAX, DRIVE_CONF_RES_REF, DRIVE_CONF_EXC_REF,
                        g->y_ref_pu) != IDENT_CONF_INIT_OK) {
        return 1;
    }
    /* the tracker's judging window and the wait for it, in tracker updates and
     * slow-task samples (drive_adapt.c: the tracker every DRIVE_ADAPT_TRACK_DECIM slow
     * samples) */
    {
        /* the believed Tr (the nameplate's; 30 % off changes the wait by at
         * most 0.9 Tr) */
        float valid_s = tr_track_settle_s(c->ident.track_memory_s, g->tr);
        d->k.track_valid_updates =
            (uint32_t)(valid_s / (g->Ts_slow * (float)DRIVE_ADAPT_TRACK_DECIM) + 0.5f);
        d->k.conf_track_updates =
            (uint16_t)(DRIVE_CONF_TRACK_S / (g->Ts_slow * (float)DRIVE_ADAPT_TRACK_DECIM) + 0.5f);
        /* (twice the tracker's time: a free shaft's tracker learns only while
         * the excitation's ramps give it torque) */
        d->k.conf_track_wait = (uint32_t)((2.0f * (valid_s + DRIVE_CONF_TRACK_S) +
                                           DRIVE_CONF_TRACK_WAIT_S) / g->Ts_slow + 0.5f);
    }
    /* the tracker's standard error per relative residual: (1 - lambda)/2 for a
     * forgetting RLS, c = f_upd / (2 B_n) samples per independent one for its
     * first-order 10 Hz low-pass (B_n = pi f / 2): sqrt(c (1 - lambda) / 2) =
     * 1 / sqrt(2 pi f T_memory) */
    d->k.conf_track_se =
        _IQ(1.0f / sqrtf(DRIVE_TWO_PI_F * TRACK_LPF_HZ * c->ident.track_memory_s));
    d->k.speed_tol = _IQ(g->speed_tol_pu);
    if (id_sequence_init(&d->seq, g->Ts_slow, id->magnetize_time_s, 0.2f, 0.2f, 3.0f, id->rls_tail_s,
                         d->k.speed_tol, _IQ(g->im_tol_pu), _IQ(g->it_tol_pu),
                         _IQ(g->im_pu), _IQ(g->target_pu)) != 0) {
        return 2;
    }
    return 0;
}

int16_t drive_init(drive_t *d, const drive_config_t *c)
{
    int16_t st;

    memset(d, 0, sizeof *d);
    d->telemetry.fault = FAULT_CONFIG;   /* until init completes */
    /* every limit in one table (drive_limits.h), which names what failed;
     * each module below still checks its own arguments.  The check's frame
     * (its own design of the gains) is gone before drive_init_checked's
     * (drive_internal.h) is made: the two are never on the stack together */
    st = drive_config_check(c, NULL);
    if (st != DRIVE_CFG_OK) {
        d->k.config_status = (uint16_t)st;
        return st;
    }
    return drive_init_checked(d, c);
}

int16_t drive_init_checked(drive_t *d, const drive_config_t *c)
{
    const drive_motor_t *m = &c->motor;
    drive_design_t g;
    float Ts, Tr;

    d->k.config_status = DRIVE_CFG_BASES;
    if (drive_design_bases(&d->base, c) != BASE_OK) {
        return DRIVE_CFG_BASES;
    }
    drive_design(&g, c, &d->base);
    Ts = g.Ts;
    d->k.config_status = DRIVE_CFG_PWM;
    d->k.t1pr = (uint16_t)(g.t1pr + 0.5f);
    if (svgen_init(&d->pwm.svgen, d->k.t1pr) != 0) {
        return DRIVE_CFG_PWM;
    }
    d->k.config_status = DRIVE_CFG_SENSORS;
    if (init_sensing(d, c, Ts) != 0) {
        return DRIVE_CFG_SENSORS;
    }
    d->k.config_status = DRIVE_CFG_CURRENT_LOOP;
    if (init_current_loops(d, c, &g) != 0) {
        return DRIVE_CFG_CURRENT_LOOP;
    }
    d->k.config_status = DRIVE_CFG_SPEED_LOOP;
    if (init_speed_loop(d, c, &g) != 0) {
        return DRIVE_CFG_SPEED_LOOP;
    }
    d->k.config_status = DRIVE_CFG_ORIENTATION;
    Tr = g.tr;
    if (ifo_init(&d->frame.ifo, Tr, &d->base,
                 DRIVE_IMR_MIN_OF_IM * m->magnetizing_current_A / d->base.I_base_A) != 0) {
        return DRIVE_CFG_ORIENTATION;
    }
    d->k.three_half_step = _IQ(1.5f * d->base.f_base_Hz * Ts);
    d->k.orientation = c->control.orientation;
    drive_set_run_ifo(d, 0u);   /* the control frame: ifo's in mode 0, the observer's in 1 */
    if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
        /* one step per slow period, on the window's mean voltage and
         * current (drive_slow.c, OBSERVER slot) */
        if (flux_obs_init(&d->frame.fobs, &d->base, m->Rs_ohm, m->Ls_H, m->Lr_H, m->Lm_H, Tr,
                          FOBS_WC_HZ, FOBS_WS_LPF_HZ) != FLUX_OBS_OK ||
            flux_obs_set_step(&d->frame.fobs, &d->base, DRIVE_SLOTS, FOBS_WC_HZ, FOBS_WS_LPF_HZ) !=
                FLUX_OBS_OK) {
            return DRIVE_CFG_ORIENTATION;
        }
        d->k.rls_ws_min = _IQ(FOBS_RLS_WS_OVER_WC * FOBS_WC_HZ / d->base.f_base_Hz);
        /* as ifo's imr_min: 20 % of the believed rated flux Lm i_M */
        d->k.psi_min = _IQ(0.2f * (m->Lm_H / d->base.L_base_H) *
                           (m->magnetizing_current_A / d->base.I_base_A));
    } else if (d->k.orientation != DRIVE_ORIENT_IFO) {
        return DRIVE_CFG_ORIENTATION;
    }
    d->k.config_status = DRIVE_CFG_VOLTAGE_MODEL;
    /* with ident.vi_test the compensation stays off until the bridge's
     * curve is measured (drive_vi.c), and the linear zone here is unused */
    if (volt_calc_init(&d->pwm.volt, c->board.dead_time_s, Ts,
                       c->board.device_drop_V / d->base.V_base_V,
                       drive_design_volt_band_pu(c, &d->base), drive_design_volt_comp(c)) != 0) {
        return DRIVE_CFG_VOLTAGE_MODEL;
    }
    d->k.config_status = DRIVE_CFG_IDENT;
    {
        int16_t r = init_identification(d, c, &g);
        if (r == 2) {
            d->k.config_status = DRIVE_CFG_SEQUENCE;
            return DRIVE_CFG_SEQUENCE;
        }
        if (r != 0) {
            return DRIVE_CFG_IDENT;
        }
        /* the target within the measured bus, and the rotor at rest for the
         * standstill phases (and at a start): DRIVE_REST_SPEED_OF_RATED, at
         * least two counts of the QEP's speed window */
        if (drive_target_init(&d->target, c, &d->base, g.Ts_slow) != 0) {
            d->k.config_status = DRIVE_CFG_SEQUENCE;
            return DRIVE_CFG_SEQUENCE;
        }
        d->k.rest_speed = _IQ(fmaxf(DRIVE_REST_SPEED_OF_RATED * m->rated_speed_rpm /
                                        d->base.n_base_rpm,
                                    2.0f * _IQtoF(d->sense.qep.k_speed)));
        id_sequence_set_rest(&d->seq, d->k.rest_speed);
        id_sequence_set_excite(&d->seq, _IQmpy(d->target.least, _IQ(DRIVE_EXCITE_FLOOR_OF_LEAST)));
        if (drive_adapt_init(d, c, Ts) != 0) {
            return DRIVE_CFG_IDENT;
        }
    }
    d->k.config_status = DRIVE_CFG_PROTECTION;
    if (protect_init(&d->prot.trip, _IQ(c->board.overcurrent_A / d->base.I_base_A),
                     _IQ(c->board.vdc_max_V / d->base.V_base_V),
                     _IQ(c->board.vdc_min_V / d->base.V_base_V)) != 0 ||
        drive_design_oc_ok(&c->board) == 0) {
        return DRIVE_CFG_PROTECTION;
    }
    /* encoder plausibility (encoder_check.h): counts frozen for 50 ms with
     * |i_T| above 30 % of its limit, or a speed above 4 pu in one sample */
    if (encoder_check_init(&d->prot.enc, Ts, DRIVE_ENC_FROZEN_S,
                           DRIVE_ENC_IT_OF_IMAX * c->control.max_torque_current_A /
                               d->base.I_base_A,
                           DRIVE_ENC_SPEED_MAX_PU,
                           d->base.f_base_Hz, c->board.encoder_lines,
                           m->pole_pairs) != ENCODER_CHECK_OK ||
        encoder_check_set_rate(&d->prot.enc, DRIVE_SLOTS) != 0) {
        return DRIVE_CFG_PROTECTION;
    }
    /* current feedback (current_check.h): tau 2 ms, trip at 0.15 pu of
     * filtered |e_M| + |e_T|.  Measured (tests/fault): the worst healthy
     * value is the magnetising step, 0.073 pu (paper motor; 1.1 kW 0.035);
     * a phase-b sensor lost at the zero-current level trips in 8-10 samples,
     * before the true current reaches the trip level.  It runs in the SPEED
     * slot; below a 2 kHz PWM (a slow period above 2 ms) tau is that period. */
    if (current_check_init(&d->prot.feedback, g.Ts_slow, fmaxf(0.002f, g.Ts_slow), 0.15f) !=
            CURRENT_CHECK_OK) {
        return DRIVE_CFG_PROTECTION;
    }
    if (drive_safety_init(d, c) != 0) {
        return DRIVE_CFG_PROTECTION;
    }
    if (drive_vi_init(d, c, g.Ts_slow, g.sls, g.tr) != 0) {
        d->k.config_status = DRIVE_CFG_VOLTAGE_MODEL;
        return DRIVE_CFG_VOLTAGE_MODEL;
    }
    isr_monitor_init(&d->prot.ovr);
    clarke_init(&d->sense.clarke);
    park_init(&d->loop.park);
    ipark_init(&d->loop.ipark);
    d->pwm.duty_next[0] = d->pwm.duty_next[1] = d->pwm.duty_next[2] = _IQ(0.5);
    d->pwm.volt.da = d->pwm.volt.db = d->pwm.volt.dc = _IQ(0.5);   /* the period before the first */
    d->k.config_status = DRIVE_CFG_OK;
    d->telemetry.fault = FAULT_NONE;
    return DRIVE_CFG_OK;
}
