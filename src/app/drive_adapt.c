/**
 * Parameter adaptation (beyond the paper; orientation 1 only), the ISR's
 * part and the set-up.  What is adapted, and why:
 *
 *  1. standstill Rs and sigma Ls: at the end of the magnetisation the
 *     machine is at DC steady state (i_M constant, flux settled, w = 0), so
 *     u_M = Rs i_M (method §1 with every derivative and speed zero).  The
 *     filtered u_M, i_M of the regression (dead-time compensated, method
 *     §5 filter) give Rs = u_M / i_M.  Over the last SSZ_CYCLES + 1 periods
 *     of the magnetisation a small sinusoid on i_M gives sigma Ls
 *     (standstill_z.h).  The observer and the current loops take both
 *     before the first acceleration; the observer is re-seated on the DC
 *     solution (flux_obs_seat_dc).  This is what lets the observer start
 *     from a nameplate 30 % off: above its crossover its angle depends on
 *     Rs and sigma Ls only (flux_obs.h).
 *  2. passes: each pass's extraction (background, drive_background.c)
 *     becomes the model of the next pass: in REFINE (or RUN after the last
 *     pass) the observer's Rs, Lm, Lr, Ls, Tr, the d-axis decoupling
 *     sigma Ls and the current-loop gains (kp = w_c sigma Ls, ki = w_c Ts
 *     Rs) move to it linearly over DRIVE_ADAPT_BLEND_S (the safe blend),
 *     each target first limited to a factor 2 of the value in use (the rate
 *     limit per pass); an implausible extraction leaves the model as it
 *     is.  Held: Rs and sigma Ls when measured at standstill (the RLS's own
 *     come through the frame computed with them: a loop), Tr when the
 *     tracker is on.
 *  3. tracking: in RUN the tracker (tr_track.h) follows 1/Tr from the
 *     observer's slip; the observer's current model and ifo take the
 *     tracked Tr, its change limited to DRIVE_ADAPT_TR_RATE per second,
 *     and ifo (encoder angle + slip on that Tr) becomes the control frame
 *     (quieter than the observer's angle, which carries the current noise
 *     through sigma Ls i); the observer runs on as the tracker's reference.
 *  4. fused mode (standstill and track_rr): the published set takes Rs
 *     from the standstill test, Rr and Tr from the tracker and only Lm, Lr,
 *     psi_r from the RLS (drive_background.c), and the RLS is judged on K2
 *     and K4 alone (theta_guard_set_required): on a motor with a large
 *     w_r Tr its K1, K3 are ill-conditioned (15 kW: K3 came out negative
 *     with the believed Lm 30 % low) while K2, K4 stay within 0.3 %.
 *
 * Who does what.  Every model and its constants (the divisions, the
 * exponential, the re-seat, the blend, the rate limit) are the background's
 * (drive_adapt_bg.c, float allowed there); the ISR here, in its SEQUENCE
 * slot, only:
 *   - runs the sigma Ls lock-in's injection (every period, drive_adapt_fast)
 *     and, at the end of the magnetisation, captures what the standstill
 *     result needs (drive_adapt_capture_t: a dozen word copies);
 *   - copies a posted model set in (drive_model_set_t: the observer's seven
 *     constants, ifo's three, both PIs' three, the decoupling; with the
 *     re-seat twelve more words; all in one ISR, never half), if it was
 *     made for the sequence's present state and pass, and does what its
 *     flags say (adapt_ready, the tracker's start, the hand-over of the
 *     control frame to ifo);
 *   - feeds the tracker (tr_track_step: its scalar RLS stays in the ISR,
 *     in a slot of its own, drive_adapt_track; its 1/Tr goes to the
 *     background).
 * The sequence waits for the background: at the end of MAGNETIZE for the
 * standstill set (id_sequence_set_wait), in REFINE for the blend's last
 * set; each wait ends after DRIVE_ADAPT_WAIT_S with the model in use,
 * counted in seq.adapt_timeouts.
 * No float, no division in the ISR's functions; float only in the inits.
 */
#include "drive_adapt.h"
#include "drive_design.h"
#include "drive_internal.h"
#include "drive_static.h"

#include <math.h>


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
    return tr_track_init(t, Ts * (float)DRIVE_SLOTS, DRIVE_ADAPT_TRACK_DECIM, TRACK_LPF_HZ,
                         c->ident.track_memory_s, TRACK_PHI_MIN_OF_RATED * psi_pu * it_pu,
                         fmaxf(0.25f / tr_pu, 1.0f / IFO_TR_MAX_PU), 4.0f / tr_pu, 1.0f / tr_pu);
}

/* The background's starting point: the believed model as drive_init gave
 * it to the observer, ifo, the current PIs and the decoupling. */
