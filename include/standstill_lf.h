/**
 * @file standstill_lf.h
 * The standstill sequence's low-frequency impedance test (beyond the paper;
 * `[ident] sequence = standstill`): a multisine added to the i_M reference
 * of a held, non-rotating frame, and the M-axis impedance at each of its
 * three frequencies found by a lock-in (correlation with the sample's sine
 * and cosine over whole periods), in two halves for a repeatability check.
 *
 * Why.  With the rotor held (w_r = 0) and the current on one axis of a
 * fixed frame, the torque is zero by construction, and the stator sees the
 * standstill impedance of method §1 at w = 0:
 *     Z(jw) = Rs + jw sigma Ls + jw L_M / (1 + jw Tr),   L_M = Lm^2 / Lr
 * (inverse-Gamma form; standstill_fit.h turns three points of it into Rs,
 * Tr, L_M).  Its rotor branch shows only near w = 1/Tr: the fundamental is
 * w1 = 0.5 / Tr (the believed Tr), the harmonics 2 w1 and 4 w1, so the test
 * samples w Tr = 0.5, 1, 2 of the true Tr for a Tr within a factor 2 of the
 * belief.  Low frequencies also keep skin effect out (method assumption).
 *
 * Dead time.  The injection rides on the magnetising current: every phase
 * current keeps its sign (i_M + i_add > 0 for a peak of 3 ampl below
 * i_M: STANDSTILL_LF_AMPL_MAX_OF_IM), so the bridge's voltage error is a
 * constant that the lock-in rejects (a DC input has no component at the
 * sine's frequencies over whole periods).
 *
 * Rate and timing.  It runs in the slow task (f_pwm / DRIVE_SLOTS) on the
 * regression's filtered u_M, i_M (ident_regressor.h): one linear filter on
 * both, so it cancels in U / I.  u_M is the mean voltage of the PWM period
 * before i_M's sample, half a fast period earlier: standstill_fit.h turns
 * U back by w Ts / 2.
 *
 * Phase.  The sample's angle in the fundamental's period is ph / per
 * (pu of a revolution, Q24, from a Q32 reciprocal: |error| < 2^-24 rev);
 * the harmonics' angles are 2 and 4 times it (_IQsinPU wraps), so every
 * weight is a fixed function of ph and repeats exactly every period.
 *
 * Scaling and overflow (Q24).  Weights g sin, g cos with g = 16 / (samples
 * in one half), rounded (iq_rmpy.h: a truncated weight would let the
 * inputs' DC into the phasors); each product u w truncated (_IQmpy), its
 * mean bias of -1/2 LSB given back by the reader (standstill_lf_sum, n/2
 * LSB on each sum: what stays is the fractions' spread, ~sqrt(n/12) LSB;
 * not in the ISR: the worst slow ISR is the one that would do it); the sums of
 * one half stay below 16 |x|max: with the inputs saturated at
 * +-STANDSTILL_LF_IN_MAX (4 pu) below 64, within Q24's 128.  The
 * harmonics' sine and cosine come from the fundamental's by the double
 * angle (a few LSB off a true sine, the same every period).  The weights'
 * rounding repeats every period: measured against double in
 * test_standstill_lf.c (the whole fit within 0.05 % of the model).
 * Per sample: 2 _IQsinPU/_IQcosPU, 16 multiplies, 12 sums.
 */
#ifndef STANDSTILL_LF_H
#define STANDSTILL_LF_H

#include <stdint.h>
#include "IQmathLib.h"

#define STANDSTILL_LF_NH 3           /* harmonics 1, 2, 4 of the fundamental */
#define STANDSTILL_LF_HALVES 2
#define STANDSTILL_LF_NSUM 4         /* the sums of one harmonic in one half (SSLF_*) */
#define STANDSTILL_LF_IN_MAX 4.0f    /* pu: inputs saturated to +- this */
#define STANDSTILL_LF_W1_TR 0.5f     /* the fundamental: w1 Tr = 0.5 (believed Tr) */
#define STANDSTILL_LF_LEAD_TR 5.0f   /* the lead before the sums: 5 Tr (the flux's transient
                                        e^-5 of its start) */
