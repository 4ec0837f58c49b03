/**
 * @file sim_run.h
 * One closed-loop run of the unchanged firmware (drive_isr through the host
 * HAL) against the plant, with a scenario, optional injected faults, a CSV
 * trace and the identification results.  Used by motor_sim and by the
 * closed-loop tests (in-process, so they can assert on the results).
 */
#ifndef SIM_RUN_H
#define SIM_RUN_H

#include <stdint.h>
#include "drive.h"
#include "plant.h"
#include "sim_config.h"
#include "vi_curve.h"

#define SIM_MAX_FAULTS 8

#define SIM_MAX_CMDS 8

/* The trace's size: a row is at most about SIM_TRACE_ROW_BYTES characters
 * (measured: 327 on average, 352 at most over the identification and the
 * adaptive runs; 400 leaves room for signs and exponents), the header
 * SIM_TRACE_HEADER_BYTES.  motor_sim's default limit and its ceiling, MB. */
#define SIM_TRACE_ROW_BYTES 400.0
#define SIM_TRACE_HEADER_BYTES 512.0
#define SIM_TRACE_MAX_MB_DEFAULT 256.0
#define SIM_TRACE_MAX_MB_LIMIT 1e6
#define SIM_STATES 8   /* id_state_t: IDLE .. REFINE */

/* SCEN_SOAK: after the identification, repeated speed reversals
 * (+-target every 4 s) and load steps (+50 % of the rated load for 1 s,
 * 2 s after each reversal): the long-run soak test.
 * SCEN_DRIFT: after the identification, the rotor resistance rises as the
 * rotor warms while the load changes ([drift] keys, drift.h): the test of
 * the drive's Rr tracking (drift tracking). */
typedef enum {
    SCEN_START = 0, SCEN_REVERSAL, SCEN_LOAD_STEPS, SCEN_SOAK, SCEN_DRIFT
} sim_scenario_t;

/** A command given to the drive at a time (as from the telemetry link). */
typedef struct {
    double t_s;
    uint16_t cmd;   /* drive_cmd_t */
} sim_cmd_t;

typedef struct {
    plant_fault_t kind;
    double t_s;        /* when: seconds from the start, or after the state's first entry */
    double value;
    uint16_t at_state; /* 0 (ID_IDLE): t_s is absolute; another id_state_t: t_s after the
                          sequence first enters that state (the drive's telemetry) */
} sim_fault_t;

typedef struct {
    sim_scenario_t scenario;
    double duration_s;           /* <= 0: the scenario's default */
    const char *trace_path;      /* CSV, or NULL */
    double trace_rate_Hz;        /* rows per simulated second (default 1000) */
    uint32_t trace_every;        /* one row every this many PWM periods (0: trace_rate_Hz) */
    double trace_max_bytes;      /* the trace stops (the run goes on) beyond this size
                                    (0: no limit): trace_truncated_at_s; motor_sim sizes the
                                    trace before a run of known length (sim_trace_bytes) so
                                    that this is not reached */
    uint16_t quiet;              /* no progress on stderr */
    uint16_t n_faults;
    sim_fault_t faults[SIM_MAX_FAULTS];
    uint16_t n_cmds;
    sim_cmd_t cmds[SIM_MAX_CMDS];
    /* the board's background loop over a serial link (motor_sim --serial,
     * sim_serial.h): no start at t = 0 (the board waits for $C,S or its
     * button), and a hook run after each drive_background (1 kHz) with the
     * ISRs run so far and the time; a non-zero return ends the run there */
    uint16_t stop_when_decided;  /* end DECIDED_GRACE_S after the drive's publication verdict
                                    (motor_sim's start scenario without --duration): the
                                    default duration is then the time-out */
    uint16_t no_autostart;
    double stop_after_fault_s;   /* > 0: the run ends this long after the first fault latched */
    int (*background_hook)(void *ctx, drive_t *d, uint64_t isr_count, double t_s);
    void *hook_ctx;
} sim_options_t;

