/**
 * The slow tasks of the multi-rate ISR (drive_step.c): one per ISR, in turn,
 * each at f_pwm / DRIVE_SLOTS (3.75 kHz at 15 kHz).  Every slot's work is
 * bounded and similar in size, so that no ISR carries more than the fast
 * path plus one of them.
 *
 *   SPEED     identification sequence, adaptation (drive_adapt.c), speed
 *             ramp + PI (i_T reference for the fast current loop), the
 *             slow constants of the fast path (1/(Tr i_mr) of the slip, the
 *             bus for the SVPWM's 1/vdc), telemetry and the snapshots for
 *             the background
 *   FILTERS   the confidence's residual sums of the last RLS sample
 *             (ident_conf.h), the regression's filters on the window means
 *             (method §5), y1, y2 and the rows; whether the RLS may update
 *   RLS_ROW1  forgetting + row 1 (method §3)
 *   RLS_ROW2  row 2, then the estimator guard on the completed sample
 *
 * The order within a slow period is SPEED, FILTERS, ROW1, ROW2: the rows
 * use the regressors the FILTERS slot formed in the same period, the
 * sequence sees the filtered di/dt of the previous one.
 */
#include "drive_internal.h"

#include "drive_adapt.h"

/* Hand the last good theta and the filtered i_M to the background
 * (drive_background.c): data first, the ready flag last. */
static void take_snapshot(drive_snapshot_t *snap, const drive_t *d)
{
    uint16_t i;
    for (i = 0u; i < RLS_N; i++) {
        snap->theta[i] = d->guard.theta_good[i];
    }
    snap->i_m = d->reg.i_mf;
    snap->ready = 1u;
}

static void sequence(drive_t *d)
{
    id_sequence_t *s = &d->seq;
    s->fault = (uint16_t)(d->prot.fault != FAULT_NONE);
    s->ramp_done = d->speed_ramp.done;
    s->speed_err = _IQabs(d->speed_ramp.out - d->qep.speed);
    s->i_mf = d->reg.i_mf;
    s->i_tf = d->reg.i_tf;
    id_sequence_step(s);
    if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS && s->state == ID_MAGNETIZE &&
        s->t_state == 0u) {
        /* just entered (t_state restarts at 0 on entry): demagnetised
         * machine, start both models from zero flux (the voltage model has
         * integrated offsets while the bridge was off) */
        flux_obs_reset(&d->fobs);
    }
    if (s->magnetize_end != 0u || s->rls_restart != 0u) {
        ident_conf_acc_reset(&d->conf_acc);   /* a new RLS window begins */
    }
    if (s->extract_now != 0u) {
        /* the covariance and the residual sums go with the estimate */
        rls_cov_save(&d->snap_cov, &d->rls);
        d->snap_acc = d->conf_acc;
        d->snap_pd = d->rls.pd_count;
        take_snapshot(&d->snap, d);
    }
    if (++d->live_div >= d->k.live_period) {
        d->live_div = 0u;
        if (d->live_snap.ready == 0u) {
            take_snapshot(&d->live_snap, d);
        }
    }
}

/* Speed ramp and PI: the torque-current reference of the fast current loop. */
static void speed_loop(drive_t *d)
{
    const id_sequence_t *s = &d->seq;

    d->speed_ramp.target = s->speed_cmd;
    ramp_gen_step(&d->speed_ramp);
    if (s->speed_loop_on != 0u && d->prot.fault == FAULT_NONE) {
        d->pi_speed.ref = d->speed_ramp.out;
        d->pi_speed.fbk = d->qep.speed;
        d->pi_speed.ff = _IQ(0.0);
        pi_step(&d->pi_speed);
        d->i_t_ref = d->pi_speed.out;
    } else {
        pi_reset(&d->pi_speed);
        d->i_t_ref = _IQ(0.0);
    }
}

static void telemetry(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    t->speed = d->qep.speed;
    t->speed_ref = d->speed_ramp.out;
    t->i_m = d->park.ds;
    t->i_t = d->park.qs;
    t->vdc = d->bus.vdc;
    t->rls_sat_count = d->rls.sat_count;
    t->theta_rejects = d->guard.reject_count;
}

/* Current feedback check: the M-T currents against the references the
 * current loops followed in the last period (current_check.h; its 2 ms
 * filter needs no more than this slot's rate).  A trip latches the fault,
 * and the bridge is off in this same ISR (the fast path decides after the
 * slow task). */
