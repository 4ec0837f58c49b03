/* Private to src/app: the numbers drive_init derives from a drive_config_t
 * before it hands them to the modules (bases, PWM period, loop gains, the
 * believed motor's regression coefficients, the extraction's ranges).  One
 * place, so that drive_init and the table of limits (drive_limits.c) judge
 * the very same floats.  Float: initialisation only, never the ISR. */
#ifndef DRIVE_DESIGN_H
#define DRIVE_DESIGN_H

#include "base_values.h"
#include "drive_config.h"
#include "drive_types.h"   /* DRIVE_SLOTS */
#include "param_extract.h"
#include "rls.h"

#define DRIVE_TWO_PI_F 6.28318530717958647692f
#define DRIVE_SQRT3_F 1.73205080756887729353f
#define DRIVE_SQRT3 1.7320508075688772   /* in constant _IQ() expressions */
/* The current loops' voltage limit per unit of vdc / sqrt(3) of the bus
 * measured, each axis (drive_slow.c voltage_limits): the inscribed circle,
 * as 1 pu was at the nominal bus.  One axis at its limit stays in the
 * modulator's linear range (the magnetisation's step: at 1.10 the
 * modulator's over-modulation, a division in the control ISR, made
 * MAGNETIZE's worst control ISR 3 032 cycles); both at theirs reach the
 * hexagon (over-modulation, the current check holds). */
#define DRIVE_VMAX_OF_VLIN 1.0

/* Rotor-flux observer (orientation 1).  Crossover 3 Hz: the current model's
 * weight is 3 (w_c/w_e)^2, 3 % at 10 w_c (flux_obs.h), and an offset of
 * 0.2 A leaves no drift (tests/orient/test_flux_obs.c).  ws_f, used for
 * decoupling and the modulation angle, is ws low-passed at 200 Hz: the
 * current noise through sigma Ls i makes the raw angle step noisy, and
 * 200 Hz lags by 0.8 ms, 0.3 rad/s of w_s on the paper motor's 2000 r/min/s
 * ramp.  The RLS learns only above FOBS_RLS_WS_OVER_WC w_c, where a wrong
 * Tr reaches the angle at most 3 (1/10)^2 = 3 % of its current-model error. */
#define FOBS_WC_HZ 3.0f
#define FOBS_WS_LPF_HZ 200.0f
#define FOBS_RLS_WS_OVER_WC 10.0f

#define DRIVE_QEP_WINDOW 16u           /* QEP speed: difference over 16 periods */
#define DRIVE_IMR_MIN_OF_IM 0.2f       /* ifo's least i_mr: 20 % of the i_M reference */
#define DRIVE_SPEED_REF_MAX_PU 2.0f    /* the speed reference ramp's limits, +-pu */
#define DRIVE_ENC_FROZEN_S 0.05f       /* encoder check: counts frozen this long ... */
#define DRIVE_ENC_SPEED_MAX_PU 4.0f    /* ... or a jump above this speed in one sample */
#define DRIVE_ENC_IT_OF_IMAX 0.3f      /* ... with |i_T| above this part of its limit */
#define DRIVE_VDC_FILTER_HZ 200.0f     /* the bus reading's low-pass (protections, display) */
#define DRIVE_CUR_PI_OUT_MAX 1.0f      /* the current PIs' limits at init, +-pu (drive_slow.c
                                          then sets them from the measured bus) */
#define DRIVE_THETA_GUARD_SPAN 8.0f    /* the estimator safeguard: K within a factor 8 */
/* The rotor at rest (id_sequence_set_rest): a start, CALIBRATE and
 * MAGNETIZE need |speed| below 1 % of the rated speed (at least two counts
 * of the QEP's speed window, its resolution).  There the back-EMF is 1 % of
 * the rated voltage, and in the frame that follows the rotor (the flux's
 * build-up) it stands on the T axis, not on u_M that gives the standstill
 * Rs; a rotor coasting after a stop is far above it. */
#define DRIVE_REST_SPEED_OF_RATED 0.01f
/* The publication (ident_conf.h; drive_background.c), from the motor family
 * (tools/family_sweep.py --subset all --ops all: 64 motors x 8 operating
 * choices x 2 sequences x 2 builds, 1 528 runs the firmware accepts):
 *  - a set is published only if every parameter's confidence is at most
 *    3 %, the accuracy asked of it: no run with all confidences <= 3 % was
 *    off by more than 3 % (worst 2.45 %, adaptive; 1.88 %, the paper's);
 *    at 4 % three of the paper's sets 3.4-3.9 % off would pass (their
 *    confidences 3.2-3.95 %).
 *  - a refusal is said to come from the residual above 0.02: the adaptive
 *    sequence's largest was 0.018 in a run within 3 %; the paper's runs
 *    above 0.02 (up to 0.045) are the 0.2 kW motors on 400-460 V buses and
 *    two 0.55-1.5 kW 8-pole ones, whose refusals are then put down to their
 *    residual (the healthy paper motor: 5e-4; a 20 % current-sensor gain
 *    error on it: 0.028);
 *  - ... from the excitation below 0.2: the smallest of a run within 3 %
 *    was 0.26 (the paper's sequence to half the rated speed). */
#define DRIVE_CONF_MAX 0.03f           /* the largest confidence published */
#define DRIVE_CONF_RES_REF 0.02f       /* a refusal with a larger residual: high_residual */
#define DRIVE_CONF_EXC_REF 0.2f        /* ... with a smaller excitation: low_excitation */
#define DRIVE_CONF_TRACK_S 0.5f        /* the tracker's fit judged over its first 0.5 s */
#define DRIVE_CONF_TRACK_WAIT_S 1.5f   /* no tracker verdict 1.5 s after its validity and the
                                          judged window: low_excitation */