static void init_background(drive_t *d, const drive_config_t *c, float Ts)
{
    const float Ts_slow = Ts * (float)DRIVE_SLOTS;
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;
    drive_adapt_bg_t *g = &d->adapt.bg;
    drive_model_set_t *s = &g->applied_set;
    float wc = DRIVE_TWO_PI_F * c->control.current_bw_Hz;
    float rs_pu = m->Rs_ohm / b->Z_base_ohm;
    float lm_pu = m->Lm_H / b->L_base_H;

    g->ts_pu = b->Ts_pu;
    g->obs_ts_pu = b->Ts_pu * (float)d->frame.fobs.n;   /* the observer's step (flux_obs_set_step) */
    g->imr_min_pu = DRIVE_IMR_MIN_OF_IM * m->magnetizing_current_A / b->I_base_A;   /* as ifo_init */
    g->kp_per_sls = wc / b->w_base_rad_s;
    g->ki_per_rs = wc * Ts;
    g->rs_lo = _IQ(0.25f * rs_pu);
    g->rs_hi = _IQ(fminf(4.0f * rs_pu, FLUX_OBS_RS_MAX));
    g->blend_step = _IQ(Ts_slow / DRIVE_ADAPT_BLEND_S);
    g->blend_ticks = (uint16_t)ceilf(DRIVE_ADAPT_BLEND_S / Ts_slow);
    g->tr_rate = _IQ(DRIVE_ADAPT_TR_RATE * (float)DRIVE_ADAPT_TRACK_DECIM * Ts_slow);
    g->applied[DRIVE_P_RS] = d->frame.fobs.rs;
    g->applied[DRIVE_P_LM] = d->frame.fobs.lm;
    g->applied[DRIVE_P_LR] = _IQ(m->Lr_H / b->L_base_H);
    g->applied[DRIVE_P_LS] = _IQ(m->Ls_H / b->L_base_H);
    g->applied[DRIVE_P_TR] = d->frame.fobs.tr;
    g->lr = g->applied[DRIVE_P_LR];
    flux_obs_get_model(&d->frame.fobs, &s->fobs);
    s->ifo.tr = d->frame.ifo.tr;
    s->ifo.inv_tr = d->frame.ifo.inv_tr;
    s->ifo.kf = d->frame.ifo.kf;
    s->pi.kp = d->loop.pi_id.kp;
    s->pi.ki = d->loop.pi_id.ki;
    s->pi.e_max = d->loop.pi_id.e_max;
    s->lm2_lr = d->k.lm2_lr;
    s->inv_lm = _IQ(fminf(1.0f / lm_pu, 16.0f));
}

