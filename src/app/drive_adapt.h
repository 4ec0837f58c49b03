/* Private to src/app: parameter adaptation between passes, standstill Rs,
 * Rr/Tr tracking (issue 8).  See drive_adapt.c. */
#ifndef DRIVE_ADAPT_H
#define DRIVE_ADAPT_H

#include "drive_types.h"

/* The standstill test and the tracker's guard (also read by the table of
 * limits, drive_limits.c, to say which bound a configuration misses). */
#define TRACK_PHI_MIN_OF_RATED 0.1f    /* least |psi x i|: 10 % of rated flux x rated i_T */
#define TRACK_DECIM 4u                 /* tracker RLS at 938 Hz (the slow task's 3.75 kHz / 4) */
#define TRACK_LPF_HZ 10.0f             /* as the regression's Butterworth corner */
#define SSZ_F_OF_BW 0.4f               /* injection at 40 % of the current-loop bandwidth */
#define SSZ_F_MAX_HZ 400.0f            /* ... at most (>= 37 samples per period at 15 kHz) */
#define SSZ_CYCLES 20u                 /* periods summed */
#define SSZ_AMPL_OF_IM 0.15f           /* amplitude: 15 % of i_M (no phase current crosses 0) */
#define SSZ_GAP_S 0.02f                /* DC only after the injection: the current loop and the
                                          filtered u_M, i_M settle before Rs is taken */

/** Once, after the observer and the sequence are initialised (float).
 *  Returns 0, or 1 for a bad option (passes > 4, a flag > 1, a feature
 *  without orientation 1, tracker constants out of range). */
int16_t drive_adapt_init(drive_t *d, const drive_config_t *c, float Ts);

/** The standstill test as drive_adapt_init sets it up (also for the table of
 *  limits, drive_limits.c, on a scratch instance): the injection frequency,
 *  the pause before Rs is taken (PWM periods), and the test's own init. */
float drive_adapt_ssz_freq_Hz(const drive_config_t *c);
uint16_t drive_adapt_ssz_gap(float Ts);
standstill_z_status_t drive_adapt_ssz_init(standstill_z_t *z, const drive_config_t *c,
                                           const base_values_t *b, float Ts);

/** The Rr/Tr tracker as drive_adapt_init sets it up (idem). */
tr_track_status_t drive_adapt_track_init(tr_track_t *t, const drive_config_t *c,
                                         const base_values_t *b, float Ts);

/** ISR, every period: the standstill lock-in on i_M (its injection into
 *  d->im_inject) during the magnetisation. */
void drive_adapt_fast(drive_t *d);

/** ISR, slot SPEED after the sequence step: standstill Rs at the end of the
 *  magnetisation, RLS restart per pass, the blend of a pass's model, the
 *  tracker. */
void drive_adapt_slow(drive_t *d);

/** Background, after an extraction at the end of a pass: post the result
 *  to the ISR (dropped if the mailbox is still full).  @p full: 1 for
 *  param_extract_step's set, 0 for param_extract_magnetic's (Lm, Lr only). */
void drive_adapt_post(drive_t *d, const param_extract_t *p, uint16_t full);

#endif /* DRIVE_ADAPT_H */
