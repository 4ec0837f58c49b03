/**
 * @file drive.h
 * The drive application: owns one instance of every control and estimation
 * module and runs them in the order of the 15 kHz ISR.  drive_t itself is in
 * drive_types.h (its rooms: docs/architecture.md); outside src/app it is read
 * only through drive_probe.h (host, tests) or drive_get_telemetry (firmware).
 *
 * drive_isr()  = hal_adc_read + hal_qep_read_count + drive_step + hal_pwm_write
 * drive_step() = the pure core: raw inputs in, compare values out, no HAL,
 *                so the co-simulation API and tests can call it directly.
 */
#ifndef DRIVE_H
#define DRIVE_H

#include <stdint.h>
#include "IQmathLib.h"
#include "drive_config.h"
#include "hal_adc.h"
#include "hal_pwm.h"
#include "hal_qep.h"

typedef struct drive drive_t;   /* defined in drive_types.h */

/** Commands from the application / telemetry link (background context). */
typedef enum {
    DRIVE_CMD_NONE = 0,
    DRIVE_CMD_START_IDENT,   /* calibrate, magnetise, accelerate, identify */
    DRIVE_CMD_STOP,          /* ramp to zero speed, PWM off */
    DRIVE_CMD_RESET_FAULT,   /* clear a latched fault once its cause is gone */
    DRIVE_CMD_SELECT_STANDSTILL,  /* the next starts run the standstill sequence (IDLE only;
                                     a drive configured without the standstill test,
                                     ident.standstill = 0, refuses the next start instead:
                                     DRIVE_PUB_NO_STANDSTILL) */
    DRIVE_CMD_SELECT_ROTATING     /* the next starts run the configured rotating sequence
                                     (IDLE only) */
} drive_cmd_t;

/** Why the last identification's set is, or is not, published
 *  (drive_telemetry_t.publish_reason; drive_background.c decides, once per
 *  identification, from the final pass's data: ident_conf.h). */
typedef enum {
    DRIVE_PUB_PENDING = 0,      /* no verdict yet (the sequence has not reached it) */
    DRIVE_PUB_PUBLISHED,        /* the set is published, every parameter within the limits */
    DRIVE_PUB_NOT_CONVERGED,    /* no plausible estimate, or the estimate still moved: the
                                   mid-window extraction differs by more than the limit */
    DRIVE_PUB_LOW_EXCITATION,   /* the acceleration did not excite the regression enough:
                                   a regression error is amplified beyond the limit */
    DRIVE_PUB_HIGH_RESIDUAL,    /* the model does not fit the data (residual above the limit) */
    DRIVE_PUB_LOW_CONFIDENCE,   /* a parameter's confidence bound above the limit */
    DRIVE_PUB_IMPLAUSIBLE,      /* the extraction failed or left its plausibility range */
    DRIVE_PUB_FAULT,            /* a protection tripped before the set was complete */
    DRIVE_PUB_TIMEOUT,          /* steady state not confirmed within the SETTLE limit */
    DRIVE_PUB_STOPPED,          /* stopped by a command before the verdict */
    DRIVE_PUB_BUS_LOW,          /* not started: the measured bus cannot carry the no-load
                                   voltage at the least target speed (drive_target.h) */
    DRIVE_PUB_ROTOR_TURNING,    /* not started, or ended at standstill: the rotor turned
                                   while the drive needs it at rest (a coasting load) */
    DRIVE_PUB_TORQUE_LIMIT,     /* SETTLE's limit ran out with the speed loop at its torque
                                   current's limit: the load needs more torque than
                                   controller.max_torque_current_A gives at the target */
    DRIVE_PUB_NO_STANDSTILL,    /* not started: the standstill sequence was selected and this
                                   configuration cannot run it (ident.standstill = 0, or its
                                   injection out of range): nothing turned */
    DRIVE_PUB_N
} drive_pub_reason_t;

/** A short name of a drive_pub_reason_t ("published", "not_converged", ...;
 *  "unknown" out of range): telemetry decoders and reports use the same. */
const char *drive_pub_reason_str(uint16_t reason);

#define DRIVE_CONF_NP 6u   /* confidences: Rs, Rr, Lm, Lr, psi_r, Tr (ident_conf.h) */

