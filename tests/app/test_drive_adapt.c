/* app_drive_adapt: the parameter adaptation split between the background
 * (drive_adapt_bg.c: every model and its constants, posted as one set) and
 * the ISR (drive_adapt.c: copies a set in its SEQUENCE slot), on a drive
 * initialised from host_sim/config/paper_motor_wrong_nameplate.ini (the
 * adaptive sequence: orientation 1, standstill, 2 passes, tracking).
 *
 * The sequence's state is set by hand (the state machine itself is
 * app_id_sequence's); "the ISR" is drive_adapt_slow, "the background"
 * drive_adapt_background, called in turn as the two contexts would.
 *
 *  - the constants of a posted set equal what the inits compute from the
 *    same SI values (flux_obs_init, ifo_init exactly; the PI gains and the
 *    decoupling against double formulas);
 *  - the mailbox: a set the background is still writing (ready 0) is never
 *    read, a posted set is never rewritten before the ISR has taken it, the
 *    ISR applies all of it in one call; and under real preemption (a POSIX
 *    timer whose handler runs the ISR part while the background posts
 *    blend steps) every model the ISR runs is one whole set;
 *  - the standstill result (Rs, sigma Ls, the observer's DC re-seat) against
 *    double references and flux_obs_set_rs_dc;
 *  - the standstill sequence's set seeds the model at rest (drive_adapt_seed);
 *  - sets for a state the sequence has left are dropped;
 *  - tracking: the rate limit per tracker update against its closed form,
 *    the hand-over to ifo with the first tracked set, the telemetry. */
#define _XOPEN_SOURCE 700   /* sigaction, setitimer, clock_gettime */
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>

#include <cmocka.h>

#include "angle.h"
#include "drive_adapt.h"
#include "drive_static.h"
#include "drive_types.h"
#include "sim_config.h"

/* Tr (cur/to/posted[DRIVE_P_TR], fobs.tr, ifo.tr, Tr_track) is Q20: to_d20, LSB20 */
#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
static double to_d20(_iq20 x) { return ldexp((double)x, -20); }
#define LSB (1.0 / 16777216.0)
#define LSB20 (1.0 / 1048576.0)
#else
static double to_d(_iq x) { return (double)x; }
static double to_d20(_iq20 x) { return (double)x; }
#define LSB 0.0
#define LSB20 0.0
#endif

static sim_config_t g_cfg;
static drive_config_t g_dc;
static drive_t g_d;

