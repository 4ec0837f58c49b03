/**
 * Co-simulation API: independent firmware instances on the host; see
 * include/imfoc_api.h.  Each instance is one heap-allocated drive_t (malloc
 * is fine here, on the host; never in src/) driven through drive_step(), the
 * HAL-free body of the ISR, so nothing global is shared between instances.
 */
#include "imfoc_api.h"

#include <math.h>

#define IMFOC_TWO_PI 6.28318530717958647692
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "drive_limits.h"
#include "drive_probe.h"
#include "imfoc_convert.h"
#include "sim_config.h"
#include "sim_limits.h"

#define IMFOC_BACKGROUND_DIV 15u   /* 1 kHz background at 15 kHz, as motor_sim */

struct imfoc {
    drive_t drive;
    drive_probe_t pv;        /* what the API reads of it */
    imfoc_info_t info;
    hal_pwm_compare_t cmp;   /* last compare values */
    uint32_t isr_count;
    uint16_t bg_left;        /* periods to the next background call */
    uint16_t have_angle;     /* theta_in / theta_unwrapped valid */
    double theta_in;         /* last physical angle given */
    double theta_unwrapped;  /* its unwrapped sum */
};

static void set_err(char *err, size_t len, const char *msg, const char *detail)
{
    if (err != NULL && len > 0u) {
        snprintf(err, len, "%s%s%s", msg, (detail != NULL) ? ": " : "",
                 (detail != NULL) ? detail : "");
    }
}

int32_t imfoc_api_version(void) { return IMFOC_API_VERSION; }

const char *imfoc_status_str(int32_t status)
{
    switch (status) {
    case IMFOC_OK: return "ok";
    case IMFOC_ERR_NULL: return "NULL instance or pointer";
    case IMFOC_ERR_CONFIG: return "configuration refused";
    case IMFOC_ERR_NOMEM: return "out of memory";
    case IMFOC_ERR_RANGE: return "argument out of range or not finite";
    case IMFOC_ERR_COMMAND: return "unknown command";
    default: return "unknown status";
    }
}

imfoc_t *imfoc_create(const drive_config_t *cfg, char *err, size_t err_len)
{
    imfoc_t *h;
    int16_t st;
    const base_values_t *b;

    if (cfg == NULL) {
        set_err(err, err_len, imfoc_status_str(IMFOC_ERR_NULL), NULL);
        return NULL;
    }
    h = (imfoc_t *)calloc(1u, sizeof *h);
    if (h == NULL) {
        set_err(err, err_len, imfoc_status_str(IMFOC_ERR_NOMEM), NULL);
        return NULL;
    }
    st = drive_init(&h->drive, cfg);
    if (st != DRIVE_CFG_OK) {
        drive_limit_fail_t lim;
        char detail[SIM_CONFIG_ERR_LEN];
        int n = snprintf(detail, sizeof detail, "%s", drive_cfg_status_str(st));
        if (drive_config_check(cfg, &lim) != DRIVE_CFG_OK && n > 0 &&
            (size_t)n + 2u < sizeof detail) {
            detail[n++] = ':';
            detail[n++] = ' ';
            sim_limit_message(detail + n, sizeof detail - (size_t)n, &lim);
        }
        set_err(err, err_len, "drive_init rejected the configuration", detail);
        free(h);
        return NULL;
    }
    drive_probe(&h->drive, &h->pv);
    b = h->pv.base;
    h->info.Ts_s = (double)b->Ts_s;
    h->info.I_base_A = (double)b->I_base_A;
    h->info.V_base_V = (double)b->V_base_V;
    h->info.f_base_Hz = (double)b->f_base_Hz;
    h->info.w_base_rad_s = (double)b->w_base_rad_s;
    h->info.t_base_s = (double)b->t_base_s;
    h->info.Z_base_ohm = (double)b->Z_base_ohm;
    h->info.L_base_H = (double)b->L_base_H;
    h->info.psi_base_Wb = (double)b->psi_base_Wb;
    h->info.n_base_rpm = (double)b->n_base_rpm;
    h->info.current_full_scale_A = (double)cfg->board.current_full_scale_A;
    h->info.vdc_full_scale_V = (double)cfg->board.vdc_adc_full_scale_V;
    h->info.t1pr = h->pv.k->t1pr;
    h->info.pole_pairs = b->pole_pairs;
    h->info.encoder_lines = cfg->board.encoder_lines;
    h->info.background_div = IMFOC_BACKGROUND_DIV;
    h->bg_left = 0u;   /* background right after the first ISR, as motor_sim */
    h->cmp.cmpr[0] = h->cmp.cmpr[1] = h->cmp.cmpr[2] = h->pv.k->t1pr;
    return h;
}

