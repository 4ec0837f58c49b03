/**
 * Parameter adaptation, the background's part (drive_adapt.c says what is
 * adapted and why).  Everything that divides or needs the exponential runs
 * here, below the ISR, and reaches the ISR as one complete model set
 * through a one-slot mailbox (drive_adapt_box_t):
 *
 *   - the standstill result: from the ISR's capture at the end of the
 *     magnetisation, Rs = u_M / i_M (method §1 at DC) and sigma Ls from the
 *     lock-in's sums (standstill_z_finish), the new model, and the
 *     observer's re-seat on the DC solution (flux_obs_seat_dc) with the
 *     filtered DC voltage and current turned back to alpha-beta at the held
 *     frame's angle; posted with READY (the sequence holds the end of
 *     MAGNETIZE for it);
 *   - a pass's model: the blend from the model in use to the new one over
 *     DRIVE_ADAPT_BLEND_S, timed by the ISR's SEQUENCE ticks (the fraction
 *     is ticks elapsed x blend_step, what the ISR's per-tick sum gave), one
 *     intermediate set per background pass; the last with READY in REFINE;
 *     in RUN the first starts the tracker;
 *   - the tracked Tr: the tracker's 1/Tr (tr_track_step runs in the ISR)
 *     rate limited per tracker update as before (step = Tr in use x
 *     tr_rate per update, updates counted by n_updates), posted; the first
 *     tracked set hands the control frame to ifo (ALIGN).
 * Each set holds everything that depends on the model (flux_obs_model_t,
 * ifo_tr_t, pi_gains_t, Lm^2/Lr, 1/Lm), designed in float from the pu
 * model (flux_obs_design_*, ifo_design_tr, pi_design_gains: the same
 * functions the inits use); a group a design refuses keeps the constants
 * in use (as the fixed-point setters refused before).
 *
 * The mailbox.  One writer, one reader: the background writes the set only
 * while ready = 0 (it posts nothing new until it has read the answer to
 * the last post), then ready = 1; the ISR copies it only while ready = 1,
 * in one ISR, writes taken (applied, or dropped when the sequence has left
 * the state and pass the set was made for) and clears ready last.  The set
 * is written through a volatile lvalue and ready is volatile, so the
 * compiler keeps every store of the set before the one of ready.  So the
 * ISR never sees half a set, and the background always knows which model
 * the ISR runs (applied, applied_set).
 */
#include "drive_adapt.h"
#include "drive_internal.h"

#include "angle.h"

#include <math.h>

/* Limit x to [ref / 2, 2 ref] (ref > 0): the rate limit per pass; the
 * upper end at most top (same Q as x and ref: 2 ref stays in range). */
static _iq within_factor_2(_iq x, _iq ref, _iq top)
{
    _iq lo = _IQmpy(ref, _IQ(0.5));   /* any Q times Q24 0.5: the same Q */
    _iq hi = (ref < top - ref) ? ref + ref : top;
    if (x < lo) {
        return lo;
    }
    return (x > hi) ? hi : x;
}

/* The constants of the model v, starting from the set in use: a group a
 * design refuses keeps its constants (flux_obs.h).  Float, pu. */
static void design(const drive_adapt_bg_t *g, const _iq v[DRIVE_ADAPT_NP], drive_model_set_t *s)
{
    const float lm = _IQtoF(v[DRIVE_P_LM]);
    const float lr = _IQtoF(v[DRIVE_P_LR]);

    *s = g->applied_set;
    (void)flux_obs_design_rs(&s->fobs, _IQtoF(v[DRIVE_P_RS]));
    if (flux_obs_design_l(&s->fobs, lm, lr, _IQtoF(v[DRIVE_P_LS])) == FLUX_OBS_OK) {
        s->lm2_lr = _IQ(lm * lm / lr);            /* < Lm < 16 */
        s->inv_lm = _IQ(fminf(1.0f / lm, 16.0f));
    }
    (void)flux_obs_design_tr(&s->fobs, g->obs_ts_pu, _IQ20toF(v[DRIVE_P_TR]));   /* Q20 */
    /* ifo runs on the observer's Tr */
    (void)ifo_design_tr(&s->ifo, g->ts_pu, _IQ20toF(s->fobs.tr), g->imr_min_pu);
    /* kp = w_c sigma Ls <= 100, ki = w_c Ts Rs <= 1: else refused */
    (void)pi_design_gains(&s->pi, g->kp_per_sls * _IQtoF(s->fobs.sigma_ls),
                          g->ki_per_rs * _IQtoF(s->fobs.rs));
    s->theta0 = _IQ(0.0);
    s->flags = 0u;
}

