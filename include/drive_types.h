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
#include "current_model_check.h"
#include "publish_guard.h"
#include "sensor_test.h"
#include "stall_check.h"
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
#include "drive_target.h"
#include "standstill_z.h"
#include "standstill_lf.h"
#include "tr_track.h"
#include "vi_curve.h"
#include "volt_calc.h"

/** The multi-rate schedule of the ISR (drive_step.c): every ISR runs the
 *  fast path, and one of DRIVE_SLOTS slow tasks in turn, so that each ISR
 *  carries an equal share and the slow tasks run at f_pwm / DRIVE_SLOTS
 *  (1.875 kHz at 15 kHz).  Eight slots: no slow task needs more than one
 *  eighth of the slow work (drive_slow.c lists what runs where, and why). */
#define DRIVE_SLOTS_LOG2 3u
#define DRIVE_SLOTS (1u << DRIVE_SLOTS_LOG2)
typedef enum {
    DRIVE_SLOT_SPEED = 0,   /* speed ramp + PI, the fast path's slow constants; the
                               model check's positive sequence (half 0) */
    DRIVE_SLOT_FILTERS_A,   /* the regression's window means, the i_M, i_T filters */
    DRIVE_SLOT_FILTERS_B,   /* the u_M, u_T, w_s i_T filters; the model check's
                               negative sequence and DC (half 1) */
    DRIVE_SLOT_FILTERS_C,   /* the w_s i_M, w_r filters, the rows to the RLS; the checks */
    DRIVE_SLOT_SEQUENCE,    /* identification sequence, adaptation, telemetry, snapshot events */
    DRIVE_SLOT_OBSERVER_A,  /* the rotor-flux observer's models (orientation 1) */
    DRIVE_SLOT_OBSERVER_B,  /* its rotor flux, angle and speed */
    DRIVE_SLOT_SAFETY       /* the model-based protections' slow step (drive_safety.c:
                               the model check's residual, its halves in 0 and 2) */
} drive_slot_t;
/** The firmware's data log runs in the ISR after this slot's, one of the
 *  lightest of the schedule in every state of both orientations
 *  (drive_log_due; tools/bench_isr.py adds its cost there): FILTERS_A, not
 *  FILTERS_B, which carries the model check's heavier half. */
#define DRIVE_LOG_SLOT DRIVE_SLOT_FILTERS_A

/** Gains and constants derived once by drive_init (pu, Q24). */
typedef struct {
    _iq sigma_ls;       /* sigma Ls, pu of L_base: d-axis decoupling */
    _iq lm2_lr;         /* Lm^2 / Lr, pu of L_base: back-EMF feed-forward */
    _iq three_half_step;/* 1.5 f_base Ts: pu angle per pu speed over 1.5 periods */
    _iq i_max;          /* torque-current limit, pu */
    _iq speed_tol;      /* steady state: |speed error| below, pu */
    _iq rest_speed;     /* a start is refused while |speed| is above this, pu
                           (DRIVE_REST_SPEED_OF_RATED) */
    _iq ramp_step;      /* Q24 pu: the speed ramp's step a slow period, configured ... */
    _iq excite_step;    /* ... and in RUN's excitation (drive_adapt.h) */
    uint16_t cal_samples;
    uint16_t live_period;       /* samples between live snapshots */
    uint16_t orientation;       /* DRIVE_ORIENT_IFO or DRIVE_ORIENT_FLUX_OBS */
    _iq rls_ws_min;             /* flux observer: the RLS runs only while |ws_f| is above
                                   this (pu), where the voltage model dominates */
    _iq psi_min;                /* flux observer: below this |psi_r| (pu) its angle is
                                   noise; the frame follows the encoder angle instead */
    uint32_t track_valid_updates;/* tracker updates before Rr_track is valid (tr_track_settle_s) */
    uint16_t conf_track_updates;/* fused set: tracker updates judged (DRIVE_CONF_TRACK_S) */
    uint32_t conf_track_wait;   /* ... RUN samples waited for them (DRIVE_CONF_TRACK_WAIT_S) */
    _iq conf_track_se;          /* Q24: the tracker's standard error per relative residual */
    uint16_t t1pr;              /* the PWM period register (hal_pwm_init) */
    uint16_t config_status;     /* drive_cfg_status_t of drive_init */
} drive_consts_t;

