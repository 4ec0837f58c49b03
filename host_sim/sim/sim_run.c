/* One closed-loop run: the firmware ISR against the plant.  See sim_run.h. */
#include "sim_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "drift.h"
#include "drive_limits.h"
#include "drive_probe.h"
#include "drive_static.h"
#include "standstill_lf.h"
#include "vi_curve.h"
#include "hal_host.h"
#include "sim_limits.h"

#define BACKGROUND_DIV 15u   /* background loop at 1 kHz */
#define DECIDED_GRACE_S 0.5  /* stop_when_decided: simulated time after the verdict */

static const char *const k_scen[] = {"start", "reversal", "load_steps", "soak", "drift"};

int sim_scenario_parse(const char *name, sim_scenario_t *out)
{
    unsigned i;
    for (i = 0; i < sizeof k_scen / sizeof k_scen[0]; i++) {
        if (strcmp(name, k_scen[i]) == 0) {
            *out = (sim_scenario_t)i;
            return 0;
        }
    }
    return -1;
}

const char *sim_scenario_name(sim_scenario_t s)
{
    return ((unsigned)s < sizeof k_scen / sizeof k_scen[0]) ? k_scen[s] : "unknown";
}

unsigned sim_scenario_count(void) { return (unsigned)(sizeof k_scen / sizeof k_scen[0]); }

static void params_si(const base_values_t *b, const drive_params_t *p, sim_params_t *o)
{
    o->Rs_ohm = (double)_IQtoF(p->Rs) * b->Z_base_ohm;
    o->Rr_ohm = (double)_IQtoF(p->Rr) * b->Z_base_ohm;
    o->Lm_H = (double)_IQtoF(p->Lm) * b->L_base_H;
    o->Lr_H = (double)_IQtoF(p->Lr) * b->L_base_H;
    o->psi_r_Wb = (double)_IQtoF(p->psi_r) * b->psi_base_Wb;
    o->Tr_s = (double)_IQ20toF(p->Tr) * b->t_base_s;   /* Q20 */
}

static void to_si(const base_values_t *b, const param_extract_t *p, sim_params_t *o)
{
    const drive_params_t q = {p->Rs, p->Rr, p->Lm, p->Lr, p->psi_r, p->Tr};
    params_si(b, &q, o);
}

static double pct(double est, double truth) { return 100.0 * (est - truth) / truth; }

/* Series of live estimates (100 Hz) for the convergence time. */
typedef struct {
    double t;
    sim_params_t p;
} live_row_t;

static double converge_time(const live_row_t *rows, size_t n, const sim_params_t *fin,
                            double t0)
{
    /* the last time any estimate was more than 2 % from its final value */
    double last_bad = t0;
    size_t i;
    for (i = 0; i < n; i++) {
        const sim_params_t *p = &rows[i].p;
        if (rows[i].t < t0) {
            continue;
        }
        if (fabs(pct(p->Rs_ohm, fin->Rs_ohm)) > 2.0 || fabs(pct(p->Rr_ohm, fin->Rr_ohm)) > 2.0 ||
            fabs(pct(p->Lm_H, fin->Lm_H)) > 2.0 || fabs(pct(p->Lr_H, fin->Lr_H)) > 2.0 ||
            fabs(pct(p->psi_r_Wb, fin->psi_r_Wb)) > 2.0 || fabs(pct(p->Tr_s, fin->Tr_s)) > 2.0 ||
            !isfinite(p->Rs_ohm)) {
            last_bad = rows[i].t;
        }
    }
    return last_bad - t0;
}

static void published_si(const base_values_t *b, const drive_telemetry_t *t, sim_params_t *o)
{
    const drive_params_t p = {t->Rs, t->Rr, t->Lm, t->Lr, t->psi_r, t->Tr};
    params_si(b, &p, o);
}

static void errors_pct(const sim_params_t *v, const sim_params_t *truth, sim_params_t *e)
{
    e->Rs_ohm = pct(v->Rs_ohm, truth->Rs_ohm);
    e->Rr_ohm = pct(v->Rr_ohm, truth->Rr_ohm);
    e->Lm_H = pct(v->Lm_H, truth->Lm_H);
    e->Lr_H = pct(v->Lr_H, truth->Lr_H);
    e->psi_r_Wb = pct(v->psi_r_Wb, truth->psi_r_Wb);
    e->Tr_s = pct(v->Tr_s, truth->Tr_s);
}

/* The fused set the drive judged and refused (nothing published): the
 * drive's own fused set (drive_fused_set, what it would have published), so
 * that a refusal is judged on the set it concerned, not on the RLS's own Rr
 * and Tr that the fused set does not use.  0 when there was no such set. */
static uint16_t refused_fused_si(const drive_t *drv, const drive_probe_t *d, sim_params_t *o)
{
    drive_params_t f;
    if (d->telemetry->publish_reason == (uint16_t)DRIVE_PUB_PENDING ||
        drive_fused_set(drv, &f) == 0u) {
        return 0u;
    }
    params_si(d->base, &f, o);
    return 1u;
}

static void extreme(double v, double *lo, double *hi)
{
    if (v < *lo) { *lo = v; }
    if (v > *hi) { *hi = v; }
}

/* Worst live estimate against truth (psi_r: against Lm * i_M, as extracted). */
static void live_extremes(const base_values_t *b, const param_extract_t *p,
                          const sim_params_t *truth, sim_result_t *r)
{
    sim_params_t l;
    to_si(b, p, &l);
    extreme(pct(l.Rs_ohm, truth->Rs_ohm), &r->live_min_pct, &r->live_max_pct);
    extreme(pct(l.Rr_ohm, truth->Rr_ohm), &r->live_min_pct, &r->live_max_pct);
    extreme(pct(l.Lm_H, truth->Lm_H), &r->live_min_pct, &r->live_max_pct);
    extreme(pct(l.Lr_H, truth->Lr_H), &r->live_min_pct, &r->live_max_pct);
    extreme(pct(l.Tr_s, truth->Tr_s), &r->live_min_pct, &r->live_max_pct);
}