/* Into the mailbox (free: no post pending), ready last. */
static void post(drive_t *d, const drive_model_set_t *s, const _iq v[DRIVE_ADAPT_NP])
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_adapt_box_t *box = &d->adapt.box;
    uint16_t i;

    *(volatile drive_model_set_t *)&box->set = *s;   /* every store before ready's */
    box->taken = 0u;
    box->ready = 1u;
    for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
        g->posted[i] = v[i];
    }
    g->pending = 1u;
}

/* The model in use, unchanged, for a state that waits for it. */
static void post_ready(drive_t *d, uint16_t st, uint16_t pass)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_model_set_t s = g->applied_set;
    s.flags = DRIVE_SET_READY;
    s.state = st;
    s.pass = pass;
    post(d, &s, g->applied);
}

/* The ISR's answer to the last post: applied (the model in use is now the
 * posted one) or dropped (the sequence moved on: a blend for that state
 * ends where the ISR is).  0 while the set is still in the mailbox. */
static uint16_t answer(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_adapt_box_t *box = &d->adapt.box;
    uint16_t i;

    if (g->pending == 0u) {
        return 1u;
    }
    if (box->ready != 0u) {
        return 0u;
    }
    if (box->taken == DRIVE_BOX_APPLIED) {
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            g->applied[i] = g->posted[i];
        }
        g->applied_set = box->set;
    } else {
        g->blending = 0u;
    }
    g->pending = 0u;
    return 1u;
}

/* The standstill result from the ISR's capture (drive_adapt.c): Rs from the
 * DC part, sigma Ls from the injection (if valid), the new model and the
 * observer's DC re-seat; posted with READY either way (an implausible
 * result keeps the believed model, Rs_dc reads 0). */
static void standstill_set(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_adapt_capture_t c = d->adapt.cap;
    const uint16_t pass = d->seq.pass;
    drive_model_set_t s;
    _iq v[DRIVE_ADAPT_NP];
    _iq rs;
    uint16_t i;

    d->adapt.cap.ready = 0u;   /* copied: the ISR may capture again */
    if (d->seq.state != ID_MAGNETIZE) {
        return;   /* the sequence did not wait (time-out, stop): too late */
    }
    /* a usable i_M (a quarter of the reference) and a quotient inside Q24:
     * |u_M| < 4 |i_M| bounds Rs_pu below 4 (flux_obs's range) */
    if (!(c.i_mf > _IQmpy(d->seq.im_ref, _IQ(0.25))) ||
        !(_IQabs(c.u_mf) < _IQmpy(c.i_mf, _IQ(4.0)))) {
        post_ready(d, ID_MAGNETIZE, pass);
        return;
    }
    rs = _IQdiv(c.u_mf, c.i_mf);
    if (rs < g->rs_lo || rs > g->rs_hi) {
        post_ready(d, ID_MAGNETIZE, pass);
        return;
    }
    for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
        v[i] = g->applied[i];
    }
    v[DRIVE_P_RS] = rs;
    d->telemetry.Rs_dc = rs;
    if (c.ssz_done != 0u) {
        /* the lock-in's result from its sums, on a copy (its constants are
         * fixed after init; the ISR does not touch the sums once done) */
        standstill_z_t z = d->adapt.ssz;
        z.us = c.us;
        z.uc = c.uc;
        z.is = c.is;
        z.ic = c.ic;
        z.done = 1u;
        standstill_z_finish(&z);
        if (z.valid != 0u) {
            /* keep the believed Lm, Lr: Ls = sigma Ls + Lm^2/Lr (< 8 + 16) */
            _iq ls = z.sigma_ls + _IQmpy(g->applied_set.fobs.lm, g->applied_set.fobs.lm_lr);
            v[DRIVE_P_LS] = within_factor_2(ls, v[DRIVE_P_LS], _IQ(120.0));
            d->telemetry.sigma_ls_dc = z.sigma_ls;
        }
    }
    design(g, v, &s);
    {
        /* the filtered (DC) M-T voltage and current back to alpha-beta at
         * the held frame angle (the encoder's: drive_step.c) */
        _iq sn, cs;
        angle_sincos(c.theta_r, &sn, &cs);
        if (flux_obs_seat_dc(&d->frame.fobs, &s.fobs, c.psi_cm_alpha, c.psi_cm_beta,
                             _IQmpy(cs, c.u_mf) - _IQmpy(sn, c.u_tf),
                             _IQmpy(sn, c.u_mf) + _IQmpy(cs, c.u_tf),
                             _IQmpy(cs, c.i_mf) - _IQmpy(sn, c.i_tf),
                             _IQmpy(sn, c.i_mf) + _IQmpy(cs, c.i_tf), &s.seat) == FLUX_OBS_OK) {
            s.flags = DRIVE_SET_SEAT;
        }
    }
    s.flags |= DRIVE_SET_READY;
    s.state = ID_MAGNETIZE;
    s.pass = pass;
    post(d, &s, v);
}

