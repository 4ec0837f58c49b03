/**
 * @file vi_curve.h
 * The bridge's voltage error against the current, measured at standstill
 * before the first magnetisation (commissioning; id_sequence.h CALIBRATE,
 * after the sensor test): what the dead-time compensation (volt_calc.h)
 * needs, measured instead of set by hand (method §6 "Dead time").
 *
 * At standstill with a DC current along the alpha axis (i_a = I,
 * i_b = i_c = -I/2: no torque, the rotor does not turn) the stator equation
 * in steady state (every derivative zero, method §1) reduces to
 *   u_ref = Rs I + u_err(I),
 * u_ref the voltage the duties ask for (vdc d, volt_calc without its
 * compensation) and u_err the bridge's loss.  With the per-pole error of
 * volt_calc.h, E s(i) (E = vdc td/Ts + v_drop, s(i) = sat(i / b, -1, 1), b
 * the transition's half-width), the alpha-axis error of that current
 * pattern is
 *   u_err(I) = (2/3) E (s(I) + s(I/2))                              (1)
 * (pole a carries I, poles b and c -I/2; the floating star removes the
 * common mode): E I / b inside |I| < b, (4/3) E beyond 2 b.  Any part
 * linear in I (the devices' on-resistance) is indistinguishable from Rs
 * and goes with it, as it does in the drive's Rs.
 *
 * The test, ten levels and a rest, each held before its window (the rotor
 * flux that follows a step dI of the stator current induces
 * (Lm/Lr)^2 Rr dI e^(-t/Tr) in the stator) and then averaged over
 * 2^avg_shift samples (>= Tr).  A current level is held 6 Tr: the line
 * through two levels i1 apart takes the tail of both steps into its slope,
 * (e^-3 + 2 e^-3)(1 - e^-1) = 9.5 % of (Lm/Lr)^2 Rr after 3 Tr, which
 * moved the 1.1 kW motor's E by -1 %, and E moves the identified Rs by
 * several times that (at its 1 A, Rs i is only 7 V against E's 19 V);
 * after 6 Tr 0.5 %.  A voltage level is held 3 Tr (there the error is
 * large against the tail):
 *   current levels (PI on i_alpha):  +2 i1, +i1   then  -2 i1, -i1
 *     beyond the transition, u = Rs I + (4/3) E: two levels per polarity
 *     separate the two, (4/3) E = 2 u(i1) - u(2 i1);
 *   voltage levels (u_alpha held):   0.9, 0.6, 0.3 of that (4/3) E, each
 *     polarity after its current levels: inside the transition the
 *     current loop's plant is the bridge's steep E/b (up to 200 ohm on the
 *     15 kW bridge against its 0.2 ohm Rs), so there the voltage is set and
 *     the current read: by (1), 0.9, 0.6, 0.3 of (4/3) E give I = 1.6 b,
 *     0.8 b, 0.4 b;
 *   rest (u = 0): the rotor flux decays before the magnetisation starts.
 * vi_curve_fit (float, background) then gives Rs, E, b and the table.
 *
 * Safety: a current level whose mean is not within 1/8 of its reference
 * (no current: a leg or a sensor open; or the PI at its limit) ends the
 * test with fail = 1 and zero voltage; a voltage level is below the
 * error measured at i1, so its current stays below i1.
 *
 * Per step (ISR, slow rate, the sequence's slot): one PI step or a copy,
 * three saturations, shifts and additions into the window.  No division,
 * no float.  The schedule (each window's means, the check, the next
 * level) is the background's (vi_curve_next), as is the fit.
 */
#ifndef VI_CURVE_H
#define VI_CURVE_H

#include <stdint.h>
#include "IQmathLib.h"
#include "pi_ctrl.h"

/** Measured levels (the table's rows); the rest follows them. */
#define VI_CURVE_LEVELS 10u
/** Largest current level 2 i1, pu. */
#define VI_CURVE_I_MAX_PU 4.0f

