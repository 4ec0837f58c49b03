/**
 * @file drift.h
 * The thermal-drift scenario (SCEN_DRIFT, `--scenario drift`): once the
 * identification is complete, the rotor warms, so the plant's rotor
 * resistance rises while the load varies, and the drive's tracked Rr
 * (telemetry Rr_track) is compared with the true one.
 *
 * From the drift start t0 = (identification complete) + [drift] start_s:
 *
 *   Rr(t) = Rr0 (1 + rr_rise_pct/100 * clamp((t - t0) / ramp_s, 0, 1))
 *
 *   extra load: the levels 0, +50 %, -30 % of the rated load
 *   (load.const_Nm + load.fan_Nm), in turn, each for load_period_s, each
 *   reached from the one before by a linear ramp of DRIFT_LOAD_RAMP_S
 *   (a machine changing duty, not a shock: the tracker should be judged on
 *   the drift and on realistic load changes, not on a torque step that no
 *   thermal process comes with).
 *
 * Rr0 is plant.Rr_ohm; the leakages and Lm stay (copper resistance changes
 * with temperature, inductances do not).  The window of the figures runs
 * from t0 to the end of the run.  Host only.
 */
#ifndef DRIFT_H
#define DRIFT_H

#include <stddef.h>
#include <stdint.h>

#include "sim_config.h"
#include "sim_run.h"

#define DRIFT_LOAD_RAMP_S 0.5   /* ramp between two load levels */
#define DRIFT_TAIL_S 5.0        /* the run goes on this long after the Rr ramp */

/** What the run observes in one PWM period of the window. */
typedef struct {
    double psi_d_Wb, psi_q_Wb;  /* true rotor flux in the drive's frame */
    double speed_err_rpm;       /* speed reference - true speed */
    double rr_true_ohm;         /* the plant's Rr */
    double rr_track_ohm;        /* telemetry Rr_track in ohm */
    uint16_t track_valid;
} drift_obs_t;

typedef struct {
    /* profile (sim_config_t [drift], [plant], [load]) */
    double rr0_ohm, rise, ramp_s, start_s, period_s, load_rated_Nm;
    double t0_s;                /* drift start; -1 until drift_begin */
    /* 100 Hz series over the window */
    uint32_t div;               /* PWM periods per sample */
    double dt_s;                /* sample interval (div PWM periods) */
    uint32_t periods;           /* PWM periods observed in the window */
    double *rr_true_ohm, *rr_track_ohm;
    unsigned char *valid;
    size_t n, cap;
    /* psi_q/psi_d over the last 20 ms, one entry per PWM period */
    double *ring;
    size_t ring_len, ring_pos, ring_fill;
    double ring_sum;
    double max_qd, max_qd_20ms, max_speed_err_rpm;
    double rr_last_ohm;         /* the plant's Rr in the last period observed */
} drift_t;

/** Allocate for a window of at most @p window_s; 0, or -1 out of memory. */
int drift_init(drift_t *d, const sim_config_t *c, double window_s);
void drift_free(drift_t *d);
/** The identification is complete at @p t_s: the drift starts start_s later. */
void drift_begin(drift_t *d, double t_s);
/** 1 from the drift start on. */
int drift_in_window(const drift_t *d, double t_s);
/** Time the default run ends (ramp done + DRIFT_TAIL_S); -1 before drift_begin. */
double drift_end_s(const drift_t *d);
/** The plant's rotor resistance at @p t_s (Rr0 before the drift). */
double drift_rr_ohm(const drift_t *d, double t_s);
/** The extra load torque at @p t_s (0 before the drift), N m. */
double drift_extra_load_Nm(const drift_t *d, double t_s);
/** One PWM period of the window. */
void drift_observe(drift_t *d, const drift_obs_t *o);
/** The window's figures into @p r (-1 where there is nothing to report). */
void drift_figures(const drift_t *d, sim_result_t *r);

#endif /* DRIFT_H */
