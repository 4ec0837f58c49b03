/**
 * Parameter adaptation (issue 8, beyond the paper; orientation 1 only):
 *
 *  1. standstill Rs and sigma Ls: at the end of the magnetisation the
 *     machine is at DC steady state (i_M constant, flux settled, w = 0), so
 *     u_M = Rs i_M (method §1 with every derivative and speed zero).  The
 *     filtered u_M, i_M of the regression (dead-time compensated, method
 *     §5 filter) give Rs = u_M / i_M.  Over the last SSZ_CYCLES + 1 periods
 *     of the magnetisation a small sinusoid on i_M gives sigma Ls
 *     (standstill_z.h).  The observer and the current loops take both
 *     before the first acceleration; the observer is re-seated on the DC
 *     solution (flux_obs_set_rs_dc).  This is what lets the observer start
 *     from a nameplate 30 % off: above its crossover its angle depends on
 *     Rs and sigma Ls only (flux_obs.h).
 *  2. passes: each pass's extraction (background, drive_background.c)
 *     comes back through a mailbox; in REFINE (or RUN after the last pass)
 *     the observer's Rs, Lm, Lr, Ls, Tr, the d-axis decoupling sigma Ls and
 *     the current-loop gains (kp = w_c sigma Ls, ki = w_c Ts Rs) move to it
 *     linearly over DRIVE_ADAPT_BLEND_S (the safe blend), each target first
 *     limited to a factor 2 of the value in use (the rate limit per pass);
 *     an implausible extraction leaves the model as it is.  Held: Rs and
 *     sigma Ls when measured at standstill (the RLS's own come through the
 *     frame computed with them: a loop), Tr when the tracker is on.
 *  3. tracking (track_rr): in RUN the tracker (tr_track.h) follows 1/Tr
 *     from the observer's slip; the observer's current model and ifo take
 *     the tracked Tr, its change limited to DRIVE_ADAPT_TR_RATE per second,
 *     and ifo (encoder angle + slip on that Tr) becomes the control frame
 *     (quieter than the observer's angle, which carries the current noise
 *     through sigma Ls i); the observer runs on as the tracker's reference.
 *  4. fused mode (standstill and track_rr): the published set takes Rs
 *     from the standstill test, Rr and Tr from the tracker and only Lm, Lr,
 *     psi_r from the RLS (drive_background.c), and the RLS is judged on K2
 *     and K4 alone (theta_guard_set_required): on a motor with a large
 *     w_r Tr its K1, K3 are ill-conditioned (15 kW: K3 came out negative
 *     with the believed Lm 30 % low) while K2, K4 stay within 0.3 %.
 * Float only in drive_adapt_init.
 */
#include "drive_adapt.h"
#include "drive_internal.h"

#include "angle.h"

#include <math.h>

#define DRIVE_ADAPT_BLEND_S 0.1f
#define DRIVE_ADAPT_TR_RATE 0.2f       /* relative per second */
#define TRACK_VALID_UPDATES 1000u      /* 1 s of tracker updates before Rr_track is valid */

enum { P_RS = 0, P_LM, P_LR, P_LS, P_TR };

float drive_adapt_ssz_freq_Hz(const drive_config_t *c)
{
    return fminf(SSZ_F_OF_BW * c->control.current_bw_Hz, SSZ_F_MAX_HZ);
}

uint16_t drive_adapt_ssz_gap(float Ts)
{
    return (uint16_t)(SSZ_GAP_S / Ts + 0.5f);
}

standstill_z_status_t drive_adapt_ssz_init(standstill_z_t *z, const drive_config_t *c,
                                           const base_values_t *b, float Ts)
{
    const drive_motor_t *m = &c->motor;
    float f = drive_adapt_ssz_freq_Hz(c);
    float im_pu = m->magnetizing_current_A / b->I_base_A;
    return standstill_z_init(z, Ts, b->f_base_Hz, f, SSZ_CYCLES, SSZ_AMPL_OF_IM * im_pu,
                             standstill_z_corr(f, m->Lm_H, m->Lr_H, m->Rr_ohm, b->L_base_H));
}

