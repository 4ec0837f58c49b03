/**
 * @file standstill_z.h
 * Standstill measurement of the transient inductance sigma Ls (adaptive sequence,
 * beyond the paper): a small sinusoid added to the i_M reference at the end
 * of the magnetisation, and the M-axis impedance at that frequency found by
 * correlating u_M and i_M with the injection's sine and cosine over a whole
 * number of periods (a lock-in).
 *
 * Why.  The rotor-flux observer's angle above its crossover depends on Rs
 * and sigma Ls only (flux_obs.h).  Rs comes from the DC part of the same
 * test (drive_adapt.c).  sigma Ls can be identified by the RLS (1/K2), but
 * only in a frame computed with sigma Ls: with the believed Lm 30 % low
 * the first pass's sigma Ls came out 4.7 % low and further passes moved it
 * by only 0.4 % each (measured, paper motor).  Measured here it is
 * independent of the frame, of Lm, Lr and (to 0.2 %) of Tr.
 *
 * Model (method §1 at w = 0, M axis only; the rotor at standstill):
 *     Z(jw) = Rs + jw Ls + w^2 Lm^2 / (Rr + jw Lr)
 *     Im Z / w = sigma Ls + (Lm^2/Lr) / (1 + (w Tr)^2)
 * so sigma Ls = Im Z / w - c, with c = (Lm^2/Lr)/(1 + (w Tr)^2) from the
 * believed motor (w Tr = 25 on the paper motor at 200 Hz: c is 0.15 % of
 * sigma Ls, so a 30 % error in it costs 0.05 %).  No torque: the current
 * stays on the M axis; the dead-time error stays constant because the
 * injection (15 % of i_M) never takes a phase current through zero.
 *
 * Timing: u_M of sample k is the mean voltage over the period k-1 -> k; it
 * is paired with the mean of i_M(k-1) and i_M(k), the same instant, so the
 * half-period between sampling and averaging cancels in U/I.
 *
 * The sine and cosine of the sample's phase come from a rotation
 * recurrence in Q30, (s, c) <- (s C + c S, c C - s S) with C, S the cosine
 * and sine of 2 pi / per_period (four multiplies instead of an IQmath sine
 * and cosine), re-seeded exactly to (0, 1) at the start of every period.
 * Drift, LSB of Q30: each step's two truncated products lose at most 1 LSB
 * per component after the bias correction (the sum gets +1 LSB): sqrt(2) of
 * the vector a step; C rounded to Q30 scales it by at most 0.5 LSB a step;
 * S from a float sine (2^-22 relative, with its conversion) turns it by at
 * most 2^-22 S rad a step, 2 pi 2^-22 over a period (1 608 LSB): in all
 * below 2 (per_period - 1) + 1 608 LSB at a period's end, < 1e-5 of the
 * unit amplitude for per_period <= 4096.  The re-seed makes the error a
 * pattern that repeats exactly every period, as the weights do
 * (test_standstill_z.c measures it against double).  The FLOAT build, the
 * host's reference model, takes the sine and cosine themselves.
 * Scaling and overflow (Q24): the weights 16 sin/N, 16 cos/N (|.| <= 16/N
 * <= 0.5) are formed once per sample in Q30 and rounded to Q24 (a
 * truncated weight is biased by
 * -1/2 LSB and lets the DC of u and i leak into the phasors); each product
 * u w, i w is rounded (iq_rmpy.h: _IQrmpy bit for bit
 * without the library call, +-0.5 LSB, not biased); the sums stay below
 * 4 * 16 = 64 for inputs saturated at +-4 pu, and the factor 16 keeps 4
 * more bits of the phasors for the final products.  Rounding over the
 * window: up to N/2 LSB for an exactly periodic input (the errors repeat
 * each period), ~sqrt(N)/2 LSB for a noisy one.  The result:
 * X = Im(U/I) = (Uc Is - Us Ic)/(Is^2 + Ic^2) by one _IQdiv, only if every
 * phasor sum is below 7.9 (each product < 64) and |I|^2 is above
 * 4 ampl^2 (a current amplitude of at least ampl/4), else invalid;
 * sigma Ls = X / w - c, valid only in (0, 4] pu.
 */
#ifndef STANDSTILL_Z_H
#define STANDSTILL_Z_H

#include <stdint.h>
#include "IQmathLib.h"

#define STANDSTILL_Z_IN_MAX 4.0f

