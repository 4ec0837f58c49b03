/**
 * @file imfoc_api.h
 * Co-simulation API (host only): independent firmware instances that an
 * external plant (Python, Simulink, another C program) drives one ISR period
 * at a time.  Built as the shared library `libimfoc` (host_sim/api/); wrapped
 * for Python by the `imfoc` package (tools/python/).
 *
 * Each instance owns its own drive_t (heap-allocated here, on the host; the
 * firmware itself never allocates) and runs the unchanged core:
 * imfoc_step_*() is drive_step() - the body of the F2812's 15 kHz ISR without
 * the HAL - plus, every `background_div` periods, drive_background() (the
 * background loop: commands, parameter publication), as motor_sim does.
 * Instances share nothing: any number may run side by side, and instances on
 * different threads need no lock (one instance must not be stepped from two
 * threads at once).
 *
 * Timing contract (hal_pwm.h, as on the F2812): the inputs of a step are the
 * values sampled at the start of PWM period k (ADC at the EV-A T1 underflow,
 * the QEP counter T2CNT); the compare values / duties returned must be
 * applied by the plant over period k+1 (the next one), not period k.
 *
 * Inputs, two forms:
 *   raw       ADCRESULTn as the F2812 reads them (12-bit code left-justified,
 *             code << 4) and T2CNT;
 *   physical  phase currents (A), DC bus (V) and mechanical rotor angle (rad),
 *             converted with the board's scaling of the configuration:
 *             current  pin = 1.5 V + 1.5 V i / I_fs  (+-I_fs -> 0..3 V)
 *             bus      pin = 3.0 V vdc / Vdc_fs
 *             ADC      code = floor(4095 pin / 3.0 V), clamped to 0..4095
 *                      (the F281x quantiser, no noise), result = code << 4
 *             angle    T2CNT = round(theta_m 4 N / 2 pi) mod 2^16 (N lines,
 *                      x4 decoding, 16-bit wrap; count 0 at theta_m = 0).
 *             The angle may be given wrapped or unwrapped: the instance
 *             accumulates its change wrapped to (-pi, pi], so the rotor must
 *             turn less than half a revolution per period (at 15 kHz: below
 *             450 000 r/min).
 *
 * Errors: every function checks its pointers and arguments and returns an
 * imfoc_status_t (< 0) instead of touching bad memory; a failed create
 * returns NULL with the reason in the caller's buffer.  Non-finite physical
 * inputs are rejected (IMFOC_ERR_RANGE) and the step is not run.
 */
#ifndef IMFOC_API_H
#define IMFOC_API_H

#include <stddef.h>
#include <stdint.h>

#include "drive_config.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Bumped whenever a struct below changes layout (wrappers check it). */
#define IMFOC_API_VERSION 4   /* 2: the adaptive sequence's signals at the end of imfoc_signals_t;
                                 3: Rs_ohm..Tr_s are the published set, the last
                                    extraction moved to extract_*;
                                 4: the publication's verdict and confidences at the
                                    end (publish_reason, conf_*) and
                                    imfoc_publish_reason_str */

typedef struct imfoc imfoc_t;   /* opaque: one firmware instance */

typedef enum {
    IMFOC_OK = 0,
    IMFOC_ERR_NULL = -1,      /* a NULL instance or pointer */
    IMFOC_ERR_CONFIG = -2,    /* the INI file or drive_init refused the configuration */
    IMFOC_ERR_NOMEM = -3,
    IMFOC_ERR_RANGE = -4,     /* an argument out of range or not finite */
    IMFOC_ERR_COMMAND = -5    /* unknown command */
} imfoc_status_t;

/** Commands (drive_cmd_t), acted on at once (the background loop is run). */
typedef enum {
    IMFOC_CMD_START_IDENT = 1,  /* calibrate, magnetise, accelerate, identify */
    IMFOC_CMD_STOP = 2,
    IMFOC_CMD_RESET_FAULT = 3,
    IMFOC_CMD_SELECT_STANDSTILL = 4,  /* the next starts: the standstill sequence (drive.h) */
    IMFOC_CMD_SELECT_ROTATING = 5     /* the next starts: the configured rotating sequence */
} imfoc_cmd_t;