/** An estimate for the parameter extraction: taken by drive_rls_drain at
 *  the queue's event (DRIVE_RLSQ_EXTRACT, DRIVE_RLSQ_LIVE), in the RLS's
 *  own order, and extracted by drive_background right after the drain (both
 *  background: no hand-over between contexts). */
typedef struct {
    _iq theta[RLS_N];   /* RLS estimate at the snapshot (the guard's last good) */
    _iq i_m;            /* steady (filtered) M current, pu */
} drive_snapshot_t;

/** ISR -> background: the regression's samples for the RLS.  The RLS and
 *  its guard run in the background (drive_rls_bg.c), on every sample in
 *  the order the ISR formed them: the ISR forms the filtered rows at the
 *  slow rate (drive_slow.c) and queues them; a queue of DRIVE_RLSQ_LEN
 *  entries rides out DRIVE_RLSQ_LEN - 1 slow periods of a busy background.  Events travel with the next entry and act before
 *  its update: a restart of the RLS (a new pass), the steady-state
 *  snapshot, a live snapshot.  Single writer each side: the ISR writes an
 *  entry, then head; the background reads up to head, then writes tail
 *  (16-bit stores: atomic on the C28x). */
#ifndef DRIVE_RLSQ_LEN
#define DRIVE_RLSQ_LEN 16u          /* power of two: 8.5 ms of background latency at 1.875 kHz
                                       (the 8 KB AVR co-simulation builds with 4) */
#endif
#define DRIVE_RLSQ_UPDATE 1u        /* the sample updates the RLS (rls_on) */
#define DRIVE_RLSQ_RESTART 2u       /* before it: the RLS restarts from rls_start */
#define DRIVE_RLSQ_EXTRACT 4u       /* before it: the steady-state snapshot (snap) */
#define DRIVE_RLSQ_LIVE 8u          /* before it: a live snapshot (live_snap) */
#define DRIVE_RLSQ_WINDOW 16u       /* before it: a new RLS window begins (the confidence's
                                       residual sums restart, ident_conf.h) */
typedef struct {
    _iq y1, y2;                     /* Q24 pu per pu time: rls_t's left-hand sides */
    _iq i_mf, u_mf, i_tf, u_tf, wr_f;   /* Q24 pu: its regressors */
    _iq c1, d1, c2;                 /* Q24 pu: the period-mean form's (rls.h RLS_FORM_FLUX) */
    uint16_t flags;                 /* DRIVE_RLSQ_* */
} drive_rls_sample_t;
typedef struct {
    drive_rls_sample_t e[DRIVE_RLSQ_LEN];
    volatile uint16_t head;         /* next entry the ISR writes */
    volatile uint16_t tail;         /* next entry the background reads */
    uint16_t pending;               /* ISR: events waiting for the next entry */
    uint16_t dropped;               /* ISR: samples lost to a full queue (saturates) */
    uint16_t max_fill;              /* ISR: the most entries waiting at a push */
} drive_rls_queue_t;

/** Parameter adaptation (drive_adapt.c in the ISR, drive_adapt_bg.c in the
 *  background): the ISR's part.  All pu, Q24. */
typedef struct {
    /* configuration (drive_adapt_init) */
    uint16_t passes, standstill, track_rr;
    uint16_t fused;           /* standstill and track_rr: Rs from standstill, Rr and Tr from
                                 the tracker, only Lm, Lr, psi_r from the RLS */
    uint16_t ssz_gap;         /* samples of DC between the sigma Ls test and the Rs reading */
    /* state */
    uint16_t ssz_started;     /* the sigma Ls test of this magnetisation has been started */
    uint16_t blending;        /* the last set applied is a blend step: the tracker does not learn */
    uint16_t track_armed;     /* the tracker has its start value (final pass in) */
    uint16_t prev_state;      /* id_state_t of the last sample */
    uint16_t ticks;           /* SEQUENCE-slot ticks (wraps): the background's clock for the blend */
    uint16_t starved;         /* SEQUENCE-slot ticks in RUN with the tracker held (saturating) */
    uint16_t starve_ticks;    /* ... that start the excitation (DRIVE_EXCITE_STARVE_S) */
    uint16_t ready;           /* the model the sequence waits for is applied (drive_adapt_ready) */
    uint16_t excite;          /* RUN: a free shaft, the speed swings (drive_adapt_excite) */
    uint16_t static_count0;   /* INJECT: the encoder's count at its start */
    uint16_t static_moved;    /* ... and the largest |count - count0| since, counts */
} drive_adapt_t;

