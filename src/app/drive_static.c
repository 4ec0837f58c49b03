/* The standstill sequence's drive side.  See drive_static.h. */
#include "drive_static.h"

#include "drive_adapt.h"
#include "drive_internal.h"
#include "standstill_fit.h"

#include <math.h>

/* INJECT's length in slow samples: the test starts in INJECT's second
 * (the first is the state change's, drive_adapt_slow) and needs
 * standstill_lf_samples; two more for the last sums' margin.  0: no test. */
static uint32_t drive_static_samples(const drive_t *d)
{
    return (d->adapt.lf.per > 0u) ? standstill_lf_samples(&d->adapt.lf) + 2u : 0u;
}

int16_t drive_static_init(drive_t *d, const drive_config_t *c, float Ts)
{
    const drive_motor_t *m = &c->motor;
    const base_values_t *b = &d->base;
    const float im_pu = m->magnetizing_current_A / b->I_base_A;
    standstill_lf_status_t st = STANDSTILL_LF_ERR_TIME;

    d->verdict.static_unavailable = 0u;
    if (c->ident.static_id > 1u) {
        return 1;
    }
    /* with the standstill test (its Rs and sigma Ls), the injection is set
     * up whichever sequence is configured: the other can be selected at
     * run time (drive_static_select) */
    if (c->ident.standstill != 0u) {
        /* the injection ramped over the slow period's DRIVE_SLOTS fast
         * periods, the regression's window (standstill_lf.h, Hold) */
        st = standstill_lf_init(&d->adapt.lf, Ts * (float)DRIVE_SLOTS, m->Lr_H / m->Rr_ohm,
                                DRIVE_STATIC_AMPL_OF_IM * im_pu, im_pu, DRIVE_STATIC_WINDOW_S,
                                DRIVE_SLOTS_LOG2);
    }
    if (c->ident.static_id == 0u) {
        return 0;
    }
    /* configured: one pass, no tracker (nothing turns) */
    if (st != STANDSTILL_LF_OK || c->ident.passes > 1u || c->ident.track_rr != 0u) {
        return 1;
    }
    return id_sequence_set_static(&d->seq, 1u, drive_static_samples(d));
}

void drive_static_select(drive_t *d, uint16_t on)
{
    const uint16_t ready = (uint16_t)(d->adapt.lf.per > 0u && d->adapt.isr.standstill != 0u);
    d->verdict.static_unavailable = (uint16_t)(on != 0u && ready == 0u);
    (void)id_sequence_set_static(&d->seq, (uint16_t)(on != 0u && ready != 0u),
                                 drive_static_samples(d));
}

void drive_static_slow(drive_t *d)
{
    standstill_lf_t *z = &d->adapt.lf;
    drive_adapt_t *a = &d->adapt.isr;
    uint16_t moved;

    if (z->running == 0u && z->done == 0u) {
        standstill_lf_start(z);
        a->static_count0 = d->sense.qep.count;
        a->static_moved = 0u;
    }
    /* the counter's difference modulo 2^16 and its magnitude as the smaller
     * way round (unsigned throughout: no int16_t negation of -32768); exact
     * for |moves| <= 32768 */
    moved = (uint16_t)(d->sense.qep.count - a->static_count0);
    if (moved > 32768u) {
        moved = (uint16_t)(0u - moved);
    }
    if (moved > a->static_moved) {
        a->static_moved = moved;
    }
    z->u_m = d->id.reg.u_mf;
    z->i_m = d->id.reg.i_mf;
    standstill_lf_step(z);   /* its i_add reaches the i_M reference by a ramp over the next
                                DRIVE_SLOTS periods (drive_adapt_fast, standstill_lf_fast) */
}

/* The reason a fit is refused, or PUBLISHED. */
static uint16_t static_verdict(drive_t *d, const standstill_fit_t *f, standstill_fit_status_t st,
                      const param_extract_t *p)
{
    const float lim = _IQtoF(d->verdict.conf.conf_max);
    uint16_t j;
    if (d->adapt.isr.static_moved > (uint16_t)DRIVE_STATIC_MOVE_COUNTS) {
        return DRIVE_PUB_ROTOR_TURNING;
    }
    if (st == STANDSTILL_FIT_ERR_CURRENT) {
        return DRIVE_PUB_LOW_EXCITATION;
    }
    if (st != STANDSTILL_FIT_OK || p->valid == 0u) {
        return DRIVE_PUB_IMPLAUSIBLE;
    }
    for (j = 0u; j < (uint16_t)SSFIT_NP; j++) {
        if (!(f->conf[j] <= lim)) {
            return DRIVE_PUB_LOW_CONFIDENCE;
        }
    }
    return DRIVE_PUB_PUBLISHED;
}