static void observe_protection(const drive_probe_t *d, sim_result_t *r, double t)
{
    double e = (double)_IQtoF(d->prot->feedback.e_f);
    const current_model_check_t *m = &d->prot->model.cmc;
    double sls = (double)_IQtoF(m->sigma_ls), rs = (double)_IQtoF(m->rs);
    if (e > r->max_cur_check_pu) {
        r->max_cur_check_pu = e;
        r->t_max_cur_check_s = t;
    }
    /* right after each of the sequence tests' halves (the SPEED and the
     * FILTERS_B slot: a trip in either is seen before the SAFETY slot's next
     * residual clears the state with the bridge off), under the conditions
     * the check judges them in */
    const uint16_t judged = (uint16_t)(m->at_speed >= m->seq_settle &&
                                       m->model_n >= m->seq_settle);
    if (sls > 0.0 && (d->sched->slot == 1u || d->sched->slot == 3u)) {
        double ib = d->base->I_base_A;
        double rr = sqrt((double)_IQtoF(m->r2)) / sls * ib;
        double ia = (double)_IQtoF(m->i_alpha), ibt = (double)_IQtoF(m->i_beta);
        double imag = sqrt(ia * ia + ibt * ibt);
        if (rr > r->max_cmc_r_A) {
            r->max_cmc_r_A = rr;
            r->t_max_cmc_r_s = t;
        }
        {
            /* each test against the level it was compared with (the check keeps
             * them): abs(r) against MISMATCH's with the back-EMF allowance; at
             * speed the part the positive sequence has not followed against the
             * level without it, UNBALANCE, OFFSET */
            double thr_all = (double)_IQtoF(m->thr) + (double)_IQtoF(m->r_allow_emf);
            double u = (thr_all > 0.0) ? sqrt((double)_IQtoF(m->r2)) / thr_all : 0.0;
            if (judged) {
                if (m->thr > 0) {
                    u = fmax(u, sqrt((double)_IQtoF(m->q2)) / (double)_IQtoF(m->thr));
                }
                if (m->neg_level2 > 0 && m->dc_level2 > 0) {
                    double un = sqrt((double)_IQtoF(m->neg2) / (double)_IQtoF(m->neg_level2));
                    double ud = sqrt((double)_IQtoF(m->dc2) / (double)_IQtoF(m->dc_level2));
                    if (un > r->max_cmc_util_neg) {
                        r->max_cmc_util_neg = un;
                    }
                    if (ud > r->max_cmc_util_dc) {
                        r->max_cmc_util_dc = ud;
                    }
                }
            }
            if (m->active != 0u && u > r->max_cmc_util_r) {
                r->max_cmc_util_r = u;
            }
        }
        if (judged && imag > 0.05) {
            double neg = sqrt((double)_IQtoF(m->neg2)) / sls / imag;
            if (neg > r->max_cmc_neg) {
                r->max_cmc_neg = neg;
                r->t_max_cmc_neg_s = t;
            }
            if (rs > 0.0) {
                /* d_max_tau / d_max = tau_r (pu time) */
                double dc = sqrt((double)_IQtoF(m->dc2)) / (rs * d->prot->model.tau_r_pu) * ib;
                if (dc > r->max_cmc_dc_A) {
                    r->max_cmc_dc_A = dc;
                    r->t_max_cmc_dc_s = t;
                }
            }
        }
    }
}

/* Control-path flags after the magnetisation, and the RLS estimate range. */
static void observe_soak(const drive_probe_t *d, sim_result_t *r, double t)
{
    uint16_t i;
    if (d->seq->state == ID_ACCELERATE && d->sense->bus.vdc > 0) {
        double head = (double)_IQtoF(d->target->u_f) / ((double)_IQtoF(d->sense->bus.vdc) / sqrt(3.0));
        if (head > r->max_volt_head) {
            r->max_volt_head = head;
        }
    }
    if (d->seq->state == ID_ACCELERATE || d->seq->state == ID_SETTLE || d->seq->state == ID_RUN) {
        if (d->pwm->svgen.overmod != 0u) {
            if (r->n_overmod == 0u) {
                r->t_first_overmod_s = t;
            }
            r->t_last_overmod_s = t;
            r->n_overmod++;
        }
        if (d->loop->pi_id.sat != 0u || d->loop->pi_iq.sat != 0u) { r->n_current_pi_sat++; }
        if (d->frame->ifo.imr_low != 0u) { r->n_imr_low++; }
        if (d->sense->qep.speed_raw >= _IQmpyI32(d->sense->qep.k_speed, d->sense->qep.d_max) ||
            d->sense->qep.speed_raw <= -_IQmpyI32(d->sense->qep.k_speed, d->sense->qep.d_max)) {
            r->n_speed_sat++;
        }
    }
    for (i = 0u; i < RLS_N; i++) {
        double a = fabs((double)_IQtoF(d->id->rls.theta[i]));
        if (a > r->max_abs_theta) {
            r->max_abs_theta = a;
        }
    }
}

/* Voltage reconstruction against the bridge (dead-time compensation): the drive's
 * alpha-beta voltage of the period that just ended (volt_calc, after this
 * ISR) minus the plant's period-average voltage of that same period, split
 * along and across the period-mean current, averaged over the steady state
 * (SETTLE and RUN: constant speed, so the mean is the bias of the
 * fundamental).  Along the current it acts as a resistance error. */
static void observe_voltage(const drive_probe_t *d, const plant_t *p, double V_base_V, sim_result_t *r)
{
    const inverter_t *inv = &p->inv;
    double ia, ib, im, ea, eb;
    if (d->seq->state != ID_SETTLE && d->seq->state != ID_RUN) {
        return;
    }
    /* period-mean current: the start of the period (phase currents held by
     * the inverter, Clarke-transformed) and now (the motor's state vector) */
    ia = 0.5 * (inv->i_A[0] + p->motor.i_alpha_A);
    ib = 0.5 * ((inv->i_A[1] - inv->i_A[2]) / sqrt(3.0) + p->motor.i_beta_A);
    im = sqrt(ia * ia + ib * ib);
    if (im < 1e-6) {
        return;
    }
    ea = (double)_IQtoF(d->pwm->volt.valpha) * V_base_V - inv->v_alpha_V;
    eb = (double)_IQtoF(d->pwm->volt.vbeta) * V_base_V - inv->v_beta_V;
    r->v_err_along_i_V += (ea * ia + eb * ib) / im;
    r->v_err_across_i_V += (eb * ia - ea * ib) / im;
    r->i_mag_steady_A += im;
    r->n_v_err++;
}