tr_track_status_t drive_adapt_track_init(tr_track_t *t, const drive_config_t *c,
                                         const base_values_t *b, float Ts)
{
    const drive_motor_t *m = &c->motor;
    float tr_pu = m->Lr_H / m->Rr_ohm / b->t_base_s;
    float psi_pu = m->Lm_H * m->magnetizing_current_A / b->psi_base_Wb;
    float it_pu = c->control.max_torque_current_A / b->I_base_A;
    /* the tracker runs in the slow task (drive_slow.c): its period is Ts_slow */
    return tr_track_init(t, Ts * (float)DRIVE_SLOTS, TRACK_DECIM, TRACK_LPF_HZ, c->ident.track_memory_s,
                         TRACK_PHI_MIN_OF_RATED * psi_pu * it_pu, 0.25f / tr_pu, 4.0f / tr_pu,
                         1.0f / tr_pu);
}

int16_t drive_adapt_init(drive_t *d, const drive_config_t *c, float Ts)
{
    /* the slow task's period: the blend, the tracker and the Tr rate limit
     * run there (drive_slow.c); the standstill lock-in runs every period */
    const float Ts_slow = Ts * (float)DRIVE_SLOTS;
    const drive_ident_t *id = &c->ident;
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;
    drive_adapt_t *a = &d->adapt;
    uint16_t passes = (id->passes == 0u) ? 1u : id->passes;
    float wc = 6.2831853f * c->control.current_bw_Hz;
    float rs_pu = m->Rs_ohm / b->Z_base_ohm;

    a->passes = passes;
    a->standstill = id->standstill;
    a->track_rr = id->track_rr;
    a->fused = (uint16_t)(id->standstill != 0u && id->track_rr != 0u);
    if (a->fused != 0u && theta_guard_set_required(&d->guard, 0xAu) != THETA_GUARD_OK) {
        return 1;   /* K2 (bit 1) and K4 (bit 3): what the magnetic extraction uses */
    }
    if (passes > ID_PASSES_MAX || id->standstill > 1u || id->track_rr > 1u) {
        return 1;
    }
    if ((passes > 1u || id->standstill != 0u || id->track_rr != 0u) &&
        c->control.orientation != DRIVE_ORIENT_FLUX_OBS) {
        return 1;   /* each needs the Tr-independent observer frame */
    }
    /* the sequence slows to 40 % of the target between passes: below the
     * RLS's 0.6 pu window, so the next pass sees a whole acceleration */
    if (id_sequence_set_passes(&d->seq, passes, _IQ(0.4)) != 0) {
        return 1;
    }
    a->ssz_gap = drive_adapt_ssz_gap(Ts);
    if (id->standstill != 0u &&
        (drive_adapt_ssz_init(&d->ssz, c, b, Ts) != STANDSTILL_Z_OK ||
         /* the test and the gap fit in the second half of the magnetisation */
         2u * ((uint32_t)standstill_z_samples(&d->ssz) + a->ssz_gap) >
             d->seq.magnetize_samples * DRIVE_SLOTS)) {
        return 1;
    }
    a->rs_lo = _IQ(0.25f * rs_pu);
    a->rs_hi = _IQ(fminf(4.0f * rs_pu, FLUX_OBS_RS_MAX));
    a->blend_step = _IQ(Ts_slow / DRIVE_ADAPT_BLEND_S);
    a->kp_per_sls = _IQ(wc / b->w_base_rad_s);
    a->ki_per_rs = _IQ(wc * Ts);
    a->tr_rate = _IQ(DRIVE_ADAPT_TR_RATE * (float)TRACK_DECIM * Ts_slow);
    a->from[P_RS] = d->fobs.rs;
    a->from[P_LM] = d->fobs.lm;
    a->from[P_LR] = _IQ(m->Lr_H / b->L_base_H);
    a->from[P_LS] = _IQ(m->Ls_H / b->L_base_H);
    a->from[P_TR] = d->fobs.tr;
    a->lr = a->from[P_LR];
    if (id->track_rr != 0u && drive_adapt_track_init(&d->track, c, b, Ts) != TR_TRACK_OK) {
        return 1;
    }
    return 0;
}

/* The model v (rs, lm, lr, ls, tr) into the observer, decoupling and current
 * loops.  A setter that refuses keeps its old value (flux_obs.h), so an
 * inconsistent set cannot reach the observer half-applied. */