imfoc_t *imfoc_create_ini(const char *path, char *err, size_t err_len)
{
    sim_config_t sc;
    drive_config_t dc;
    char msg[SIM_CONFIG_ERR_LEN];

    if (path == NULL) {
        set_err(err, err_len, imfoc_status_str(IMFOC_ERR_NULL), NULL);
        return NULL;
    }
    if (sim_config_load_drive(path, &sc, msg, sizeof msg) != 0) {
        set_err(err, err_len, msg, NULL);
        return NULL;
    }
    sim_config_to_drive(&sc, &dc);
    return imfoc_create(&dc, err, err_len);
}

void imfoc_destroy(imfoc_t *h) { free(h); }

int32_t imfoc_get_info(const imfoc_t *h, imfoc_info_t *info)
{
    if (h == NULL || info == NULL) {
        return IMFOC_ERR_NULL;
    }
    *info = h->info;
    return IMFOC_OK;
}

int32_t imfoc_set_background_div(imfoc_t *h, uint16_t div)
{
    if (h == NULL) {
        return IMFOC_ERR_NULL;
    }
    h->info.background_div = div;
    h->bg_left = 0u;
    return IMFOC_OK;
}

int32_t imfoc_background(imfoc_t *h)
{
    if (h == NULL) {
        return IMFOC_ERR_NULL;
    }
    drive_background(&h->drive);
    return IMFOC_OK;
}

int32_t imfoc_command(imfoc_t *h, int32_t cmd)
{
    drive_cmd_t c;
    if (h == NULL) {
        return IMFOC_ERR_NULL;
    }
    switch (cmd) {
    case IMFOC_CMD_START_IDENT: c = DRIVE_CMD_START_IDENT; break;
    case IMFOC_CMD_STOP: c = DRIVE_CMD_STOP; break;
    case IMFOC_CMD_RESET_FAULT: c = DRIVE_CMD_RESET_FAULT; break;
    case IMFOC_CMD_SELECT_STANDSTILL: c = DRIVE_CMD_SELECT_STANDSTILL; break;
    case IMFOC_CMD_SELECT_ROTATING: c = DRIVE_CMD_SELECT_ROTATING; break;
    default: return IMFOC_ERR_COMMAND;
    }
    drive_command(&h->drive, c);
    drive_background(&h->drive);
    return IMFOC_OK;
}

int32_t imfoc_set_speed_rpm(imfoc_t *h, double rpm)
{
    double pu;
    if (h == NULL) {
        return IMFOC_ERR_NULL;
    }
    pu = rpm / h->info.n_base_rpm;
    /* the ramp and the speed loop keep headroom: well inside Q24's +-128 */
    if (!isfinite(pu) || fabs(pu) > 4.0) {
        return IMFOC_ERR_RANGE;
    }
    drive_set_speed(&h->drive, _IQ((float)pu));
    return IMFOC_OK;
}

static void fill_out(const imfoc_t *h, imfoc_out_t *out)
{
    const drive_probe_t *d = &h->pv;
    double t1pr = (double)h->info.t1pr, mean = 0.0, vdc;
    unsigned i;

    out->pwm_on = d->telemetry->pwm_on;
    for (i = 0; i < 3u; i++) {
        out->cmpr[i] = h->cmp.cmpr[i];
        out->duty[i] = (t1pr - (double)h->cmp.cmpr[i]) / t1pr;
        mean += out->duty[i] / 3.0;
    }
    vdc = (double)_IQtoF(d->sense->bus.vdc) * h->info.V_base_V;
    for (i = 0; i < 3u; i++) {
        out->v_phase_V[i] = (out->pwm_on != 0u) ? (out->duty[i] - mean) * vdc : 0.0;
    }
}

int32_t imfoc_step_raw(imfoc_t *h, const imfoc_raw_in_t *in, imfoc_out_t *out)
{
    hal_adc_sample_t adc;

    if (h == NULL || in == NULL) {
        return IMFOC_ERR_NULL;
    }
    adc.ia_raw = in->ia_raw;
    adc.ib_raw = in->ib_raw;
    adc.vdc_raw = in->vdc_raw;
    /* drive_isr() without the HAL: PDPINTA in, compares and enable out */
    drive_set_hw_trip(&h->drive, (uint16_t)(in->trip != 0u));
    drive_step(&h->drive, &adc, in->qep_count, &h->cmp);
    h->isr_count++;
    if (h->info.background_div != 0u) {
        if (h->bg_left == 0u) {
            drive_background(&h->drive);
            h->bg_left = h->info.background_div;
        }
        h->bg_left--;
    }
    if (out != NULL) {
        fill_out(h, out);
    }
    return IMFOC_OK;
}