/* A pu value within the extraction's range [lim0, lim1]. */
static uint16_t in_range(float v, const _iq lim[2])
{
    return (uint16_t)(v >= _IQtoF(lim[0]) && v <= _IQtoF(lim[1]));
}

void drive_static_background(drive_t *d)
{
    const base_values_t *b = &d->base;
    param_extract_t *p = &d->id.pex;   /* the sequence's extraction: its ranges, its result */
    standstill_fit_in_t in;
    standstill_fit_t f;
    standstill_fit_status_t st;
    uint16_t verdict;
    uint16_t j;

    /* the multisine's ramp ends with INJECT, however INJECT ends: the test's
     * own end clears it, a stop or a fault does not, and the control ISR
     * would go on adding the last step (standstill_lf_fast) until the next
     * start.  Here rather than in the slow ISR's state change (12 cycles
     * where 14 are left); till the background passes, the ramp runs on by
     * its step, about 1e-3 pu a period, the bridge off or its currents
     * going down.  The step is read first: it is set only in INJECT, so a
     * state read after it that is not INJECT means INJECT has ended. */
    if (d->adapt.lf.i_step != _IQ(0.0) && d->seq.state != ID_INJECT) {
        d->adapt.lf.i_step = _IQ(0.0);   /* the step first: an ISR between the two adds nothing */
        d->adapt.lf.i_ref = _IQ(0.0);
    }
    if (d->seq.static_done == 0u || d->verdict.static_judged != 0u ||
        d->seq.state != ID_IDLE) {
        return;
    }
    d->verdict.static_judged = 1u;
    in.w1_pu = standstill_lf_w1_rad_s(&d->adapt.lf, b->Ts_s * (float)DRIVE_SLOTS) /
               b->w_base_rad_s;
    in.half_ts_pu = 0.5f * b->Ts_pu;
    in.sigma_ls_pu = _IQtoF(d->telemetry.sigma_ls_dc);
    in.im_pu = _IQtoF(d->seq.im_ref);
    /* the drive's RLS is idle at standstill (a start re-initialises it) */
    st = (d->adapt.lf.done != 0u) ? standstill_fit(&f, &d->adapt.lf, &in, &d->id.rls)
                                  : STANDSTILL_FIT_ERR_CURRENT;
    p->valid = 0u;
    if (st == STANDSTILL_FIT_OK) {
        p->Rs = _IQ(f.p[SSFIT_RS]);
        p->Rr = _IQ(f.p[SSFIT_RR]);
        p->Lm = _IQ(f.p[SSFIT_LM]);
        p->Lr = _IQ(f.p[SSFIT_LR]);
        p->psi_r = _IQ(f.p[SSFIT_PSI]);
        p->Tr = _IQ20(f.p[SSFIT_TR]);
        p->valid = (uint16_t)(in_range(f.p[SSFIT_RS], p->Rs_lim) &
                              in_range(f.p[SSFIT_RR], p->Rr_lim) &
                              in_range(f.p[SSFIT_LM], p->Lm_lim) &
                              in_range(f.p[SSFIT_LR], p->Lr_lim) &
                              in_range(f.p[SSFIT_PSI], p->psi_lim) &
                              (uint16_t)(f.p[SSFIT_TR] >= _IQ20toF(p->Tr_lim[0]) &&
                                         f.p[SSFIT_TR] <= _IQ20toF(p->Tr_lim[1])));
    }
    for (j = 0u; j < (uint16_t)SSFIT_NP; j++) {
        d->telemetry.conf[j] = (st == STANDSTILL_FIT_OK) ? _IQ(fminf(f.conf[j], 100.0f))
                                                         : -_IQ(1.0);
    }
    d->telemetry.conf_residual = (st == STANDSTILL_FIT_OK) ? _IQ(fminf(f.residual, 100.0f))
                                                           : _IQ(0.0);
    d->telemetry.conf_amp = _IQ(0.0);
    verdict = static_verdict(d, &f, st, p);
    drive_publish(&d->telemetry, p, verdict);
    if (verdict == (uint16_t)DRIVE_PUB_PUBLISHED) {
        drive_adapt_seed(d, p);   /* a later rotating start begins from this set */
    }
}