static int trace_header(FILE *f)
{
    return fprintf(f, "t_s,state,fault,pwm_on,speed_ref_rpm,speed_rpm,speed_meas_rpm,i_m_A,i_t_A,"
               "ia_A,ib_A,u_m_V,u_t_V,vdc_V,Te_Nm,TL_Nm,psi_r_true_Wb,psi_rq_over_d,"
               "Rs_ohm,Rr_ohm,Lm_H,Lr_H,psi_r_Wb,Tr_s,est_valid,"
               "K1,K2,K3,K4,"
               /* appended (tools/batch_ls.py): the RLS regression, pu, method §2 */
               "rls_on,y1,y2,i_mf,u_mf,i_tf,u_tf,wr_f,"
               /* appended (adaptive sequence): the plant's Rr, the drive's tracking and
                * adaptation telemetry */
               "Rr_true_ohm,Rr_track_ohm,track_valid,pass,Rs_dc_ohm,Tr_track_s,"
               /* appended (ident.period_mean = 1; 0 otherwise): the rows' flux columns */
               "m_mf,m_tf,wm_tf\n");
}

/* The appended columns of a trace row, and its end. */
static int trace_row_adaptation(FILE *f, const drive_probe_t *d, const plant_t *p)
{
    const drive_telemetry_t *t = d->telemetry;
    double z = d->base->Z_base_ohm;
    return fprintf(f, ",%.6g,%.6g,%u,%u,%.6g,%.6g,%.9g,%.9g,%.9g\n", p->motor.p.Rr_ohm,
                   (double)_IQtoF(t->Rr_track) * z, t->track_valid, t->pass,
                   (double)_IQtoF(t->Rs_dc) * z, (double)_IQ20toF(t->Tr_track) * d->base->t_base_s,
                   (double)_IQtoF(d->id->reg.m_mf), (double)_IQtoF(d->id->reg.m_tf),
                   (double)_IQtoF(d->id->reg.wm_tf));
}

double sim_vi_test_s(const sim_config_t *c)
{
    const sim_nameplate_t *n = &c->nameplate;
    if (c->controller.dead_time_comp == 0.0 || c->ident.vi_test == 0.0) {
        return 0.0;
    }
    return (double)vi_curve_duration_s((float)((double)DRIVE_SLOTS / c->board.pwm_freq_Hz),
                                       (float)((n->Lm_H + n->Llr_H) / n->Rr_ohm)) + 0.1;
}

/* Simulated time when none is given: calibration (with the bridge's
 * voltage-error test), magnetisation, the ramp
 * and the longest SETTLE (3 s), once per pass (a later pass slows down and
 * accelerates again), then what the scenario does after the identification.
 * The drift scenario ends earlier, when its window is over (sim_run). */
/* The standstill sequence's injection (drive_static.c's set-up), s; 0 if
 * the drive would refuse it. */
static double static_inject_s(const sim_config_t *c)
{
    const sim_nameplate_t *n = &c->nameplate;
    const double ts_slow = (double)DRIVE_SLOTS / c->board.pwm_freq_Hz;
    const double im_pu = c->controller.magnetizing_current_A / c->board.current_full_scale_A;
    standstill_lf_t z;
    if (standstill_lf_init(&z, (float)ts_slow, (float)((n->Lm_H + n->Llr_H) / n->Rr_ohm),
                           (float)(DRIVE_STATIC_AMPL_OF_IM * im_pu), (float)im_pu,
                           DRIVE_STATIC_WINDOW_S, DRIVE_SLOTS_LOG2) != STANDSTILL_LF_OK) {
        return 0.0;
    }
    return (double)standstill_lf_samples(&z) * ts_slow;
}

static double default_duration_s(const sim_config_t *c, sim_scenario_t s)
{
    double ident = 0.1 + c->ident.magnetize_s +
                   sim_config_target_rpm(c) / c->controller.speed_ramp_rpm_s + 3.2;
    double d = ident * c->ident.passes + sim_vi_test_s(c);
    if (c->ident.static_id != 0.0) {
        /* nothing turns: the magnetisation (with its wait for the standstill
         * set), the injection, the background's fit */
        d = 0.1 + c->ident.magnetize_s + 0.5 + static_inject_s(c) + sim_vi_test_s(c) + 0.5;
    }
    if (c->ident.track_rr != 0.0) {
        /* the fused set: the tracker valid once it has forgotten RUN's start
         * (tr_track_settle_s, as drive_init), then its fit judged for 0.5 s */
        const sim_nameplate_t *n = &c->nameplate;
        d += (double)tr_track_settle_s((float)c->ident.track_memory_s,
                                       (float)((n->Lm_H + n->Llr_H) / n->Rr_ohm)) + 1.0;
    }
    if (s == SCEN_DRIFT) {
        return d + c->drift.start_s + c->drift.ramp_s + DRIFT_TAIL_S;
    }
    /* the start scenario ends at the verdict: its time-out also allows the
     * bridge's test to run twice (drive_vi.c: a second test when the first
     * one's current levels were inside the transition) */
    return (s != SCEN_START) ? d + 2.5 : d + sim_vi_test_s(c);
}

uint64_t sim_trace_every(const sim_config_t *c, const sim_options_t *opt)
{
    uint64_t n;
    if (opt->trace_every > 0u) {
        return opt->trace_every;
    }
    n = (uint64_t)(c->board.pwm_freq_Hz /
                   ((opt->trace_rate_Hz > 0.0) ? opt->trace_rate_Hz : 1000.0));
    return (n == 0u) ? 1u : n;
}

double sim_trace_bytes(const sim_config_t *c, double duration_s, uint64_t every)
{
    uint64_t rows = (sim_run_periods(c, duration_s) + every - 1u) / every;
    return SIM_TRACE_HEADER_BYTES + SIM_TRACE_ROW_BYTES * (double)rows;
}

