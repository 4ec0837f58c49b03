/**
 * @file drive_types.h
 * The full drive_t, so that the application can own an instance
 * (`static drive_t g_drive;` in firmware/main.c; one per instance on the host).
 * Every member is a module instance or a small piece of glue state; no module
 * sees the whole struct (each step function gets its own module only).
 */
#ifndef DRIVE_TYPES_H
#define DRIVE_TYPES_H

#include "drive.h"

#include "base_values.h"
#include "clarke.h"
#include "current_check.h"
#include "dc_bus.h"
#include "encoder_check.h"
#include "flux_obs.h"
#include "id_sequence.h"
#include "ident_regressor.h"
#include "ident_conf.h"
#include "ifo.h"
#include "ipark.h"
#include "isr_monitor.h"
#include "param_extract.h"
#include "park.h"
#include "phase_current.h"
#include "pi_ctrl.h"
#include "protect.h"
#include "qep_speed.h"
#include "ramp_gen.h"
#include "rls.h"
#include "svgen.h"
#include "theta_guard.h"
#include "standstill_z.h"
#include "tr_track.h"
#include "volt_calc.h"

/** The multi-rate schedule of the ISR (drive_step.c): every ISR runs the
 *  fast path, and one of DRIVE_SLOTS slow tasks in turn, so that each ISR
 *  carries an equal share and the slow tasks run at f_pwm / DRIVE_SLOTS. */
#define DRIVE_SLOTS_LOG2 2u
#define DRIVE_SLOTS (1u << DRIVE_SLOTS_LOG2)
typedef enum {
    DRIVE_SLOT_SPEED = 0,   /* speed ramp + PI, sequence, adaptation, slow constants, snapshots */
    DRIVE_SLOT_FILTERS,     /* the regression's Butterworth filters on the window means */
    DRIVE_SLOT_RLS_ROW1,    /* RLS: forgetting + row 1 */
    DRIVE_SLOT_RLS_ROW2     /* RLS: row 2, then the estimator guard */
} drive_slot_t;

/** Gains and constants derived once by drive_init (pu, Q24). */
typedef struct {
    _iq sigma_ls;       /* sigma Ls, pu of L_base: d-axis decoupling */
    _iq lm2_lr;         /* Lm^2 / Lr, pu of L_base: back-EMF feed-forward */
    _iq three_half_step;/* 1.5 f_base Ts: pu angle per pu speed over 1.5 periods */
    _iq i_max;          /* torque-current limit, pu */
    _iq speed_tol;      /* steady state: |speed error| below, pu */
    uint16_t cal_samples;
    uint16_t live_period;       /* samples between live snapshots */
    uint16_t orientation;       /* DRIVE_ORIENT_IFO or DRIVE_ORIENT_FLUX_OBS */
    _iq rls_ws_min;             /* flux observer: the RLS runs only while |ws_f| is above
                                   this (pu), where the voltage model dominates */
    _iq psi_min;                /* flux observer: below this |psi_r| (pu) its angle is
                                   noise; the frame follows the encoder angle instead */
    uint16_t conf_track_updates;/* fused set: tracker updates judged (DRIVE_CONF_TRACK_S) */
    uint32_t conf_track_wait;   /* ... RUN samples waited for them (DRIVE_CONF_TRACK_WAIT_S) */
    _iq conf_track_se;          /* Q24: the tracker's standard error per relative residual */
} drive_consts_t;

/** What the ISR hands to the background for the parameter extraction. */
typedef struct {
    _iq theta[RLS_N];   /* RLS estimate at the snapshot */
    _iq i_m;            /* steady (filtered) M current, pu */
    uint16_t ready;     /* set by the ISR, cleared by the background */
} drive_snapshot_t;

/** Background -> ISR: a pass's extracted parameters (pu), one-slot mailbox
 *  as drive_snapshot_t (the background writes while ready = 0, sets ready
 *  last; the ISR reads while ready = 1 and clears it last). */
typedef struct {
    _iq rs, lm, lr, ls, tr;   /* Q24 pu (tr: pu time) */
    uint16_t valid;           /* 0: the extraction was implausible (keep the old model) */
    uint16_t full;            /* 1: all six parameters; 0: the magnetic part only (lm, lr, ls) */
    uint16_t ready;
} drive_adapt_mail_t;

/** Parameter adaptation (issue 8): standstill Rs, the model handed from
 *  pass to pass, the Rr/Tr tracker's feed.  All pu, Q24. */
#define DRIVE_ADAPT_NP 5u   /* rs, lm, lr, ls, tr */
typedef struct {
    /* configuration (drive_adapt_init) */
    uint16_t passes, standstill, track_rr;
    uint16_t fused;           /* standstill and track_rr: Rs from standstill, Rr and Tr from
                                 the tracker, only Lm, Lr, psi_r from the RLS */
    _iq rs_lo, rs_hi;         /* plausible standstill Rs (a factor 4 of the believed) */
    _iq blend_step;           /* Q24 fraction per sample: the blend lasts DRIVE_ADAPT_BLEND_S */
    _iq kp_per_sls;           /* current-loop kp per pu of sigma Ls (kp = w_c sigma Ls) */
    _iq ki_per_rs;            /* current-loop ki per pu of Rs (ki = w_c Ts Rs) */
    _iq tr_rate;              /* largest relative change of the applied Tr per tracker tick */
    uint16_t ssz_gap;         /* samples of DC between the sigma Ls test and the Rs reading */
    uint16_t ssz_started;     /* the sigma Ls test of this magnetisation has been started */
    /* the model in use (the observer's values) and the blend towards a new one */
    _iq from[DRIVE_ADAPT_NP], to[DRIVE_ADAPT_NP];
    _iq frac;                 /* Q24 blend position 0..1 */
    uint16_t blending;
    _iq lr;                   /* Lr of the last identification (Rr_track = Lr / Tr) */
    uint16_t track_armed;     /* the tracker has its start value (final pass in) */
    uint16_t prev_state;      /* id_state_t of the last sample */
} drive_adapt_t;