static void apply_model(drive_t *d, const _iq v[DRIVE_ADAPT_NP])
{
    const drive_adapt_t *a = &d->adapt;
    (void)flux_obs_set_rs(&d->fobs, v[P_RS]);
    (void)flux_obs_set_inductances(&d->fobs, v[P_LM], v[P_LR], v[P_LS]);
    (void)flux_obs_set_tr(&d->fobs, v[P_TR]);
    d->k.sigma_ls = d->fobs.sigma_ls;
    d->k.lm2_lr = _IQmpy(d->fobs.lm, d->fobs.lm_lr);   /* < 16 */
    (void)ifo_set_tr(&d->ifo, d->fobs.tr);
    /* kp = (w_c / w_base) sigma Ls <= 100, ki = w_c Ts Rs <= 1: else refused */
    (void)pi_set_gains(&d->pi_id, _IQmpy(a->kp_per_sls, d->fobs.sigma_ls),
                       _IQmpy(a->ki_per_rs, d->fobs.rs));
    (void)pi_set_gains(&d->pi_iq, _IQmpy(a->kp_per_sls, d->fobs.sigma_ls),
                       _IQmpy(a->ki_per_rs, d->fobs.rs));
}

/* Limit x to [ref / 2, 2 ref] (ref > 0): the rate limit per pass. */
static _iq within_factor_2(_iq x, _iq ref)
{
    _iq lo = _IQmpy(ref, _IQ(0.5));
    _iq hi = (ref < _IQ(60.0)) ? ref + ref : _IQ(120.0);
    if (x < lo) {
        return lo;
    }
    return (x > hi) ? hi : x;
}

static void take_mail(drive_t *d)
{
    drive_adapt_t *a = &d->adapt;
    drive_adapt_mail_t *m = &d->adapt_mail;
    uint16_t i;
    uint16_t st = (uint16_t)d->seq.state;

    if (m->valid != 0u && (st == (uint16_t)ID_REFINE || st == (uint16_t)ID_RUN)) {
        a->to[P_RS] = m->rs;
        a->to[P_LM] = m->lm;
        a->to[P_LR] = m->lr;
        a->to[P_LS] = m->ls;
        a->to[P_TR] = m->tr;
        /* Measured standstill values stay: the RLS's Rs and sigma Ls come
         * through the frame the observer computes with them, so feeding
         * them back closes a loop (measured, believed Rs +30 %: the RLS's
         * Rs rose +3.7, +5.1, +5.9 % pass after pass; sigma Ls crept
         * +0.13 % a pass).  With both held, the passes refine only Lm, Lr
         * and Tr, which reach the angle only below the crossover. */
        if (d->telemetry.Rs_dc != _IQ(0.0) || m->full == 0u) {
            a->to[P_RS] = a->from[P_RS];
        }
        /* with tracking the tracker is the authority on Tr (the RLS's Tr
         * comes from K3, ill-conditioned when w_r Tr is large: 15 kW motor,
         * Tr +10 %); it starts from the RLS's value when there is one */
        if (a->track_rr != 0u || m->full == 0u) {
            a->to[P_TR] = a->from[P_TR];
        }
        if (d->telemetry.sigma_ls_dc != _IQ(0.0)) {
            /* Ls = sigma Ls + Lm^2/Lr of the new Lm, Lr (Lr > Lm > 0: the
             * quotient < 1 by _IQdiv; < 8 + 16) */
            a->to[P_LS] = d->telemetry.sigma_ls_dc +
                          _IQmpy(a->to[P_LM], _IQdiv(a->to[P_LM], a->to[P_LR]));
        }
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            a->to[i] = within_factor_2(a->to[i], a->from[i]);
        }
        a->frac = _IQ(0.0);
        a->blending = 1u;
        a->lr = a->to[P_LR];
        if (st == (uint16_t)ID_RUN && a->track_rr != 0u) {
            /* 1/Tr of the last pass: 1 / Tr_pu with Tr_pu >= 10 Ts (set_tr's bound) */
            tr_track_restart(&d->track,
                             _IQdiv(_IQ(1.0), (m->full != 0u) ? m->tr : a->to[P_TR]));
            a->track_armed = 1u;
        }
    } else if (st == (uint16_t)ID_REFINE) {
        d->seq.adapt_ready = 1u;   /* nothing usable: the next pass runs on the old model */
    } else {
        /* a stale mail (the sequence moved on): dropped */
    }
    m->ready = 0u;
}