double sim_run_duration_s(const sim_config_t *c, const sim_options_t *opt)
{
    return (opt->duration_s > 0.0) ? opt->duration_s : default_duration_s(c, opt->scenario);
}

uint64_t sim_run_periods(const sim_config_t *c, double duration_s)
{
    return (uint64_t)(duration_s * c->board.pwm_freq_Hz + 0.5);
}

/* The identification is complete: RUN after the last pass (a sequence of
 * several passes may go through RUN between them; pass 0 is a firmware
 * without passes, i.e. one). */
static int ident_complete(const drive_probe_t *d, const sim_config_t *c)
{
    double pass = (d->telemetry->pass == 0u) ? 1.0 : (double)d->telemetry->pass;
    return d->telemetry->state == ID_RUN && pass >= c->ident.passes;
}

/* The drift scenario in one PWM period: start it when the identification
 * is complete, set the plant's Rr and load, observe the window.  The motor
 * model derives nothing from Rr (it reads p.Rr_ohm in every derivative), so
 * setting it between two periods is exactly a step of the parameter. */
static void drift_period(drift_t *dr, const drive_probe_t *d, const sim_config_t *c, plant_t *p,
                         double t, double psi_d, double psi_q)
{
    if (dr->t0_s < 0.0 && ident_complete(d, c)) {
        drift_begin(dr, t);
    }
    p->motor.p.Rr_ohm = drift_rr_ohm(dr, t);
    p->extra_load_Nm = drift_extra_load_Nm(dr, t);
    if (drift_in_window(dr, t)) {
        drift_obs_t o;
        o.psi_d_Wb = psi_d;
        o.psi_q_Wb = psi_q;
        o.speed_err_rpm =
            (double)_IQtoF(d->loop->speed_ramp.out) * d->base->n_base_rpm - p->motor.n_rpm;
        o.rr_true_ohm = p->motor.p.Rr_ohm;
        o.rr_track_ohm = (double)_IQtoF(d->telemetry->Rr_track) * d->base->Z_base_ohm;
        o.track_valid = d->telemetry->track_valid;
        drift_observe(dr, &o);
    }
}

/* The publication's verdict and the confidences at the end of the run (%). */
static void conf_figures(const drive_probe_t *d, sim_result_t *r)
{
    const ident_conf_t *c = &d->verdict->conf;
    unsigned i;
    for (i = 0; i < 6u; i++) {
        double v = (double)_IQtoF(d->telemetry->conf[i]);
        r->conf_pct[i] = (v < 0.0) ? -1.0 : 100.0 * v;
        r->bound_pct[i] = 100.0 * (double)_IQtoF(c->bound[i]);
        r->drift_pct[i] = 100.0 * (double)_IQtoF(c->drift[i]);
    }
    r->conf_residual = (double)_IQtoF(d->telemetry->conf_residual);
    r->conf_amp = (double)_IQtoF(d->telemetry->conf_amp);
    r->conf_samples = d->id->snap_acc.n;
    r->conf_excitation = (double)_IQtoF(c->excitation);
    r->conf_pd = d->id->snap_pd;
}

/* One run's state: the drive, the plant and the host HAL between them, the
 * trace, and what the observers carry from one period to the next. */
typedef struct {
    const sim_config_t *cfg;
    const sim_options_t *opt;
    sim_result_t *res;
    drive_t *drive;             /* the firmware's instance (static in sim_run: large) */
    drive_probe_t pv;           /* what the simulator reads of it */
    const base_values_t *b;
    plant_t plant;
    hal_host_port_t port;
    hal_pwm_compare_t active;   /* the compares the plant runs this period */
    double Ts, duration;
    FILE *trace;
    uint64_t trace_div;         /* one trace row every trace_div periods */
    double trace_bytes;         /* written so far (the size guard) */
    int trace_full;             /* 1: cut at the size limit, 2: and its close failed */
    live_row_t *rows;           /* the live estimates at 100 Hz (the convergence time) */
    size_t n_rows, cap_rows;
    drift_t drift;
    uint16_t fault_applied[SIM_MAX_FAULTS];
    uint16_t cmd_given[SIM_MAX_CMDS];
    double t_run;               /* RUN first entered (-1: not yet) */
    double t_soak_rev, t_soak_load;
    int pub_seen, scen_done;
    uint16_t last_fault, prev_state;
} sim_ctx_t;

static void result_defaults(sim_result_t *res)
{
    unsigned i;
    memset(res, 0, sizeof *res);
    res->converge_s = -1.0;
    res->t_fault_visible_s = -1.0;
    res->t_first_published_s = -1.0;
    res->t_first_overmod_s = -1.0;
    res->t_last_overmod_s = -1.0;
    res->t_accel_start_s = -1.0;
    res->plant_diverged_at_s = -1.0;
    res->trace_truncated_at_s = -1.0;
    res->t_over_trip_first_s = -1.0;
    res->t_over_trip_last_s = -1.0;
    res->max_pub_err_after_fault_pct = -1.0;
    for (i = 0; i < SIM_MAX_FAULTS; i++) {
        res->t_injected_s[i] = -1.0;
    }
    for (i = 0; i < SIM_STATES; i++) {
        res->t_state_s[i] = -1.0;
    }
    res->t_decided_s = -1.0;
}

/* The drive, the plant, the HAL, the buffers and the trace.  0, or the
 * sim_run error code with @p err set. */
