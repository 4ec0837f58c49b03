/**
 * Background work of the drive (the main loop, below both ISRs): commands,
 * the RLS on the slow task's queued samples (drive_rls_bg.c), the parameter
 * extraction (method §4), which needs square roots and divisions and has no
 * reason to run at 15 kHz, the verdict and the publication.
 */
#include <math.h>

#include "drive_adapt.h"
#include "drive_design.h"
#include "drive_internal.h"
#include "drive_static.h"
#include "drive_safety.h"
#include "drive_target.h"
#include "drive_vi.h"

/* the telemetry's confidences are ident_conf's parameters, in its order */
typedef char drive_conf_np_matches[(DRIVE_CONF_NP == IDENT_NP &&
                                    IDENT_NP == (unsigned)IDENT_P_TR + 1u) ? 1 : -1];

const char *drive_pub_reason_str(uint16_t reason)
{
    static const char *const names[DRIVE_PUB_N] = {
        "pending", "published", "not_converged", "low_excitation", "high_residual",
        "low_confidence", "implausible", "fault", "timeout", "stopped", "bus_low",
        "rotor_turning", "torque_limit", "no_standstill"};
    return (reason < (uint16_t)DRIVE_PUB_N) ? names[reason] : "unknown";
}

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

/* What a gain error e of one current sensor that the model check has not
 * found does to each parameter, per unit of e (IDENT_P_ order): the largest
 * effect measured, with about 15 % margin (motor_sim, IQ_MATH, the adaptive
 * sequence, phase a's gain off from MAGNETIZE on; per unit of e: Rs
 * 0.99-1.06, Rr 0.78-1.67, Lm 0.01-0.25, Lr 0.03-0.36, psi_r 0.03-0.32,
 * Tr 0.66-1.25 over the family's 7.5 kW 8-pole, 11 kW 4-pole 575 V, 15 kW
 * 6-pole, the shipped 1.1 kW, 15 kW, 37 kW and the paper motor at 3 % and
 * 5 %; the paper motor's Rr and Tr the largest; before, sets 3-5 % off
 * were published with 0.5-2.9 % stated and none for Rs).  In the fused
 * set Rr's is Tr's plus Lr's (Rr = Lr / Tr).  An offset the model check
 * has not found (below 1.5 % of full scale) moved no published parameter
 * beyond 0.3 %; a 2 % offset latched CURRENT_SENSOR on every motor
 * measured. */
static const float k_sensor_effect[IDENT_NP] = {1.2f, 1.9f, 0.3f, 0.4f, 0.4f, 1.5f};

/* Each confidence of @p mask that is available (>= 0) with what the
 * sensor's possible gain error e does to it, in quadrature (two
 * independent sources: the estimate's own spread and the sensor's; the
 * k_sensor_effect bound alone covers the gain's effect); 1 if one then
 * exceeds the limit.  (Q24 relative: e <= 1 from the caller's clamp, the
 * result saturated at IDENT_CONF_MAX.) */
static uint16_t widen_by_sensor(_iq *conf, uint16_t mask, float e, _iq lim)
{
    uint16_t i, over = 0u;
    for (i = 0u; i < IDENT_NP; i++) {
        if ((mask & (1u << i)) != 0u && conf[i] >= _IQ(0.0)) {
            float v = hypotf(_IQtoF(conf[i]), k_sensor_effect[i] * e);
            conf[i] = _IQ(fminf(v, IDENT_CONF_MAX));
            over |= (uint16_t)(conf[i] > lim);
        }
    }
    return over;
}

/* The extraction of the mid-window estimate with the final i_M, in the
 * form the final one has (the magnetic part alone in fused mode). */
static void extract_mid(drive_t *d, param_extract_t *mid)
{
    uint16_t i;
    *mid = d->id.pex;                 /* limits, form and i_M; the outputs are recomputed */
    for (i = 0u; i < RLS_N; i++) {
        mid->theta[i] = d->verdict.theta_mid[i];
    }
    if (d->adapt.isr.fused != 0u) {
        param_extract_magnetic(mid);
    } else {
        param_extract_step(mid);
    }
}