/* Ls of a new model's Lm, Lr with the standstill test's sigma Ls: sigma Ls +
 * Lm^2/Lr (Lr > Lm > 0: the quotient < 1 by _IQdiv; < 8 + 16); without that
 * test, ls as given. */
static void ls_from_sigma(const drive_t *d, _iq v[DRIVE_ADAPT_NP])
{
    if (d->telemetry.sigma_ls_dc != _IQ(0.0)) {
        v[DRIVE_P_LS] = d->telemetry.sigma_ls_dc +
                        _IQmpy(v[DRIVE_P_LM], _IQdiv(v[DRIVE_P_LM], v[DRIVE_P_LR]));
    }
}

/* Each parameter of a new model within a factor 2 of the model in use (the
 * designs' ranges): Q24 parameters below 120 pu, Tr (Q20) below
 * IFO_TR_MAX_PU. */
static void within_factor_2_of_applied(const drive_adapt_bg_t *g, _iq v[DRIVE_ADAPT_NP])
{
    uint16_t i;
    for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
        v[i] = within_factor_2(v[i], g->applied[i],
                               (i == DRIVE_P_TR) ? _IQ20(IFO_TR_MAX_PU) : _IQ(120.0));
    }
}

/* The standstill sequence's set as the model in use, whole (at rest nothing
 * runs on it: no blend): Rs, Lm, Lr, Tr as published; Ls = sigma Ls +
 * Lm^2/Lr with the standstill test's sigma Ls (its lock-in ran in the
 * sequence's MAGNETIZE), else Lr (method §4).  Each within a factor 2 of the
 * model in use, as a pass's (the designs' ranges). */
static void seed(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_model_set_t s;
    _iq v[DRIVE_ADAPT_NP];

    v[DRIVE_P_RS] = g->m_rs;
    v[DRIVE_P_LM] = g->m_lm;
    v[DRIVE_P_LR] = g->m_lr;
    v[DRIVE_P_LS] = g->m_ls;
    v[DRIVE_P_TR] = g->m_tr;
    ls_from_sigma(d, v);
    within_factor_2_of_applied(g, v);
    g->lr = v[DRIVE_P_LR];
    design(g, v, &s);
    s.state = ID_IDLE;
    s.pass = d->seq.pass;
    post(d, &s, v);
}

/* A pass's extraction: the blend's target (or, in REFINE with nothing
 * usable, the model in use with READY: the next pass runs on it). */