/** Background -> ISR: one complete model set, computed by the background
 *  (drive_adapt_bg.c) and copied in by the ISR in its SEQUENCE slot
 *  (drive_adapt.c), all at once or not at all.  Each value one aligned
 *  32-bit word (Q24 pu). */
#define DRIVE_SET_SEAT 0x1u         /* re-seat the observer on the DC solution (standstill) */
#define DRIVE_SET_READY 0x2u        /* the sequence waits for this set: adapt_ready once applied */
#define DRIVE_SET_BLENDING 0x4u     /* a blend step, more follow: the tracker does not learn */
#define DRIVE_SET_TRACK_START 0x8u  /* restart the tracker from theta0 and arm it */
#define DRIVE_SET_ALIGN 0x10u       /* hand the control frame to ifo (the first tracked set) */
typedef struct {
    flux_obs_model_t fobs;    /* the observer's model (7 words); sigma Ls also decouples */
    ifo_tr_t ifo;             /* ifo's Tr constants (3) */
    pi_gains_t pi;            /* the current PIs' gains, both axes (3) */
    _iq lm2_lr;               /* Lm^2 / Lr, pu of L_base: the back-EMF feed-forward */
    _iq inv_lm;               /* 1 / Lm (<= 16): ifo_align's flux -> i_mr */
    _iq theta0;               /* the tracker's start 1/Tr (DRIVE_SET_TRACK_START) */
    flux_obs_seat_t seat;     /* the DC re-seat (DRIVE_SET_SEAT) */
    uint16_t flags;           /* DRIVE_SET_* */
    uint16_t state, pass;     /* the id_state_t and pass it was made for: applied only then */
} drive_model_set_t;

/** The one-slot mailbox of model sets.  The background writes the set only
 *  while ready = 0 and sets ready last; the ISR reads only while ready = 1,
 *  says what it did in taken and clears ready last.  The background writes
 *  the set through a volatile lvalue (drive_adapt_bg.c): its stores are
 *  done, in program order, before the one of ready, so the ISR never sees
 *  ready set before the whole set is written.  The ISR reads the set plainly:
 *  the background cannot run while it does. */
#define DRIVE_BOX_APPLIED 1u
#define DRIVE_BOX_DROPPED 2u        /* made for a state (or pass) the sequence has left */
typedef struct {
    drive_model_set_t set;
    volatile uint16_t taken;    /* DRIVE_BOX_APPLIED or _DROPPED (ISR, before clearing ready) */
    volatile uint16_t ready;
} drive_adapt_box_t;

/** ISR -> background: what the standstill result needs, captured at the end
 *  of the magnetisation (data first, ready last; the background copies it
 *  and clears ready). */
typedef struct {
    _iq u_mf, u_tf, i_mf, i_tf;     /* the regression's filtered M-T voltage, current (DC) */
    _iq theta_r;                    /* the encoder angle: the frame they are in */
    _iq psi_cm_alpha, psi_cm_beta;  /* the observer's current-model rotor flux */
    _iq us, uc, is, ic;             /* the sigma Ls lock-in's sums (standstill_z) */
    uint16_t ssz_done;              /* its window completed */
    uint16_t ready;
} drive_adapt_capture_t;

/** Parameter adaptation: the background's part (drive_adapt_bg.c; float
 *  allowed).  The model as (Rs, Lm, Lr, Ls, Tr), pu Q24. */