static void blend(drive_t *d)
{
    drive_adapt_t *a = &d->adapt;
    _iq v[DRIVE_ADAPT_NP];
    uint16_t i;

    a->frac += a->blend_step;
    if (a->frac >= _IQ(1.0)) {
        for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
            a->from[i] = a->to[i];
        }
        apply_model(d, a->from);
        a->blending = 0u;
        d->seq.adapt_ready = 1u;
        return;
    }
    /* |to - from| <= 2 from < 128 (factor-2 limit, values < 60) */
    for (i = 0u; i < DRIVE_ADAPT_NP; i++) {
        v[i] = a->from[i] + _IQmpy(a->to[i] - a->from[i], a->frac);
    }
    apply_model(d, v);
}

/* Rs from the DC part, sigma Ls from the injection (if valid), at the last
 * sample of the magnetisation; the model then goes to the observer and the
 * current loops, and the observer is re-seated at DC. */
static void standstill_result(drive_t *d)
{
    drive_adapt_t *a = &d->adapt;
    _iq im = d->reg.i_mf;
    _iq um = d->reg.u_mf;
    _iq rs;

    /* a usable i_M (a quarter of the reference) and a quotient inside Q24:
     * |u_M| < 4 |i_M| bounds Rs_pu below 4 (flux_obs's range) */
    if (!(im > _IQmpy(d->seq.im_ref, _IQ(0.25))) || !(_IQabs(um) < _IQmpy(im, _IQ(4.0)))) {
        return;
    }
    rs = _IQdiv(um, im);
    if (rs < a->rs_lo || rs > a->rs_hi) {
        return;   /* implausible: the believed model stays, Rs_dc reads 0 */
    }
    a->from[P_RS] = rs;
    d->telemetry.Rs_dc = rs;
    if (d->ssz.valid != 0u) {
        /* keep the believed Lm, Lr: Ls = sigma Ls + Lm^2/Lr (< 8 + 16) */
        _iq ls = d->ssz.sigma_ls + _IQmpy(d->fobs.lm, d->fobs.lm_lr);
        a->from[P_LS] = within_factor_2(ls, a->from[P_LS]);
        d->telemetry.sigma_ls_dc = d->ssz.sigma_ls;
    }
    apply_model(d, a->from);
    {
        /* the filtered (DC) M-T voltage and current back to alpha-beta at
         * the held frame angle (the encoder's: drive_step.c) */
        _iq sn, cs;
        const ident_regressor_t *r = &d->reg;
        angle_sincos(d->qep.theta_elec, &sn, &cs);
        (void)flux_obs_set_rs_dc(&d->fobs, rs, _IQmpy(cs, r->u_mf) - _IQmpy(sn, r->u_tf),
                                 _IQmpy(sn, r->u_mf) + _IQmpy(cs, r->u_tf),
                                 _IQmpy(cs, r->i_mf) - _IQmpy(sn, r->i_tf),
                                 _IQmpy(sn, r->i_mf) + _IQmpy(cs, r->i_tf));
    }
}

/* The injection over the end of the magnetisation: started by the slow
 * task (the sequence counts slow samples) so that the test and the gap
 * after it (in fast samples: ssz_gap) end before the magnetisation does. */
static void standstill_test_start(drive_t *d)
{
    standstill_z_t *z = &d->ssz;
    const id_sequence_t *s = &d->seq;
    uint32_t left;

    if (s->state != ID_MAGNETIZE || z->running != 0u || s->t_state == 0u) {
        return;
    }
    /* fast samples left in the magnetisation; t_state <= magnetize_samples */
    left = (s->magnetize_samples - s->t_state) * DRIVE_SLOTS;
    if (left <= (uint32_t)standstill_z_samples(z) + d->adapt.ssz_gap &&
        d->adapt.ssz_started == 0u) {
        standstill_z_start(z);
        d->adapt.ssz_started = 1u;
    }
}

void drive_adapt_fast(drive_t *d)
{
    standstill_z_t *z = &d->ssz;

    if (z->running == 0u) {
        d->im_inject = _IQ(0.0);
        return;
    }
    /* the sequence's i_M reference plus the injection (drive_step.c) */
    z->u_m = d->reg.u_m;
    z->i_m = d->park.ds;
    standstill_z_step(z);
    d->im_inject = z->i_add;
}