static int load(void **state)
{
    char err[256];
    (void)state;
    if (sim_config_load(MC_CONFIG_DIR "/paper_motor_wrong_nameplate.ini", &g_cfg, err,
                        sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    sim_config_to_drive(&g_cfg, &g_dc);
    return 0;
}

/* A fresh drive, the sequence put in @p st, @p pass (and the adaptation's
 * record of the state, so that the ISR part sees no state change). */
static void fresh(drive_t *d, id_state_t st, uint16_t pass)
{
    assert_int_equal(drive_init(d, &g_dc), DRIVE_CFG_OK);
    d->seq.state = st;
    d->seq.pass = pass;
    d->adapt.isr.prev_state = (uint16_t)st;
}

static void isr(drive_t *d) { drive_adapt_slow(d); }
static void background(drive_t *d) { drive_adapt_background(d); }

/* A pass's extraction (all six parameters) in pu. */
static void mail(drive_t *d, _iq rs, _iq lm, _iq lr, _iq tr)
{
    param_extract_t p;
    memset(&p, 0, sizeof p);
    p.valid = 1u;
    p.Rs = rs;
    p.Lm = lm;
    p.Lr = lr;
    p.Tr = tr;
    drive_adapt_post(d, &p, 1u);
}

/* ISR and background in turn until the sequence's wait is answered (at
 * most @p max rounds); returns the ISR ticks it took. */
static uint32_t run_until_ready(drive_t *d, uint32_t max)
{
    uint32_t k;
    for (k = 0u; k < max && d->adapt.isr.ready == 0u; k++) {
        background(d);
        isr(d);
    }
    assert_int_equal(d->adapt.isr.ready, 1u);
    return k;
}

/* A float SI value whose quotient by @p base is exactly @p pu (so that an
 * init from SI sees the very pu float the background designs from): the
 * nearest of the floats around pu x base that has it; 0 if none does. */
static float si_for(float pu, float base)
{
    const float si0 = pu * base;
    float up = si0, down = si0;
    int i;
    for (i = 0; i < 32; i++) {
        if (up / base == pu) {
            return up;
        }
        if (down / base == pu) {
            return down;
        }
        up = nextafterf(up, 2.0f * si0);
        down = nextafterf(down, 0.0f);
    }
    return 0.0f;
}

/* The model the ISR runs, as a set's words (to compare with a posted set). */
static void applied_words(const drive_t *d, _iq w[16])
{
    w[0] = d->frame.fobs.rs;   w[1] = d->frame.fobs.lm;     w[2] = d->frame.fobs.sigma_ls;
    w[3] = d->frame.fobs.lr_lm; w[4] = d->frame.fobs.lm_lr; w[5] = d->frame.fobs.tr;
    w[6] = d->frame.fobs.kf;   w[7] = d->frame.ifo.tr;      w[8] = d->frame.ifo.inv_tr;
    w[9] = d->frame.ifo.kf;    w[10] = d->loop.pi_id.kp;   w[11] = d->loop.pi_id.ki;
    w[12] = d->loop.pi_id.e_max; w[13] = d->k.sigma_ls; w[14] = d->k.lm2_lr;
    w[15] = d->loop.pi_iq.kp;
}

static void set_words(const drive_model_set_t *s, _iq w[16])
{
    w[0] = s->fobs.rs;   w[1] = s->fobs.lm;     w[2] = s->fobs.sigma_ls;
    w[3] = s->fobs.lr_lm; w[4] = s->fobs.lm_lr; w[5] = s->fobs.tr;
    w[6] = s->fobs.kf;   w[7] = s->ifo.tr;      w[8] = s->ifo.inv_tr;
    w[9] = s->ifo.kf;    w[10] = s->pi.kp;     w[11] = s->pi.ki;
    w[12] = s->pi.e_max; w[13] = s->fobs.sigma_ls; w[14] = s->lm2_lr;
    w[15] = s->pi.kp;
}

/* The set's constants are those the inits compute from the same SI model.
 * The model: pu values exact in float and in Q24 (dyadic; near the true
 * motor's, within the factor 2 of the believed one), SI values whose
 * quotient by the base is exactly that float (si_for).  Then flux_obs_init
 * and ifo_init see the very floats the background designs from: every
 * constant equal.  The PI gains against double, kp = (w_c / w_base)
 * sigma Ls, ki = w_c Ts Rs (pu): sigma Ls = Ls - Lm^2/Lr in float carries
 * 3 roundings of terms up to Ls (1.67 pu against sigma Ls 0.87: 7e-7
 * relative), the products 2 more: 1 LSB + 1.5e-6 relative for kp (and
 * 2e-6 for e_max = 64/kp, one more division), 1 LSB + 3e-7 for ki;
 * Lm^2/Lr (two roundings): 1 LSB + 2e-7 relative.  The blend reaches it
 * in blend_ticks ISR ticks (one background pass per tick here: the last
 * set is posted on the tick the time is up, applied on the next) and says
 * so (adapt_ready) with its last set. */
/* The dyadic model of the two tests below (pu, exact in float and Q24,
 * SI values on this base exact: si_for): Rs, Lm, Tr and the first Lr of a
 * list that has an exact SI value. */
static void exact_model(const base_values_t *b, float *rs, float *lm, float *lr, float *tr)
{
    static const float lr_try[] = {1.671875f, 1.6875f, 1.65625f, 1.703125f, 1.640625f};
    unsigned i;
    *rs = 0.59375f;
    *lm = 1.15625f;
    *tr = 6.1875f;
    *lr = 0.0f;
    for (i = 0u; i < sizeof lr_try / sizeof lr_try[0] && *lr == 0.0f; i++) {
        if (si_for(lr_try[i], b->L_base_H) != 0.0f) {
            *lr = lr_try[i];
        }
    }
    assert_true(*lr != 0.0f && si_for(*rs, b->Z_base_ohm) != 0.0f &&
                si_for(*lm, b->L_base_H) != 0.0f && si_for(*tr, b->t_base_s) != 0.0f);
}

/* The ISR runs the model (rs, lm, lr, tr; Ls = Lr): every constant as the
 * inits compute it from the same SI model (flux_obs_init, ifo_init exactly;
 * the PI gains and the decoupling against double formulas, bounds below). */
static void assert_runs_model(const drive_t *d, float rs, float lm, float lr, float tr)
{
    const base_values_t *b = &d->base;
    flux_obs_t o;
    ifo_t f;
    double wc, sls, kp, ki;

    assert_int_equal(flux_obs_init(&o, b, si_for(rs, b->Z_base_ohm), si_for(lr, b->L_base_H),
                                   si_for(lr, b->L_base_H), si_for(lm, b->L_base_H),
                                   si_for(tr, b->t_base_s), 3.0f, 200.0f),
                     FLUX_OBS_OK);
    /* as drive_init: one observer step a slow period */
    assert_int_equal(flux_obs_set_step(&o, b, DRIVE_SLOTS, 3.0f, 200.0f), FLUX_OBS_OK);
    assert_true(d->frame.fobs.rs == o.rs && d->frame.fobs.lm == o.lm && d->frame.fobs.sigma_ls == o.sigma_ls);
    assert_true(d->frame.fobs.lr_lm == o.lr_lm && d->frame.fobs.lm_lr == o.lm_lr);
    assert_true(d->frame.fobs.tr == o.tr && d->frame.fobs.kf == o.kf);
    assert_int_equal(ifo_init(&f, si_for(tr, b->t_base_s), b, d->adapt.bg.imr_min_pu), IFO_OK);
    assert_true(d->frame.ifo.tr == f.tr && d->frame.ifo.inv_tr == f.inv_tr && d->frame.ifo.kf == f.kf);

    wc = 2.0 * 3.14159265358979 * (double)g_dc.control.current_bw_Hz;
    sls = (double)lr - (double)lm * (double)lm / (double)lr;
    kp = wc / (double)b->w_base_rad_s * sls;
    ki = wc * (double)b->Ts_s * (double)rs;
    print_message("gains: kp %.7f (double %.7f), ki %.9f (double %.9f)\n", to_d(d->loop.pi_id.kp), kp,
                  to_d(d->loop.pi_id.ki), ki);
    assert_true(fabs(to_d(d->loop.pi_id.kp) - kp) <= LSB + 1.5e-6 * kp);
    assert_true(fabs(to_d(d->loop.pi_id.ki) - ki) <= LSB + 3e-7 * ki);
    assert_true(fabs(to_d(d->loop.pi_id.e_max) - ((kp <= 1.0) ? 64.0 : 64.0 / kp)) <=
                LSB + 2e-6 * 64.0 / kp);
    assert_true(d->loop.pi_iq.kp == d->loop.pi_id.kp && d->loop.pi_iq.ki == d->loop.pi_id.ki &&
                d->loop.pi_iq.e_max == d->loop.pi_id.e_max);
    assert_true(d->k.sigma_ls == d->frame.fobs.sigma_ls);
    assert_true(fabs(to_d(d->k.lm2_lr) - (double)lm * (double)lm / (double)lr) <=
                LSB + 2e-7 * (double)lm);
    /* the background's record of the model in use */
    assert_true(d->adapt.bg.applied[DRIVE_P_RS] == _IQ(rs) && d->adapt.bg.applied[DRIVE_P_TR] == _IQ20(tr));
}

/* The set's constants are those the inits compute from the same SI model.
 * The model: pu values exact in float and in Q24 (dyadic; near the true
 * motor's, within the factor 2 of the believed one), SI values whose
 * quotient by the base is exactly that float (si_for).  Then flux_obs_init
 * and ifo_init see the very floats the background designs from: every
 * constant equal.  The PI gains against double, kp = (w_c / w_base)
 * sigma Ls, ki = w_c Ts Rs (pu): sigma Ls = Ls - Lm^2/Lr in float carries
 * 3 roundings of terms up to Ls (1.67 pu against sigma Ls 0.87: 7e-7
 * relative), the products 2 more: 1 LSB + 1.5e-6 relative for kp (and
 * 2e-6 for e_max = 64/kp, one more division), 1 LSB + 3e-7 for ki;
 * Lm^2/Lr (two roundings): 1 LSB + 2e-7 relative.  The blend reaches it
 * in blend_ticks ISR ticks (one background pass per tick here: the last
 * set is posted on the tick the time is up, applied on the next) and says
 * so (adapt_ready) with its last set. */
static void test_set_equals_init(void **state)
{
    drive_t *d = &g_d;
    float rs, lm, lr, tr;
    uint32_t ticks;
    (void)state;

    fresh(d, ID_REFINE, 1u);
    exact_model(&d->base, &rs, &lm, &lr, &tr);
    d->adapt.isr.track_rr = 0u;   /* the pass's Tr is taken (not the tracker's) */
    mail(d, _IQ(rs), _IQ(lm), _IQ(lr), _IQ20(tr));
    ticks = run_until_ready(d, 1000u);
    background(d);   /* reads the answer to the last set */
    print_message("blend: %u ISR ticks (blend_ticks %u)\n", (unsigned)ticks,
                  (unsigned)d->adapt.bg.blend_ticks);
    assert_true(ticks >= d->adapt.bg.blend_ticks && ticks <= d->adapt.bg.blend_ticks + 2u);
    assert_runs_model(d, rs, lm, lr, tr);
    assert_int_equal(d->adapt.bg.blending, 0u);
    assert_int_equal(d->adapt.isr.blending, 0u);
}

/* The standstill sequence's published set seeds the model a later rotating
 * start begins from (drive_adapt_seed): at rest, posted whole (no blend:
 * one background pass, one ISR tick), the tracker's Tr included (a pass's
 * keeps the tracker's).  With the standstill test's sigma Ls, Ls = sigma Ls
 * + Lm^2/Lr: the observer's sigma Ls is that sigma Ls within 2 LSB (the
 * _IQdiv and _IQmpy truncations) + 1e-6 relative (the design's float
 * difference of terms up to Ls).  A start before the background's pass:
 * nothing posted, the model unchanged. */
static void test_seed_from_standstill(void **state)
{
    drive_t *d = &g_d;
    drive_t before;
    param_extract_t p;
    float rs, lm, lr, tr;
    const double sls = 0.8125;
    (void)state;

    fresh(d, ID_IDLE, 1u);
    exact_model(&d->base, &rs, &lm, &lr, &tr);
    memset(&p, 0, sizeof p);
    p.valid = 1u;
    p.Rs = _IQ(rs);
    p.Lm = _IQ(lm);
    p.Lr = _IQ(lr);
    p.Tr = _IQ20(tr);
    assert_int_equal(d->adapt.isr.track_rr, 1u);   /* the INI's: the tracker would keep its Tr */
    drive_adapt_seed(d, &p);
    background(d);
    assert_int_equal(d->adapt.box.ready, 1u);
    assert_int_equal(d->adapt.box.set.state, ID_IDLE);
    assert_int_equal(d->adapt.box.set.flags, 0u);
    isr(d);
    assert_int_equal(d->adapt.box.taken, DRIVE_BOX_APPLIED);
    background(d);   /* reads the answer */
    assert_int_equal(d->adapt.bg.pending, 0u);
    assert_int_equal(d->adapt.bg.blending, 0u);
    assert_runs_model(d, rs, lm, lr, tr);
    assert_true(d->adapt.bg.lr == _IQ(lr));

    /* with the standstill test's sigma Ls */
    fresh(d, ID_IDLE, 1u);
    d->telemetry.sigma_ls_dc = _IQ(sls);
    drive_adapt_seed(d, &p);
    background(d);
    isr(d);
    print_message("seeded sigma Ls %.8f (the test's %.8f)\n", to_d(d->frame.fobs.sigma_ls), sls);
    assert_true(fabs(to_d(d->frame.fobs.sigma_ls) - sls) <= 2.0 * LSB + 1e-6 * sls);
    assert_true(d->frame.fobs.lm == _IQ(lm) && d->frame.ifo.tr == _IQ20(tr));

    /* a start first: the seed is dropped, nothing posted */
    fresh(d, ID_IDLE, 1u);
    drive_adapt_seed(d, &p);
    d->seq.state = ID_CALIBRATE;
    d->adapt.isr.prev_state = (uint16_t)ID_CALIBRATE;
    before = *d;
    background(d);
    isr(d);
    assert_int_equal(d->adapt.box.ready, 0u);
    assert_memory_equal(&d->frame.fobs, &before.frame.fobs, sizeof before.frame.fobs);
    assert_memory_equal(&d->frame.ifo, &before.frame.ifo, sizeof before.frame.ifo);
    assert_int_equal(d->adapt.bg.m_seed, 0u);
}

/* INJECT's encoder watch (drive_static_slow): the largest excursion from
 * the count at its start, either way, across the 16-bit counter's wrap:
 * -3, then -6 (the counter below 0), then +40000 modulo 2^16 (25536 the
 * other way round). */
static void test_static_encoder_watch(void **state)
{
    drive_t *d = &g_d;
    static const uint16_t counts[] = {2u, 65535u, 40005u, 5u};
    static const uint16_t moved[] = {3u, 6u, 25536u, 25536u};
    unsigned i;
    (void)state;

    fresh(d, ID_INJECT, 1u);
    assert_true(d->adapt.lf.per > 0u);   /* the INI's standstill test sets the injection up */
    d->sense.qep.count = 5u;
    drive_static_slow(d);                /* starts the test: the count at its start */
    assert_int_equal(d->adapt.isr.static_moved, 0u);
    for (i = 0u; i < sizeof counts / sizeof counts[0]; i++) {
        d->sense.qep.count = counts[i];
        drive_static_slow(d);
        assert_int_equal(d->adapt.isr.static_moved, moved[i]);
    }
}

/* INJECT cut short (a stop or a fault: the sequence leaves it before the
 * test's end): the multisine's ramp runs on by its last step until the
 * background passes (drive_static_background), then the injection is 0 in
 * every control ISR (it used to run on until the next start cleared it,
 * from the 0.17 pu it had reached, wrapping int32 in the end). */
static void test_static_ramp_stops_with_inject(void **state)
{
    drive_t *d = &g_d;
    uint32_t k;
    _iq most = _IQ(0.0);
    (void)state;

    fresh(d, ID_INJECT, 1u);
    for (k = 0u; k < 64u; k++) {   /* 64 slow periods of the test, 8 control ISRs each */
        uint16_t n;
        isr(d);
        for (n = 0u; n < DRIVE_SLOTS; n++) {
            drive_adapt_fast(d);
            most = (d->loop.im_inject > most) ? d->loop.im_inject : most;
        }
    }
    assert_true(d->adapt.lf.running == 1u && d->adapt.lf.i_step != _IQ(0.0));
    assert_true(to_d(most) > 0.01);   /* it injected */
    d->seq.state = ID_IDLE;           /* a stop */
    isr(d);
    for (k = 0u; k < DRIVE_SLOTS; k++) {   /* till the background passes: by the last step */
        const _iq before = d->adapt.lf.i_ref;
        drive_adapt_fast(d);
        assert_true(d->loop.im_inject == before + d->adapt.lf.i_step);
    }
    drive_static_background(d);
    for (k = 0u; k < 100000u; k++) {
        drive_adapt_fast(d);
        if (d->loop.im_inject != _IQ(0.0)) {
            fail_msg("control ISR %u after the stop: im_inject %g pu", (unsigned)k,
                     to_d(d->loop.im_inject));
        }
    }
}

/* The mailbox protocol, deterministically:
 *  (a) ready 0 and the set half written (any bytes): the ISR reads nothing
 *      and changes nothing;
 *  (b) a posted set is not rewritten while ready is 1, whatever the
 *      background is asked meanwhile (blend steps due, a new extraction,
 *      tracker updates);
 *  (c) one ISR call applies every word of it. */
static void test_mailbox_whole_sets(void **state)
{
    drive_t *d = &g_d;
    drive_t before;
    drive_model_set_t posted;
    _iq w[16], want[16];
    uint16_t k, i;
    (void)state;

    fresh(d, ID_REFINE, 1u);
    d->adapt.isr.track_rr = 0u;
    /* (a) */
    memset((void *)&d->adapt.box.set, 0x5A, sizeof d->adapt.box.set);
    d->adapt.box.ready = 0u;
    before = *d;
    isr(d);
    assert_memory_equal(&d->frame.fobs, &before.frame.fobs, sizeof d->frame.fobs);
    assert_memory_equal(&d->frame.ifo, &before.frame.ifo, sizeof d->frame.ifo);
    assert_memory_equal(&d->loop.pi_id, &before.loop.pi_id, sizeof d->loop.pi_id);
    assert_memory_equal(&d->loop.pi_iq, &before.loop.pi_iq, sizeof d->loop.pi_iq);
    assert_memory_equal(&d->k, &before.k, sizeof d->k);
    assert_int_equal(d->adapt.isr.ready, 0u);

    /* (b) */
    mail(d, _IQmpy(d->frame.fobs.rs, _IQ(0.8)), _IQmpy(d->frame.fobs.lm, _IQ(1.3)),
         _IQmpy(d->adapt.bg.applied[DRIVE_P_LR], _IQ(1.2)), _IQmpy(d->frame.fobs.tr, _IQ(0.8)));
    background(d);
    assert_int_equal(d->adapt.box.ready, 1u);
    posted = d->adapt.box.set;
    for (k = 0u; k < 50u; k++) {
        d->adapt.isr.ticks = (uint16_t)(d->adapt.isr.ticks + 7u);   /* the blend runs on */
        if (k == 10u) {
            mail(d, d->frame.fobs.rs, d->frame.fobs.lm, d->adapt.bg.applied[DRIVE_P_LR], d->frame.fobs.tr);
        }
        d->adapt.track.n_updates += 3u;
        background(d);
        assert_int_equal(d->adapt.box.ready, 1u);
        assert_memory_equal((const void *)&d->adapt.box.set, &posted, sizeof posted);
    }
    /* (c) */
    isr(d);
    assert_int_equal(d->adapt.box.ready, 0u);
    assert_int_equal(d->adapt.box.taken, DRIVE_BOX_APPLIED);
    applied_words(d, w);
    set_words(&posted, want);
    for (i = 0u; i < 16u; i++) {
        assert_true(w[i] == want[i]);
    }
    assert_true(d->loop.pi_iq.ki == posted.pi.ki && d->loop.pi_iq.e_max == posted.pi.e_max);
    assert_int_equal(d->adapt.isr.blending, 1u);   /* a blend step: more follow */
}

/* ---- preemption: the ISR part in a timer signal ------------------------- */

static volatile sig_atomic_t g_applied, g_bad;
static _iq g_bad_w[16];

/* The words of one set hang together: ifo's Tr constants are the
 * observer's Tr's (the same float design), both PIs have the gains of the
 * observer's Rs and sigma Ls, the decoupling's sigma Ls is the observer's.
 * A copy torn between two sets of a blend (every parameter moving) breaks
 * one of them. */
static int consistent(const drive_t *d)
{
    const drive_adapt_bg_t *g = &d->adapt.bg;
    pi_gains_t pg;
    ifo_tr_t it;
    flux_obs_model_t om;   /* the observer's kf is for its own step, n Ts */
    (void)ifo_design_tr(&it, g->ts_pu, _IQ20toF(d->frame.fobs.tr), g->imr_min_pu);
    (void)flux_obs_design_tr(&om, g->obs_ts_pu, _IQ20toF(d->frame.fobs.tr));
    (void)pi_design_gains(&pg, g->kp_per_sls * _IQtoF(d->frame.fobs.sigma_ls),
                          g->ki_per_rs * _IQtoF(d->frame.fobs.rs));
    return d->frame.ifo.tr == it.tr && d->frame.ifo.inv_tr == it.inv_tr && d->frame.ifo.kf == it.kf &&
           d->frame.fobs.kf == om.kf && d->loop.pi_id.kp == pg.kp && d->loop.pi_id.ki == pg.ki &&
           d->loop.pi_id.e_max == pg.e_max && d->loop.pi_iq.kp == pg.kp && d->loop.pi_iq.ki == pg.ki &&
           d->loop.pi_iq.e_max == pg.e_max && d->k.sigma_ls == d->frame.fobs.sigma_ls;
}

static void on_timer(int sig)
{
    drive_t *d = &g_d;
    const uint16_t had = d->adapt.box.ready;
    (void)sig;
    isr(d);
    if (had != 0u && d->adapt.box.taken == DRIVE_BOX_APPLIED) {
        g_applied++;
    }
    /* (drive_init's PI gains come from its own SI formula: the relation
     * holds from the first set on) */
    if (g_applied > 0 && !consistent(d) && g_bad == 0) {
        applied_words(d, g_bad_w);
        g_bad = 1;
    }
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The background posts blend steps without pause (two models 25 % apart,
 * Rs, Lm, Lr, Ls and Tr all moving, a new blend whenever one ends) while a
 * 20 us interval timer runs the ISR part in its signal handler, wherever
 * the background is.  After every ISR the model it runs must be one whole
 * set (consistent()).  Until 3000 sets are applied (measured: ~2500 a
 * second on a loaded host: the kernel's timer slack), at most 10 s; at
 * least 1000. */
static void test_preemption(void **state)
{
    drive_t *d = &g_d;
    struct sigaction sa;
    struct itimerval it;
    _iq a[4], bm[4];
    uint32_t blends = 0u;
    double t_end;
    (void)state;

    fresh(d, ID_REFINE, 1u);
    d->adapt.isr.track_rr = 0u;
    a[0] = d->frame.fobs.rs;
    a[1] = d->frame.fobs.lm;
    a[2] = d->adapt.bg.applied[DRIVE_P_LR];
    a[3] = d->frame.fobs.tr;
    bm[0] = _IQmpy(a[0], _IQ(1.25));
    bm[1] = _IQmpy(a[1], _IQ(1.25));
    bm[2] = _IQmpy(a[2], _IQ(1.25));
    bm[3] = _IQmpy(a[3], _IQ(1.25));
    g_applied = 0;
    g_bad = 0;

    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_timer;
    sigemptyset(&sa.sa_mask);
    assert_int_equal(sigaction(SIGALRM, &sa, NULL), 0);
    it.it_interval.tv_sec = 0;
    it.it_interval.tv_usec = 20;
    it.it_value = it.it_interval;
    assert_int_equal(setitimer(ITIMER_REAL, &it, NULL), 0);
    t_end = now_s() + 10.0;
    while (g_applied < 3000 && now_s() < t_end) {
        const drive_adapt_bg_t *g = &d->adapt.bg;
        background(d);
        if (g->blending == 0u && g->pending == 0u && g->m_ready == 0u) {
            const _iq *m = ((blends & 1u) == 0u) ? bm : a;
            mail(d, m[0], m[1], m[2], m[3]);
            blends++;
        }
    }
    memset(&it, 0, sizeof it);
    assert_int_equal(setitimer(ITIMER_REAL, &it, NULL), 0);
    sa.sa_handler = SIG_DFL;
    assert_int_equal(sigaction(SIGALRM, &sa, NULL), 0);

    print_message("preemption: %ld sets applied over %u blends, %s\n", (long)g_applied,
                  (unsigned)blends, g_bad ? "TORN" : "every one whole");
    if (g_bad != 0) {
        print_error("torn: rs %.7f sls %.7f tr %.7f kf %.9f | ifo tr %.7f kf %.9f | kp %.7f\n",
                    to_d(g_bad_w[0]), to_d(g_bad_w[2]), to_d(g_bad_w[5]), to_d(g_bad_w[6]),
                    to_d(g_bad_w[7]), to_d(g_bad_w[9]), to_d(g_bad_w[10]));
    }
    assert_int_equal(g_bad, 0);
    assert_true(g_applied >= 1000);
    assert_true(blends >= 4u);
}

/* ---- the standstill result ---------------------------------------------- */

/* The capture at the end of the magnetisation, as the ISR takes it, of a
 * DC state: i = (i_M, i_T) at the frame angle th, u = R i. */
static void capture_dc(drive_t *d, double im, double it, double r_pu, double th)
{
    volatile drive_adapt_capture_t *c = &d->adapt.cap;
    c->i_mf = _IQ(im);
    c->i_tf = _IQ(it);
    c->u_mf = _IQ(r_pu * im);
    c->u_tf = _IQ(r_pu * it);
    c->theta_r = _IQ(th);
    c->psi_cm_alpha = _IQ(0.55 * cos(2.0 * 3.14159265358979 * th));
    c->psi_cm_beta = _IQ(0.55 * sin(2.0 * 3.14159265358979 * th));
    c->us = c->uc = c->is = c->ic = _IQ(0.0);
    c->ssz_done = 0u;
    c->ready = 1u;
}

/* Rs = u_M / i_M (method §1 at DC): against the double quotient of the
 * captured Q24 values, 1 LSB (_IQdiv truncates) + 1e-6 relative in float;
 * sigma Ls from lock-in sums built for a known reactance X (I = 0.4
 * along sin, the size of the drive's, U = (R + jX) I): X / w - corr
 * against double, 4 LSB (two
 * truncated products, one _IQdiv); the model, applied with the re-seat:
 * the observer equals flux_obs_set_rs_dc of the same model on a copy of
 * it, bit for bit (the seat's own accuracy is orient_flux_obs's); the
 * sequence's wait answered.  An implausible Rs: READY alone, the model
 * and the observer unchanged, Rs_dc 0. */
static void test_standstill(void **state)
{
    drive_t *d = &g_d;
    const double r_pu = 0.6, x_pu = 3.0, im = 0.33;
    flux_obs_t ref;
    drive_model_set_t s;
    double want_sls;
    (void)state;

    fresh(d, ID_MAGNETIZE, 1u);
    capture_dc(d, im, 0.01, r_pu, 0.3);
    d->adapt.cap.is = _IQ(0.4);
    d->adapt.cap.ic = _IQ(0.0);
    d->adapt.cap.us = _IQ(0.4 * r_pu);
    d->adapt.cap.uc = _IQ(0.4 * x_pu);
    d->adapt.cap.ssz_done = 1u;
    background(d);
    assert_int_equal(d->adapt.cap.ready, 0u);
    assert_int_equal(d->adapt.box.ready, 1u);
    s = d->adapt.box.set;
    assert_int_equal(s.flags, DRIVE_SET_SEAT | DRIVE_SET_READY);
    assert_int_equal(s.state, ID_MAGNETIZE);
    assert_true(fabs(to_d(d->telemetry.Rs_dc) -
                     to_d(d->adapt.cap.u_mf) / to_d(d->adapt.cap.i_mf)) <= LSB + 1e-6 * r_pu);
    want_sls = x_pu / to_d(d->adapt.ssz.w) - to_d(d->adapt.ssz.corr);
    print_message("standstill: Rs %.7f (u/i %.7f), sigma Ls %.7f (want %.7f)\n",
                  to_d(d->telemetry.Rs_dc), to_d(d->adapt.cap.u_mf) / to_d(d->adapt.cap.i_mf),
                  to_d(d->telemetry.sigma_ls_dc), want_sls);
    assert_true(fabs(to_d(d->telemetry.sigma_ls_dc) - want_sls) <= 4.0 * LSB + 1e-6 * want_sls);
    assert_true(s.fobs.rs == _IQ(_IQtoF(d->telemetry.Rs_dc)));

    /* the ISR applies it; the reference: the same model and the old
     * fixed-point re-seat on a copy of the observer */
    ref = d->frame.fobs;
    flux_obs_apply_model(&ref, &s.fobs);
    ref.psi_cm_alpha = d->adapt.cap.psi_cm_alpha;
    ref.psi_cm_beta = d->adapt.cap.psi_cm_beta;
    {
        const _iq th = d->adapt.cap.theta_r;
        _iq sn, cs;
        angle_sincos(th, &sn, &cs);
        assert_int_equal(
            flux_obs_set_rs_dc(&ref, s.fobs.rs,
                               _IQmpy(cs, d->adapt.cap.u_mf) - _IQmpy(sn, d->adapt.cap.u_tf),
                               _IQmpy(sn, d->adapt.cap.u_mf) + _IQmpy(cs, d->adapt.cap.u_tf),
                               _IQmpy(cs, d->adapt.cap.i_mf) - _IQmpy(sn, d->adapt.cap.i_tf),
                               _IQmpy(sn, d->adapt.cap.i_mf) + _IQmpy(cs, d->adapt.cap.i_tf)),
            FLUX_OBS_OK);
    }
    isr(d);
    assert_int_equal(d->adapt.box.taken, DRIVE_BOX_APPLIED);
    assert_int_equal(d->adapt.isr.ready, 1u);
    ref.psi_cm_alpha = d->frame.fobs.psi_cm_alpha;   /* the observer's own (not re-seated) */
    ref.psi_cm_beta = d->frame.fobs.psi_cm_beta;
    assert_memory_equal(&d->frame.fobs, &ref, sizeof ref);
    assert_true(d->k.sigma_ls == s.fobs.sigma_ls && d->loop.pi_id.kp == s.pi.kp);
    background(d);   /* reads the answer */
    assert_true(d->adapt.bg.applied[DRIVE_P_RS] == d->telemetry.Rs_dc);

    /* implausible: |u| >= 4 |i| */
    fresh(d, ID_MAGNETIZE, 1u);
    capture_dc(d, im, 0.0, 4.5, 0.0);
    {
        flux_obs_t obs0 = d->frame.fobs;
        background(d);
        assert_int_equal(d->adapt.box.set.flags, DRIVE_SET_READY);
        isr(d);
        assert_int_equal(d->adapt.isr.ready, 1u);
        assert_memory_equal(&d->frame.fobs, &obs0, sizeof obs0);
        assert_true(d->telemetry.Rs_dc == _IQ(0.0));
    }
    /* too late: the sequence left MAGNETIZE (its wait ran out): nothing posted */
    fresh(d, ID_ACCELERATE, 1u);
    capture_dc(d, im, 0.0, r_pu, 0.0);
    background(d);
    assert_int_equal(d->adapt.cap.ready, 0u);
    assert_int_equal(d->adapt.box.ready, 0u);
}

/* A set made for a state (or pass) the sequence has left is dropped: the
 * model stays, the background reads "dropped", keeps its record of the
 * model in use and ends the blend it belonged to. */
static void test_stale_dropped(void **state)
{
    drive_t *d = &g_d;
    drive_t before;
    (void)state;

    fresh(d, ID_REFINE, 1u);
    d->adapt.isr.track_rr = 0u;
    mail(d, _IQmpy(d->frame.fobs.rs, _IQ(0.8)), d->frame.fobs.lm, d->adapt.bg.applied[DRIVE_P_LR],
         _IQmpy(d->frame.fobs.tr, _IQ(1.2)));
    background(d);
    assert_int_equal(d->adapt.box.ready, 1u);
    assert_int_equal(d->adapt.bg.blending, 1u);
    d->seq.state = ID_ACCELERATE;   /* the wait ran out: pass 2 */
    d->seq.pass = 2u;
    d->adapt.isr.prev_state = ID_ACCELERATE;
    before = *d;
    isr(d);
    assert_int_equal(d->adapt.box.ready, 0u);
    assert_int_equal(d->adapt.box.taken, DRIVE_BOX_DROPPED);
    assert_memory_equal(&d->frame.fobs, &before.frame.fobs, sizeof d->frame.fobs);
    assert_memory_equal(&d->frame.ifo, &before.frame.ifo, sizeof d->frame.ifo);
    assert_memory_equal(&d->loop.pi_id, &before.loop.pi_id, sizeof d->loop.pi_id);
    assert_int_equal(d->adapt.isr.ready, 0u);
    background(d);
    assert_int_equal(d->adapt.bg.blending, 0u);
    assert_int_equal(d->adapt.bg.pending, 0u);
    assert_int_equal(d->adapt.box.ready, 0u);
    assert_memory_equal(d->adapt.bg.applied, before.adapt.bg.applied, sizeof d->adapt.bg.applied);
}

/* Tracking.  The last pass's extraction in RUN: a blend whose first set
 * restarts the tracker from the pass's 1/Tr and arms it, the tracker
 * learning only after the last.  Then tracker updates (written by hand:
 * the tracker's own RLS is estim_tr_track's; with no flux it holds):
 *  - one update towards a Tr 30 % higher: the applied Tr moves by exactly
 *    one step, Tr + Tr tr_rate (Tr Q20: the product truncated), and this
 *    first tracked set hands the frame to ifo (run_ifo; ifo's angle the
 *    observer's);
 *  - 10 updates at once: 10 steps, against the closed form Tr (1 +
 *    rate)^10 in double within 10 LSB20 (one truncation per step);
 *  - a target within one step: reached exactly;
 *  - telemetry: Tr_track (Q20) = 1/theta within 1 LSB20 + 1e-7 relative, Rr_track
 *    = Lr theta, track_valid from k.track_valid_updates on: the updates
 *    (f_pwm / 16) in tr_track_settle_s(track_memory_s, the nameplate's
 *    Lr / Rr), recomputed here from the INI's SI values (1 update). */
static void test_tracking(void **state)
{
    drive_t *d = &g_d;
    drive_adapt_bg_t *g = &d->adapt.bg;
    _iq20 tr0, tr1, target;   /* Q20 */
    _iq theta;
    double rate, want;
    uint32_t k;
    (void)state;

    fresh(d, ID_RUN, 2u);
    assert_int_equal(d->adapt.isr.track_rr, 1u);
    mail(d, d->frame.fobs.rs, d->frame.fobs.lm, g->applied[DRIVE_P_LR], _IQmpy(d->frame.fobs.tr, _IQ(0.9)));
    background(d);
    assert_int_equal(d->adapt.box.set.flags, DRIVE_SET_BLENDING | DRIVE_SET_TRACK_START);
    isr(d);
    assert_int_equal(d->adapt.isr.track_armed, 1u);
    assert_int_equal(d->adapt.isr.blending, 1u);
    assert_true(fabs(to_d(d->adapt.track.theta) - 1.0 / (0.9 * to_d20(g->applied[DRIVE_P_TR]))) <=
                1e-3 / to_d20(g->applied[DRIVE_P_TR]));
    for (k = 0u; k < 400u && g->blending != 0u; k++) {
        background(d);
        isr(d);
    }
    background(d);
    assert_int_equal(g->blending, 0u);
    assert_int_equal(d->adapt.isr.blending, 0u);
    assert_int_equal(d->frame.run_ifo, 0u);
    assert_int_equal(d->adapt.track.n_updates, 0u);

    /* one update towards Tr x 1.3 */
    tr0 = g->applied[DRIVE_P_TR];
    target = _IQmpy(tr0, _IQ(1.3));
    theta = _IQ20div(_IQ(1.0), target);   /* Q24 / Q20 -> Q24 */
    d->adapt.track.theta = theta;
    d->adapt.track.n_updates = 1u;
    background(d);
    assert_int_equal(d->adapt.box.set.flags, DRIVE_SET_ALIGN);
    /* the hand-over takes the frame's angle of this period (obs_theta, carried
     * forward every period), not the observer's last sample (fobs.theta, 7
     * periods older: the rotor has turned since) */
    d->frame.fobs.theta = _IQ(0.21);
    d->frame.obs_theta = _IQ(0.37);
    d->frame.fobs.psi_mag = _IQmpy(d->frame.fobs.lm, _IQ(0.33));
    isr(d);
    tr1 = tr0 + _IQmpy(tr0, g->tr_rate);
    assert_true(d->frame.fobs.tr == _IQ20(_IQ20toF(tr1)));
    assert_true(d->frame.ifo.tr == d->frame.fobs.tr);
    assert_int_equal(d->frame.run_ifo, 1u);
    assert_int_equal(d->frame.is_ifo, 1u);
    assert_true(d->frame.ifo.theta == _IQ(0.37));
    assert_true(fabs(to_d(d->frame.ifo.imr) - 0.33) <= 1e-4);
    assert_true(fabs(to_d20(d->telemetry.Tr_track) - 1.0 / to_d(theta)) <=
                LSB20 + 1e-7 * to_d20(d->telemetry.Tr_track));
    assert_true(fabs(to_d(d->telemetry.Rr_track) - to_d(g->lr) * to_d(theta)) <= LSB + 1e-7);
    assert_int_equal(d->telemetry.track_valid, 0u);

    /* ten at once */
    background(d);   /* the answer */
    d->adapt.track.n_updates = 11u;
    background(d);
    assert_int_equal(d->adapt.box.set.flags, 0u);   /* ifo has the frame already */
    isr(d);
    rate = to_d(g->tr_rate);
    want = to_d20(tr1) * pow(1.0 + rate, 10.0);
    print_message("tracking: 10 updates, Tr %.7f want %.7f (%.2f LSB20)\n",
                  to_d20(g->posted[DRIVE_P_TR]), want,
                  LSB20 > 0.0 ? (to_d20(g->posted[DRIVE_P_TR]) - want) / LSB20 : 0.0);
    assert_true(fabs(to_d20(g->posted[DRIVE_P_TR]) - want) <= 10.0 * LSB20 + 1e-6 * want);

    /* within one step: exactly the target */
    background(d);
    theta = _IQ20div(_IQ(1.0), g->applied[DRIVE_P_TR] + _IQmpy(g->applied[DRIVE_P_TR], _IQ(1e-5)));
    d->adapt.track.theta = theta;
    {
        const drive_motor_t *m = &g_dc.motor;
        double f_upd = (double)g_dc.board.pwm_freq_Hz / 16.0;
        double want_n = (3.0 * (double)m->Lr_H / (double)m->Rr_ohm +
                         2.0 * (double)g_dc.ident.track_memory_s) * f_upd;
        print_message("tracking: valid after %u updates (want %.1f)\n",
                      (unsigned)d->k.track_valid_updates, want_n);
        assert_true(fabs((double)d->k.track_valid_updates - want_n) <= 1.0);
    }
    d->adapt.track.n_updates = d->k.track_valid_updates - 1u;
    background(d);
    assert_int_equal(d->telemetry.track_valid, 0u);
    background(d);   /* the answer */
    d->adapt.track.n_updates = d->k.track_valid_updates;
    background(d);
    assert_true(g->posted[DRIVE_P_TR] == _IQ20div(_IQ(1.0), theta));   /* Q24 / Q24 -> Q20 */
    assert_int_equal(d->telemetry.track_valid, 1u);
    isr(d);

    /* out of RUN: the tracker disarmed, the telemetry invalid, ifo hands back */
    d->seq.state = ID_IDLE;
    isr(d);
    assert_int_equal(d->adapt.isr.track_armed, 0u);
    assert_int_equal(d->frame.run_ifo, 0u);
    background(d);
    assert_int_equal(d->telemetry.track_valid, 0u);
}

/* drive_init sets the sequence's waits: the adaptive configuration holds
 * the end of MAGNETIZE for the standstill set, every wait at most
 * DRIVE_ADAPT_WAIT_S in slow samples; without the standstill test only
 * REFINE waits. */
static void test_waits_configured(void **state)
{
    drive_t *d = &g_d;
    drive_config_t dc = g_dc;
    (void)state;
    const double ts_slow = (double)DRIVE_SLOTS / (double)g_dc.board.pwm_freq_Hz;
    fresh(d, ID_IDLE, 1u);
    assert_int_equal(d->seq.wait_magnetize, 1u);
    /* round(0.5 s / Ts_slow) = 937.5 at 15 kHz: either neighbour */
    assert_true(fabs((double)d->seq.wait_max_samples * ts_slow - (double)DRIVE_ADAPT_WAIT_S) <=
                ts_slow);
    dc.ident.standstill = 0u;
    assert_int_equal(drive_init(d, &dc), DRIVE_CFG_OK);
    assert_int_equal(d->seq.wait_magnetize, 0u);
}

/* A large motor's Tr (tens of kW: 0.3-1 s, beyond Q24's 128 pu; Tr is
 * Q20 in the adaptation, drive_adapt_bg.c): the believed Rr / 25 makes
 * Tr 25 x that of this INI's nameplate, 202 pu (0.64 s).
 *  - drive_init accepts it; the background's Tr in use is the observer's;
 *  - a pass's Tr x 1.8 (364 pu, beyond the 120 pu the factor-2 limit once
 *    capped) is blended to: the observer and ifo end on its design
 *    (flux_obs_design_tr, ifo_design_tr of the Q20 value), Tr within
 *    1 LSB20 + 1e-7 relative of it;
 *  - a pass's Tr x 3 (1091 pu) is limited to twice the Tr in use (727);
 *  - the tracker's 1/Tr = 1/400 gives Tr_track = 400 pu within 1 LSB20 +
 *    1e-7 relative, and the Tr in use moves towards it by one step. */
static void test_large_tr(void **state)
{
    drive_t *d = &g_d;
    drive_adapt_bg_t *g = &d->adapt.bg;
    const drive_config_t keep = g_dc;
    double tr0, want;
    _iq20 tr_in_use;
    uint32_t k;
    ifo_tr_t it;
    flux_obs_model_t om;
    (void)state;

    g_dc.motor.Rr_ohm = keep.motor.Rr_ohm / 25.0f;
    fresh(d, ID_REFINE, 1u);
    tr0 = (double)g_dc.motor.Lr_H / (double)g_dc.motor.Rr_ohm / (double)d->base.t_base_s;
    print_message("large Tr: %.3f pu (Q20 %.6f)\n", tr0, to_d20(d->frame.fobs.tr));
    assert_true(tr0 > 128.0 && 3.0 * 1.8 * tr0 < 2047.0);
    assert_true(fabs(to_d20(d->frame.fobs.tr) - tr0) <= LSB20 + 1e-7 * tr0);
    assert_true(d->frame.ifo.tr == d->frame.fobs.tr && g->applied[DRIVE_P_TR] == d->frame.fobs.tr);

    /* a pass's Tr x 1.8, taken (not the tracker's) */
    d->adapt.isr.track_rr = 0u;
    mail(d, d->frame.fobs.rs, d->frame.fobs.lm, g->applied[DRIVE_P_LR], _IQ20(1.8 * tr0));
    (void)run_until_ready(d, 1000u);
    background(d);
    want = to_d20(_IQ20(1.8 * tr0));
    print_message("large Tr x 1.8: %.4f pu, want %.4f\n", to_d20(d->frame.fobs.tr), want);
    assert_true(g->applied[DRIVE_P_TR] == _IQ20(1.8 * tr0));
    assert_true(fabs(to_d20(d->frame.fobs.tr) - want) <= LSB20 + 1e-7 * want);
    (void)ifo_design_tr(&it, g->ts_pu, _IQ20toF(d->frame.fobs.tr), g->imr_min_pu);
    (void)flux_obs_design_tr(&om, g->obs_ts_pu, _IQ20toF(d->frame.fobs.tr));
    assert_true(d->frame.ifo.tr == it.tr && d->frame.ifo.inv_tr == it.inv_tr && d->frame.ifo.kf == it.kf);
    assert_true(d->frame.fobs.tr == om.tr && d->frame.fobs.kf == om.kf);

    /* x 3 of the Tr in use: limited to x 2 */
    tr_in_use = g->applied[DRIVE_P_TR];
    fresh(d, ID_REFINE, 1u);
    d->adapt.isr.track_rr = 0u;
    g->applied[DRIVE_P_TR] = tr_in_use;   /* the record the limit is taken from */
    mail(d, d->frame.fobs.rs, d->frame.fobs.lm, g->applied[DRIVE_P_LR], _IQ20(3.0 * to_d20(tr_in_use)));
    background(d);
    assert_true(g->to[DRIVE_P_TR] == tr_in_use + tr_in_use);

    /* tracking: theta = 1/400 pu */
    fresh(d, ID_RUN, 2u);
    assert_int_equal(d->adapt.isr.track_rr, 1u);
    mail(d, d->frame.fobs.rs, d->frame.fobs.lm, g->applied[DRIVE_P_LR], d->frame.fobs.tr);
    for (k = 0u; k < 400u && (g->blending != 0u || g->pending != 0u || k == 0u); k++) {
        background(d);
        isr(d);
    }
    background(d);
    assert_int_equal(g->blending, 0u);
    tr_in_use = g->applied[DRIVE_P_TR];
    d->adapt.track.theta = _IQ(1.0 / 400.0);
    d->adapt.track.n_updates = 1u;
    background(d);
    want = 1.0 / to_d(_IQ(1.0 / 400.0));
    print_message("large Tr tracked: Tr_track %.5f pu, want %.5f\n",
                  to_d20(d->telemetry.Tr_track), want);
    assert_true(fabs(to_d20(d->telemetry.Tr_track) - want) <= LSB20 + 1e-7 * want);
    assert_true(g->posted[DRIVE_P_TR] == tr_in_use + _IQmpy(tr_in_use, g->tr_rate));
    g_dc = keep;
}

/* drive_fused_set: the fused set exactly as its four sources hold it, and
 * only when each exists (the set publish_tracked publishes and a refusal
 * reports) */
static void test_fused_set(void **state)
{
    drive_t *d = &g_d;
    drive_params_t f;
    const drive_params_t untouched = {_IQ(-1.0), _IQ(-2.0), _IQ(-3.0), _IQ(-4.0), _IQ(-5.0),
                                      _IQ20(-6.0)};
    (void)state;
    fresh(d, ID_RUN, 2u);
    assert_int_equal(d->adapt.isr.fused, 1u);   /* the adaptive configuration fuses */
    d->verdict.fused_ready = 1u;
    d->verdict.fused_lm = _IQ(1.9);
    d->verdict.fused_lr = _IQ(2.0);
    d->verdict.fused_psi = _IQ(0.95);
    d->telemetry.Rs_dc = _IQ(0.031);
    d->telemetry.Rr_track = _IQ(0.027);
    d->telemetry.Tr_track = _IQ20(74.5);
    assert_int_equal(drive_fused_set(d, &f), 1u);
    assert_true(f.Rs == _IQ(0.031) && f.Rr == _IQ(0.027) && f.Tr == _IQ20(74.5));
    assert_true(f.Lm == _IQ(1.9) && f.Lr == _IQ(2.0) && f.psi_r == _IQ(0.95));
    /* each source missing in turn: 0, the caller's set untouched */
    {
        unsigned i;
        for (i = 0u; i < 4u; i++) {
            fresh(d, ID_RUN, 2u);
            d->verdict.fused_ready = (uint16_t)(i != 0u);
            d->telemetry.Rs_dc = (i != 1u) ? _IQ(0.031) : _IQ(0.0);
            d->telemetry.Tr_track = (i != 2u) ? _IQ20(74.5) : 0;
            d->adapt.isr.fused = (uint16_t)(i != 3u);
            f = untouched;
            assert_int_equal(drive_fused_set(d, &f), 0u);
            assert_memory_equal(&f, &untouched, sizeof f);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fused_set),
        cmocka_unit_test(test_set_equals_init),
        cmocka_unit_test(test_seed_from_standstill),
        cmocka_unit_test(test_static_encoder_watch),
        cmocka_unit_test(test_static_ramp_stops_with_inject),
        cmocka_unit_test(test_mailbox_whole_sets),
        cmocka_unit_test(test_preemption),
        cmocka_unit_test(test_standstill),
        cmocka_unit_test(test_stale_dropped),
        cmocka_unit_test(test_tracking),
        cmocka_unit_test(test_large_tr),
        cmocka_unit_test(test_waits_configured),
    };
    return cmocka_run_group_tests(tests, load, NULL);
}
