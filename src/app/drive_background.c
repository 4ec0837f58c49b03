/**
 * Background work of the drive (main loop, below the ISR): commands, and the
 * parameter extraction (method §4), which needs square roots and divisions
 * and has no reason to run at 15 kHz.
 *
 * ISR -> background hand-over: a one-slot mailbox per snapshot.  The ISR
 * writes a snapshot only while its `ready` is 0 and sets `ready` last; the
 * background reads only while `ready` is 1 and clears it last.  With one
 * producer and one consumer no snapshot is ever read half-written.
 */
#include "drive_adapt.h"
#include "drive_internal.h"
#include "drive_safety.h"

static void extract(param_extract_t *p, const drive_snapshot_t *s, uint16_t form)
{
    uint16_t i;
    for (i = 0u; i < RLS_N; i++) {
        p->theta[i] = s->theta[i];
    }
    p->form = form;
    p->i_m = s->i_m;
    param_extract_step(p);
}

/* Only a plausible set is published; an implausible extraction leaves the
 * last good set (and params_valid) untouched and is counted. */
static void publish(drive_telemetry_t *t, const param_extract_t *p)
{
    if (p->valid == 0u) {
        if (t->publish_rejects < 0xFFFFu) {
            t->publish_rejects++;
        }
        return;
    }
    t->Rs = p->Rs;
    t->Rr = p->Rr;
    t->Lm = p->Lm;
    t->Lr = p->Lr;
    t->psi_r = p->psi_r;
    t->Tr = p->Tr;
    t->params_valid = 1u;
}

/* With the tracker valid (RUN, track_rr), the published set takes the
 * estimates that are well conditioned for each parameter (issue 8): Rs
 * from the standstill test (independent of the frame), Rr and Tr from the
 * tracker (the slip in the observer's frame: an angle error delta moves it
 * by ~2 delta, against ~w_r Tr delta for the RLS's K3, w_r Tr = 81 on the
 * 15 kW motor), Lm, Lr, psi_r from the RLS (K2, K4: the large back-EMF
 * terms).  Each value is one aligned 32-bit word the ISR writes whole. */
static void publish_tracked(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    if (t->track_valid == 0u) {
        return;
    }
    if (d->adapt.fused != 0u) {
        /* every value from its well-conditioned source, or nothing */
        if (d->fused_ready == 0u || t->Rs_dc == _IQ(0.0)) {
            return;
        }
        t->Lm = d->fused_lm;
        t->Lr = d->fused_lr;
        t->psi_r = d->fused_psi;
    } else if (t->params_valid == 0u) {
        return;
    } else {
        /* the RLS's Lm, Lr, psi_r (and Rs, unless measured) stay */
    }
    if (t->Rs_dc != _IQ(0.0)) {
        t->Rs = t->Rs_dc;
    }
    t->Rr = t->Rr_track;
    t->Tr = t->Tr_track;
    t->params_tracked = 1u;
    t->params_valid = 1u;
}

/* After a pass's extraction: in fused mode keep the magnetic part (from the
 * full set, or from K2, K4 alone when K1, K3 made the full one implausible),
 * and hand the model to the ISR for the next pass or the tracker. */
static void after_extraction(drive_t *d)
{
    param_extract_t mag;
    const param_extract_t *p = &d->pex;
    uint16_t full = d->pex.valid;

    if (d->adapt.fused != 0u && full == 0u) {
        mag = d->pex;   /* limits and inputs; the outputs are recomputed */
        param_extract_magnetic(&mag);
        p = &mag;
    }
    if (d->adapt.fused != 0u && p->valid != 0u) {
        d->fused_lm = p->Lm;
        d->fused_lr = p->Lr;
        d->fused_psi = p->psi_r;
        d->fused_ready = 1u;
    }
    drive_adapt_post(d, p, full);   /* the next pass (or the tracker) starts from it */
}