/* Steady state (id_sequence.h): the net change of the filtered i_M and i_T
 * over the 0.2 s hold window, not the instantaneous di/dt.  The filtered
 * derivative carries the dead time's 6 f_e current ripple multiplied by
 * 6 w_e: on a 37 kW 8-pole motor with 3 us on a 650 V bus (the family's
 * m37kW_8p_50Hz_400V_s080) 1.2e-4 pu against the former fixed 5 %-of-rated-
 * peak-per-second threshold, 6.2e-5 pu, so SETTLE timed out (and the
 * observer's frame in the adaptive sequence, with i_M wandering 0.1-0.2 %
 * over 0.2 s, timed out on the paper motor too: measured).  The net change
 * carries the filtered current's ripple, 6 w_e times smaller.  Tolerances:
 *   i_M: 0.5 % of the i_M reference (the extraction takes the steady i_M as
 *        psi_r / Lm: a 0.5 % drift is at most 0.5 % in Lm, psi_r; measured
 *        wander 0.21 % at most, 37 kW, observer frame),
 *   i_T: 2 % of the torque-current limit (the end of the ramp: the
 *        acceleration current settles; the speed loop's answer to the
 *        encoder's quantisation moved i_T by 0.8 % of i_M at most, 37 kW),
 * each at least DRIVE_SETTLE_RIPPLE_K times the dead-time ripple of the
 * filtered current (drive_design.c: the describing function of the
 * dead-time and drop voltage, its 5th and 7th harmonics through the current
 * loop and the regression's filter at 6 w_e of the target speed). */
/* The speed error: 0.5 % of the target, and at least two counts of the
 * QEP's speed window (its resolution, DRIVE_QEP_WINDOW periods: on the
 * family's 0.2 kW 6-pole motor with 1024 lines 13.7 r/min, 1.6 % of its
 * target; the measured error reached 15.7 r/min in steady state and SETTLE
 * timed out on it alone). */
#define DRIVE_SETTLE_SPEED_FRAC 0.005f
#define DRIVE_SETTLE_SPEED_COUNTS 2.0f
#define DRIVE_SETTLE_IM_FRAC 0.005f
#define DRIVE_SETTLE_IT_FRAC 0.02f
#define DRIVE_SETTLE_RIPPLE_K 4.0f     /* peak-to-peak is twice the amplitude; x2 margin */

/** What drive_init gives the modules, in SI or pu as each module takes it. */
typedef struct {
    float Ts;          /* PWM period, s */
    float Ts_slow;     /* the slow task's period, DRIVE_SLOTS Ts, s */
    float t1pr;        /* EV-A T1 period, counts (up/down: sysclk / (2 f_pwm)) */
    float sigma;       /* leakage factor 1 - Lm^2/(Ls Lr) */
    float sls;         /* sigma Ls, H */
    float cur_kp;      /* current PI: Kp = w_c sigma Ls / Z_base, pu */
    float cur_ki;      /* Kp Ts / Ti, Ti = sigma Ls / Rs */
    float spd_kp;      /* speed PI: Kp = w_sc / gain, pu */
    float spd_ki;      /* Kp Ts_slow w_sc / 4 */
    float i_max;       /* torque-current limit, pu of I_base */
    float ramp;        /* speed reference ramp, pu per second */
    float accel_per_it;/* the believed acceleration, pu speed per second per pu i_T */
    float tr;          /* believed rotor time constant Lr / Rr, s */
    float im_pu;       /* i_M reference, pu */
    float target_pu;   /* the sequence's target speed (rated when not set), pu */
    float ripple_pu;   /* the dead time's 6 w_e ripple of the filtered currents, pu */
    float im_tol_pu;   /* steady state: net change of the filtered i_M over the hold, pu */
    float it_tol_pu;   /* ... of the filtered i_T, pu */
    float speed_tol_pu;/* steady state: |speed error| below, pu */
    float y_ref_pu;    /* the regression's rms signal of a ramp to rated speed, pu */
} drive_design_t;

/** The per-unit bases of @p c (base_values_init's status). */
base_status_t drive_design_bases(base_values_t *b, const drive_config_t *c);

/** Every number of drive_design_t.  @p b from drive_design_bases. */
void drive_design(drive_design_t *g, const drive_config_t *c, const base_values_t *b);

/** The believed motor's K1..K4 (method §2), pu, as the RLS estimates them
 *  (K3 or K3' by c->ident.paper_regressor). */
void drive_design_k_nominal(float k[RLS_N], const drive_config_t *c, const base_values_t *b);

/** volt_calc_init's linear zone (pu) and compensation switch as drive_init
 *  gives them: with ident.vi_test the zone is unused and the compensation
 *  stays off until the bridge's measured curve is applied (drive_vi.c). */
float drive_design_volt_band_pu(const drive_config_t *c, const base_values_t *b);
uint16_t drive_design_volt_comp(const drive_config_t *c);

/** The drive's own rules, the ones no module checks, judged once for
 *  drive_init and the table of limits: 1 if the speed PI's torque-current
 *  limit @p i_max_pu (drive_design_t.i_max) is in (0, 1] pu (the current
 *  loops' range; NaN fails), else 0. */
int16_t drive_design_imax_ok(float i_max_pu);
/** 1 if @p bd's overcurrent trip is below the current sensors' full scale
 *  (a trip level the sensors cannot read never trips; NaN fails), else 0. */
int16_t drive_design_oc_ok(const drive_board_t *bd);

/** The extraction's plausibility ranges: a factor of 4 either way of the
 *  believed motor, every upper end kept below 120 pu (Q24). */
void drive_design_param_limits(param_limits_t *lim, const drive_config_t *c,
                               const base_values_t *b);

#endif /* DRIVE_DESIGN_H */
