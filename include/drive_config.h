/**
 * @file drive_config.h
 * Everything the firmware needs to know about its motor and board, in SI
 * units.  drive_init() derives every per-unit constant and controller gain
 * from it once; nothing in the ISR path reads it.  Both the host and the
 * target get it from an INI file's drive side (host_sim/sim/sim_config.h): the
 * simulator converts it at load, the firmware's build writes the same
 * conversion into a const instance (board_config.c, board_config_gen).
 */
#ifndef DRIVE_CONFIG_H
#define DRIVE_CONFIG_H

#include <stdint.h>

/** What the controller believes about the motor (nameplate / nominal values;
 *  the identification finds the true ones). */
typedef struct {
    float Rs_ohm;
    float Rr_ohm;          /* referred to the stator */
    float Lm_H;
    float Ls_H;            /* stator self-inductance, Lm + Lls */
    float Lr_H;            /* rotor self-inductance,  Lm + Llr */
    uint16_t pole_pairs;
    float rated_speed_rpm;
    float rated_current_A_rms;
    float rated_freq_Hz;   /* also the per-unit frequency base */
    float magnetizing_current_A;  /* i_M reference (peak, M-axis) */
} drive_motor_t;

/** The power stage and its sensors. */
typedef struct {
    float sysclk_Hz;           /* 150e6 */
    float pwm_freq_Hz;         /* 15e3: T1PR = sysclk / (2 * pwm_freq) */
    float dead_time_s;         /* programmed dead band */
    float device_drop_V;       /* switch/diode forward drop, for compensation */
    uint16_t dead_time_comp;   /* 1: compensate dead time and drop in the voltage reconstruction */
    float dead_time_band_A;    /* current over which the dead-time error changes sign
                                  (measured on the inverter at commissioning) */
    float vdc_nominal_V;       /* sets the voltage base: V_base = vdc_nominal / sqrt(3) */
    float vdc_adc_full_scale_V;/* bus voltage that reads 3.0 V at the ADC pin */
    float current_full_scale_A;/* Hall: +-full scale maps to 0..3 V around 1.5 V; also I_base */
    uint16_t encoder_lines;    /* lines per revolution (x4 in the QEP) */
    float overcurrent_A;       /* phase-current trip, peak */
    float vdc_max_V;           /* bus overvoltage trip */
    float vdc_min_V;           /* bus undervoltage trip */
} drive_board_t;

/** Field orientation (drive_control_t.orientation). */
#define DRIVE_ORIENT_IFO 0u       /* indirect: encoder angle + slip from the believed Tr (the paper's) */
#define DRIVE_ORIENT_FLUX_OBS 1u  /* direct: rotor-flux observer (flux_obs.h); above its crossover
                                     the angle does not depend on Tr */

/** Controller design targets; the gains follow from these and the motor. */
typedef struct {
    float current_bw_Hz;       /* d/q current-loop bandwidth */
    float speed_bw_Hz;         /* speed-loop bandwidth */
    float max_torque_current_A;/* i_T limit (peak) */
    float inertia_kgm2;        /* the speed loop's assumed inertia */
    float speed_ramp_rpm_s;    /* reference ramp rate */
    float speed_filter_Hz;     /* low-pass of the measured speed */
    uint16_t orientation;      /* DRIVE_ORIENT_IFO (0, default) or DRIVE_ORIENT_FLUX_OBS (1) */
} drive_control_t;

/** Identification options (method.md sections 3-5). */
typedef struct {
    float filter_wc_rad_s;     /* Butterworth cut-off, default 2 pi 10 */
    uint16_t euler_passes;     /* improved-Euler corrector passes N, default 10 */
    uint16_t paper_regressor;  /* 1: previous K2 as third regressor (eq. 9); 0: constant (eq. 7) */
    uint16_t period_mean;      /* 1: the period-mean regression (ident_regressor.h; IFO only) */
    float rls_p0;              /* P(0) = p0 * I, per unit */
    float forgetting;          /* lambda in (0.9, 1]; 1 = none (paper) */
    float magnetize_time_s;    /* pre-magnetisation, >= 5 Tr */
    float target_speed_rpm;    /* speed the sequence accelerates to */
    float rls_tail_s;          /* the RLS runs this long after the ramp ends */
    /* beyond the paper (the adaptive sequence); every one needs orientation = DRIVE_ORIENT_FLUX_OBS
     * except passes = 1 and the zeros, which keep the paper's sequence */
    uint16_t passes;           /* identification passes, 1..4 (0 = 1): from the 2nd on each
                                  starts with the previous pass's parameters in the observer
                                  and the controller (decelerate, accelerate again) */
    uint16_t standstill;       /* 1: standstill tests at the end of the magnetisation: Rs from
                                  u_M / i_M, sigma Ls from a small sinusoid on i_M; given to
                                  the observer and the current loops before the first
                                  acceleration */
    uint16_t track_rr;         /* 1: track Rr (and Tr) in RUN from the observer's slip; with
                                  standstill = 1 the published set is fused (drive_adapt.c) */
    float track_memory_s;      /* tracker's forgetting time constant, s (0.2 .. 20) */
    uint16_t static_id;        /* 1: the standstill sequence (with standstill = 1, one pass, no
                                  tracker): after the magnetisation a low-frequency multisine
                                  on i_M at standstill, every parameter from it, nothing turns
                                  (drive_static.h) */
    uint16_t vi_test;          /* 1 (with dead_time_comp): the bridge's voltage error measured
                                  at standstill in CALIBRATE (vi_curve.h) and the compensation
                                  run on that curve; board.dead_time_band_A then unused */
} drive_ident_t;

typedef struct {
    drive_motor_t motor;
    drive_board_t board;
    drive_control_t control;
    drive_ident_t ident;
} drive_config_t;

#endif /* DRIVE_CONFIG_H */