static void handle_command(drive_t *d, drive_cmd_t cmd)
{
    switch (cmd) {
    case DRIVE_CMD_START_IDENT:
        /* a restart from a running sequence would re-initialise the RLS under
         * the ISR: only from IDLE */
        if (d->seq.state == ID_IDLE && d->config_status == DRIVE_CFG_OK &&
            d->prot.fault == FAULT_NONE) {
            /* same parameters as drive_init: cannot fail here */
            (void)drive_rls_start(d);
            d->seq.cal_done = 0u;
            /* the published set stays (last good values) until a new
             * plausible one replaces it; the guard starts afresh */
            theta_guard_reset(&d->guard);
            d->fused_ready = 0u;
            /* this run's standstill test decides (an old measurement must
             * not stand in for one that fails now); the ISR writes them
             * only at the end of the magnetisation, not in IDLE */
            d->telemetry.Rs_dc = _IQ(0.0);
            d->telemetry.sigma_ls_dc = _IQ(0.0);
            id_sequence_start(&d->seq);
        }
        break;
    case DRIVE_CMD_STOP:
        id_sequence_stop(&d->seq);
        break;
    case DRIVE_CMD_RESET_FAULT:
        /* the plausibility checks judge a running drive: re-armed here, they
         * trip again if their cause is still there once it runs */
        encoder_check_reset(&d->enc_chk);
        current_check_reset(&d->cur_chk);
        drive_safety_reset(d);
        isr_monitor_reset(&d->ovr);
        d->prot.encoder_fault = 0u;
        d->prot.current_fault = 0u;
        if (d->config_status == DRIVE_CFG_OK && protect_clear(&d->prot) != 0u) {
            id_sequence_clear_fault(&d->seq);
        }
        break;
    case DRIVE_CMD_NONE:
    default:
        break;
    }
}

/* The requests of one background period in their defined order (drive.h):
 * reset, then stop, then start unless a stop came too. */
static void handle_requests(drive_t *d, uint16_t req)
{
    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_RESET_FAULT)) != 0u) {
        handle_command(d, DRIVE_CMD_RESET_FAULT);
    }
    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_STOP)) != 0u) {
        handle_command(d, DRIVE_CMD_STOP);
    } else if ((req & DRIVE_CMD_BIT(DRIVE_CMD_START_IDENT)) != 0u) {
        handle_command(d, DRIVE_CMD_START_IDENT);
    } else {
        /* neither */
    }
}

void drive_background(drive_t *d)
{
    uint16_t req = d->cmd_requests;
    d->cmd_requests = 0u;
    handle_requests(d, req);

    drive_rls_drain(d);   /* the RLS on the ISR's queued samples, and their snapshots */

    if (d->snap.ready != 0u) {
        extract(&d->pex, &d->snap, d->rls.form);
        if (d->adapt.fused == 0u) {
            publish(&d->telemetry, &d->pex);
        }   /* fused mode publishes once the tracker is valid (publish_tracked) */
        after_extraction(d);
        d->snap.ready = 0u;
    }
    if (d->live_snap.ready != 0u) {
        extract(&d->live, &d->live_snap, d->rls.form);
        d->live_snap.ready = 0u;
    }
    drive_adapt_background(d);   /* the adaptation's models and constants (drive_adapt_bg.c) */
    publish_tracked(d);
    drive_safety_background(d);   /* nothing learned while a fault developed stays published */
}

void drive_command(drive_t *d, drive_cmd_t cmd)
{
    if (cmd == DRIVE_CMD_START_IDENT || cmd == DRIVE_CMD_STOP || cmd == DRIVE_CMD_RESET_FAULT) {
        d->cmd_requests = (uint16_t)(d->cmd_requests | DRIVE_CMD_BIT(cmd));
    }   /* DRIVE_CMD_NONE, or a value no command has: nothing to request */
}

/* One aligned 32-bit store: atomic on the C28x (MOVL), so the ISR never sees
 * half a value. */
void drive_set_speed(drive_t *d, _iq speed_pu) { d->seq.speed_target = speed_pu; }

void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t) { *t = d->telemetry; }