#define DRIVE_ADAPT_NP 5u   /* rs, lm, lr, ls, tr */
typedef struct {
    /* configuration (drive_adapt_init) */
    float ts_pu;              /* Ts, pu time (the design functions) */
    float obs_ts_pu;          /* the observer's step n Ts, pu time (its Tr constants) */
    float imr_min_pu;         /* ifo's guard (its Tr bound) */
    float kp_per_sls;         /* current-loop kp per pu of sigma Ls (kp = w_c sigma Ls) */
    float ki_per_rs;          /* current-loop ki per pu of Rs (ki = w_c Ts Rs) */
    _iq rs_lo, rs_hi;         /* plausible standstill Rs (a factor 4 of the believed) */
    _iq blend_step;           /* Q24 fraction per SEQUENCE tick: the blend lasts DRIVE_ADAPT_BLEND_S */
    uint16_t blend_ticks;     /* ticks of a whole blend */
    _iq tr_rate;              /* largest relative change of the applied Tr per tracker update */
    /* the model the ISR runs (the last set it applied) and its constants;
     * in applied, posted, from and to each parameter in Q24 pu except
     * [DRIVE_P_TR], Q20 pu time (as ifo_tr_t.tr: large motors' Tr > 128) */
    _iq applied[DRIVE_ADAPT_NP];
    drive_model_set_t applied_set;
    _iq posted[DRIVE_ADAPT_NP];   /* the model of the set in the mailbox */
    uint16_t pending;         /* a set was posted and its answer (taken) not yet read */
    /* the blend towards a pass's model */
    _iq from[DRIVE_ADAPT_NP], to[DRIVE_ADAPT_NP];
    uint16_t blending;
    uint16_t blend_t0;        /* drive_adapt_t.ticks at its start */
    uint16_t blend_state, blend_pass;   /* the sequence's state and pass it is for */
    uint16_t blend_track;     /* the first set starts the tracker (RUN) */
    _iq theta0;               /* ... from this 1/Tr */
    _iq lr;                   /* Lr of the last identification (Rr_track = Lr / Tr) */
    /* a pass's extraction (drive_adapt_post) */
    _iq m_rs, m_lm, m_lr, m_ls;
    _iq20 m_tr;               /* Q20, pu time (param_extract_t.Tr) */
    uint16_t m_valid;         /* 0: the extraction was implausible (keep the old model) */
    uint16_t m_full;          /* 1: all parameters; 0: the magnetic part only (lm, lr, ls) */
    uint16_t m_ready;
    uint16_t m_seed;          /* 1: the standstill sequence's set (drive_adapt_seed), applied at rest */
    /* tracking */
    uint32_t n_seen;          /* the tracker's n_updates the last Tr was made from */
} drive_adapt_bg_t;

/** The protections that do not trust one sensor (drive_safety.c): the
 *  model-based current plausibility (SAFETY slot), the sensors' pulse test
 *  before the magnetisation, the rotor checks (count step every period,
 *  locked rotor at the encoder's frozen trip), and what they need of the
 *  drive's constants (pu, Q24). */
typedef struct {
    current_model_check_t cmc;   /* measured currents against the model -> FAULT_CURRENT_SENSOR */
    sensor_test_t stest;         /* pulse test in CALIBRATE -> FAULT_SENSOR_TEST */
    stall_check_t stall;         /* count step -> FAULT_ENCODER; locked rotor -> FAULT_STALL */
    publish_guard_t pguard;      /* background: a set published while a fault developed is
                                    withdrawn */
    _iq rs;                      /* Q24 pu: the nameplate's Rs (the model in orientation 0) */
    float tau_r_pu;              /* the model check's memory, pu time (diagnostic, host) */
    _iq k_allow;                 /* Q24: tau_r alpha_max Ts_slow (pu), the back-EMF allowance
                                    per slow step of frozen counts per pu of |psi_e| */
    uint16_t allow_n_max;        /* the frozen count is taken at most this (k_allow n <= 2) */
    _iq k_emf;                   /* Q24: k_emf tau_r (pu time): the allowance for the model's
                                    back-EMF error per pu of |w_s| |psi_e| */
    _iq k_emf_ident;             /* Q24: the same once the model is identified (the tracker
                                    valid) */
    _iq ws_slip_max;             /* Q24 pu: the frame speed's bound above the encoder's rotor
                                    speed, CMC_SLIP_MARGIN times the believed slip at the
                                    torque-current limit (<= 2) */
    _iq psi_e;                   /* Q24 pu: the model's back-EMF flux of the last slow step */
    uint16_t model_step;         /* SEQUENCE slot -> SAFETY slot: the model stepped (a pass's
                                    blend, the frame's hand-over; drive_adapt.c take_set) */
    uint16_t test_done;          /* SAFETY slot: the sensor test passed
                                    (drive_safety_test_done) */
} drive_safety_t;