static int run_open(sim_ctx_t *c, char *err, unsigned err_len)
{
    const sim_config_t *cfg = c->cfg;
    sim_result_t *res = c->res;
    drive_config_t dc;
    int16_t st;

    sim_config_to_drive(cfg, &dc);
    st = drive_init(c->drive, &dc);
    if (st != DRIVE_CFG_OK) {
        /* sim_config_load refuses such a file; a test may set the values */
        drive_limit_fail_t f;
        char why[SIM_CONFIG_ERR_LEN];
        if (drive_config_check(&dc, &f) != DRIVE_CFG_OK) {
            sim_limit_message(why, sizeof why, &f);
        } else {
            snprintf(why, sizeof why, "a limit include/drive_limits.h does not hold");
        }
        snprintf(err, err_len, "drive_init rejected the configuration: %s: %s",
                 drive_cfg_status_str(st), why);
        return 1;
    }
    if (plant_init(&c->plant, cfg, c->pv.k->t1pr, err, err_len) != 0) {
        return 2;
    }
    hal_host_port_init(&c->port, c->pv.k->t1pr);
    hal_host_bind(&c->port);
    c->active = c->port.cmp;

    c->Ts = 1.0 / cfg->board.pwm_freq_Hz;
    c->duration = sim_run_duration_s(cfg, c->opt);
    res->duration_s = c->duration;
    c->trace_div = sim_trace_every(cfg, c->opt);
    c->cap_rows = (size_t)(c->duration * 100.0) + 16;
    c->rows = (live_row_t *)calloc(c->cap_rows, sizeof *c->rows);
    if (c->rows == NULL) {
        snprintf(err, err_len, "out of memory");
        return 3;
    }
    if (drift_init(&c->drift, cfg, (c->opt->scenario == SCEN_DRIFT) ? c->duration : 0.0) != 0) {
        snprintf(err, err_len, "out of memory");
        free(c->rows);
        return 3;
    }
    if (c->opt->trace_path != NULL) {
        c->trace = fopen(c->opt->trace_path, "w");
        if (c->trace == NULL) {
            snprintf(err, err_len, "cannot write %s", c->opt->trace_path);
            free(c->rows);
            drift_free(&c->drift);
            return 4;
        }
        c->trace_bytes += (double)trace_header(c->trace);
    }
    res->truth.Rs_ohm = cfg->plant.Rs_ohm;
    res->truth.Rr_ohm = cfg->plant.Rr_ohm;
    res->truth.Lm_H = cfg->plant.Lm_H;
    res->truth.Lr_H = cfg->plant.Lm_H + cfg->plant.Llr_H;
    res->truth.Tr_s = res->truth.Lr_H / cfg->plant.Rr_ohm;
    return 0;
}

/* The faults and commands due at @p t (--fault, --cmd). */
static void inject_events(sim_ctx_t *c, double t)
{
    const sim_options_t *opt = c->opt;
    unsigned i;
    for (i = 0; i < opt->n_faults; i++) {
        const sim_fault_t *f = &opt->faults[i];
        const double t0 = (f->at_state == 0u)
                              ? 0.0
                              : ((f->at_state < SIM_STATES) ? c->res->t_state_s[f->at_state]
                                                            : -1.0);
        if (!c->fault_applied[i] && t0 >= 0.0 && t >= t0 + f->t_s) {
            plant_inject(&c->plant, f->kind, f->value);
            c->fault_applied[i] = 1u;
            c->res->t_injected_s[i] = t;
        }
    }
    for (i = 0; i < opt->n_cmds; i++) {
        if (!c->cmd_given[i] && t >= opt->cmds[i].t_s) {
            if (opt->cmds[i].cmd == DRIVE_CMD_RESET_FAULT) {
                (void)hal_host_clear_trip(&c->port);   /* the board's latch first (main.c) */
            }
            drive_command(c->drive, (drive_cmd_t)opt->cmds[i].cmd);
            c->cmd_given[i] = 1u;
        }
    }
}

/* Period start: ADC and QEP, the control ISR, its slow ISR and, every
 * BACKGROUND_DIV periods, the background.  1 when the background hook ends
 * the run. */
static int run_firmware(sim_ctx_t *c, uint64_t period, double t)
{
    plant_sample(&c->plant, &c->port);
    c->port.trip_input = plant_trip_line(&c->plant);
    drive_isr(c->drive);
    drive_slow_isr(c->drive);   /* the target's INT14, right after (hal_slow_isr_request) */
    if ((period % BACKGROUND_DIV) == 0u) {
        drive_background(c->drive);
        if (c->opt->background_hook != NULL &&
            c->opt->background_hook(c->opt->hook_ctx, c->drive, period + 1u, t) != 0) {
            c->res->duration_s = t;   /* ended by the hook (the serial link closed) */
            return 1;
        }
    }
    return 0;
}

/* The extraction and the verdict; 1 when the run has told what it can
 * (stop_when_decided). */
static int observe_verdict(sim_ctx_t *c, double t)
{
    const drive_probe_t *d = &c->pv;
    sim_result_t *res = c->res;
    if (d->telemetry->fault != 0u && c->port.outputs_enabled != 0u) {
        res->pwm_periods_with_fault++;
    }
    if ((d->seq->extract_now != 0u && d->seq->pass >= d->seq->passes) ||
        d->seq->static_done != 0u) {
        res->extracted = 1u;   /* (the standstill sequence: its fit is the extraction) */
    }
    if (res->t_decided_s < 0.0 && d->verdict->run != 0u &&
        d->telemetry->publish_reason != (uint16_t)DRIVE_PUB_PENDING) {
        res->t_decided_s = t;
    }
    if (c->opt->stop_when_decided != 0u && res->t_decided_s >= 0.0 &&
        t >= res->t_decided_s + DECIDED_GRACE_S) {
        res->duration_s = t;   /* the verdict is in */
        return 1;
    }
    return 0;
}

/* The published set: when it first came, whether it changed, the live
 * estimates' extremes, its error after a fault. */
static void observe_publication(sim_ctx_t *c, double t)
{
    const drive_probe_t *d = &c->pv;
    sim_result_t *res = c->res;
    sim_params_t pub;
    if (d->telemetry->params_valid == 0u) {
        return;
    }
    published_si(c->b, d->telemetry, &pub);
    if (!c->pub_seen) {
        c->pub_seen = 1;
        res->t_first_published_s = t;
        res->published_first = pub;
    } else if (memcmp(&pub, &res->published_first, sizeof pub) != 0) { /* NOLINT */
        /* bitwise on purpose (hence the NOLINT): any change of a
         * published word counts */
        res->published_changed = 1u;
    }
    if (d->id->live.valid != 0u) {
        live_extremes(c->b, &d->id->live, &res->truth, res);
    }
    if (res->n_faults_seen > 0u && t >= res->fault_time_s[0] + 0.002) {
        double w = fabs(pct(pub.Rs_ohm, res->truth.Rs_ohm));
        w = fmax(w, fabs(pct(pub.Rr_ohm, res->truth.Rr_ohm)));
        w = fmax(w, fabs(pct(pub.Lm_H, res->truth.Lm_H)));
        w = fmax(w, fabs(pct(pub.Lr_H, res->truth.Lr_H)));
        w = fmax(w, fabs(pct(pub.Tr_s, res->truth.Tr_s)));
        if (res->truth.psi_r_Wb > 0.0) {
            w = fmax(w, fabs(pct(pub.psi_r_Wb, res->truth.psi_r_Wb)));
        }
        res->max_pub_err_after_fault_pct = fmax(res->max_pub_err_after_fault_pct, w);
    }
}