typedef enum {
    VI_CURVE_OK = 0,
    VI_CURVE_ERR_PERIOD,    /* Ts_s NaN or not > 0, or Tr_s NaN or not > 0 */
    VI_CURVE_ERR_CURRENT,   /* i1_pu NaN, not > 0 or 2 i1 > VI_CURVE_I_MAX_PU */
    VI_CURVE_ERR_TIME,      /* 6 Tr longer than 65535 samples */
    VI_CURVE_ERR_GAINS      /* the PI refused kp, ki or u_max */
} vi_curve_status_t;

/** The window's sums are _iq-typed: IQ_MATH a Q16 sum (int32) of samples
 *  limited to +-VI_CURVE_IN_MAX_PU, at most 2^VI_CURVE_AVG_MAX_SHIFT of
 *  them (8 * 2^16 * 2^10 = 2^29 < 2^31: no overflow); FLOAT_MATH the sum. */
#define VI_CURVE_IN_MAX_PU 8.0f
#define VI_CURVE_AVG_MAX_SHIFT 10u

typedef struct {
    /* inputs (each slow sample) */
    uint16_t run;          /* 1: the test drives the bridge (the sequence's vi_testing) */
    _iq i_alpha;           /* measured alpha current, pu, Q24 */
    _iq u_alpha;           /* alpha voltage the duties applied (volt_calc, compensation
                              off), pu, Q24 */
    _iq vdc;               /* bus voltage, pu, Q24 */
    /* parameters (vi_curve_init) */
    uint16_t settle_n;     /* slow samples before a voltage level's window (3 Tr) */
    uint16_t settle_i_n;   /* ... before a current level's (6 Tr) */
    uint16_t avg_shift;    /* the window is 2^avg_shift samples, <= VI_CURVE_AVG_MAX_SHIFT */
    float i1;              /* the smaller current level, pu */
    pi_ctrl_t pi;          /* the current levels' loop on i_alpha (gains, limits) */
    /* the level under way (background -> ISR; n written last, see vi_curve_next) */
    uint16_t current;      /* 1: i_ref through the PI; 0: u_ref held */
    _iq i_ref;             /* pu, Q24 */
    _iq u_ref;             /* pu, Q24 */
    uint16_t settle;       /* this level's settle_n or settle_i_n */
    /* outputs */
    _iq u_cmd;             /* alpha voltage to apply, pu, Q24 (beta: 0) */
    volatile uint16_t done;/* 1: every level measured, or failed (background); u_cmd = 0 */
    uint16_t fail;         /* 1: a current level missed its reference (see above) */
    uint16_t fail_level;   /* the level that did */
    /* state: the ISR's window */
    uint16_t t;            /* samples into the level, up to settle */
    volatile uint16_t n;   /* samples in the window; 2^avg_shift: full, the background's */
    _iq su, si, sv;        /* the window's sums of u, i, vdc (IQ_MATH: Q16, see above) */
    /* state: the background's schedule and results (pu, float) */
    uint16_t level;        /* 0 .. VI_CURVE_LEVELS (the rest) */
    float ea_hat;          /* (4/3) E of the polarity under way, signed */
    float mean_u[VI_CURVE_LEVELS];  /* each level's mean u_alpha */
    float mean_i[VI_CURVE_LEVELS];  /* and i_alpha */
    float mean_vdc;        /* the windows' mean bus */
} vi_curve_t;

/** What vi_curve_fit found (SI units, float: background). */
typedef enum {
    VI_FIT_OK = 0,
    VI_FIT_NOT_DONE,       /* the test has not finished */
    VI_FIT_NO_CURRENT,     /* it failed: a current level missed its reference */
    VI_FIT_RS,             /* Rs from the two current levels not > 0 */
    VI_FIT_ERROR,          /* E not > 0, or the two polarities' E differ by > 25 % */
    VI_FIT_BAND            /* no voltage level inside the transition, a band not
                              finite and > 0, or 2 b above i1 (the current levels
                              were not beyond it) */
} vi_fit_status_t;

