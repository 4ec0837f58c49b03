/* Private to src/app: parameter adaptation between passes, standstill Rs
 * and sigma Ls, Rr/Tr tracking.  The ISR's part is drive_adapt.c (captures,
 * copies a posted model set in, feeds the tracker), the background's
 * drive_adapt_bg.c (computes every model and its constants, posts them). */
#ifndef DRIVE_ADAPT_H
#define DRIVE_ADAPT_H

#include "drive_types.h"

/** The model set the sequence waits for is applied: its adapt_ready. */
static inline uint16_t drive_adapt_ready(const drive_t *d) { return d->adapt.isr.ready; }
/** RUN on a free shaft: the speed swings (the sequence's excite). */
static inline uint16_t drive_adapt_excite(const drive_t *d) { return d->adapt.isr.excite; }

/* The standstill test and the tracker's guard (also read by the table of
 * limits, drive_limits.c, to say which bound a configuration misses). */
#define TRACK_PHI_MIN_OF_RATED 0.1f    /* least |psi x i|: 10 % of rated flux x rated i_T */
#define TRACK_LPF_HZ 10.0f             /* as the regression's Butterworth corner */
#define SSZ_F_OF_BW 0.4f               /* injection at 40 % of the current-loop bandwidth */
#define SSZ_F_MAX_HZ 400.0f            /* ... at most (>= 37 samples per period at 15 kHz) */
#define SSZ_CYCLES 20u                 /* periods summed */
#define SSZ_AMPL_OF_IM 0.15f           /* amplitude: 15 % of i_M (no phase current crosses 0) */
#define SSZ_GAP_S 0.02f                /* DC only after the injection: the current loop and the
                                          filtered u_M, i_M settle before Rs is taken */

/* The blend, the tracker's rate limit and the waits (drive_adapt.c says why). */
#define DRIVE_ADAPT_BLEND_S 0.1f
#define DRIVE_ADAPT_TR_RATE 0.2f       /* relative per second */
#define DRIVE_ADAPT_TRACK_DECIM (16u >> DRIVE_SLOTS_LOG2)   /* tracker RLS at f_pwm / 16: 938 Hz */
#define DRIVE_ADAPT_WAIT_S 0.5f        /* longest wait of the sequence for the background's set */
/* A free shaft (drive_adapt.c excite): the tracker held for want of torque
 * this long in RUN makes the speed swing (id_sequence.h excite), its ramp's
 * torque DRIVE_EXCITE_OF_IMAX of the torque-current limit on the believed
 * inertia (the configured ramp when that is faster), the swing's low end at
 * least DRIVE_EXCITE_FLOOR_OF_LEAST of the least target (the frame the
 * tracker learns in, above the observer's crossover). */
#define DRIVE_EXCITE_STARVE_S 0.3f
#define DRIVE_EXCITE_OF_IMAX 0.4f
#define DRIVE_EXCITE_FLOOR_OF_LEAST 1.1

/* The model's members in drive_adapt_bg_t's arrays. */
enum { DRIVE_P_RS = 0, DRIVE_P_LM, DRIVE_P_LR, DRIVE_P_LS, DRIVE_P_TR };

/** Once, after the observer, the current loops and the sequence are
 *  initialised (float).  Returns 0, or 1 for a bad option (passes > 4, a
 *  flag > 1, a feature without orientation 1, tracker constants out of
 *  range). */
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
 *  d->loop.im_inject) during the magnetisation.  Inline: outside its few
 *  hundred ms it is one test and a store, cheaper than a call. */
static inline void drive_adapt_fast(drive_t *d)
{
    standstill_z_t *z = &d->adapt.ssz;

    if (z->running == 0u) {
        /* the standstill sequence's multisine (drive_static.c), each slow
         * sample's value reached by a ramp over the slow period (a held
         * value's images would fold onto the lock-in's tones:
         * standstill_lf.h, Hold): 0 but while it runs in INJECT (a start
         * clears a test a stop cut short) */
        d->loop.im_inject = standstill_lf_fast(&d->adapt.lf);
        return;
    }
    /* the sequence's i_M reference plus the injection (drive_step.c) */
    z->u_m = d->id.reg.u_m;
    z->i_m = d->loop.park.ds;
    standstill_z_step(z);
    d->loop.im_inject = z->i_add;
}

/** ISR, slot SEQUENCE after the sequence step: the standstill test's start
 *  and, at the end of the magnetisation, the capture of what its result
 *  needs; the RLS restart per pass; a posted model set copied in (one
 *  bounded step). */
void drive_adapt_slow(drive_t *d);

/** ISR, slot OBSERVER (a slot of its own: its scalar RLS divides twice):
 *  the Rr/Tr tracker's inputs and step while it is armed (RUN with
 *  tracking); learning only when no blend is under way. */
void drive_adapt_track(drive_t *d);

/** Background, after an extraction at the end of a pass: the model the next
 *  pass (or the tracker) starts from.  @p full: 1 for param_extract_step's
 *  set, 0 for param_extract_magnetic's (Lm, Lr only).  Taken up by the next
 *  drive_adapt_background. */
void drive_adapt_post(drive_t *d, const param_extract_t *p, uint16_t full);

/** Background, after the standstill sequence published its set
 *  (drive_static.c): the model a later rotating start begins from, when the
 *  drive adapts its model (orientation 1 with passes or tracking).  Applied
 *  whole while the drive rests (IDLE: nothing runs on the model), by the
 *  next drive_adapt_background; dropped if a start comes first (within a
 *  slow period of the verdict). */
void drive_adapt_seed(drive_t *d, const param_extract_t *p);

/** Background, every pass of the loop (float allowed): the standstill
 *  result from the ISR's capture, a pass's blend step by step, the tracked
 *  Tr rate limited; each as a complete model set posted to the ISR; the
 *  tracker's telemetry (Tr_track, Rr_track, track_valid). */
void drive_adapt_background(drive_t *d);

#endif /* DRIVE_ADAPT_H */