/** Fixed facts of an instance: per-unit bases, timing, board scaling (SI). */
typedef struct {
    double Ts_s;                 /* ISR / PWM period */
    double I_base_A, V_base_V, f_base_Hz, w_base_rad_s, t_base_s;
    double Z_base_ohm, L_base_H, psi_base_Wb, n_base_rpm;
    double current_full_scale_A; /* Hall full scale (+-) */
    double vdc_full_scale_V;     /* bus voltage that reads 3.0 V */
    uint16_t t1pr;               /* EV-A T1 period: CMPR range [0, T1PR] */
    uint16_t pole_pairs;
    uint16_t encoder_lines;      /* x4 counts per revolution in T2CNT */
    uint16_t background_div;     /* ISR periods per background call (0: never) */
} imfoc_info_t;

/** One period of raw inputs, as the F2812 sees them. */
typedef struct {
    uint16_t ia_raw, ib_raw, vdc_raw;  /* ADCRESULTn, 12-bit code << 4 */
    uint16_t qep_count;                /* T2CNT */
    uint16_t trip;                     /* PDPINTA: 1 = power stage tripped */
} imfoc_raw_in_t;

/** One period of physical inputs (sampled at the period start). */
typedef struct {
    double ia_A, ib_A;     /* phase currents, into the motor */
    double vdc_V;          /* DC bus */
    double theta_m_rad;    /* mechanical rotor angle (wrapped or not) */
    uint16_t trip;         /* PDPINTA: 1 = power stage tripped */
} imfoc_phys_in_t;

/** What the ISR hands to the inverter, for the NEXT period. */
typedef struct {
    uint16_t cmpr[3];      /* CMPR1..3, [0, T1PR]; T1PR = upper switch off */
    uint16_t pwm_on;       /* 1: the bridge switches; 0: all six switches off */
    double duty[3];        /* upper-switch on-time fraction, (T1PR - CMPR) / T1PR */
    double v_phase_V[3];   /* commanded phase-to-neutral voltages (period averages,
                              ideal inverter at the firmware's measured bus:
                              (duty_x - mean duty) vdc); 0 while pwm_on = 0 */
} imfoc_out_t;

/** Internal signals after the last step (SI unless marked pu). */
typedef struct {
    uint32_t isr_count;            /* steps run since create */
    uint16_t state;                /* id_state_t (id_sequence.h) */
    uint16_t fault;                /* fault_code_t (protect.h), 0 = none */
    uint16_t pwm_on;
    uint16_t params_valid;         /* identified parameters published */
    uint16_t live_valid;           /* the running estimates passed their checks */
    uint16_t rls_on;               /* the RLS updates in this state */
    double speed_rpm;              /* measured mechanical speed (speed-loop filter) */
    double speed_ref_rpm;          /* ramped reference */
    double ia_A, ib_A, vdc_V;      /* the firmware's measurements */
    double i_m_A, i_t_A;           /* M-T currents */
    double i_mr_A;                 /* magnetising current of the orientation model */
    double theta_e_rad;            /* frame (rotor-flux) angle, electrical, [0, 2 pi) */
    double w_frame_rad_s;          /* frame speed, electrical */
    double u_alpha_V, u_beta_V;    /* reconstructed voltage of the period just ended */
    double u_m_ref_V, u_t_ref_V;   /* current-PI outputs (voltage references) */
    /* identification (method §2-§3), pu: the RLS estimate and its regression */
    double K[4];                   /* K1, K2, K3 (or K3'), K4 */
    double y1, y2, i_mf, u_mf, i_tf, u_tf, wr_f;
    uint32_t rls_updates;          /* scalar RLS updates done */
    /* parameters: live (from the running RLS, 100 Hz) and published (what the drive
     * reports as identified, the telemetry's Rs..Tr: the last plausible extraction, or
     * with [ident] track_rr = 1 the fused set of standstill Rs, tracked Rr and Tr and the
     * RLS's Lm, Lr, psi_r; valid when params_valid) */
    double live_Rs_ohm, live_Rr_ohm, live_Lm_H, live_Lr_H, live_psi_r_Wb, live_Tr_s;
    double Rs_ohm, Rr_ohm, Lm_H, Lr_H, psi_r_Wb, Tr_s;
    /* the adaptive sequence: adaptation and tracking (0 when not measured / not valid) */
    uint16_t pass;                 /* identification pass */
    uint16_t track_valid;          /* Rr_track, Tr_track follow the motor */
    uint16_t params_tracked;       /* the published set is the fused one */
    double Rs_dc_ohm;              /* standstill Rs */
    double sigma_ls_dc_H;          /* standstill sigma Ls */
    double Rr_track_ohm, Tr_track_s;   /* tracked */
    /* API version 3: the last extraction from the RLS (end of SETTLE, each pass), as
     * extracted, whether or not it was plausible and published (extract_valid) */
    uint16_t extract_valid;
    double extract_Rs_ohm, extract_Rr_ohm, extract_Lm_H, extract_Lr_H, extract_psi_r_Wb,
        extract_Tr_s;
    /* API version 4: why the last identification's set is or is not published
     * (drive_pub_reason_t of drive.h: 0 pending, 1 published, 2 not_converged, ...;
     * imfoc_publish_reason_str names it), and the confidence of each parameter of the
     * set judged, relative (0.01 = 1 %; negative: not available), with the regression's
     * relative residual, amplification and excitation (ident_conf.h) */
    uint16_t publish_reason;
    double conf_Rs, conf_Rr, conf_Lm, conf_Lr, conf_psi_r, conf_Tr;
    double conf_residual, conf_amplification, conf_excitation;
} imfoc_signals_t;

