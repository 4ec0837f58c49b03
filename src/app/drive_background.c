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

void drive_background(drive_t *d)
{
    drive_cmd_t cmd = d->pending_cmd;
    d->pending_cmd = DRIVE_CMD_NONE;
    handle_command(d, cmd);

    if (d->snap.ready != 0u) {
        extract(&d->pex, &d->snap, d->rls.form);
        publish(&d->telemetry, &d->pex);
        drive_adapt_post(d, &d->pex);   /* the next pass (or the tracker) starts from it */
        d->snap.ready = 0u;
    }
    if (d->live_snap.ready != 0u) {
        extract(&d->live, &d->live_snap, d->rls.form);
        d->live_snap.ready = 0u;
    }
}

void drive_command(drive_t *d, drive_cmd_t cmd) { d->pending_cmd = cmd; }

/* One aligned 32-bit store: atomic on the C28x (MOVL), so the ISR never sees
 * half a value. */
void drive_set_speed(drive_t *d, _iq speed_pu) { d->seq.speed_target = speed_pu; }

void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t) { *t = d->telemetry; }