static int32_t convert(const imfoc_t *h, const imfoc_phys_in_t *in, double theta,
                       imfoc_raw_in_t *raw)
{
    if (!isfinite(in->ia_A) || !isfinite(in->ib_A) || !isfinite(in->vdc_V) ||
        !isfinite(theta)) {
        return IMFOC_ERR_RANGE;
    }
    raw->ia_raw = imfoc_adc_current(in->ia_A, h->info.current_full_scale_A);
    raw->ib_raw = imfoc_adc_current(in->ib_A, h->info.current_full_scale_A);
    raw->vdc_raw = imfoc_adc_vdc(in->vdc_V, h->info.vdc_full_scale_V);
    raw->qep_count = imfoc_qep_count(theta, h->info.encoder_lines);
    raw->trip = (uint16_t)(in->trip != 0u);
    return IMFOC_OK;
}

int32_t imfoc_phys_to_raw(const imfoc_t *h, const imfoc_phys_in_t *in, imfoc_raw_in_t *raw)
{
    if (h == NULL || in == NULL || raw == NULL) {
        return IMFOC_ERR_NULL;
    }
    return convert(h, in, in->theta_m_rad, raw);
}

int32_t imfoc_step_phys(imfoc_t *h, const imfoc_phys_in_t *in, imfoc_out_t *out)
{
    imfoc_raw_in_t raw;
    double theta;
    int32_t st;

    if (h == NULL || in == NULL) {
        return IMFOC_ERR_NULL;
    }
    if (!isfinite(in->theta_m_rad)) {
        return IMFOC_ERR_RANGE;
    }
    theta = (h->have_angle != 0u) ? imfoc_unwrap(h->theta_unwrapped, h->theta_in, in->theta_m_rad)
                                  : in->theta_m_rad;
    st = convert(h, in, theta, &raw);
    if (st != IMFOC_OK) {
        return st;
    }
    h->theta_in = in->theta_m_rad;
    h->theta_unwrapped = theta;
    h->have_angle = 1u;
    return imfoc_step_raw(h, &raw, out);
}

static double f(_iq x) { return (double)_IQtoF(x); }

/* Rs, Rr, Lm, Lr, psi_r, Tr (pu, in that order) into the six SI fields given */
/* q: Rs, Rr, Lm, Lr, psi_r in Q24 and Tr in Q20 (param_extract.h) */
static void params_si(const imfoc_t *h, const _iq q[6], double *Rs, double *Rr, double *Lm,
                      double *Lr, double *psi, double *Tr)
{
    *Rs = f(q[0]) * h->info.Z_base_ohm;
    *Rr = f(q[1]) * h->info.Z_base_ohm;
    *Lm = f(q[2]) * h->info.L_base_H;
    *Lr = f(q[3]) * h->info.L_base_H;
    *psi = f(q[4]) * h->info.psi_base_Wb;
    *Tr = (double)_IQ20toF(q[5]) * h->info.t_base_s;
}

static void extract_si(const imfoc_t *h, const param_extract_t *p, double *Rs, double *Rr,
                       double *Lm, double *Lr, double *psi, double *Tr)
{
    const _iq q[6] = {p->Rs, p->Rr, p->Lm, p->Lr, p->psi_r, p->Tr};
    params_si(h, q, Rs, Rr, Lm, Lr, psi, Tr);
}