/** Parameter set in SI. */
typedef struct {
    double Rs_ohm, Rr_ohm, Lm_H, Lr_H, psi_r_Wb, Tr_s;
} sim_params_t;

typedef struct {
    double duration_s;
    double wall_s;                  /* wall-clock time of the run */
    uint16_t identified;            /* this run's set published (publish_reason published) */
    uint16_t publish_reason;        /* drive_pub_reason_t at the end (pending: the run ended
                                       before the drive's verdict) */
    double t_decided_s;             /* when the verdict came (-1: never) */
    uint16_t extracted;             /* the final extraction ran: ident holds it */
    /* the confidence of the set judged (ident_conf.h), %: the telemetry's, -1 where not
     * available; then the RLS's figures of the final pass (background's evaluation) */
    double conf_pct[6];             /* Rs, Rr, Lm, Lr, psi_r, Tr */
    double conf_residual, conf_amp; /* sqrt(J/Y); largest amplification */
    double conf_excitation;         /* sqrt(Y/2n) against a ramp to rated speed */
    uint32_t conf_pd;               /* the final window's RLS covariance repairs */
    double bound_pct[6], drift_pct[6];
    uint32_t conf_samples;          /* RLS samples of the final window */
    uint16_t settle_timeout;        /* published after the SETTLE time limit */
    double t_accel_start_s;         /* the sequence entered ACCELERATE */
    double t_published_s;
    sim_params_t truth, ident;
    sim_params_t error_pct;         /* 100 (ident - truth) / truth */
    uint16_t ident_valid;           /* ident (the last extraction, d->id.pex) was plausible */
    double converge_s;              /* after t_accel_start: all live estimates stay
                                       within 2 % of the published values (-1: never) */
    /* closed-loop figures */
    double max_abs_i_A;             /* largest phase current */
    double max_speed_err_rpm_ramp;  /* |ref - true| during ACCELERATE (after 0.2 s) */
    double max_flux_q_over_d;       /* |psi_rq/psi_rd| after magnetisation */
    double final_speed_rpm;
    double target_rpm;              /* the identification's target as the drive ran it (the
                                       configured one, lowered to what the bus gives:
                                       drive_target.h), at RUN or at the end */
    uint16_t target_lowered;        /* the acceleration ended at the voltage limit */
    double max_volt_head;           /* the largest commanded voltage in ACCELERATE as
                                       drive_target.h low-passes it, per unit of
                                       vdc / sqrt(3) (the limit: 0.95) */
    uint16_t final_state, final_fault, final_pwm_on;
    uint16_t n_faults_seen;
    uint16_t fault_code[SIM_MAX_FAULTS];
    double fault_time_s[SIM_MAX_FAULTS];
    uint16_t fault_state[SIM_MAX_FAULTS];   /* the sequence's state when it latched (id_state_t) */
    uint16_t fault_pass[SIM_MAX_FAULTS];    /* ... and its pass */
    uint16_t fault_cause[SIM_MAX_FAULTS];   /* current_sensor: which check (report.c) */
    double t_injected_s[SIM_MAX_FAULTS];   /* when each --fault was applied (-1: never) */
    double t_state_s[SIM_STATES];   /* the sequence's first entry into each id_state_t (-1) */
    /* protection figures */
    double t_fault_visible_s;       /* first sample an injected fault reached the ADC/QEP
                                       (-1: none) */
    uint32_t pwm_periods_with_fault;/* periods the bridge switched with a fault latched
                                       (after the ISR): must be 0 */
    double t_first_published_s;     /* -1: never */
    sim_params_t published_first;   /* the published set when it first appeared */
    sim_params_t published_end;     /* the published set at the end of the run (the adaptive sequence: with
                                       tracking, Rs standstill, Rr and Tr tracked) */
    sim_params_t published_end_error_pct;   /* against the truth at the start of RUN */
    uint16_t params_tracked;        /* the end set carries the tracked values */
    uint16_t refused_fused;         /* nothing published, and the drive had judged a fused set
                                       (the adaptive sequence): refused_set is that set */
    sim_params_t refused_set;       /* ... the standstill Rs, the tracker's Rr and Tr, the RLS's
                                       Lm, Lr, psi_r: what publish_tracked would have written */
    sim_params_t refused_set_error_pct;   /* against the truth at the start of RUN */
    uint16_t params_withdrawn;      /* sets the publish guard withdrew (publish_guard.h) */
    uint16_t withdraw_reason;       /* the fault code of the last withdrawal */
    double max_pub_err_after_fault_pct;  /* the worst |error| of any published parameter
                                       (psi_r once its truth is known) from 2 ms after the
                                       first fault on (-1: nothing published then) */
    uint16_t published_changed;     /* a published value changed after that */
    /* the TRUE currents (the motor's and the bridge legs', not the sensors'):
     * what a protection must bound whatever the measurements say */
    double max_true_phase_A;        /* largest |motor phase current| at any period end or
                                       comparator trip instant */
    double max_true_leg_A;          /* the same for the legs (with an a-b short's current) */
    double rotor_turn_counts;       /* the rotor's largest excursion from its start angle, in
                                       encoder counts (4 lines a revolution; the TRUE angle) */
    double locked_torque_peak_Nm;   /* [load] locked: the largest torque the lock held */
    double over_trip_s;             /* time the true phase current spent above
                                       controller.overcurrent_A (sample instants) */
    double t_over_trip_first_s, t_over_trip_last_s;   /* -1: never above */
    uint32_t hw_trips;              /* the bridge's comparator turned the outputs off */
    double t_hw_trip_s;             /* its first trip (-1: never) */
    double max_cur_check_pu;        /* largest filtered current-tracking error */
    /* the model check (current_model_check.h), in the units of its levels:
     * |r| / sigma Ls (A), the negative sequence per unit of |i|, the DC part
     * / (Rs tau_r) (A: the offset it stands for); largest values and when */
    double max_cmc_r_A, t_max_cmc_r_s;
    double max_cmc_neg, t_max_cmc_neg_s;
    double max_cmc_dc_A, t_max_cmc_dc_s;
    /* each test's value over its level (the level with its allowances and
     * leak terms, as the firmware forms it), largest while the test is armed:
     * the healthy margin is 1 / this */
    double max_cmc_util_r, max_cmc_util_neg, max_cmc_util_dc;
    double t_max_cur_check_s;       /* when */
    /* soak figures: control-path flags, counted in samples after the
     * magnetisation, and the estimator's counters at the end */
    uint32_t n_overmod;             /* svgen clamped onto the hexagon */
    double t_first_overmod_s, t_last_overmod_s;   /* -1: never */
    uint32_t n_current_pi_sat;      /* a current PI at its voltage limit */
    uint32_t n_imr_low;             /* orientation: i_mr below its minimum */
    uint32_t n_speed_sat;           /* QEP speed at its saturation (d_max counts) */
    uint32_t rls_sat_count, rls_pd_count, theta_rejects, publish_rejects;
    double max_abs_theta;           /* largest |RLS theta_i|, pu */
    double live_min_pct, live_max_pct; /* live estimates (valid ones, after
                                       publication) relative to truth, worst */
    double max_settled_speed_err_rpm; /* soak: |ref - speed| just before each reversal */
    /* voltage reconstruction (dead-time compensation), means over SETTLE and RUN:
     * drive's voltage minus the bridge's, along / across the current */
    double v_err_along_i_V, v_err_across_i_V;
    double i_mag_steady_A;          /* mean current-vector magnitude (peak phase) */
    uint32_t n_v_err;               /* samples averaged */
    /* the bridge's voltage-error test at standstill (vi_curve.h): the
     * drive's fit, and the simulated bridge's true E and band (the
     * plant's dead time, source bus, drop, transition) */
    vi_fit_t vi;
    double vi_true_e_pole_V, vi_true_band_A;
    double vi_i1_A;          /* the test's smaller current level (the retry's if it ran) */
    int vi_retried;          /* 1: the test ran again with its levels beyond the band */
    /* adaptation (the adaptive sequence), telemetry at the end */
    uint16_t final_pass;            /* identification pass under way or last done */
    double Rs_dc_ohm;               /* standstill Rs; 0: none measured */
    double sensor_gain_pct;         /* the current sensors' possible gain error the verdict
                                       counted (drive_safety_sensor_gain), % */
    uint16_t adapt_timeouts;        /* waits for the background's model that ran out (the
                                       sequence went on with the model in use) */
    /* drift scenario (SCEN_DRIFT), over the window from the drift start to the
     * end of the run; -1: none (no window, no valid tracked sample) */
    double drift_t_start_s;         /* -1: the drift never started */
    uint32_t track_samples;         /* 100 Hz samples with track_valid */
    double track_err_lag0_pct;      /* max |Rr_track(t) - Rr(t)| / Rr(t), % */
    double track_best_lag_s;        /* the lag L in 0..3 s that minimises ... */
    double track_err_best_lag_pct;  /* ... max |Rr_track(t) - Rr(t - L)| / Rr(t - L), % */
    double drift_max_q_over_d;      /* max |psi_rq/psi_rd| */
    double drift_max_q_over_d_20ms; /* max |20 ms mean of psi_rq/psi_rd| */
    double drift_speed_ripple_rpm;  /* max |speed ref - speed| */
    double drift_rr_true_end_ohm;   /* the plant's Rr at the end */
    /* the plant's state stopped being finite numbers (the integration
     * diverged; sim_config_check refuses the time constants that make it):
     * the time, and the run ended there; -1: never */
    double plant_diverged_at_s;
    double trace_truncated_at_s;    /* the trace reached trace_max_bytes and stopped; -1: no */
} sim_result_t;