struct drive {
    base_values_t base;
    drive_consts_t k;
    uint16_t t1pr;
    uint16_t config_status;     /* drive_cfg_status_t of drive_init */
    drive_ident_t ident_cfg;    /* kept to restart the RLS (background only) */

    /* sensing */
    phase_current_t cur;
    dc_bus_t bus;
    qep_speed_t qep;            /* angle; speed for the loops (window 16); speed over one
                                   sample for the regression (speed_1: its lag, half a
                                   period, matches the mid-period voltage) */
    /* control */
    clarke_t clarke;
    park_t park;
    ipark_t ipark;
    pi_ctrl_t pi_speed, pi_id, pi_iq;
    ramp_gen_t speed_ramp;
    ifo_t ifo;                  /* orientation 0: indirect (not run in mode 1) */
    flux_obs_t fobs;            /* orientation 1: rotor-flux observer (not run in mode 0) */
    uint16_t run_ifo;           /* orientation 1, RUN with tracking: control frame from ifo with
                                   the tracked Tr (drive_adapt.c) */
    uint16_t fobs_hold;         /* orientation 1: frame held on the encoder angle (|psi_r| <
                                   psi_min or magnetising) */
    svgen_t svgen;
    volt_calc_t volt;
    /* identification */
    ident_regressor_t reg;
    rls_t rls;
    rls_t rls_start;            /* the RLS as drive_rls_start leaves it: copied in at the start
                                   of each further pass (no float in the ISR) */
    param_extract_t pex;
    id_sequence_t seq;
    protect_t prot;
    encoder_check_t enc_chk;    /* encoder plausibility -> FAULT_ENCODER */
    current_check_t cur_chk;    /* current feedback plausibility -> FAULT_CURRENT_SENSOR */
    theta_guard_t guard;        /* last good theta: what the snapshots carry */
    isr_monitor_t ovr;          /* ISR overruns -> FAULT_ISR_OVERRUN */

    /* PWM pipeline: duties computed at sample k apply during period k+1 and
     * are reconstructed into voltages at sample k+2 (hal_pwm.h timing). */
    _iq duty_next[3];           /* computed at k-1, applied now */
    _iq duty_last[3];           /* computed at k-2, applied in the period just ended */
    uint16_t on_next, on_last;  /* bridge switching in those periods */
    _iq ia_prev, ib_prev;       /* phase currents of the previous sample, pu */

    drive_adapt_t adapt;        /* issue 8: model adaptation between passes, tracking */
    drive_adapt_mail_t adapt_mail;  /* background -> ISR: each pass's parameters */
    _iq fused_lm, fused_lr, fused_psi;   /* background, fused mode: the last good magnetic set */
    uint16_t fused_ready;
    tr_track_t track;           /* Rr/Tr tracker in RUN (track_rr) */
    standstill_z_t ssz;         /* standstill sigma Ls (standstill) */

    /* multi-rate schedule and what the slow tasks hand to the fast path */
    uint16_t slot;              /* drive_slot_t of this ISR (0 .. DRIVE_SLOTS-1) */
    uint16_t frame_ifo;         /* this ISR's control frame is ifo's (drive_ifo_frame) */
    _iq theta_k, theta_prev;    /* Q24 pu [0, 1): the frame angle of this and the last sample */
    _iq ws_k;                   /* Q24 pu: the frame's speed over the period that just ended */
    _iq ws_ctl;                 /* Q24 pu: the frame speed for decoupling and modulation */
    _iq i_t_ref;                /* Q24 pu: the speed loop's torque-current reference */
    _iq im_inject;              /* Q24 pu: added to the i_M reference (standstill test) */
    uint16_t reg_count;         /* encoder count at the last FILTERS slot (the regression's window) */

    drive_snapshot_t snap;      /* ISR -> background: the steady-state extraction */
    /* the identification's confidence (ident_conf.h): the ISR's sums over
     * the RLS pass under way; the covariance and the sums handed over with
     * snap (written before snap.ready, read while it is set); the
     * background's evaluation, its estimate at the middle of the window and
     * the tracker's residual (fused set) */
    ident_conf_acc_t conf_acc;
    rls_cov_t snap_cov;
    ident_conf_acc_t snap_acc;
    uint32_t snap_pd;           /* rls_t.pd_count of the window */
    ident_conf_t conf;
    _iq conf_theta_mid[RLS_N];  /* Q24 pu: the guarded estimate at mid-window */
    _iq conf_speed_mid;         /* Q24 pu: |speed| at which it is taken */
    uint16_t conf_mid;          /* 0: none, 1: armed (conf_speed_mid set), 2: taken */
    uint16_t conf_pass;         /* the pass the capture belongs to */
    ident_conf_fit_t trk_fit;   /* the tracker's fit while it is valid (fused set) */
    _iq trk_theta0;             /* Q24: its 1/Tr at the first sample of the fit */
    uint32_t trk_updates;       /* the tracker's n_updates at the last sample taken */
    uint16_t conf_run;          /* an identification was started (a verdict is owed) */
    uint16_t conf_judged;       /* fused set: the final pass's RLS part passed its verdict */
    drive_snapshot_t live_snap; /* ISR -> background: running estimates, 100 Hz */
    uint16_t live_div;          /* samples since the last live snapshot */
    param_extract_t live;       /* background: estimates from the running RLS */
    drive_telemetry_t telemetry;
    drive_cmd_t pending_cmd;
};

#endif /* DRIVE_TYPES_H */