/** A snapshot for telemetry and data logging (per unit, Q GLOBAL_Q; Tr Q20). */
typedef struct {
    uint16_t state;          /* identification / drive state (id_state_t) */
    uint16_t fault;          /* latched fault code, 0 = none */
    uint16_t pwm_on;         /* 1 while the bridge switches */
    uint16_t params_valid;   /* 1 once identified parameters are published */
    _iq speed;               /* rotor electrical speed, pu of w_base */
    _iq speed_ref;           /* pu */
    _iq i_m, i_t;            /* M/T currents, pu of I_base */
    _iq vdc;                 /* DC bus, pu of V_base */
    _iq Rs, Rr, Lm, Lr, psi_r;  /* published parameters, pu; only a plausible set is
                                   published, an implausible one leaves the last good
                                   set (and params_valid) as is */
    _iq20 Tr;                /* published Tr, Q20 pu time (up to 2048: large motors) */
    uint32_t rls_sat_count;  /* RLS saturation events (rls_t.sat_count), never wraps */
    uint32_t theta_rejects;  /* RLS samples whose theta the guard rejected (theta_guard.h) */
    uint16_t publish_rejects;/* identifications whose set was refused (publish_reason), not published */
    /* the adaptive sequence: adaptation and drift tracking (orientation 1 only) */
    uint16_t pass;           /* identification pass under way or last done (1, 2, ...) */
    uint16_t track_valid;    /* 1 while Rr_track / Tr_track follow the motor (RUN, tracking on) */
    _iq Rs_dc;               /* Rs measured at standstill (end of magnetisation), pu; 0: none */
    _iq sigma_ls_dc;         /* sigma Ls measured at standstill, pu of L_base; 0: none */
    _iq Rr_track;            /* tracked rotor resistance, pu of Z_base */
    _iq20 Tr_track;          /* tracked Tr, Q20 pu time */
    uint16_t isr_overruns;   /* control ISRs that ran past their period (isr_monitor.h), saturating */
    uint16_t params_tracked; /* 1: the published Rs is the standstill one and Rr, Tr the tracked
                                ones (each background pass while track_valid); Lm, Lr, psi_r
                                stay the RLS's */
    uint16_t rls_dropped;    /* RLS samples lost to a full ISR -> background queue (the
                                background fell behind by more than DRIVE_RLSQ_LEN slow
                                periods), saturating */
    uint16_t params_withdrawn;   /* published sets withdrawn because a fault latched within
                                    the guard's window after them (publish_guard.h) */
    uint16_t withdraw_reason;    /* the fault code of the last withdrawal (0: none) */
    /* the publication's verdict and the confidence of each parameter (ident_conf.h) */
    uint16_t publish_reason; /* drive_pub_reason_t of the last identification */
    _iq conf[DRIVE_CONF_NP]; /* Q24, relative (0.01 = 1 %): the confidence of each parameter
                                of the set judged (published or refused); 0: none yet */
    _iq conf_residual;       /* Q24: the regression's residual sqrt(J/Y) of the final pass */
    _iq conf_amp;            /* Q24: its largest amplification (excitation) */
} drive_telemetry_t;

/** A parameter set (per unit, Q GLOBAL_Q; Tr Q20). */
typedef struct {
    _iq Rs, Rr, Lm, Lr, psi_r;
    _iq20 Tr;
} drive_params_t;

/** drive_init results: 0 or the first configuration field found bad. */
typedef enum {
    DRIVE_CFG_OK = 0,
    DRIVE_CFG_BASES,          /* current full scale, bus, rated frequency, poles, PWM */
    DRIVE_CFG_MOTOR,          /* Rs, Rr, Lm, Ls, Lr: positive, Lm < Ls and Lm < Lr */
    DRIVE_CFG_PWM,            /* T1PR = sysclk / (2 f_pwm) outside [100, 65535] */
    DRIVE_CFG_SENSORS,        /* current/bus scaling, encoder */
    DRIVE_CFG_CURRENT_LOOP,
    DRIVE_CFG_SPEED_LOOP,
    DRIVE_CFG_ORIENTATION,
    DRIVE_CFG_VOLTAGE_MODEL,
    DRIVE_CFG_IDENT,          /* filter, RLS, extraction ranges */
    DRIVE_CFG_SEQUENCE,
    DRIVE_CFG_PROTECTION
} drive_cfg_status_t;

