/* Private to src/app: what the drive's files share (drive_init.c,
 * drive_step.c, drive_slow.c, drive_background.c, drive_adapt.c). */
#ifndef DRIVE_INTERNAL_H
#define DRIVE_INTERNAL_H

#include "drive_types.h"

/** The offsets' calibration ended, done or rejected: the sequence's cal_done. */
static inline uint16_t drive_cal_done(const drive_t *d) { return d->sense.cal_done; }

/** (Re)start the RLS from d->id.cfg: P(0) = p0 I, theta(0) = 0, the
 *  configured regressor form and forgetting (float: background and init
 *  only; the same state every time).  Returns the rls_init status. */
rls_status_t drive_rls_start(drive_t *d);

/** Hand the control frame to ifo (@p on = 1) or back to the observer; the
 *  ISR's frame flag follows it from the next ISR on (drive_step.c decides
 *  the frame once per ISR). */
static inline void drive_set_run_ifo(drive_t *d, uint16_t on);

/** Background: run the RLS and its guard on every queued sample, in order,
 *  with the events they carry (drive_rls_bg.c).  Returns the snapshots it
 *  took (DRIVE_RLSQ_EXTRACT into id.snap, the drain's last; DRIVE_RLSQ_LIVE
 *  into id.live_snap, its first) for drive_background to extract. */
uint16_t drive_rls_drain(drive_t *d);

/** Publish @p p with @p reason (DRIVE_PUB_PUBLISHED), or count the refusal
 *  and keep the last good set (drive_background.c). */
void drive_publish(drive_telemetry_t *t, const param_extract_t *p, uint16_t reason);

/** The slow task of @p slot (drive_slot_t), one per ISR (drive_slow.c). */
void drive_slow_task(drive_t *d, uint16_t slot);

/** 1 while the control frame is the ifo's: orientation 0, or orientation 1
 *  in RUN with a tracked Tr (drive_adapt.c: the observer then runs on as
 *  the tracker's Tr-independent reference, and the quieter current-model
 *  frame carries the control). */
static inline uint16_t drive_ifo_frame(const drive_t *d)
{
    return (uint16_t)(d->k.orientation != DRIVE_ORIENT_FLUX_OBS || d->frame.run_ifo != 0u);
}

static inline void drive_set_run_ifo(drive_t *d, uint16_t on)
{
    d->frame.run_ifo = on;
    d->frame.is_ifo = drive_ifo_frame(d);
}

/** drive_init after the table of limits passed (drive_init.c): the
 *  modules' constants.  Its own function so that its frame and the check's
 *  are not on the stack together (an 8 KB AVR stand-in's stack met its
 *  .bss). */
int16_t drive_init_checked(drive_t *d, const drive_config_t *c);

/** The frame speed for decoupling and the modulation angle (pu): ifo's w_s,
 *  or the observer's low-passed ws_f (ws carries the current noise through
 *  sigma Ls i), or the rotor speed while the frame is held on the encoder. */
static inline _iq drive_frame_speed(const drive_t *d)
{
    if (d->frame.is_ifo != 0u) {
        return d->frame.ifo.ws;
    }
    return (d->frame.fobs_hold != 0u) ? d->sense.qep.speed_raw : d->frame.fobs.ws_f;
}

#endif /* DRIVE_INTERNAL_H */