/* ------------------------------------------------------------------------
 * The drive's rooms: one struct a concept, each written by the module files
 * that own it (docs/architecture.md maps them).  Contexts: [F] the fast
 * path of every ISR (drive_step.c), [S] the slow task of one slot
 * (drive_slow.c), [B] the background (drive_background.c and the *_bg.c).
 * ---------------------------------------------------------------------- */

/** Sensing [F]: the phase currents (offsets, calibration), the bus, the
 *  encoder and the Clarke transform of the currents. */
typedef struct {
    phase_current_t phase;      /* the two Hall channels: offsets, scale, calibration */
    dc_bus_t bus;
    qep_speed_t qep;            /* angle; speed for the loops (window 16); speed over one
                                   sample for the regression (speed_1: its lag, half a
                                   period, matches the mid-period voltage) */
    clarke_t clarke;
    uint16_t cal_done;          /* [F]: the offsets' calibration ended (done or rejected); the
                                   background clears it at a start (drive_cal_done) */
} drive_sense_t;

/** The control loops (drive_step.c [F], the speed loop drive_slow.c [S]). */
typedef struct {
    park_t park;
    ipark_t ipark;
    pi_ctrl_t pi_speed, pi_id, pi_iq;
    ramp_gen_t speed_ramp;
    _iq i_t_ref;                /* Q24 pu: the torque-current reference of this period */
    _iq i_t_step;               /* Q24 pu: its step per period towards the speed loop's
                                   latest output (drive_slow.c: first-order hold over the
                                   slow period; |.| <= 2 / DRIVE_SLOTS) */
    _iq im_inject;              /* Q24 pu: added to the i_M reference (standstill test) */
} drive_loops_t;

/** The control frame: indirect field orientation (orientation 0) or the
 *  rotor-flux observer (orientation 1), and the angle and speed of the frame
 *  the loops run in (drive_frame.c [F], the observer's steps [S]). */
typedef struct {
    ifo_t ifo;                  /* orientation 0: indirect (not run in mode 1) */
    flux_obs_t fobs;            /* orientation 1: rotor-flux observer (not run in mode 0) */
    uint16_t run_ifo;           /* orientation 1, RUN with tracking: control frame from ifo with
                                   the tracked Tr (drive_adapt.c) */
    uint16_t fobs_hold;         /* orientation 1: frame held on the encoder angle (|psi_r| <
                                   psi_min or magnetising) */
    /* orientation 1: the observer's window (summed every period) and its
     * angle between steps (extrapolated every period on ws_f) */
    _iq su_alpha, su_beta;      /* Q24 pu: sum of the periods' voltages, each limited to
                                   the observer's input range (|.| <= 8 x 4) */
    _iq si_alpha, si_beta;      /* Q24 pu: sum of the samples' currents (|.| <= 8 x 1.2:
                                   the sensors' full scale is I_base) */
    _iq i0_alpha, i0_beta;      /* Q24 pu: the current at the window's start sample */
    _iq obs_theta;              /* Q24 pu [0, 1): the observer's angle of this sample */
    _iq obs_dtheta;             /* Q24 pu: its step per period, ws_f f_base Ts */
    /* the frame of this sample, whichever model gives it */
    uint16_t is_ifo;            /* this ISR's control frame is ifo's (drive_ifo_frame) */
    _iq theta;                  /* Q24 pu [0, 1): the frame angle of this sample */
    _iq ws;                     /* Q24 pu: the frame's speed over the period that just ended */
    _iq ws_ctl;                 /* Q24 pu: the frame speed for decoupling and modulation */
} drive_frame_t;