/* One trace row (the columns of trace_header). */
static void trace_row(sim_ctx_t *c, double t, uint16_t state, double pd, double pq)
{
    const drive_probe_t *d = &c->pv;
    const base_values_t *b = c->b;
    const motor_t *m = &c->plant.motor;
    const double rpm_per_pu = b->n_base_rpm;
    sim_params_t lp;
    to_si(b, &d->id->live, &lp);
    c->trace_bytes += (double)fprintf(c->trace,
            "%.5f,%u,%u,%u,%.3f,%.3f,%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.4f,%.5f,"
            "%.5f,%.6f,%.6f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%u,%.6g,%.6g,%.6g,%.6g,"
            "%u,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g",
            t, state, d->telemetry->fault, d->telemetry->pwm_on,
            (double)_IQtoF(d->loop->speed_ramp.out) * rpm_per_pu, m->n_rpm,
            (double)_IQtoF(d->sense->qep.speed) * rpm_per_pu,
            (double)_IQtoF(d->loop->park.ds) * b->I_base_A,
            (double)_IQtoF(d->loop->park.qs) * b->I_base_A, m->ia_A, m->ib_A,
            (double)_IQtoF(d->id->reg.u_mf) * b->V_base_V,
            (double)_IQtoF(d->id->reg.u_tf) * b->V_base_V,
            (double)_IQtoF(d->sense->bus.vdc) * b->V_base_V, m->Te_Nm, m->TL_Nm,
            sqrt(pd * pd + pq * pq), (pd > 1e-9) ? pq / pd : 0.0, lp.Rs_ohm,
            lp.Rr_ohm, lp.Lm_H, lp.Lr_H, lp.psi_r_Wb, lp.Tr_s, d->id->live.valid,
            (double)_IQtoF(d->id->rls.theta[0]), (double)_IQtoF(d->id->rls.theta[1]),
            (double)_IQtoF(d->id->rls.theta[2]), (double)_IQtoF(d->id->rls.theta[3]),
            d->seq->rls_on, (double)_IQtoF(d->id->reg.y1),
            (double)_IQtoF(d->id->reg.y2), (double)_IQtoF(d->id->reg.i_mf),
            (double)_IQtoF(d->id->reg.u_mf), (double)_IQtoF(d->id->reg.i_tf),
            (double)_IQtoF(d->id->reg.u_tf), (double)_IQtoF(d->id->reg.wr_f));
    c->trace_bytes += (double)trace_row_adaptation(c->trace, d, &c->plant);
    if (c->opt->trace_max_bytes > 0.0 && c->trace_bytes > c->opt->trace_max_bytes) {
        /* the trace ends here, the run goes on (motor_sim sizes the trace
         * before a run of known length so that this is not reached; a
         * serial-link session has none) */
        c->trace_full = 1;
        c->res->trace_truncated_at_s = t;
        if (fclose(c->trace) != 0) {
            c->trace_full = 2;
        }
        c->trace = NULL;
    }
}

/* The motor at the sample instant, in the firmware's frame (theta_k): the
 * true currents against the trip, the states' times, the flux's alignment,
 * the speed error, the faults; the live series and the trace.  The true
 * rotor flux in the drive's frame into @p psi_d, @p psi_q. */
static void observe_sample(sim_ctx_t *c, uint64_t period, double t, double *psi_d, double *psi_q)
{
    const drive_probe_t *d = &c->pv;
    sim_result_t *res = c->res;
    const motor_t *m = &c->plant.motor;
    double ia = fabs(m->ia_A), ib = fabs(m->ib_A), ic = fabs(m->ic_A);
    double imax = fmax(ia, fmax(ib, ic));
    /* the frame angle of this sample, theta_k (ifo or observer) */
    double th = (double)_IQtoF(drive_frame_angle(c->drive)) * 2.0 * M_PI;
    double pd, pq;
    uint16_t state = d->telemetry->state;
    motor_rotor_flux_dq(m, th, &pd, &pq);
    *psi_d = pd;
    *psi_q = pq;
    if (imax > res->max_abs_i_A) {
        res->max_abs_i_A = imax;
    }
    if (imax > c->cfg->controller.overcurrent_A) {
        if (res->t_over_trip_first_s < 0.0) {
            res->t_over_trip_first_s = t;
        }
        res->t_over_trip_last_s = t;
        res->over_trip_s += c->Ts;
    }
    if (state < SIM_STATES && res->t_state_s[state] < 0.0) {
        res->t_state_s[state] = t;
    }
    if (state == ID_ACCELERATE && c->prev_state != ID_ACCELERATE && res->t_accel_start_s < 0.0) {
        res->t_accel_start_s = t;
    }
    if ((state == ID_ACCELERATE || state == ID_SETTLE || state == ID_RUN) && pd > 1e-6) {
        double r = fabs(pq / pd);
        if (r > res->max_flux_q_over_d) {
            res->max_flux_q_over_d = r;
        }
    }
    if (state == ID_ACCELERATE && res->t_accel_start_s >= 0.0 &&
        t > res->t_accel_start_s + 0.2) {
        double e = fabs((double)_IQtoF(d->loop->speed_ramp.out) * c->b->n_base_rpm - m->n_rpm);
        if (e > res->max_speed_err_rpm_ramp) {
            res->max_speed_err_rpm_ramp = e;
        }
    }
    if (state == ID_INJECT && c->prev_state != ID_INJECT) {
        /* the standstill sequence: the flux at the end of the magnetisation,
         * i_M at its reference for >= 5 Tr (psi_r = Lm i_M, as extracted) */
        res->truth.psi_r_Wb = sqrt(pd * pd + pq * pq);
    }
    if (state == ID_RUN && c->prev_state != ID_RUN) {
        c->t_run = t;
        res->t_published_s = t;
        res->truth.psi_r_Wb = sqrt(pd * pd + pq * pq);
        res->settle_timeout = d->seq->settle_timeout;
        res->target_rpm = (double)_IQtoF(d->seq->speed_target) * c->b->n_base_rpm;
    }
    if (d->telemetry->fault != 0u && d->telemetry->fault != c->last_fault &&
        res->n_faults_seen < SIM_MAX_FAULTS) {
        res->fault_code[res->n_faults_seen] = d->telemetry->fault;
        res->fault_time_s[res->n_faults_seen] = t;
        res->fault_state[res->n_faults_seen] = c->prev_state;
        res->fault_pass[res->n_faults_seen] = d->seq->pass;
        /* the model check's cause bits, and the feedback check as 8 */
        res->fault_cause[res->n_faults_seen] =
            (uint16_t)(d->prot->model.cmc.cause | ((d->prot->feedback.fault != 0u) ? 8u : 0u));
        res->n_faults_seen++;
    }
    c->last_fault = d->telemetry->fault;
    c->prev_state = state;

    if ((period % (uint64_t)(c->cfg->board.pwm_freq_Hz / 100.0)) == 0u && c->n_rows < c->cap_rows) {
        c->rows[c->n_rows].t = t;
        to_si(c->b, &d->id->live, &c->rows[c->n_rows].p);
        c->n_rows++;
    }
    if (c->trace != NULL && (period % c->trace_div) == 0u) {
        trace_row(c, t, state, pd, pq);
    }
}

