/**
 * The RLS and its estimator guard in the background, on the samples the
 * ISR queued (drive_types.h, drive_rls_queue_t), every one and in order.
 *
 * Why not in the ISR: the ISR's deadline is set by its worst single
 * period, and one RLS sample (forgetting, two rows, the guard) is about
 * 2 400 C28x cycles, a quarter of the 15 kHz period, while the regression
 * changes at 10 Hz.  The ISR keeps everything that must see every period
 * (the window sums) and every slow period (the filters, which integrate):
 * what it hands over is the filtered rows, a few words per 0.53 ms.  The
 * RLS recursion itself (method §3, eq. 8-9) does not care when it runs,
 * only that it sees the samples in order: the background runs it on the
 * queue, the same arithmetic on the same samples as before, so that the
 * estimates are those of an RLS in the ISR, delayed by at most the queue's
 * length.  A sample lost to a full queue is counted (telemetry.rls_dropped)
 * and the RLS simply does without it; at the simulator's 1 kHz background
 * the queue holds two entries at most.
 *
 * The events (restart per pass, the snapshots the extraction and the live
 * estimates take) travel with the entries, so each acts on the RLS state
 * that the samples before it made.
 */
#include "drive_internal.h"

/* The last good theta and the filtered i_M for the extraction. */
static void take_snapshot(drive_snapshot_t *snap, const drive_t *d, _iq i_mf)
{
    uint16_t i;
    for (i = 0u; i < RLS_N; i++) {
        snap->theta[i] = d->id.guard.theta_good[i];
    }
    snap->i_m = i_mf;
}

/* The extraction's i_M: the filtered M current, or with the period-mean
 * rows their flux current m_M (param_extract.h, RLS_FORM_FLUX), from their
 * column m_M / i_M,nom (near 1: Q24 * Q24 -> Q24). */
static _iq snapshot_im(const drive_t *d, const drive_rls_sample_t *e)
{
    return (d->id.rls.form == (uint16_t)RLS_FORM_FLUX) ? _IQmpy(e->c1, d->id.reg.k_im_nom) : e->i_mf;
}

/* One sample: both rows (rls_step_row1, _row2: together rls_step), then
 * the guard's verdict on the completed estimate. */
static void rls_update_queued(drive_t *d, const drive_rls_sample_t *e)
{
    rls_t *r = &d->id.rls;
    uint16_t i;
    r->y1 = e->y1;
    r->y2 = e->y2;
    r->i_mf = e->i_mf;
    r->u_mf = e->u_mf;
    r->i_tf = e->i_tf;
    r->u_tf = e->u_tf;
    r->wr_f = e->wr_f;
    r->c1 = e->c1;
    r->d1 = e->d1;
    r->c2 = e->c2;
    r->enable = 1u;
    rls_step_row1(r);
    rls_step_row2(r);
    for (i = 0u; i < RLS_N; i++) {
        d->id.guard.theta[i] = r->theta[i];
    }
    d->id.guard.updated = 1u;
    d->id.guard.windup_hold = r->windup_hold;
    theta_guard_step(&d->id.guard);
}

uint16_t drive_rls_drain(drive_t *d)
{
    drive_rls_queue_t *q = &d->id.rlsq;
    uint16_t tail = q->tail;
    uint16_t taken = 0u;

    while (tail != q->head) {
        const drive_rls_sample_t *e = &q->e[tail];
        if ((e->flags & DRIVE_RLSQ_RESTART) != 0u) {
            (void)drive_rls_start(d);   /* as drive_init left it (float: the background's) */
            theta_guard_reset(&d->id.guard);
        }
        if ((e->flags & DRIVE_RLSQ_WINDOW) != 0u) {
            ident_conf_acc_reset(&d->id.acc);   /* a new RLS window begins */
        }
        if ((e->flags & DRIVE_RLSQ_EXTRACT) != 0u) {
            /* the covariance and the residual sums go with the estimate */
            rls_cov_save(&d->id.snap_cov, &d->id.rls);
            d->id.snap_acc = d->id.acc;
            d->id.snap_pd = d->id.rls.pd_count;
            take_snapshot(&d->id.snap, d, snapshot_im(d, e));
            taken |= DRIVE_RLSQ_EXTRACT;   /* the last one of the drain */
        }
        if ((e->flags & DRIVE_RLSQ_LIVE) != 0u && (taken & DRIVE_RLSQ_LIVE) == 0u) {
            take_snapshot(&d->id.live_snap, d, snapshot_im(d, e));
            taken |= DRIVE_RLSQ_LIVE;      /* the first one of the drain */
        }
        if ((e->flags & DRIVE_RLSQ_UPDATE) != 0u) {
            rls_update_queued(d, e);
            /* the a-posteriori residual of this sample, with its inputs
             * still in the RLS (ident_conf.h) */
            ident_conf_acc_step(&d->id.acc, &d->id.rls);
        }
        tail = (uint16_t)((tail + 1u) & (DRIVE_RLSQ_LEN - 1u));
        q->tail = tail;   /* the entry is free for the ISR only now */
    }
    d->telemetry.rls_sat_count = d->id.rls.sat_count;
    d->telemetry.theta_rejects = d->id.guard.reject_count;
    d->telemetry.rls_dropped = q->dropped;
    return taken;
}