/** IMFOC_API_VERSION of the library (compare with the header's). */
int32_t imfoc_api_version(void);
/** A short English text for an imfoc_status_t. */
const char *imfoc_status_str(int32_t status);
/** The name of a publish_reason ("pending", "published", "not_converged", ...;
 *  "unknown" out of range): the telemetry's and report.json's names. */
const char *imfoc_publish_reason_str(int32_t reason);

/** New instance from a simulator INI file (host_sim/config/; the firmware part
 *  of it: sim_config_load + sim_config_to_drive).  NULL on error, the reason
 *  in @p err (may be NULL). */
imfoc_t *imfoc_create_ini(const char *path, char *err, size_t err_len);
/** New instance from a drive configuration (SI).  NULL on error. */
imfoc_t *imfoc_create(const drive_config_t *cfg, char *err, size_t err_len);
/** Free an instance (NULL is ignored). */
void imfoc_destroy(imfoc_t *h);

int32_t imfoc_get_info(const imfoc_t *h, imfoc_info_t *info);
/** Background calls every @p div periods (default 15: 1 kHz at 15 kHz); 0: only
 *  through imfoc_background(). */
int32_t imfoc_set_background_div(imfoc_t *h, uint16_t div);
/** Run the background loop once (commands, publication of parameters). */
int32_t imfoc_background(imfoc_t *h);
/** Queue a command and run the background once so that it takes effect. */
int32_t imfoc_command(imfoc_t *h, int32_t cmd);
/** Target speed of the identification run, mechanical r/min (|n| < 128 pu). */
int32_t imfoc_set_speed_rpm(imfoc_t *h, double rpm);

/** One ISR with raw inputs; @p out may be NULL. */
int32_t imfoc_step_raw(imfoc_t *h, const imfoc_raw_in_t *in, imfoc_out_t *out);
/** One ISR with physical inputs (converted as in the file comment). */
int32_t imfoc_step_phys(imfoc_t *h, const imfoc_phys_in_t *in, imfoc_out_t *out);
/** The raw inputs imfoc_step_phys would feed (does not step; the angle is
 *  converted as the unwrapped value given). */
int32_t imfoc_phys_to_raw(const imfoc_t *h, const imfoc_phys_in_t *in, imfoc_raw_in_t *raw);

int32_t imfoc_get_signals(const imfoc_t *h, imfoc_signals_t *s);

#ifdef __cplusplus
}
#endif

#endif /* IMFOC_API_H */
