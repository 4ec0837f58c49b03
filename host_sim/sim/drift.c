/* The thermal-drift scenario.  See drift.h. */
#include "drift.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DRIFT_RATE_HZ 100.0   /* the tracked-Rr series */
#define DRIFT_MEAN_S 0.020    /* the q/d running mean: long against the frame
                                 angle's current noise, short against the load ramps */
#define DRIFT_LAG_STEP_S 0.1
#define DRIFT_N_LAGS 31u      /* 0, 0.1, ..., 3.0 s */

/* load levels in turn, fractions of the rated load */
static const double k_load_level[3] = {0.0, 0.5, -0.3};

int drift_init(drift_t *d, const sim_config_t *c, double window_s)
{
    double n_div = floor(c->board.pwm_freq_Hz / DRIFT_RATE_HZ + 0.5);
    double n_ring = floor(DRIFT_MEAN_S * c->board.pwm_freq_Hz + 0.5);

    memset(d, 0, sizeof *d);
    d->rr0_ohm = c->plant.Rr_ohm;
    d->rise = c->drift.rr_rise_pct / 100.0;
    d->ramp_s = c->drift.ramp_s;
    d->start_s = c->drift.start_s;
    d->period_s = c->drift.load_period_s;
    d->load_rated_Nm = c->load.const_Nm + c->load.fan_Nm;
    d->t0_s = -1.0;
    d->div = (n_div >= 1.0) ? (uint32_t)n_div : 1u;
    d->dt_s = (double)d->div / c->board.pwm_freq_Hz;
    d->cap = (size_t)(fmax(window_s, 0.0) / d->dt_s) + 16u;
    d->ring_len = (n_ring >= 1.0) ? (size_t)n_ring : 1u;
    d->rr_true_ohm = (double *)calloc(d->cap, sizeof *d->rr_true_ohm);
    d->rr_track_ohm = (double *)calloc(d->cap, sizeof *d->rr_track_ohm);
    d->valid = (unsigned char *)calloc(d->cap, sizeof *d->valid);
    d->ring = (double *)calloc(d->ring_len, sizeof *d->ring);
    if (d->rr_true_ohm == NULL || d->rr_track_ohm == NULL || d->valid == NULL ||
        d->ring == NULL) {
        drift_free(d);
        return -1;
    }
    return 0;
}

void drift_free(drift_t *d)
{
    free(d->rr_true_ohm);
    free(d->rr_track_ohm);
    free(d->valid);
    free(d->ring);
    d->rr_true_ohm = NULL;
    d->rr_track_ohm = NULL;
    d->valid = NULL;
    d->ring = NULL;
    d->cap = 0u;
    d->n = 0u;
}

void drift_begin(drift_t *d, double t_s) { d->t0_s = t_s + d->start_s; }

int drift_in_window(const drift_t *d, double t_s) { return d->t0_s >= 0.0 && t_s >= d->t0_s; }

double drift_end_s(const drift_t *d)
{
    return (d->t0_s >= 0.0) ? d->t0_s + d->ramp_s + DRIFT_TAIL_S : -1.0;
}

double drift_rr_ohm(const drift_t *d, double t_s)
{
    double x;
    if (!drift_in_window(d, t_s)) {
        return d->rr0_ohm;
    }
    x = fmin((t_s - d->t0_s) / d->ramp_s, 1.0);
    return d->rr0_ohm * (1.0 + d->rise * x);
}

double drift_extra_load_Nm(const drift_t *d, double t_s)
{
    double tau, x, cur, prev;
    uint32_t n;
    if (!drift_in_window(d, t_s)) {
        return 0.0;
    }
    tau = t_s - d->t0_s;
    n = (uint32_t)floor(tau / d->period_s);
    cur = k_load_level[n % 3u];
    /* the first level is reached from the load before the drift (no step) */
    prev = (n == 0u) ? 0.0 : k_load_level[(n - 1u) % 3u];
    x = fmin((tau - (double)n * d->period_s) / DRIFT_LOAD_RAMP_S, 1.0);
    return (prev + (cur - prev) * x) * d->load_rated_Nm;
}