/* The final pass's data judged (ident_conf.h): the verdict as a reason.
 * The confidences go to telemetry whether the set is published or not. */
static uint16_t judge_rls(drive_t *d, const param_extract_t *end)
{
    ident_conf_t *c = &d->verdict.conf;
    param_extract_t mid;
    uint16_t i;

    c->mask = (d->adapt.isr.fused != 0u) ? IDENT_MASK_MAGNETIC : IDENT_MASK_ALL;
    if (end->valid != 0u) {
        if (d->verdict.mid == 2u) {
            extract_mid(d, &mid);
        } else {
            mid.valid = 0u;   /* the window never reached its middle with an estimate */
        }
        ident_conf_eval(c, &d->id.snap_cov, &d->id.snap_acc, d->id.snap_pd, end, &mid);
        /* what the sensors may hide widens every figure (the fused set's Rs,
         * Rr, Tr: judge_fused) */
        d->verdict.sensor_gain = fminf(drive_safety_sensor_gain(d), 1.0f);
        if (widen_by_sensor(c->conf, c->mask, d->verdict.sensor_gain, c->conf_max) != 0u &&
            c->verdict == (uint16_t)IDENT_CONF_OK) {
            /* refused now: named as ident_conf names a refusal (a small
             * signal is low excitation, ident_conf.h) */
            c->verdict = (c->excitation < c->exc_ref) ? (uint16_t)IDENT_CONF_LOW_EXCITATION
                                                      : (uint16_t)IDENT_CONF_LOW_CONFIDENCE;
        }
        if (d->adapt.isr.fused != 0u) {
            /* Rs, Rr, Tr are judge_fused's: not available until it runs
             * (a set the RLS's part refuses never gets them) */
            c->conf[IDENT_P_RS] = -_IQ(1.0);
            c->conf[IDENT_P_RR] = -_IQ(1.0);
            c->conf[IDENT_P_TR] = -_IQ(1.0);
        }
    } else {
        for (i = 0u; i < IDENT_NP; i++) {
            c->conf[i] = _IQ(0.0);
        }
        c->residual = _IQ(0.0);
        c->amp = _IQ(0.0);
    }
    for (i = 0u; i < IDENT_NP; i++) {
        d->telemetry.conf[i] = c->conf[i];
    }
    d->telemetry.conf_residual = c->residual;
    d->telemetry.conf_amp = c->amp;
    if (d->id.guard.good == 0u) {
        /* no plausible estimate: the RLS never updated (the acceleration stayed below
         * the speeds where it learns), or it did and never converged */
        return (d->id.snap_acc.n == 0u) ? (uint16_t)DRIVE_PUB_LOW_EXCITATION
                                : (uint16_t)DRIVE_PUB_NOT_CONVERGED;
    }
    if (end->valid == 0u) {
        return DRIVE_PUB_IMPLAUSIBLE;
    }
    if (d->seq.settle_timeout != 0u) {
        /* the formulas' steady state not confirmed: because the load took all
         * the torque the drive may give (the speed below its target), or not */
        return (d->seq.torque_limited != 0u) ? (uint16_t)DRIVE_PUB_TORQUE_LIMIT
                                             : (uint16_t)DRIVE_PUB_TIMEOUT;
    }
    switch (c->verdict) {
    case IDENT_CONF_OK: return DRIVE_PUB_PUBLISHED;
    case IDENT_CONF_HIGH_RESIDUAL: return DRIVE_PUB_HIGH_RESIDUAL;
    case IDENT_CONF_LOW_EXCITATION: return DRIVE_PUB_LOW_EXCITATION;
    case IDENT_CONF_LOW_CONFIDENCE: return DRIVE_PUB_LOW_CONFIDENCE;
    case IDENT_CONF_NOT_CONVERGED:
    case IDENT_CONF_NO_DATA:
    default: return DRIVE_PUB_NOT_CONVERGED;
    }
}