int16_t drive_adapt_init(drive_t *d, const drive_config_t *c, float Ts)
{
    const float Ts_slow = Ts * (float)DRIVE_SLOTS;
    const drive_ident_t *id = &c->ident;
    const base_values_t *b = &d->base;
    drive_adapt_t *a = &d->adapt.isr;
    uint16_t passes = (id->passes == 0u) ? 1u : id->passes;

    a->passes = passes;
    a->standstill = id->standstill;
    a->track_rr = id->track_rr;
    a->fused = (uint16_t)(id->standstill != 0u && id->track_rr != 0u);
    if (a->fused != 0u && theta_guard_set_required(&d->id.guard, 0xAu) != THETA_GUARD_OK) {
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
    /* the end of the magnetisation waits for the standstill set; every wait
     * for the background at most DRIVE_ADAPT_WAIT_S (the sequence counts
     * slow samples) */
    if (id_sequence_set_wait(&d->seq, id->standstill,
                             (uint32_t)(DRIVE_ADAPT_WAIT_S / Ts_slow + 0.5f)) != 0) {
        return 1;
    }
    a->ssz_gap = drive_adapt_ssz_gap(Ts);
    a->starve_ticks = (uint16_t)(DRIVE_EXCITE_STARVE_S / Ts_slow + 0.5f);
    if (id->standstill != 0u &&
        (drive_adapt_ssz_init(&d->adapt.ssz, c, b, Ts) != STANDSTILL_Z_OK ||
         /* the test and the gap fit in the second half of the magnetisation */
         2u * ((uint32_t)standstill_z_samples(&d->adapt.ssz) + a->ssz_gap) >
             d->seq.magnetize_samples * DRIVE_SLOTS)) {
        return 1;
    }
    if (id->track_rr != 0u && drive_adapt_track_init(&d->adapt.track, c, b, Ts) != TR_TRACK_OK) {
        return 1;
    }
    if (drive_static_init(d, c, Ts) != 0) {
        return 1;
    }
    init_background(d, c, Ts);
    return 0;
}

/* At the end of the magnetisation: what the background needs for Rs,
 * sigma Ls and the observer's DC re-seat (drive_adapt_bg.c), data first,
 * ready last.  A capture the background has not taken yet stays (the
 * sequence's wait then runs out). */
static void capture(drive_t *d)
{
    volatile drive_adapt_capture_t *c = &d->adapt.cap;
    const ident_regressor_t *r = &d->id.reg;
    const standstill_z_t *z = &d->adapt.ssz;

    if (c->ready != 0u) {
        return;
    }
    c->u_mf = r->u_mf;
    c->u_tf = r->u_tf;
    c->i_mf = r->i_mf;
    c->i_tf = r->i_tf;
    c->theta_r = d->sense.qep.theta_elec;   /* the held frame's angle (drive_step.c) */
    c->psi_cm_alpha = d->frame.fobs.psi_cm_alpha;
    c->psi_cm_beta = d->frame.fobs.psi_cm_beta;
    c->us = z->us;
    c->uc = z->uc;
    c->is = z->is;
    c->ic = z->ic;
    c->ssz_done = z->done;
    c->ready = 1u;
}

/* MAGNETIZE: the injection over the end of the magnetisation, started by
 * the slow task (the sequence counts slow samples) so that the test and the
 * gap after it (in fast samples: ssz_gap) end before the magnetisation time
 * does; at its end the capture for the standstill result. */
static void standstill(drive_t *d)
{
    standstill_z_t *z = &d->adapt.ssz;
    const id_sequence_t *s = &d->seq;
    uint32_t left;

    if (s->magnetize_end != 0u) {
        capture(d);
    }
    if (d->adapt.isr.ssz_started != 0u || s->t_state == 0u || s->t_state >= s->magnetize_samples) {
        return;
    }
    /* fast samples left in the magnetisation; t_state < magnetize_samples */
    left = (s->magnetize_samples - s->t_state) * DRIVE_SLOTS;
    if (left <= (uint32_t)standstill_z_samples(z) + d->adapt.isr.ssz_gap) {
        standstill_z_start(z);
        d->adapt.isr.ssz_started = 1u;
    }
}

/* A posted model set, made for this state and pass, copied in at once:
 * the observer's model, ifo's Tr, both current PIs' gains, the decoupling
 * (14 words), the re-seat when flagged (14 more); then what the flags ask.
 * A set made for a state the sequence has left is dropped (the background
 * reads which in taken). */
static void take_set(drive_t *d)
{
    drive_adapt_box_t *box = &d->adapt.box;
    const drive_model_set_t *s = &box->set;
    drive_adapt_t *a = &d->adapt.isr;
    const uint16_t f = s->flags;

    if (s->state != (uint16_t)d->seq.state || s->pass != d->seq.pass) {
        box->taken = DRIVE_BOX_DROPPED;
        box->ready = 0u;
        return;
    }
    flux_obs_apply_model(&d->frame.fobs, &s->fobs);
    ifo_apply_tr(&d->frame.ifo, &s->ifo);
    pi_apply_gains(&d->loop.pi_id, &s->pi);
    pi_apply_gains(&d->loop.pi_iq, &s->pi);
    d->k.sigma_ls = s->fobs.sigma_ls;
    d->k.lm2_lr = s->lm2_lr;
    a->blending = (uint16_t)((f & DRIVE_SET_BLENDING) != 0u);
    /* a step of the model the protections compare with (not the tracker's
     * rate-limited Tr in RUN): the model check rebases (drive_safety.c) */
    d->prot.model.model_step |= (uint16_t)((f & (DRIVE_SET_BLENDING | DRIVE_SET_READY | DRIVE_SET_SEAT |
                                             DRIVE_SET_ALIGN)) != 0u);
    if ((f & DRIVE_SET_SEAT) != 0u) {
        flux_obs_apply_seat(&d->frame.fobs, &s->seat);
    }
    if ((f & DRIVE_SET_TRACK_START) != 0u) {
        tr_track_restart(&d->adapt.track, s->theta0);
        a->track_armed = 1u;
    }
    if ((f & DRIVE_SET_ALIGN) != 0u && a->track_armed != 0u && d->frame.run_ifo == 0u) {
        /* hand the control frame to ifo, now on the tracked Tr: the
         * frame's angle of this period (obs_theta: the observer's flux
         * angle carried forward every period, drive_step.c), against the
         * rotor angle of the same period (ifo.theta_r), and the flux
         * magnitude in magnetising-current pu, psi / Lm (|psi| limited to
         * 7.9, 1/Lm <= 16: the product < 128; ifo_align clamps i_mr to
         * [0, 4]).  Not fobs.theta: that is the angle at the observer's
         * last sample, 7 periods before this slot's, and the rotor has
         * turned since (at 50 Hz 0.15 rad: the hand-over would put the flux
         * 0.15 off the M axis, a transient of Tr that the tracker's first
         * fits would see; docs/accuracy.md) */
        ifo_align(&d->frame.ifo, d->frame.obs_theta,
                  _IQmpy(_IQsat(d->frame.fobs.psi_mag, _IQ(7.9), _IQ(0.0)), s->inv_lm));
        drive_set_run_ifo(d, 1u);
    }
    if ((f & DRIVE_SET_READY) != 0u) {
        d->adapt.isr.ready = 1u;
    }
    box->taken = DRIVE_BOX_APPLIED;
    box->ready = 0u;
}

void drive_adapt_track(drive_t *d)
{
    tr_track_t *t = &d->adapt.track;

    if (d->adapt.isr.track_armed == 0u) {
        return;
    }
    t->w_sl = d->frame.fobs.ws_f - d->sense.qep.speed_raw;
    t->psi_alpha = d->frame.fobs.psi_alpha;
    t->psi_beta = d->frame.fobs.psi_beta;
    /* the current of the observer's last step: its flux and this current
     * belong to the same sample */
    t->i_alpha = d->frame.fobs.i_alpha;
    t->i_beta = d->frame.fobs.i_beta;
    t->enable = (uint16_t)(d->seq.state == ID_RUN && d->adapt.isr.blending == 0u);
    tr_track_step(t);
}

/* A state change: what each state starts from. */
static void state_change(drive_t *d, uint16_t st)
{
    drive_adapt_t *a = &d->adapt.isr;

    a->blending = 0u;   /* a blend the state change cut short: no more of it */
    if (st == (uint16_t)ID_MAGNETIZE) {
        a->ssz_started = 0u;
        d->adapt.isr.ready = 0u;
        /* demagnetised machine: both observer models from zero flux (the
         * voltage model has integrated offsets while the bridge was off) */
        flux_obs_reset(&d->frame.fobs);
    }
    if (st == (uint16_t)ID_REFINE) {
        d->adapt.isr.ready = 0u;
    }
    if (st != (uint16_t)ID_RUN && (a->track_armed | d->frame.run_ifo) != 0u) {
        a->track_armed = 0u;
        drive_set_run_ifo(d, 0u);
    }
    a->prev_state = st;
}

/* A free shaft: in RUN of the fused sequence, its verdict still owed, a
 * tracker held for want of torque for DRIVE_EXCITE_STARVE_S makes the speed
 * swing (id_sequence.h excite) until the verdict comes (the background's
 * publish_reason, one 16-bit word) or RUN ends.  The load's torque, when
 * there is one, comes first: a loaded drive never swings. */
static void excite(drive_t *d)
{
    drive_adapt_t *a = &d->adapt.isr;
    const id_sequence_t *s = &d->seq;
    const uint16_t owed = (uint16_t)(a->fused != 0u && s->state == ID_RUN &&
                                     d->telemetry.publish_reason == (uint16_t)DRIVE_PUB_PENDING);
    if (owed == 0u) {
        a->starved = 0u;
        a->excite = 0u;
        return;
    }
    if (a->excite == 0u) {
        /* held throughout, not now and then */
        a->starved = (a->track_armed != 0u && d->adapt.track.held != 0u) ? (uint16_t)(a->starved + 1u)
                                                                  : 0u;
        a->excite = (uint16_t)(a->starved >= a->starve_ticks);
    }
}

void drive_adapt_slow(drive_t *d)
{
    drive_adapt_t *a = &d->adapt.isr;
    const uint16_t st = (uint16_t)d->seq.state;

    d->telemetry.pass = d->seq.pass;
    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS) {
        return;
    }
    /* a few compares while nothing happens (ACCELERATE, where the RLS makes
     * the ISR's worst case, runs only these) */
    a->ticks++;
    /* a state change first (the sequence step that entered a state left its
     * t_state at 0 and pulsed nothing of it: the standstill test has nothing
     * to do in that step).  (With the standstill test the sequence waits in
     * MAGNETIZE: its magnetize_end pulse comes in MAGNETIZE,
     * id_sequence_set_wait.) */
    if (st != a->prev_state) {
        state_change(d, st);
    } else if (st == (uint16_t)ID_MAGNETIZE && a->standstill != 0u) {
        standstill(d);
    } else if (st == (uint16_t)ID_INJECT) {
        drive_static_slow(d);   /* the standstill sequence's test (drive_static.c, from flash) */
    }
    if (d->seq.rls_restart != 0u) {
        /* the background's RLS restarts before the next queued sample */
        d->id.rlsq.pending |= DRIVE_RLSQ_RESTART;
    }
    if (d->adapt.box.ready != 0u) {
        take_set(d);
    }
    excite(d);
}
