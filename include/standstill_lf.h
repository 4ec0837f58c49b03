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
 * Hold (why the injection is ramped, not stepped).  The lock-in sees the
 * regression's window means: the mean of N = 2^hold_log2 period voltages
 * and of N current samples, one value per slow sample.  That is U/I = Z(jw)
 * only for signals that hold the tone alone.  A reference held over the N
 * periods of a slow sample (a staircase) also holds its images at w + m W
 * (W = 2 pi / (N Ts), m = 1 .. N-1), of relative size D_m = sin(N w Ts/2)
 * / (N sin((w + m W) Ts/2)), about w Ts / (2 sin(m pi / N)); the window
 * mean passes each again by D_m, and its sampling folds them all onto w.
 * At the images the current loop makes a voltage of about w_c sigma Ls
 * per unit of reference (w_c its bandwidth), far more than |Z(jw)|, so
 *     U/I = Z(jw) [1 + sum_m D_m^2 e^(-j m W t0) (T_m / T_0) (Z_m / Z(jw) - 1)]
 * (T the loop's reference-to-current gain, Z_m the impedance, at w + m W;
 * t0 the hold's offset in the window): a relative error of order
 *     5.25 (w Ts)^2 w_c sigma Ls / |Z(jw)|      (sum_m 1 / (4 sin^2(m pi / 8)) = 5.25)
 * that shrinks with Ts^2 and that the model cannot absorb.  On the paper
 * motor at 15 kHz (w Ts = 6.7e-3 at the 4th harmonic, w_c sigma Ls =
 * 11 |Z|) it is 1.8e-3 there, the fit's misfit ~0.1 % of |Z|, and its
 * imaginary part is what a turn-back of ~0.3 Ts instead of 0.5 Ts partly
 * hides (docs/accuracy.md).  So the sample's value is reached by a ramp
 * over the N periods (a first-order hold, standstill_lf_fast, as the speed
 * loop hands i_T on: drive_slow.c): its images are of size D_m^2, the
 * error of order (w Ts)^3, below 2e-5 there (test_standstill_lf.c).  The
 * ramp delays the reference by one slow sample: a delay of the injection,
 * not of u against i, so U/I does not see it.
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
#define STANDSTILL_LF_HOLD_LOG2_MAX 3u    /* the ramp over at most 8 fast periods (a step of
                                             |i_add - i_ref| / 8 <= 0.5 pu) */

/* the four sums of one harmonic in one half, in STANDSTILL_LF_NSUM */
enum { SSLF_US = 0, SSLF_UC, SSLF_IS, SSLF_IC };

typedef enum {
    STANDSTILL_LF_OK = 0,
    STANDSTILL_LF_ERR_TIME,    /* Ts or Tr not > 0, or the period outside [64, 2^20] samples */
    STANDSTILL_LF_ERR_WINDOW,  /* a half over STANDSTILL_LF_HALF_MAX samples, or the test
                                  over 2^31 samples */
    STANDSTILL_LF_ERR_AMPL,    /* amplitude not in (0, 0.3 i_M], or i_M not in (0, 2] pu */
    STANDSTILL_LF_ERR_HOLD     /* hold_log2 above STANDSTILL_LF_HOLD_LOG2_MAX */
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
    uint16_t hold_log2;     /* the ramp's fast periods per slow sample, 2^hold_log2 */
    /* outputs */
    _iq i_add;              /* Q24 pu: the injection's value for this sample (0 when not
                               running): the ramp's target */
    _iq i_ref;              /* Q24 pu: the injection of this fast period (standstill_lf_fast):
                               add to the i_M reference */
    _iq i_step;             /* Q24 pu: the ramp's step per fast period, (i_add - i_ref) /
                               2^hold_log2 rounded (|.| <= 0.5 pu) */
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
 *  one fundamental period), @p hold_log2 the fast periods per slow sample
 *  (2^hold_log2: the regression's window, DRIVE_SLOTS), over which
 *  standstill_lf_fast ramps.  Float, once.  On error the struct is zeroed
 *  (never runs). */
standstill_lf_status_t standstill_lf_init(standstill_lf_t *z, float Ts_s, float tr_s,
                                          float ampl_pu, float im_pu, float min_window_s,
                                          uint16_t hold_log2);

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

/** One slow sample while running: i_add for the next samples, the ramp's
 *  step towards it and, past the lead, the sums; done = 1 (i_add, i_ref,
 *  i_step 0) after the second half.  Not running: nothing (they stay 0). */
void standstill_lf_step(standstill_lf_t *z);

/** ISR, every fast period: the injection of this period, i_ref, one
 *  i_step further along the ramp that reaches the last i_add after
 *  2^hold_log2 periods (the Hold paragraph above).  The slow task computes
 *  i_step from i_ref where the last ramp ended, so a step's rounding
 *  (|.| <= 1/2 LSB a period, 4 LSB at the end) never accumulates.  One
 *  add; 0 while the test does not run (i_step 0, i_ref 0).  |i_ref| <= 3
 *  ampl + 4 LSB < 1.8 pu. */
static inline _iq standstill_lf_fast(standstill_lf_t *z)
{
    z->i_ref += z->i_step;
    return z->i_ref;
}

#endif /* STANDSTILL_LF_H */