typedef struct {
    vi_fit_status_t status;
    float rs_ohm;          /* Rs (with the devices' on-resistance) */
    float e_pole_V;        /* E: one pole's saturated error (vdc td/Ts + v_drop) */
    float e_split;         /* |E+ - E-| / mean(E+, E-): the two polarities' disagreement (an
                              offset d left by the calibration splits them by 2 Rs d) */
    float band_A;          /* b: the transition's half-width */
    float vdc_V;           /* the bus during the test (mean) */
    uint16_t n_band;       /* voltage levels b was taken from (of 6: a level whose current
                              has the wrong sign or whose error is saturated says nothing) */
    float i_A[VI_CURVE_LEVELS];      /* the table: each level's current */
    float u_err_V[VI_CURVE_LEVELS];  /* and its error voltage u - Rs i (alpha axis, (1)) */
} vi_fit_t;

/**
 * Ts_s: the step's period (the slow rate); i1_pu: the smaller current level
 * (beyond the transition: 2 b < i1); Tr_s: the believed rotor time constant
 * (settle_n = 3 Tr, settle_i_n = 6 Tr, the window 2^k >= max(Tr, 128 samples)); kp, ki, u_max:
 * the current levels' PI (pi_ctrl.h; out within +-u_max).
 */
vi_curve_status_t vi_curve_init(vi_curve_t *v, float Ts_s, float i1_pu, float Tr_s, float kp,
                                float ki, float u_max);
/** vi_curve_init's check of its arguments alone (no struct), the status it
 *  would return, in its order: _PERIOD, _CURRENT, _TIME (6 Tr / Ts above
 *  65535: the current levels' settling count is 16-bit), _GAINS (pi_check).
 *  The configuration's table of limits calls it too (drive_limits.c).
 *  Float: init only. */
vi_curve_status_t vi_curve_check(float Ts_s, float i1_pu, float Tr_s, float kp, float ki,
                                 float u_max);
/** Back to level 0 (background, while the ISR does not run the test: the
 *  next run starts it afresh). */
void vi_curve_restart(vi_curve_t *v);
/** The test again from its first level with the current levels at
 *  +-@p i1_pu, +-2 i1 (a fit that found its current levels inside the
 *  transition, 2 b >= i1: drive_vi.c).  Safe from the background while the
 *  ISR holds a finished test (done is written last); VI_CURVE_ERR_CURRENT
 *  (nothing changed) if i1 is not > 0 or 2 i1 > VI_CURVE_I_MAX_PU. */
vi_curve_status_t vi_curve_retry(vi_curve_t *v, float i1_pu);
/** One slow sample (ISR, fixed point): the level's PI step or its held
 *  voltage, the window's sums; u_cmd = 0 while run is 0 or when done. */
void vi_curve_step(vi_curve_t *v);
/** Background (float), each pass: once the ISR's window is full, the
 *  level's means, its check (a current level within 1/8 of its reference),
 *  the next level (or done).  Returns 1 when it took a window. */
uint16_t vi_curve_next(vi_curve_t *v);
/** Level count of the whole test, in samples (for time-outs and tests). */
uint32_t vi_curve_samples(const vi_curve_t *v);
/** The test's time, s, for a step period Ts_s and a rotor time constant
 *  Tr_s (what vi_curve_init would set; 0 if it would refuse them). */
float vi_curve_duration_s(float Ts_s, float Tr_s);
/** The fit (float, background): Rs and E from each polarity's current
 *  levels, b from the voltage levels by (1), the table.  I_base_A, V_base_V
 *  convert to SI. */
void vi_curve_fit(const vi_curve_t *v, float I_base_A, float V_base_V, vi_fit_t *f);
/** The true alpha-axis error (1) of a bridge with per-pole error E and
 *  half-width b, at current I (for the fit and the references of tests). */
float vi_curve_model_V(float e_pole_V, float band_A, float i_A);
/** A short name of a vi_fit_status_t. */
const char *vi_fit_str(vi_fit_status_t s);

#endif /* VI_CURVE_H */