/** The PWM pipeline [F]: duties computed at sample k apply during period
 *  k+1 and are reconstructed into voltages at sample k+2 (hal_pwm.h timing). */
typedef struct {
    svgen_t svgen;
    volt_calc_t volt;
    _iq duty_next[3];           /* computed at k-1, applied now (those of k-2, applied in
                                 * the period just ended: volt.da, .db, .dc) */
    uint16_t on_next, on_last;  /* bridge switching in those periods */
    _iq ia_prev, ib_prev;       /* phase currents of the previous sample, pu */
} drive_pwm_t;

/** The identification path: the regression's filters [S], the queue to the
 *  RLS, the RLS and its guard [B], the extraction [B], and the confidence's
 *  sums that travel with the steady-state snapshot. */
typedef struct {
    drive_ident_t cfg;          /* kept to restart the RLS [B] */
    ident_regressor_t reg;
    uint16_t reg_count;         /* encoder count at the last FILTERS slot (the regression's window) */
    drive_rls_queue_t rlsq;     /* [S] -> [B]: the RLS's samples and events */
    rls_t rls;                  /* [B]; each pass starts it afresh (drive_rls_start) */
    theta_guard_t guard;        /* last good theta: what the snapshots carry */
    param_extract_t pex;
    drive_snapshot_t snap;      /* [B]: the steady-state extraction's estimate */
    /* the identification's confidence (ident_conf.h): the sums over the RLS
     * pass under way; the covariance and the sums taken with snap */
    ident_conf_acc_t acc;
    rls_cov_t snap_cov;
    ident_conf_acc_t snap_acc;
    uint32_t snap_pd;           /* rls_t.pd_count of the window */
    drive_snapshot_t live_snap; /* running estimates, 100 Hz */
    uint16_t live_div;          /* samples since the last live snapshot */
    param_extract_t live;       /* [B]: estimates from the running RLS */
} drive_ident_path_t;

/** The verdict [B]: the confidence of the set, the tracker's fit, the fused
 *  set, the sensors' possible gain error, and what is published. */
typedef struct {
    ident_conf_t conf;
    _iq theta_mid[RLS_N];       /* Q24 pu: the guarded estimate at mid-window */
    _iq speed_mid;              /* Q24 pu: |speed| at which it is taken */
    uint16_t mid;               /* 0: none, 1: armed (speed_mid set), 2: taken */
    uint16_t pass;              /* the pass the capture belongs to */
    ident_conf_fit_t trk_fit;   /* the tracker's fit while it is valid (fused set) */
    _iq trk_theta0;             /* Q24: its 1/Tr at the first sample of the fit */
    uint32_t trk_updates;       /* the tracker's n_updates at the last sample taken */
    uint16_t run;               /* an identification was started (a verdict is owed) */
    uint16_t judged;            /* fused set: the final pass's RLS part passed its verdict */
    uint16_t static_judged;     /* the standstill sequence's set judged (drive_static.c) */
    uint16_t static_unavailable;   /* the standstill sequence was selected and cannot run:
                                      starts are refused (drive_static_select) */
    _iq fused_lm, fused_lr, fused_psi;   /* fused mode: the last good magnetic set */
    uint16_t fused_ready;
    float sensor_gain;          /* the current sensors' possible gain error at the verdict
                                   (drive_safety_sensor_gain), relative */
    float sg_neg_a, sg_neg_b;   /* the model check's negative sequence summed over the last
                                   pass's SETTLE and RUN (pu flux) */
    float sg_den;               /* ... and CMC_NEG_PER_GAIN sigma Ls |i|, summed alike */
    uint32_t sg_n;              /* background passes summed (0: none yet) */
} drive_verdict_t;

/** The bridge's voltage error at standstill, the compensation's curve
 *  (drive_vi.c): the test [S], its fit [B]. */