/* The scenario's events after the identification (--scenario); 1 when the
 * drift scenario's window ends the run. */
static int scenario_events(sim_ctx_t *c, double t, double psi_d, double psi_q)
{
    const sim_config_t *cfg = c->cfg;
    const sim_options_t *opt = c->opt;
    const drive_probe_t *d = &c->pv;
    if (c->t_run >= 0.0 && opt->scenario == SCEN_SOAK) {
        /* each event from a settled state: the load step 2 s after each
         * reversal (the 1.4 s ramp is over); a step at the end of a
         * reversal at rated speed reaches the 60 V bus's voltage limit */
        if (c->t_soak_rev < 0.0) {
            c->t_soak_rev = c->t_run;
            c->t_soak_load = c->t_run - 1.0;
        }
        if (t >= c->t_soak_rev + 4.0) {
            double e = fabs((double)_IQtoF(d->loop->speed_ramp.out) * c->b->n_base_rpm -
                            c->plant.motor.n_rpm);
            if (e > c->res->max_settled_speed_err_rpm) {
                c->res->max_settled_speed_err_rpm = e;
            }
            drive_set_speed(c->drive, -d->seq->speed_target);
            c->t_soak_rev = t;
        }
        if (t >= c->t_soak_load + 4.0) {
            c->t_soak_load = t;
        }
        c->plant.extra_load_Nm = (t < c->t_soak_load + 1.0 && t >= c->t_soak_load)
                                     ? 0.5 * (cfg->load.const_Nm + cfg->load.fan_Nm)
                                     : 0.0;
    }
    if (opt->scenario == SCEN_DRIFT) {
        drift_period(&c->drift, d, cfg, &c->plant, t, psi_d, psi_q);
        if (opt->duration_s <= 0.0 && c->drift.t0_s >= 0.0 && t >= drift_end_s(&c->drift)) {
            c->res->duration_s = t;   /* the default run ends with the window */
            return 1;
        }
    }
    if (c->t_run >= 0.0 && !c->scen_done) {
        if (opt->scenario == SCEN_REVERSAL && t >= c->t_run + 0.5) {
            drive_set_speed(c->drive, -d->seq->speed_target);
            c->scen_done = 1;
        } else if (opt->scenario == SCEN_LOAD_STEPS && t >= c->t_run + 0.5) {
            c->plant.extra_load_Nm = (t < c->t_run + 1.5) ? 0.5 * (cfg->load.const_Nm +
                                                                   cfg->load.fan_Nm)
                                                          : 0.0;
            c->scen_done = (t >= c->t_run + 1.5);
        }
    }
    return 0;
}

/* One PWM period of the plant: the compare values written by the ISR of
 * this period's start are loaded at this underflow; the output enable acts
 * at once.  1 when the plant diverged (nothing after it is a result). */
static int plant_step(sim_ctx_t *c, double t)
{
    plant_period(&c->plant, &c->active, c->port.outputs_enabled);
    if (c->plant.hw_fired != 0u) {
        hal_host_pdpinta_pulse(&c->port);   /* the bridge's comparator pulled PDPINTA */
    }
    c->active = c->port.cmp;
    if (!plant_finite(&c->plant)) {
        c->res->plant_diverged_at_s = t + c->Ts;
        return 1;
    }
    return 0;
}