/* The tracker's tick: its 1/Tr into telemetry and, rate limited, into the
 * observer's current model. */
static void track(drive_t *d)
{
    drive_adapt_t *a = &d->adapt;
    tr_track_t *t = &d->track;
    uint32_t n0 = t->n_updates;

    t->w_sl = d->fobs.ws_f - d->qep.speed_raw;
    t->psi_alpha = d->fobs.psi_alpha;
    t->psi_beta = d->fobs.psi_beta;
    t->i_alpha = d->clarke.alpha;
    t->i_beta = d->clarke.beta;
    t->enable = (uint16_t)(d->seq.state == ID_RUN && a->blending == 0u);
    tr_track_step(t);
    if (t->n_updates != n0) {
        /* theta in [theta_min, theta_max] > 0: 1/theta < 128 */
        _iq tr = _IQdiv(_IQ(1.0), t->theta);
        _iq step = _IQmpy(a->from[P_TR], a->tr_rate);
        _iq next = a->from[P_TR];
        if (tr > next + step) {
            next += step;
        } else if (tr < next - step) {
            next -= step;
        } else {
            next = tr;
        }
        if (flux_obs_set_tr(&d->fobs, next) == FLUX_OBS_OK &&
            ifo_set_tr(&d->ifo, next) == IFO_OK) {
            a->from[P_TR] = next;
        }
        if (d->run_ifo == 0u) {
            /* hand the control frame to ifo, now on the tracked Tr: the
             * observer's flux angle and magnitude (in magnetising-current
             * pu, psi / Lm; Lm >= 1/16 pu, |psi| < 8: the quotient < 128) */
            ifo_align(&d->ifo, d->fobs.theta, _IQdiv(d->fobs.psi_mag, d->fobs.lm));
            drive_set_run_ifo(d, 1u);
        }
        d->telemetry.Tr_track = tr;
        d->telemetry.Rr_track = _IQmpy(a->lr, t->theta);   /* Rr = Lr / Tr; < 128 */
        /* valid once the estimate has had 1 s of updates */
        d->telemetry.track_valid = (uint16_t)(t->n_updates >= TRACK_VALID_UPDATES);
    }
}

void drive_adapt_slow(drive_t *d)
{
    drive_adapt_t *a = &d->adapt;
    uint16_t st = (uint16_t)d->seq.state;

    d->telemetry.pass = d->seq.pass;
    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS) {
        return;
    }
    /* every test below is cheap while nothing happens (ACCELERATE, where the
     * RLS makes the ISR's worst case, runs only the compares) */
    if (a->standstill != 0u) {
        standstill_test_start(d);
        if (d->seq.magnetize_end != 0u) {
            standstill_result(d);
        }
    }
    if (st != a->prev_state) {
        if (st == (uint16_t)ID_MAGNETIZE) {
            a->ssz_started = 0u;
        }
        if (st == (uint16_t)ID_REFINE) {
            d->seq.adapt_ready = 0u;
        }
        if (st != (uint16_t)ID_RUN) {
            a->track_armed = 0u;
            d->telemetry.track_valid = 0u;
            drive_set_run_ifo(d, 0u);
        }
        a->prev_state = st;
    }
    if (d->seq.rls_restart != 0u) {
        d->rls = d->rls_start;
        theta_guard_reset(&d->guard);
    }
    if (d->adapt_mail.ready != 0u) {
        take_mail(d);
    }
    if (a->blending != 0u) {
        blend(d);
    }
    if (a->track_armed != 0u) {
        track(d);
    }
}

void drive_adapt_post(drive_t *d, const param_extract_t *p, uint16_t full)
{
    drive_adapt_mail_t *m = &d->adapt_mail;
    const drive_adapt_t *a = &d->adapt;

    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS ||
        (a->passes <= 1u && a->track_rr == 0u) || m->ready != 0u) {
        return;
    }
    m->valid = p->valid;
    m->full = full;
    m->rs = p->Rs;
    m->lm = p->Lm;
    m->lr = p->Lr;
    m->ls = p->Lr;   /* the extraction's Ls = Lr (method §4) */
    m->tr = p->Tr;
    m->ready = 1u;
}