typedef struct {
    vi_curve_t test;            /* [S], SEQUENCE slot: the test (CALIBRATE) */
    uint16_t status;            /* [B]: the fit's verdict (vi_fit_status_t; the table itself
                                   is recomputed from test by whoever reports it) */
    volt_calc_curve_t curve;    /* [B] -> [F]: the curve for volt_calc */
    volatile uint16_t post;     /* [B] -> [S]: DRIVE_VI_* (drive_vi.h) */
    uint16_t fitted;            /* [B]: the fit of this test is done */
    uint32_t wait;              /* [S]: slow samples waited for the background's answer */
    uint32_t wait_max;          /* the longest wait; then the test is refused */
    float dt_frac;              /* the board's td / Ts [B] */
    float i1_0;                 /* the test's first i1, pu [B] */
    float i1_max;               /* the largest i1 of a retry, pu: 2 i1 within the current
                                   limit [B] */
    float rs;                   /* [B]: the curve test's Rs (pu of Z_base; 0: none), the
                                   standstill Rs's confidence (drive_background.c) */
    uint16_t retried;           /* [B]: the test was run again with a larger i1 */
    uint16_t done;              /* [S]: the curve is measured and applied (drive_vi_done);
                                   kept over later starts */
} drive_bridge_test_t;

/** Parameter adaptation: standstill, passes, tracking (drive_adapt.c [S],
 *  drive_adapt_bg.c [B]) and the two mailboxes between them. */
typedef struct {
    drive_adapt_t isr;          /* [S]: the sequence's side */
    drive_adapt_bg_t bg;        /* [B]: the models and their constants */
    drive_adapt_box_t box;      /* [B] -> [S]: model sets */
    volatile drive_adapt_capture_t cap;     /* [S] -> [B]: the standstill values */
    tr_track_t track;           /* Rr/Tr tracker in RUN (track_rr) */
    standstill_z_t ssz;         /* standstill sigma Ls (standstill) */
    standstill_lf_t lf;         /* the standstill sequence's injection (static_id) */
} drive_adaptation_t;

/** The protections: the trips, the sensors' plausibility, the ISR monitor
 *  and the model-based checks that do not trust one sensor. */
typedef struct {
    protect_t trip;             /* over-current, bus, speed trips; the latched fault */
    encoder_check_t enc;        /* encoder plausibility -> FAULT_ENCODER */
    current_check_t feedback;   /* current feedback plausibility -> FAULT_CURRENT_SENSOR */
    isr_monitor_t ovr;          /* ISR overruns -> FAULT_ISR_OVERRUN */
    drive_safety_t model;       /* model-based plausibility (drive_safety.c) */
} drive_protections_t;

/** The multi-rate schedule (drive_step.c): the fast ISR's slot and what it
 *  hands the slow ISR (drive_slow_isr); written by both contexts, hence
 *  the volatile hand-shake. */
typedef struct {
    uint16_t slot;              /* drive_slot_t of the next fast ISR (0 .. DRIVE_SLOTS-1) */
    uint16_t slow_slot;         /* drive_slot_t of the last fast ISR */
    volatile uint16_t slow_due; /* 1: requested by the fast ISR, not yet started */
    volatile uint16_t slow_busy;/* 1: the slow task is running */
    uint16_t slow_late;         /* 1: a fast ISR found the last slow task unfinished */
} drive_schedule_t;

struct drive {
    /* in the order of the ISR's use: the rooms the control ISR touches every
     * period first, the background's large ones last (short offsets) */
    base_values_t base;
    drive_consts_t k;           /* constants drive_init derives (and its status) */
    drive_schedule_t sched;
    drive_sense_t sense;
    drive_loops_t loop;
    drive_frame_t frame;
    drive_pwm_t pwm;
    drive_protections_t prot;
    id_sequence_t seq;          /* the identification sequence's states */
    drive_target_t target;      /* the identification's target within the bus (drive_target.h) */
    drive_bridge_test_t vi;
    drive_adaptation_t adapt;
    drive_ident_path_t id;
    drive_verdict_t verdict;
    drive_telemetry_t telemetry;
    uint16_t cmd_requests;      /* DRIVE_CMD_BIT of each command requested since the last
                                   drive_background (drive_command) */
};

#endif /* DRIVE_TYPES_H */