static void check_current(drive_t *d)
{
    d->cur_chk.i_m_ref = d->pi_id.ref;
    d->cur_chk.i_m = d->park.ds;
    d->cur_chk.i_t_ref = d->pi_iq.ref;
    d->cur_chk.i_t = d->park.qs;
    d->cur_chk.active = d->on_next;   /* re-armed (filter zeroed) while the bridge is off */
    current_check_step(&d->cur_chk);
    d->prot.current_fault = d->cur_chk.fault;
    if (d->cur_chk.fault != 0u) {
        protect_latch(&d->prot, FAULT_CURRENT_SENSOR);
    }
}

static void task_speed(drive_t *d)
{
    check_current(d);
    /* the encoder's frozen test: no count in 50 ms against torque current */
    d->enc_chk.count = d->qep.count;
    d->enc_chk.i_t = d->park.qs;
    encoder_check_frozen(&d->enc_chk);
    /* the encoder's speeds right before the speed loop uses them (every
     * sample of delay in its feedback costs phase at a reversal) */
    qep_speed_update(&d->qep);
    sequence(d);
    drive_adapt_slow(d);
    speed_loop(d);
    /* the fast path's slow constants: the slip gain 1/(Tr i_mr) (one
     * division; i_mr moves with Tr >= 10 Ts) and the bus the SVPWM divides
     * by (its 1/vdc is recomputed only when this changes: once here) */
    if (d->frame_ifo != 0u) {
        ifo_update_slip_gain(&d->ifo);
    }
    d->svgen.vdc = d->bus.vdc;
    telemetry(d);
}

/* Regression signals and whether the RLS may learn (method §2-§5). */
static void task_filters(drive_t *d)
{
    ident_regressor_t *r = &d->reg;
    uint16_t rls_on = d->seq.rls_on;

    /* the residual of the sample the RLS completed in the last period, while
     * its inputs are still that sample's (ident_conf.h); here, not after
     * row 2, which is the slot that costs most */
    ident_conf_acc_step(&d->conf_acc, &d->rls);
    /* the regression's rotor speed over exactly the window the other six
     * signals were summed over (the mean of its one-period speeds) */
    r->wr = qep_mean_speed(&d->qep, &d->reg_count);
    ident_regressor_filter(r);
    if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
        if (d->fobs_hold != 0u) {
            rls_on = 0u;   /* the frame is held on the encoder angle */
        } else if (d->frame_ifo == 0u && _IQabs(d->fobs.ws_f) < d->k.rls_ws_min) {
            /* below ~10 w_c the current model (the believed Tr) steers the
             * angle: learn only where it does not (flux_obs.h) */
            rls_on = 0u;
        } else {
            /* the observer's frame above its crossover, or RUN on ifo */
        }
    }
    d->rls.y1 = r->y1;
    d->rls.y2 = r->y2;
    d->rls.i_mf = r->i_mf;
    d->rls.u_mf = r->u_mf;
    d->rls.i_tf = r->i_tf;
    d->rls.u_tf = r->u_tf;
    d->rls.wr_f = r->wr_f;
    d->rls.enable = rls_on;
}

/* Row 2 completes the sample: the estimator guard judges it (the snapshots
 * take the last good theta, theta_guard.h). */
static void task_row2(drive_t *d)
{
    uint16_t i;
    rls_step_row2(&d->rls);
    for (i = 0u; i < RLS_N; i++) {
        d->guard.theta[i] = d->rls.theta[i];
    }
    d->guard.updated = d->rls.enable;
    d->guard.windup_hold = d->rls.windup_hold;
    theta_guard_step(&d->guard);
}

void drive_slow_task(drive_t *d, uint16_t slot)
{
    switch (slot) {
    case DRIVE_SLOT_SPEED:
        task_speed(d);
        break;
    case DRIVE_SLOT_FILTERS:
        task_filters(d);
        break;
    case DRIVE_SLOT_RLS_ROW1:
        rls_step_row1(&d->rls);
        break;
    case DRIVE_SLOT_RLS_ROW2:
    default:
        task_row2(d);
        break;
    }
    /* fault and state reach telemetry in the ISR that latched them */
    d->telemetry.state = (uint16_t)d->seq.state;
    d->telemetry.fault = (uint16_t)d->prot.fault;
}