/* The run's figures from the drive and the plant at its end. */
static void run_results(sim_ctx_t *c)
{
    const drive_probe_t *d = &c->pv;
    const base_values_t *b = c->b;
    const plant_t *plant = &c->plant;
    sim_result_t *res = c->res;
    if (res->n_v_err > 0u) {
        res->v_err_along_i_V /= (double)res->n_v_err;
        res->v_err_across_i_V /= (double)res->n_v_err;
        res->i_mag_steady_A /= (double)res->n_v_err;
    }
    res->final_speed_rpm = plant->motor.n_rpm;
    if (c->t_run < 0.0) {
        res->target_rpm = (double)_IQtoF(d->seq->speed_target) * b->n_base_rpm;
    }
    res->target_lowered = d->seq->target_lowered;
    res->max_true_phase_A = plant->i_phase_peak_A;
    res->max_true_leg_A = plant->i_leg_peak_A;
    res->rotor_turn_counts = plant->turn_peak_rad * 4.0 * c->cfg->board.encoder_lines / (2.0 * M_PI);
    res->locked_torque_peak_Nm = plant->te_hold_peak_Nm;
    res->hw_trips = plant->hw_trips;
    res->t_hw_trip_s = plant->t_hw_first_s;
    res->final_state = d->telemetry->state;
    res->final_fault = d->telemetry->fault;
    res->final_pwm_on = c->port.outputs_enabled;
    res->t_fault_visible_s = plant->t_visible_s;
    res->rls_sat_count = d->id->rls.sat_count;
    res->rls_pd_count = d->id->rls.pd_count;
    res->theta_rejects = d->id->guard.reject_count;
    res->publish_rejects = d->telemetry->publish_rejects;
    res->publish_reason = d->telemetry->publish_reason;
    res->identified = (uint16_t)(d->telemetry->params_valid != 0u &&
                                 res->publish_reason == (uint16_t)DRIVE_PUB_PUBLISHED);
    res->params_withdrawn = d->telemetry->params_withdrawn;
    res->withdraw_reason = d->telemetry->withdraw_reason;
    res->final_pass = d->telemetry->pass;
    conf_figures(d, res);
    res->Rs_dc_ohm = (double)_IQtoF(d->telemetry->Rs_dc) * b->Z_base_ohm;
    res->sensor_gain_pct = 100.0 * (double)d->verdict->sensor_gain;
    res->adapt_timeouts = d->seq->adapt_timeouts;
    vi_curve_fit(&d->vi->test, b->I_base_A, b->V_base_V, &res->vi);
    if (res->vi.status == VI_FIT_OK) {
        res->vi.status = (vi_fit_status_t)d->vi->status;   /* the drive's own checks */
    }
    res->vi_true_e_pole_V = plant->inv.p.vdc_V * plant->inv.td_frac + plant->inv.v_drop_V;
    res->vi_true_band_A = plant->inv.p.i_band_A;
    res->vi_i1_A = (double)d->vi->test.i1 * b->I_base_A;
    res->vi_retried = (int)d->vi->retried;
    drift_figures(&c->drift, res);
    if (res->identified) {
        published_si(b, d->telemetry, &res->published_end);
        res->params_tracked = d->telemetry->params_tracked;
        errors_pct(&res->published_end, &res->truth, &res->published_end_error_pct);
    } else {
        res->refused_fused = refused_fused_si(c->drive, d, &res->refused_set);
        if (res->refused_fused != 0u) {
            errors_pct(&res->refused_set, &res->truth, &res->refused_set_error_pct);
        }
    }
    if (res->extracted) {
        /* the RLS's last extraction, published or refused (the paper's method) */
        to_si(b, &d->id->pex, &res->ident);
        res->ident_valid = d->id->pex.valid;
        errors_pct(&res->ident, &res->truth, &res->error_pct);
        if (res->t_accel_start_s >= 0.0 && d->id->pex.valid != 0u) {
            res->converge_s = converge_time(c->rows, c->n_rows, &res->ident, res->t_accel_start_s);
        }
    }
}

/* Frees the buffers and closes the trace: 0, or 4 with @p err set when the
 * trace could not be written whole. */
static int run_close(sim_ctx_t *c, char *err, unsigned err_len)
{
    free(c->rows);
    drift_free(&c->drift);
    if (c->trace != NULL) {
        /* a full disk must not pass for a complete trace */
        int write_failed = ferror(c->trace);
        if (fclose(c->trace) != 0 || write_failed != 0) {
            snprintf(err, err_len, "error writing %s", c->opt->trace_path);
            return 4;
        }
    }
    if (c->trace_full == 2) {
        snprintf(err, err_len, "error writing %s", c->opt->trace_path);
        return 4;
    }
    return 0;
}

int sim_run(const sim_config_t *cfg, const sim_options_t *opt, sim_result_t *res, char *err,
            unsigned err_len)
{
    static drive_t drive;   /* large; one run at a time */
    static sim_ctx_t ctx;   /* (the plant and the port are large too) */
    sim_ctx_t *c = &ctx;
    uint64_t period, n_periods;
    clock_t c0 = clock();
    int rc;

    memset(c, 0, sizeof *c);
    c->cfg = cfg;
    c->opt = opt;
    c->res = res;
    c->drive = &drive;
    c->t_run = -1.0;
    c->t_soak_rev = -1.0;
    c->t_soak_load = -1.0;
    c->prev_state = ID_IDLE;
    drive_probe(&drive, &c->pv);
    c->b = c->pv.base;
    result_defaults(res);
    rc = run_open(c, err, err_len);
    if (rc != 0) {
        return rc;
    }
    n_periods = (uint64_t)(c->duration / c->Ts + 0.5);   /* = sim_run_periods() */

    if (opt->no_autostart == 0u) {
        drive_command(&drive, DRIVE_CMD_START_IDENT);
    }
    drive_background(&drive);

    for (period = 0; period < n_periods; period++) {
        const double t = (double)period * c->Ts;
        double psi_d, psi_q;   /* true rotor flux in the drive's frame, this sample */

        inject_events(c, t);
        if (run_firmware(c, period, t) != 0 || observe_verdict(c, t) != 0) {
            break;
        }
        observe_protection(&c->pv, res, t);
        observe_soak(&c->pv, res, t);
        observe_voltage(&c->pv, &c->plant, c->b->V_base_V, res);
        observe_publication(c, t);
        observe_sample(c, period, t, &psi_d, &psi_q);
        if (scenario_events(c, t, psi_d, psi_q) != 0) {
            break;
        }
        if (opt->stop_after_fault_s > 0.0 && res->n_faults_seen > 0u &&
            t >= res->fault_time_s[0] + opt->stop_after_fault_s) {
            res->duration_s = t;   /* ended after the fault (sim_options_t.stop_after_fault_s) */
            break;
        }
        if (!opt->quiet && c->duration > 5.0 && (period % (uint64_t)cfg->board.pwm_freq_Hz) == 0u &&
            period > 0) {
            fprintf(stderr, "\r  simulated %.0f of %.0f s", t, c->duration);
        }
        if (plant_step(c, t) != 0) {
            break;
        }
    }
    if (!opt->quiet && c->duration > 5.0) {
        fprintf(stderr, "\n");
    }
    res->wall_s = (double)(clock() - c0) / CLOCKS_PER_SEC;
    run_results(c);
    return run_close(c, err, err_len);
}