static void take_mail(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    const drive_adapt_t *a = &d->adapt.isr;
    const uint16_t st = (uint16_t)d->seq.state;
    const uint16_t pass = d->seq.pass;
    uint16_t i;

    g->m_ready = 0u;
    if (g->m_seed != 0u) {
        g->m_seed = 0u;
        if (g->m_valid != 0u && st == (uint16_t)ID_IDLE) {
            seed(d);
        }
        return;   /* a start came first: the set it would have seeded is dropped */
    }
    if (g->m_valid != 0u && (st == (uint16_t)ID_REFINE || st == (uint16_t)ID_RUN)) {
        g->to[DRIVE_P_RS] = g->m_rs;
        g->to[DRIVE_P_LM] = g->m_lm;
        g->to[DRIVE_P_LR] = g->m_lr;
        g->to[DRIVE_P_LS] = g->m_ls;
        g->to[DRIVE_P_TR] = g->m_tr;
        /* Measured standstill values stay: the RLS's Rs and sigma Ls come
         * through the frame the observer computes with them, so feeding
         * them back closes a loop (measured, believed Rs +30 %: the RLS's
         * Rs rose +3.7, +5.1, +5.9 % pass after pass; sigma Ls crept
         * +0.13 % a pass).  With both held, the passes refine only Lm, Lr
         * and Tr, which reach the angle only below the crossover. */
        if (d->telemetry.Rs_dc != _IQ(0.0) || g->m_full == 0u) {
            g->to[DRIVE_P_RS] = g->applied[DRIVE_P_RS];
        }
        /* with tracking the tracker is the authority on Tr (the RLS's Tr
         * comes from K3, ill-conditioned when w_r Tr is large: 15 kW motor,
         * Tr +10 %); it starts from the RLS's value when there is one */
        if (a->track_rr != 0u || g->m_full == 0u) {
            g->to[DRIVE_P_TR] = g->applied[DRIVE_P_TR];
        }
        ls_from_sigma(d, g->to);   /* Ls of the new Lm, Lr */
        within_factor_2_of_applied(g, g->to);
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            g->from[i] = g->applied[i];
        }
        g->lr = g->to[DRIVE_P_LR];
        g->blending = 1u;
        g->blend_t0 = a->ticks;
        g->blend_state = st;
        g->blend_pass = pass;
        g->blend_track = (uint16_t)(st == (uint16_t)ID_RUN && a->track_rr != 0u);
        if (g->blend_track != 0u) {
            /* 1/Tr of the last pass: 1 / Tr_pu with Tr_pu >= 10 Ts;
             * Q24 / Q20 -> Q24 (_IQ20div shifts by 20) */
            g->theta0 = _IQ20div(_IQ(1.0), (g->m_full != 0u) ? g->m_tr : g->to[DRIVE_P_TR]);
        }
    } else if (st == (uint16_t)ID_REFINE) {
        post_ready(d, st, pass);   /* nothing usable: the next pass runs on the old model */
    } else {
        /* a stale extraction (the sequence moved on): dropped */
    }
}

/* One step of the blend: the model at the fraction the ISR's ticks give
 * (|to - from| <= 2 from < 128: the factor-2 limit, values < 60), the
 * last one exactly `to`. */
static void blend(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    const uint16_t elapsed = (uint16_t)(d->adapt.isr.ticks - g->blend_t0);
    drive_model_set_t s;
    _iq v[DRIVE_ADAPT_NP];
    uint16_t flags;
    uint16_t i;

    if (g->blend_state != (uint16_t)d->seq.state || g->blend_pass != d->seq.pass) {
        g->blending = 0u;   /* the sequence moved on (a wait ran out, a stop) */
        return;
    }
    if (elapsed >= g->blend_ticks) {
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            v[i] = g->to[i];
        }
        flags = (g->blend_state == (uint16_t)ID_REFINE) ? DRIVE_SET_READY : 0u;
        g->blending = 0u;
    } else {
        /* elapsed < blend_ticks: the fraction below 1 */
        const _iq frac = _IQmpyI32(g->blend_step, (int32_t)elapsed);
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            v[i] = g->from[i] + _IQmpy(g->to[i] - g->from[i], frac);
        }
        flags = DRIVE_SET_BLENDING;
    }
    design(g, v, &s);
    if (g->blend_track != 0u) {
        flags |= DRIVE_SET_TRACK_START;
        s.theta0 = g->theta0;
        g->blend_track = 0u;
    }
    s.flags = flags;
    s.state = g->blend_state;
    s.pass = g->blend_pass;
    post(d, &s, v);
}