#define STANDSTILL_LF_AMPL_MAX_OF_IM 0.3f   /* each harmonic's amplitude at most 0.3 i_M: the
                                               multisine's trough (-2.3 ampl) stays above 0.3 i_M */
#define STANDSTILL_LF_PER_MIN 64u    /* samples per fundamental period: the 4th harmonic gets 16 */
#define STANDSTILL_LF_HALF_MAX 1048576u   /* samples in one half: g = 16 / n >= 256 LSB */

/* the four sums of one harmonic in one half, in STANDSTILL_LF_NSUM */
enum { SSLF_US = 0, SSLF_UC, SSLF_IS, SSLF_IC };

typedef enum {
    STANDSTILL_LF_OK = 0,
    STANDSTILL_LF_ERR_TIME,    /* Ts or Tr not > 0, or the period outside [64, 2^20] samples */
    STANDSTILL_LF_ERR_WINDOW,  /* a half over STANDSTILL_LF_HALF_MAX samples, or the test
                                  over 2^31 samples */
    STANDSTILL_LF_ERR_AMPL     /* amplitude not in (0, 0.3 i_M], or i_M not in (0, 2] pu */
} standstill_lf_status_t;

typedef struct {
    /* inputs (the slow task, each sample) */
    _iq u_m;                /* Q24 pu: filtered M voltage (the regression's u_Mf) */
    _iq i_m;                /* Q24 pu: filtered M current (i_Mf) */
    /* parameters (standstill_lf_init) */
    _iq ampl;               /* Q24 pu: each harmonic's amplitude */
    _iq gain;               /* Q24: 16 / samples per half */
    uint32_t inv_per_q32;   /* round(2^32 / per): the angle's step (IQ build) */
    _iq ang_step;           /* Q24: 1 / per (the FLOAT build's angle; diagnostic in IQ) */
    uint32_t per;           /* samples per fundamental period */
    uint32_t lead;          /* samples before the first half */
    uint32_t half;          /* samples per half (whole periods) */
    /* outputs */
    _iq i_add;              /* Q24 pu: add to the i_M reference (0 when not running) */
    uint16_t done;          /* 1 once both halves are summed (the sums then hold) */
    /* state */
    _iq sum[STANDSTILL_LF_HALVES][STANDSTILL_LF_NH][STANDSTILL_LF_NSUM];   /* Q24 */
    uint32_t k;             /* samples since the start */
    uint32_t ph;            /* sample within the fundamental's period */
    uint16_t running;
} standstill_lf_t;

/** @p Ts_s the slow task's period, @p tr_s the believed Tr, @p ampl_pu each
 *  harmonic's amplitude, @p im_pu the magnetising current it rides on,
 *  @p min_window_s the least time summed (both halves; each half at least
 *  one fundamental period).  Float, once.  On error the struct is zeroed
 *  (never runs). */
standstill_lf_status_t standstill_lf_init(standstill_lf_t *z, float Ts_s, float tr_s,
                                          float ampl_pu, float im_pu, float min_window_s);

/** standstill_lf_init's check alone (no struct): the configuration's
 *  limits table calls it (drive_limits.c), so the limits are said once. */
standstill_lf_status_t standstill_lf_check(float Ts_s, float tr_s, float ampl_pu, float im_pu,
                                           float min_window_s);

/** Samples the test takes (lead + both halves). */
uint32_t standstill_lf_samples(const standstill_lf_t *z);

/** The fundamental's angular frequency (rad/s) for the slow period @p Ts_s. */
float standstill_lf_w1_rad_s(const standstill_lf_t *z, float Ts_s);

/** A finished half's sum (@p half 0/1, harmonic @p h, SSLF_* @p k) as a
 *  float, the truncated products' bias given back (background only). */
float standstill_lf_sum(const standstill_lf_t *z, uint16_t half, uint16_t h, uint16_t k);

/** Start (sums cleared, done 0). */
void standstill_lf_start(standstill_lf_t *z);

/** One slow sample while running: i_add for the next samples and, past the
 *  lead, the sums; done = 1 (i_add 0) after the second half.  Not running:
 *  nothing (i_add stays 0). */
void standstill_lf_step(standstill_lf_t *z);

#endif /* STANDSTILL_LF_H */