/* q/d: the instantaneous peak and the peak of its 20 ms mean (the bias of
 * the orientation, without the frame angle's sample-to-sample noise) */
static void observe_orientation(drift_t *d, double psi_d, double psi_q)
{
    double qd;
    if (!(psi_d > 1e-6)) {
        return;
    }
    qd = psi_q / psi_d;
    d->max_qd = fmax(d->max_qd, fabs(qd));
    d->ring_sum += qd - d->ring[d->ring_pos];
    d->ring[d->ring_pos] = qd;
    d->ring_pos = (d->ring_pos + 1u) % d->ring_len;
    if (d->ring_fill < d->ring_len) {
        d->ring_fill++;
    }
    if (d->ring_fill == d->ring_len) {
        d->max_qd_20ms = fmax(d->max_qd_20ms, fabs(d->ring_sum / (double)d->ring_len));
    }
}

void drift_observe(drift_t *d, const drift_obs_t *o)
{
    observe_orientation(d, o->psi_d_Wb, o->psi_q_Wb);
    d->max_speed_err_rpm = fmax(d->max_speed_err_rpm, fabs(o->speed_err_rpm));
    d->rr_last_ohm = o->rr_true_ohm;
    if ((d->periods % d->div) == 0u && d->n < d->cap) {
        d->rr_true_ohm[d->n] = o->rr_true_ohm;
        d->rr_track_ohm[d->n] = o->rr_track_ohm;
        d->valid[d->n] = (unsigned char)(o->track_valid != 0u);
        d->n++;
    }
    d->periods++;
}

/* Worst relative error of the tracked Rr against the true Rr of lag samples
 * before, over the valid samples at least lag samples into the window, %;
 * -1 when there is no such sample. */
static double worst_err_pct(const drift_t *d, size_t lag)
{
    double worst = -1.0;
    size_t i;
    for (i = lag; i < d->n; i++) {
        if (d->valid[i] != 0u) {
            double ref = d->rr_true_ohm[i - lag];
            worst = fmax(worst, 100.0 * fabs(d->rr_track_ohm[i] - ref) / ref);
        }
    }
    return worst;
}

/* The lag that makes the tracked Rr fit the true one best: a tracker with a
 * memory follows a ramp with a delay, so the error at lag 0 mixes the delay
 * with the bias; at the best lag what remains is the bias and the noise. */
static void best_lag(const drift_t *d, sim_result_t *r)
{
    uint32_t j;
    r->track_err_lag0_pct = worst_err_pct(d, 0u);
    r->track_best_lag_s = -1.0;
    r->track_err_best_lag_pct = -1.0;
    for (j = 0u; j < DRIFT_N_LAGS; j++) {
        double lag_s = DRIFT_LAG_STEP_S * (double)j;
        double e = worst_err_pct(d, (size_t)floor(lag_s / d->dt_s + 0.5));
        if (e >= 0.0 && (r->track_err_best_lag_pct < 0.0 || e < r->track_err_best_lag_pct)) {
            r->track_err_best_lag_pct = e;
            r->track_best_lag_s = lag_s;
        }
    }
}

void drift_figures(const drift_t *d, sim_result_t *r)
{
    size_t i;
    /* a window the run ended before is no window */
    r->drift_t_start_s = (d->n > 0u) ? d->t0_s : -1.0;
    r->track_samples = 0u;
    for (i = 0; i < d->n; i++) {
        if (d->valid[i] != 0u) {
            r->track_samples++;
        }
    }
    best_lag(d, r);
    if (d->n == 0u) {
        /* the run ended before the drift started */
        r->drift_max_q_over_d = -1.0;
        r->drift_max_q_over_d_20ms = -1.0;
        r->drift_speed_ripple_rpm = -1.0;
        r->drift_rr_true_end_ohm = -1.0;
        return;
    }
    r->drift_max_q_over_d = d->max_qd;
    r->drift_max_q_over_d_20ms = (d->ring_fill == d->ring_len) ? d->max_qd_20ms : -1.0;
    r->drift_speed_ripple_rpm = d->max_speed_err_rpm;
    r->drift_rr_true_end_ohm = d->rr_last_ohm;
}