typedef enum {
    STANDSTILL_Z_OK = 0,
    STANDSTILL_Z_ERR_FREQ,     /* fewer than 8 samples per period, w not in [0.01, 30] pu, or Ts, f_base not > 0 */
    STANDSTILL_Z_ERR_CYCLES,   /* periods not in [4, 200], or the window over 65535 samples */
    STANDSTILL_Z_ERR_AMPL,     /* amplitude not in (0, 0.5] pu */
    STANDSTILL_Z_ERR_CORR      /* rotor-branch correction NaN, < 0 or > 1 pu */
} standstill_z_status_t;

typedef struct {
    /* inputs */
    _iq u_m;                /* Q24 pu: M voltage over the period that just ended */
    _iq i_m;                /* Q24 pu: M current sampled now */
    /* parameters */
    _iq ampl;               /* Q24 pu: injection amplitude */
    _iq inv_n;              /* Q24: 16 / (samples in the window): the sums' weight */
    _iq30 rot_c, rot_s;     /* Q30: cos, sin of 2 pi / per_period (the weights' rotation) */
    _iq w;                  /* Q24: w_inj, pu of w_base, in [0.01, 30] */
    _iq inv_w;              /* Q24: 1 / w_inj */
    _iq corr;               /* Q24 pu: rotor-branch term c subtracted */
    uint16_t per_period;    /* samples per injection period */
    uint16_t lead;          /* samples injected before the sums start (loop transient) */
    uint16_t window;        /* samples summed (whole periods) */
    /* outputs */
    _iq i_add;              /* Q24 pu: add to the i_M reference this sample */
    _iq x;                  /* Q24 pu: Im Z (diagnostic) */
    _iq r;                  /* Q24 pu: Re Z (diagnostic: Rs + Rr (Lm/Lr)^2 (wTr)^2/(1+(wTr)^2)) */
    _iq sigma_ls;           /* Q24 pu of L_base: the result */
    uint16_t done;          /* 1 once the window is complete */
    uint16_t valid;         /* 1 if done and standstill_z_finish found the result plausible */
    /* state */
    _iq us, uc, is, ic;     /* Q24 phasor sums */
    _iq i_prev;
    _iq30 s, c;             /* Q30: sin, cos of the next sample's phase (the recurrence) */
    _iq rev_step;           /* Q24: revolutions per sample, 1 / per_period (the FLOAT build's
                               direct sin, cos; unused by the IQ build's recurrence) */
    uint16_t k;             /* samples since the start */
    uint16_t ph;            /* sample within the period */
    uint16_t running;
} standstill_z_t;

/** @p Ts_s sample period, @p f_base_Hz frequency base, @p f_Hz wanted
 *  injection frequency (rounded to a whole number of samples per period),
 *  @p cycles periods summed (plus one lead period), @p ampl_pu amplitude,
 *  @p corr_pu the rotor-branch term (Lm^2/Lr)/(1+(w Tr)^2) of the believed
 *  motor at that frequency (standstill_z_corr). */
standstill_z_status_t standstill_z_init(standstill_z_t *z, float Ts_s, float f_base_Hz,
                                        float f_Hz, uint16_t cycles, float ampl_pu,
                                        float corr_pu);

/** The injection frequency actually used (after rounding), Hz. */
float standstill_z_freq_Hz(const standstill_z_t *z, float Ts_s);

/** The rotor-branch term for a motor (SI in, pu of L_base out). */
float standstill_z_corr(float f_Hz, float Lm_H, float Lr_H, float Rr_ohm, float L_base_H);

/** Total samples the test needs (lead + window). */
uint16_t standstill_z_samples(const standstill_z_t *z);

/** Start (sums cleared, outputs invalid). */
void standstill_z_start(standstill_z_t *z);

/** One sample while running: i_add for this sample; at the end of the
 *  window done = 1 (then i_add = 0 and nothing more; the sums hold).  The
 *  result is standstill_z_finish's: no division here (ISR). */
void standstill_z_step(standstill_z_t *z);

/** The result from the four sums once done (fixed point, one _IQdiv each
 *  for x and r; not in the ISR: the drive's background calls it on a copy
 *  of the sums, drive_adapt_bg.c): x, r, sigma_ls and valid (header
 *  comment).  Before done it sets nothing (valid stays 0). */
void standstill_z_finish(standstill_z_t *z);

#endif /* STANDSTILL_Z_H */