/** The time the bridge's voltage-error test adds to CALIBRATE (vi_curve.h;
 *  with [ident] vi_test and the compensation on, else 0): its levels on the
 *  believed Tr and the background's fit, s (for the durations of runs that
 *  must reach a later state). */
double sim_vi_test_s(const sim_config_t *c);

/** Run; returns 0, or non-zero with a message in err (drive_init or a model
 *  refused the configuration, or the trace file could not be written). */
int sim_run(const sim_config_t *cfg, const sim_options_t *opt, sim_result_t *res, char *err,
            unsigned err_len);

/** PWM periods between two trace rows of a run with @p opt (trace_every, or
 *  the period count of trace_rate_Hz, default 1 kHz; at least 1). */
uint64_t sim_trace_every(const sim_config_t *c, const sim_options_t *opt);
/** A trace's size at most (header and rows of SIM_TRACE_ROW_BYTES), bytes. */
double sim_trace_bytes(const sim_config_t *c, double duration_s, uint64_t every);

/** The simulated time of a run with @p opt: --duration, or the scenario's
 *  default (long enough for the identification and what the scenario does
 *  after it; the drift scenario's default run may end earlier, with its
 *  window). */
double sim_run_duration_s(const sim_config_t *c, const sim_options_t *opt);
/** PWM periods a run of @p duration_s simulates; period k starts at
 *  k / board.pwm_freq_Hz, so a fault or command at t acts in the run only
 *  if t is at most the last one's start, (periods - 1) / f. */
uint64_t sim_run_periods(const sim_config_t *c, double duration_s);

/** Parse "start" | "reversal" | "load_steps" | "soak" | "drift". Returns 0 or -1. */
int sim_scenario_parse(const char *name, sim_scenario_t *out);
const char *sim_scenario_name(sim_scenario_t s);
/** Number of scenarios: sim_scenario_name(0 .. count - 1) lists them all. */
unsigned sim_scenario_count(void);

#endif /* SIM_RUN_H */