static void count_reject(drive_telemetry_t *t)
{
    if (t->publish_rejects < 0xFFFFu) {
        t->publish_rejects++;
    }
}

/* Only a set the data stand behind is published (the verdict of
 * judge_rls); a refused one leaves the last good set (and params_valid)
 * untouched and is counted. */
void drive_publish(drive_telemetry_t *t, const param_extract_t *p, uint16_t reason)
{
    t->publish_reason = reason;
    if (reason != (uint16_t)DRIVE_PUB_PUBLISHED) {
        count_reject(t);
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

/* The tracker's fit while it is valid (fused set): each new update's
 * filtered regression (y_f, phi_f, theta: tr_track.h) into its relative
 * residual (ident_conf_fit_t).  Three words the ISR writes in one slow
 * task: a sample torn by an ISR in between is skipped. */
static void sample_tracker(drive_t *d)
{
    /* volatile: the ISR may update the tracker between these reads (the
     * second read of y_f must be a read, not the compiler's copy) */
    const volatile tr_track_t *t = &d->adapt.track;
    _iq y, phi, th;
    if (t->n_updates == d->verdict.trk_updates || t->held != 0u) {
        return;
    }
    d->verdict.trk_updates = t->n_updates;
    y = t->y_f;
    phi = t->phi_f;
    th = t->theta;
    if (y == t->y_f) {
        if (d->verdict.trk_fit.n == 0u) {
            d->verdict.trk_theta0 = th;
        }
        ident_conf_fit_add(&d->verdict.trk_fit, y, phi, th);
    }
}

static void tracker_reset(drive_t *d)
{
    ident_conf_fit_reset(&d->verdict.trk_fit);
    d->verdict.trk_updates = d->adapt.track.n_updates;
    d->verdict.trk_theta0 = _IQ(0.0);
}

/* The fused set's verdict, once the tracker has fitted for
 * DRIVE_CONF_TRACK_S: Lm, Lr, psi_r by the RLS's data (judge_rls of the
 * final pass); Tr by the tracker: its standard error (the relative residual
 * of its fit times k.conf_track_se: the tracker averages noise, and a bias
 * of its frame leaves no residual at all, so its worst-case bound would say
 * nothing more) plus how far its estimate moved over the window; Rr = Lr/Tr
 * by both (the sum of the two relative figures).  The standstill Rs by the
 * bridge's curve test, when it ran: its Rs is the slope between two current
 * levels, in which the bridge's error voltage cancels, where the standstill
 * Rs divides one level's voltage less the compensation's: their difference
 * is the compensation's error at i_M, the standstill Rs's own (measured:
 * 15 kW -0.50 % off, the two 0.74 % apart; 1.1 kW, paper, 2.2 kW, 0.75 kW
 * 0.01-0.18 % off, 0.05-0.16 % apart); without the test only the sensors'
 * share (the RLS's Rs, the only other measurement, is the worse one in
 * this sequence: docs/method.md "Beyond the paper").  Each plus what a
 * current sensor's gain error the model check cannot see would do
 * (widen_by_sensor).  DRIVE_PUB_PENDING while it waits; a tracker
 * that never learns (no torque: tr_track.h's wind-up guard) within
 * DRIVE_CONF_TRACK_WAIT_S of RUN is low_excitation. */
static uint16_t judge_fused(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    _iq trk, drift, lim = d->verdict.conf.conf_max;
    if (t->Rs_dc == _IQ(0.0)) {
        return DRIVE_PUB_IMPLAUSIBLE;   /* the standstill Rs was implausible: no fused set */
    }
    if (d->verdict.trk_fit.n < d->k.conf_track_updates) {
        return (d->seq.state == ID_RUN && d->seq.t_state >= d->k.conf_track_wait)
                   ? (uint16_t)DRIVE_PUB_LOW_EXCITATION : (uint16_t)DRIVE_PUB_PENDING;
    }
    trk = ident_conf_fit_bound(&d->verdict.trk_fit);
    trk = (trk < _IQ(IDENT_CONF_MAX)) ? _IQmpy(trk, d->k.conf_track_se) : trk;
    drift = ident_conf_rel_change(d->adapt.track.theta, d->verdict.trk_theta0);   /* 1/Tr: the same relative change */
    /* as ident_conf's: the sum of the two figures (each < 100) */
    t->conf[IDENT_P_TR] = (trk + drift < _IQ(IDENT_CONF_MAX)) ? trk + drift : _IQ(IDENT_CONF_MAX);
    t->conf[IDENT_P_RS] = (d->vi.rs > 0.0f)
                              ? _IQ(fminf(fabsf(_IQtoF(t->Rs_dc) - d->vi.rs) /
                                              _IQtoF(t->Rs_dc), IDENT_CONF_MAX))
                              : _IQ(0.0);
    /* (the larger of the final pass's figure and RUN's, now) */
    d->verdict.sensor_gain = fmaxf(d->verdict.sensor_gain, fminf(drive_safety_sensor_gain(d), 1.0f));
    (void)widen_by_sensor(t->conf, (1u << IDENT_P_RS) | (1u << IDENT_P_TR), d->verdict.sensor_gain, lim);
    /* (Lr's widened by judge_rls: Rr's sum carries both shares) */
    t->conf[IDENT_P_RR] = (t->conf[IDENT_P_TR] < _IQ(IDENT_CONF_MAX / 2.0f) &&
                           t->conf[IDENT_P_LR] < _IQ(IDENT_CONF_MAX / 2.0f))
                              ? t->conf[IDENT_P_TR] + t->conf[IDENT_P_LR]
                              : _IQ(IDENT_CONF_MAX);
    if (t->conf[IDENT_P_TR] > lim || t->conf[IDENT_P_RR] > lim || t->conf[IDENT_P_RS] > lim) {
        return (drift > trk && t->conf[IDENT_P_TR] > lim) ? (uint16_t)DRIVE_PUB_NOT_CONVERGED
                                                           : (uint16_t)DRIVE_PUB_LOW_CONFIDENCE;
    }
    return DRIVE_PUB_PUBLISHED;
}

uint16_t drive_fused_set(const drive_t *d, drive_params_t *s)
{
    const drive_telemetry_t *t = &d->telemetry;
    if (d->adapt.isr.fused == 0u || d->verdict.fused_ready == 0u || t->Rs_dc == _IQ(0.0) ||
        t->Tr_track == 0) {
        return 0u;
    }
    s->Rs = t->Rs_dc;
    s->Rr = t->Rr_track;
    s->Lm = d->verdict.fused_lm;
    s->Lr = d->verdict.fused_lr;
    s->psi_r = d->verdict.fused_psi;
    s->Tr = t->Tr_track;
    return 1u;
}

/* With the tracker valid (RUN, track_rr), the published set takes the
 * estimates that are well conditioned for each parameter (the fused set): Rs
 * from the standstill test (independent of the frame), Rr and Tr from the
 * tracker (the slip in the observer's frame: an angle error delta moves it
 * by ~2 delta, against ~w_r Tr delta for the RLS's K3, w_r Tr = 81 on the
 * 15 kW motor), Lm, Lr, psi_r from the RLS (K2, K4: the large back-EMF
 * terms).  Each value is one aligned 32-bit word the ISR writes whole. */
static void publish_tracked(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    drive_params_t f;
    if (t->track_valid == 0u) {
        return;
    }
    if (d->adapt.isr.fused != 0u) {
        /* every value from its well-conditioned source, or nothing */
        if (drive_fused_set(d, &f) == 0u ||
            t->publish_reason != (uint16_t)DRIVE_PUB_PUBLISHED) {
            return;   /* not yet, or refused (fused_verdict): the last good set stays */
        }
        t->Lm = f.Lm;
        t->Lr = f.Lr;
        t->psi_r = f.psi_r;
        /* and, below, its Rs, Rr, Tr: the standstill and tracked ones */
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

/* The fused set's verdict (judge_fused), from the final pass's extraction
 * on, until it is given: the tracker's fit sampled while it is valid. */
static void fused_verdict(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    uint16_t reason;
    if (d->adapt.isr.fused == 0u || d->verdict.judged == 0u ||
        t->publish_reason != (uint16_t)DRIVE_PUB_PENDING) {
        return;
    }
    if (t->track_valid != 0u) {
        sample_tracker(d);
    }
    reason = judge_fused(d);
    if (reason != (uint16_t)DRIVE_PUB_PENDING) {
        t->publish_reason = reason;
        if (reason != (uint16_t)DRIVE_PUB_PUBLISHED) {
            count_reject(t);
        }
    }
}

/* After a pass's extraction: in fused mode keep the magnetic part (from the
 * full set, or from K2, K4 alone when K1, K3 made the full one implausible),
 * and hand the model to the ISR for the next pass or the tracker. */
static void after_extraction(drive_t *d)
{
    param_extract_t mag;
    const param_extract_t *p = &d->id.pex;
    uint16_t full = d->id.pex.valid;

    if (d->adapt.isr.fused != 0u && full == 0u) {
        mag = d->id.pex;   /* limits and inputs; the outputs are recomputed */
        param_extract_magnetic(&mag);
        p = &mag;
    }
    if (d->adapt.isr.fused != 0u && p->valid != 0u) {
        d->verdict.fused_lm = p->Lm;
        d->verdict.fused_lr = p->Lr;
        d->verdict.fused_psi = p->psi_r;
        d->verdict.fused_ready = 1u;
    }
    drive_adapt_post(d, p, full);   /* the next pass (or the tracker) starts from it */
}

/* A start, from IDLE: refused with its reason while the rotor still turns
 * (the standstill phases need it at rest: id_sequence_set_rest); else the
 * configured target (a run before may have lowered it: drive_target.h) and
 * the identification's state afresh. */
static void start_identification(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;

    /* a new verdict is owed for this run */
    d->verdict.run = 1u;
    if (d->verdict.static_unavailable != 0u) {
        /* the standstill sequence was asked for: never a rotating one instead */
        t->publish_reason = (uint16_t)DRIVE_PUB_NO_STANDSTILL;
        count_reject(t);
        return;
    }
    if (_IQabs(d->sense.qep.speed) > d->k.rest_speed) {
        t->publish_reason = (uint16_t)DRIVE_PUB_ROTOR_TURNING;
        count_reject(t);
        return;
    }
    t->publish_reason = (uint16_t)DRIVE_PUB_PENDING;
    id_sequence_set_target(&d->seq, d->target.target);
    /* same parameters as drive_init: cannot fail here */
    (void)drive_rls_start(d);
    d->sense.cal_done = 0u;
    /* the published set stays (last good values) until a new
     * plausible one replaces it; the guard starts afresh */
    theta_guard_reset(&d->id.guard);
    drive_safety_sensor_gain_reset(d);
    d->verdict.fused_ready = 0u;
    d->verdict.judged = 0u;
    d->verdict.static_judged = 0u;
    d->verdict.mid = 0u;
    d->verdict.pass = 0u;
    tracker_reset(d);
    /* this run's standstill test decides (an old measurement must
     * not stand in for one that fails now); the ISR writes them
     * only at the end of the magnetisation, not in IDLE */
    t->Rs_dc = _IQ(0.0);
    t->sigma_ls_dc = _IQ(0.0);
    /* the standstill sequence's test afresh (the ISR runs it only in INJECT) */
    d->adapt.lf.running = 0u;
    d->adapt.lf.done = 0u;
    d->adapt.lf.i_add = _IQ(0.0);
    d->adapt.lf.i_step = _IQ(0.0);   /* the step first: an ISR between the two adds nothing */
    d->adapt.lf.i_ref = _IQ(0.0);
    id_sequence_start(&d->seq);
}

static void handle_command(drive_t *d, drive_cmd_t cmd)
{
    switch (cmd) {
    case DRIVE_CMD_START_IDENT:
        /* a restart from a running sequence would re-initialise the RLS under
         * the ISR: only from IDLE */
        if (d->seq.state == ID_IDLE && d->k.config_status == DRIVE_CFG_OK &&
            d->prot.trip.fault == FAULT_NONE) {
            start_identification(d);
        }
        break;
    case DRIVE_CMD_STOP:
        id_sequence_stop(&d->seq);
        if (d->verdict.run != 0u && d->telemetry.publish_reason == (uint16_t)DRIVE_PUB_PENDING) {
            d->telemetry.publish_reason = (uint16_t)DRIVE_PUB_STOPPED;
        }
        break;
    case DRIVE_CMD_RESET_FAULT:
        /* the plausibility checks judge a running drive: re-armed here, they
         * trip again if their cause is still there once it runs */
        encoder_check_reset(&d->prot.enc);
        current_check_reset(&d->prot.feedback);
        drive_safety_reset(d);
        isr_monitor_reset(&d->prot.ovr);
        d->prot.trip.encoder_fault = 0u;
        d->prot.trip.current_fault = 0u;
        if (d->k.config_status == DRIVE_CFG_OK && protect_clear(&d->prot.trip) != 0u) {
            id_sequence_clear_fault(&d->seq);
        }
        break;
    case DRIVE_CMD_SELECT_STANDSTILL:
    case DRIVE_CMD_SELECT_ROTATING:
        if (d->seq.state == ID_IDLE) {
            drive_static_select(d, (uint16_t)(cmd == DRIVE_CMD_SELECT_STANDSTILL));
        }
        break;
    case DRIVE_CMD_NONE:
    default:
        break;
    }
}

/* The estimate at the middle of the RLS window, for the drift
 * (ident_conf.h): armed at the first live snapshot of the window (the RLS
 * has updated: its sums count), halfway between that speed and the
 * target; taken at the first live snapshot at or above it. */
static void capture_mid(drive_t *d, const drive_snapshot_t *live)
{
    const id_sequence_t *s = &d->seq;
    _iq sp = _IQabs(d->sense.qep.speed);
    uint16_t i;
    if (s->pass != d->verdict.pass) {
        d->verdict.pass = s->pass;
        d->verdict.mid = 0u;
    }
    if (s->state != ID_ACCELERATE || d->id.acc.n == 0u || d->id.guard.good == 0u) {
        return;
    }
    if (d->verdict.mid == 0u) {
        /* both < 2 pu (the speed reference's range) */
        d->verdict.speed_mid = _IQmpy(sp + _IQabs(s->speed_target), _IQ(0.5));
        d->verdict.mid = 1u;
    } else if (d->verdict.mid == 1u && sp >= d->verdict.speed_mid) {
        for (i = 0u; i < RLS_N; i++) {
            d->verdict.theta_mid[i] = live->theta[i];
        }
        d->verdict.mid = 2u;
    } else {
        /* armed, below the middle; or taken */
    }
}

/* The extraction of the final pass: judged (ident_conf.h) and, unless the
 * set is the fused one (publish_tracked), published or refused.  Earlier
 * passes only hand their model on (after_extraction). */
static void extraction_done(drive_t *d)
{
    const param_extract_t *end = &d->id.pex;
    param_extract_t mag;
    uint16_t reason;
    if (d->seq.pass < d->seq.passes) {
        return;
    }
    if (d->adapt.isr.fused != 0u && d->id.pex.valid == 0u) {
        mag = d->id.pex;   /* the magnetic part alone, as after_extraction keeps it */
        param_extract_magnetic(&mag);
        end = &mag;
    }
    reason = judge_rls(d, end);
    if (d->adapt.isr.fused == 0u) {
        drive_publish(&d->telemetry, &d->id.pex, reason);
        return;
    }
    d->verdict.judged = 1u;
    if (reason != (uint16_t)DRIVE_PUB_PUBLISHED) {
        /* the RLS's part already fails: the fused set cannot be published */
        d->telemetry.publish_reason = reason;
        count_reject(&d->telemetry);
    }
}

/* The requests of one background period in their defined order (drive.h):
 * reset, then stop, then start unless a stop came too. */
static void handle_requests(drive_t *d, uint16_t req)
{
    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_RESET_FAULT)) != 0u) {
        handle_command(d, DRIVE_CMD_RESET_FAULT);
    }
    /* a selection before the start it is for (both in one pass: the rotating one wins) */
    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_SELECT_STANDSTILL)) != 0u) {
        handle_command(d, DRIVE_CMD_SELECT_STANDSTILL);
    }
    if ((req & DRIVE_CMD_BIT(DRIVE_CMD_SELECT_ROTATING)) != 0u) {
        handle_command(d, DRIVE_CMD_SELECT_ROTATING);
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
    uint16_t taken;
    uint16_t req = d->cmd_requests;
    d->cmd_requests = 0u;
    handle_requests(d, req);

    /* the RLS on the slow task's queued samples, and their snapshots */
    taken = drive_rls_drain(d);
    if ((taken & DRIVE_RLSQ_EXTRACT) != 0u) {
        extract(&d->id.pex, &d->id.snap, d->id.rls.form);
        extraction_done(d);
        after_extraction(d);
    }
    if ((taken & DRIVE_RLSQ_LIVE) != 0u) {
        extract(&d->id.live, &d->id.live_snap, d->id.rls.form);
        capture_mid(d, &d->id.live_snap);
    }
    drive_vi_background(d);      /* the bridge's curve, once measured (drive_vi.c) */
    drive_adapt_background(d);   /* the adaptation's models and constants (drive_adapt_bg.c) */
    drive_static_background(d);  /* the standstill sequence's verdict (drive_static.c) */
    fused_verdict(d);
    publish_tracked(d);
    drive_safety_background(d);   /* nothing learned while a fault developed stays published */
    /* the voltage ended the acceleration below the least target (a bus far
     * below nominal, a load the voltage cannot carry at speed): what the
     * identification would learn there cannot be trusted; the bridge off */
    if (d->verdict.run != 0u && d->telemetry.publish_reason == (uint16_t)DRIVE_PUB_PENDING &&
        d->seq.target_lowered != 0u && _IQabs(d->seq.speed_target) < d->target.least) {
        id_sequence_stop(&d->seq);
        d->telemetry.publish_reason = (uint16_t)DRIVE_PUB_BUS_LOW;
        count_reject(&d->telemetry);
    }
    /* the rotor turned in a standstill phase: the sequence went back to IDLE */
    if (d->verdict.run != 0u && d->telemetry.publish_reason == (uint16_t)DRIVE_PUB_PENDING &&
        d->seq.state == ID_IDLE && d->seq.rotor_moved != 0u) {
        d->telemetry.publish_reason = (uint16_t)DRIVE_PUB_ROTOR_TURNING;
        count_reject(&d->telemetry);
    }
    /* a protection that trips before the verdict: the set was never complete */
    if (d->verdict.run != 0u && d->telemetry.publish_reason == (uint16_t)DRIVE_PUB_PENDING &&
        d->seq.state == ID_FAULT) {
        d->telemetry.publish_reason = (uint16_t)DRIVE_PUB_FAULT;
        count_reject(&d->telemetry);
    }
}

void drive_command(drive_t *d, drive_cmd_t cmd)
{
    /* every command of drive_cmd_t (contiguous from START_IDENT): its request bit */
    if (cmd >= DRIVE_CMD_START_IDENT && cmd <= DRIVE_CMD_SELECT_ROTATING) {
        d->cmd_requests = (uint16_t)(d->cmd_requests | DRIVE_CMD_BIT(cmd));
    }   /* DRIVE_CMD_NONE, or a value no command has: nothing to request */
}

/* One aligned 32-bit store: atomic on the C28x (MOVL), so the ISR never sees
 * half a value. */
void drive_set_speed(drive_t *d, _iq speed_pu) { d->seq.speed_target = speed_pu; }

void drive_get_telemetry(const drive_t *d, drive_telemetry_t *t) { *t = d->telemetry; }