/** A short English name of a drive_cfg_status_t. */
const char *drive_cfg_status_str(int16_t status);

/** Compute every constant from the SI configuration.  Returns 0 on success,
 *  a non-zero drive_cfg_status_t naming the bad field otherwise (the drive
 *  then stays in its safe state: PWM off). */
int16_t drive_init(drive_t *d, const drive_config_t *cfg);
/** One control period: the body of the control ISR (hal_adc_read first,
 *  which on the F2812 also re-arms the ADC and the interrupt; the overrun
 *  check last).  Returns that check: 1 if this ISR ran past its period
 *  (hal_isr_overrun), for the caller's load figure. */
uint16_t drive_isr(drive_t *d);
/** The slow ISR: the slow task (drive_slow.c) of the slot of the last
 *  drive_isr, at a lower priority than it (the F2812's INT14, which the
 *  control ISR may preempt; firmware/isr.c).  Must finish before the next
 *  drive_isr ends: one that finds it unfinished counts an overrun
 *  (drive_telemetry_t.isr_overruns; several in a row latch
 *  FAULT_ISR_OVERRUN).  A caller of drive_isr without interrupts (the
 *  simulator) calls it right after drive_isr. */
void drive_slow_isr(drive_t *d);
/** The data log's four channels (i_M, i_T, speed, published Rr; pu, Q
 *  GLOBAL_Q) as the ISR last left them: for the firmware's data log, read
 *  without copying the whole telemetry snapshot. */
void drive_get_log_signals(const drive_t *d, _iq sig[4]);
/** 1 in (after) the slow ISR of DRIVE_LOG_SLOT, one of the schedule's
 *  lightest slow slots: the firmware's data log runs then, in the slow ISR,
 *  never in the control ISR (data at f_pwm / DRIVE_SLOTS, before the log's
 *  own prescaler). */
uint16_t drive_log_due(const drive_t *d);
/** The same without the HAL, and its slow task after it (drive_slow_isr):
 *  one whole period. */
void drive_step(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count,
                hal_pwm_compare_t *out);
/** The bridge's hardware trip input (PDPINTA, 1: tripped) for the next
 *  drive_step; drive_isr reads it from the HAL itself. */
void drive_set_hw_trip(drive_t *d, uint16_t tripped);
/** Low-priority work for the background loop (publishing, telemetry). */
void drive_background(drive_t *d);
/** Request a command; acted on by the next drive_background().  Requests
 *  are latched bits, one per command (DRIVE_CMD_BIT), so that commands from
 *  several sources in one background period (the start button and an SCI
 *  frame, or --cmd at the same time in the simulator) are all kept; a
 *  repeated request counts once.  drive_background takes them in a fixed
 *  order, whatever order they came in: RESET_FAULT first (a START in the
 *  same period then finds the fault cleared), then STOP, then START, which
 *  is dropped when STOP came in the same period (stop wins: a stop is never
 *  overridden).  Call it from the background context only, as
 *  drive_background (the bits are set by a read-modify-write). */
void drive_command(drive_t *d, drive_cmd_t cmd);
/** The request bit of a command in drive_t.cmd_requests. */
#define DRIVE_CMD_BIT(cmd) ((uint16_t)(1u << (unsigned)(cmd)))
/** Set the speed the sequence runs at (pu of w_base; used from ACCELERATE on). */
void drive_set_speed(drive_t *d, _iq speed_pu);
/** The frame angle theta_k the last drive_step Park-transformed its currents
 *  with (pu, [0, 1)): the ifo angle or the observer's, as configured. */
_iq drive_frame_angle(const drive_t *d);
/** Copy the telemetry snapshot (safe to call from the background loop). */
void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t);
/** The adaptive sequence's fused set (drive_background.c): the standstill
 *  Rs, the tracker's Rr and Tr, the RLS's Lm, Lr, psi_r: what the drive
 *  publishes when its verdict allows, and what a refusal concerned.  1 and
 *  *s when the set exists (fused mode, its magnetic part extracted, Rs
 *  measured, the tracker has an estimate); 0 and *s untouched otherwise.
 *  Background context. */
uint16_t drive_fused_set(const drive_t *d, drive_params_t *s);

#endif /* DRIVE_H */