/* The tracker's 1/Tr: telemetry on every new update, and (no blend under
 * way) the Tr in use moved towards it, rate limited per update, posted;
 * the first such set hands the control frame to ifo. */
static void track(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_telemetry_t *t = &d->telemetry;
    const uint32_t n = d->adapt.track.n_updates;
    const _iq theta = d->adapt.track.theta;
    drive_model_set_t s;
    _iq v[DRIVE_ADAPT_NP];
    _iq20 tr;
    uint32_t k;
    uint16_t i;

    if (d->seq.state != ID_RUN || d->adapt.isr.track_armed == 0u) {
        t->track_valid = 0u;
        g->n_seen = 0u;
        return;
    }
    if (n == g->n_seen) {
        return;
    }
    /* theta in [theta_min, theta_max], theta_min >= 1/IFO_TR_MAX_PU
     * (drive_adapt_track_init): 1/theta <= 1000 pu; Q24 / Q24 -> Q20 */
    tr = _IQ20div(_IQ(1.0), theta);
    t->Tr_track = tr;
    t->Rr_track = _IQmpy(g->lr, theta);   /* Rr = Lr / Tr; < 128 */
    /* valid once the estimate has forgotten RUN's start (tr_track_settle_s) */
    t->track_valid = (uint16_t)(n >= d->k.track_valid_updates);
    if (g->blending != 0u || g->pending != 0u) {
        return;   /* the next pass takes these updates too */
    }
    for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
        v[i] = g->applied[i];
    }
    /* each update moves the Tr in use by at most tr_rate of itself (the
     * updates since the last set, counted from a restart's 0) */
    k = (n > g->n_seen) ? n - g->n_seen : n;
    while (k > 0u && v[DRIVE_P_TR] != tr) {
        _iq20 step = _IQmpy(v[DRIVE_P_TR], g->tr_rate);   /* Q20 * Q24 -> Q20 */
        if (tr > v[DRIVE_P_TR] + step) {
            v[DRIVE_P_TR] += step;
        } else if (tr < v[DRIVE_P_TR] - step) {
            v[DRIVE_P_TR] -= step;
        } else {
            v[DRIVE_P_TR] = tr;
        }
        k--;
    }
    design(g, v, &s);
    s.flags = (d->frame.run_ifo == 0u) ? DRIVE_SET_ALIGN : 0u;
    s.state = ID_RUN;
    s.pass = d->seq.pass;
    post(d, &s, v);
    g->n_seen = n;
}

void drive_adapt_post(drive_t *d, const param_extract_t *p, uint16_t full)
{
    drive_adapt_bg_t *g = &d->adapt.bg;
    const drive_adapt_t *a = &d->adapt.isr;

    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS || (a->passes <= 1u && a->track_rr == 0u)) {
        return;
    }
    g->m_seed = 0u;
    g->m_valid = p->valid;
    g->m_full = full;
    g->m_rs = p->Rs;
    g->m_lm = p->Lm;
    g->m_lr = p->Lr;
    g->m_ls = p->Lr;   /* the extraction's Ls = Lr (method §4) */
    g->m_tr = p->Tr;
    g->m_ready = 1u;
}

void drive_adapt_seed(drive_t *d, const param_extract_t *p)
{
    drive_adapt_post(d, p, 1u);
    d->adapt.bg.m_seed = d->adapt.bg.m_ready;   /* 0 where the drive does not adapt */
}

void drive_adapt_background(drive_t *d)
{
    drive_adapt_bg_t *g = &d->adapt.bg;

    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS) {
        return;
    }
    if (answer(d) != 0u) {
        /* the mailbox is free: one post per pass of the loop, in order */
        if (d->adapt.cap.ready != 0u) {
            standstill_set(d);
        }
        if (g->pending == 0u && g->m_ready != 0u) {
            take_mail(d);
        }
        if (g->pending == 0u && g->blending != 0u) {
            blend(d);
        }
    }
    track(d);
}