int32_t imfoc_get_signals(const imfoc_t *h, imfoc_signals_t *s)
{
    const drive_probe_t *d;
    const drive_telemetry_t *t;
    const double I = (h != NULL) ? h->info.I_base_A : 0.0;
    const double V = (h != NULL) ? h->info.V_base_V : 0.0;
    unsigned i;

    if (h == NULL || s == NULL) {
        return IMFOC_ERR_NULL;
    }
    d = &h->pv;
    memset(s, 0, sizeof *s);
    s->isr_count = h->isr_count;
    s->state = d->telemetry->state;
    s->fault = d->telemetry->fault;
    s->pwm_on = d->telemetry->pwm_on;
    s->params_valid = d->telemetry->params_valid;
    s->live_valid = d->id->live.valid;
    s->rls_on = d->seq->rls_on;
    s->speed_rpm = f(d->sense->qep.speed) * h->info.n_base_rpm;
    s->speed_ref_rpm = f(d->loop->speed_ramp.out) * h->info.n_base_rpm;
    s->ia_A = f(d->sense->phase.ia) * I;
    s->ib_A = f(d->sense->phase.ib) * I;
    s->vdc_V = f(d->sense->bus.vdc) * V;
    s->i_m_A = f(d->loop->park.ds) * I;
    s->i_t_A = f(d->loop->park.qs) * I;
    if (d->k->orientation == DRIVE_ORIENT_FLUX_OBS) {
        /* observer: i_mr = |psi_r| / Lm (pu flux / pu inductance = pu current) */
        s->i_mr_A = (f(d->frame->fobs.lm) > 0.0) ? f(d->frame->fobs.psi_mag) / f(d->frame->fobs.lm) * I : 0.0;
        s->w_frame_rad_s = f(d->frame->fobs.ws) * h->info.w_base_rad_s;
    } else {
        s->i_mr_A = f(d->frame->ifo.imr) * I;
        s->w_frame_rad_s = f(d->frame->ifo.ws_frame) * h->info.w_base_rad_s;
    }
    s->theta_e_rad = f(drive_frame_angle(&h->drive)) * IMFOC_TWO_PI;
    s->u_alpha_V = f(d->pwm->volt.valpha) * V;
    s->u_beta_V = f(d->pwm->volt.vbeta) * V;
    s->u_m_ref_V = f(d->loop->pi_id.out) * V;
    s->u_t_ref_V = f(d->loop->pi_iq.out) * V;
    for (i = 0; i < RLS_N; i++) {
        s->K[i] = f(d->id->rls.theta[i]);
    }
    s->y1 = f(d->id->reg.y1);
    s->y2 = f(d->id->reg.y2);
    s->i_mf = f(d->id->reg.i_mf);
    s->u_mf = f(d->id->reg.u_mf);
    s->i_tf = f(d->id->reg.i_tf);
    s->u_tf = f(d->id->reg.u_tf);
    s->wr_f = f(d->id->reg.wr_f);
    s->rls_updates = d->id->rls.n_updates;
    extract_si(h, &d->id->live, &s->live_Rs_ohm, &s->live_Rr_ohm, &s->live_Lm_H, &s->live_Lr_H,
               &s->live_psi_r_Wb, &s->live_Tr_s);
    /* the published set: the telemetry's, what the drive reports (not d->id->pex, which
     * with tracking is the RLS's last extraction, not what is published) */
    t = d->telemetry;
    {
        const _iq q[6] = {t->Rs, t->Rr, t->Lm, t->Lr, t->psi_r, t->Tr};
        params_si(h, q, &s->Rs_ohm, &s->Rr_ohm, &s->Lm_H, &s->Lr_H, &s->psi_r_Wb, &s->Tr_s);
    }
    s->pass = d->telemetry->pass;
    s->track_valid = d->telemetry->track_valid;
    s->params_tracked = d->telemetry->params_tracked;
    s->Rs_dc_ohm = f(d->telemetry->Rs_dc) * d->base->Z_base_ohm;
    s->sigma_ls_dc_H = f(d->telemetry->sigma_ls_dc) * d->base->L_base_H;
    s->Rr_track_ohm = f(d->telemetry->Rr_track) * d->base->Z_base_ohm;
    s->Tr_track_s = (double)_IQ20toF(d->telemetry->Tr_track) * d->base->t_base_s;   /* Q20 */
    s->extract_valid = d->id->pex.valid;
    extract_si(h, &d->id->pex, &s->extract_Rs_ohm, &s->extract_Rr_ohm, &s->extract_Lm_H,
               &s->extract_Lr_H, &s->extract_psi_r_Wb, &s->extract_Tr_s);
    s->publish_reason = t->publish_reason;
    s->conf_Rs = f(t->conf[0]);
    s->conf_Rr = f(t->conf[1]);
    s->conf_Lm = f(t->conf[2]);
    s->conf_Lr = f(t->conf[3]);
    s->conf_psi_r = f(t->conf[4]);
    s->conf_Tr = f(t->conf[5]);
    s->conf_residual = f(t->conf_residual);
    s->conf_amplification = f(t->conf_amp);
    s->conf_excitation = f(d->verdict->conf.excitation);
    return IMFOC_OK;
}

const char *imfoc_publish_reason_str(int32_t reason)
{
    return (reason >= 0 && reason <= 0xFFFF) ? drive_pub_reason_str((uint16_t)reason) : "unknown";
}
