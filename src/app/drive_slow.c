/**
 * The slow tasks of the multi-rate schedule (drive_step.c): one per period,
 * in turn, in the slow ISR that follows the control ISR (drive_slow_isr),
 * each at f_pwm / DRIVE_SLOTS (1.875 kHz at 15 kHz).  Every slot's work is
 * bounded and similar in size, so that no period carries more than the
 * fast path plus one of them.
 *
 *   0 SPEED       the QEP's speeds, the speed ramp + PI (i_T reference
 *                 for the fast current loop, held first-order over the slow
 *                 period: a few Hz of bandwidth), the fast path's slow
 *                 constants (1/(Tr i_mr) of the slip, the bus the SVPWM
 *                 divides by)
 *   1 FILTERS_A   the regression's window means (the sums restart), the
 *                 i_M, i_T filters and their derivatives (method §5)
 *   2 FILTERS_B   the u_M, u_T and w_s i_T filters
 *   3 FILTERS_C   the w_s i_M and w_r filters, y1, y2 and the rows, queued
 *                 for the background's RLS (drive_rls_bg.c: one RLS sample
 *                 is a quarter of a period's cycles, and the recursion needs
 *                 its samples in order, not in time); the checks that need
 *                 no more than this rate (current feedback through its 2 ms
 *                 filter, the encoder's 50 ms frozen test)
 *   4 SEQUENCE    identification sequence (times of 0.1-1 s), adaptation
 *                 (drive_adapt.c), telemetry, the snapshot events
 *   5 OBSERVER_A  the rotor-flux observer on the window's means (mode 1):
 *                 its voltage and current models and their correction
 *   6 OBSERVER_B  its rotor flux, magnitude, angle and speed; the frame's
 *                 angle from here on; then the Rr/Tr tracker (mode 1, RUN
 *                 with tracking: drive_adapt_track)
 *   7 SAFETY      the model-based protections' slow step (drive_safety.c:
 *                 the currents against the model over the window, the
 *                 encoder's count step, the publish guard's tick; the
 *                 locked-rotor decision stays with the frozen test, slot 3;
 *                 the model check's sequence tests, which alternate two
 *                 halves from window to window, run on its residual in the
 *                 next window's slots 0 and 2, the two lighter ones of the
 *                 slots that run with both orientations: the heaviest part
 *                 of the schedule, 1300 cycles in one ISR, is then spread
 *                 over three)
 * The firmware's data log runs in the slow ISR of slot 1 (DRIVE_LOG_SLOT), the
 * lightest but one in RUN of both orientations and light in every state
 * (the observer's 5 and 6 are lighter only with IFO, slot 2 carries the
 * model check's heavier half, 4 the adaptive sequence's MAGNETIZE): its
 * cost adds there.
 *
 * The sequence sees the filtered di/dt of this period and judges the RLS's
 * enable for the next one.  The 10 Hz regression band and the speed loop's
 * few Hz leave a wide margin below 1.875 kHz; the window mean of 8 samples
 * before the filters is their anti-alias stage (ident_regressor.h).
 */
#include "drive_internal.h"

#include "angle.h"
#include "drive_adapt.h"
#include "drive_design.h"
#include "drive_safety.h"
#include "drive_target.h"
#include "drive_vi.h"

/* The sequence's inputs, all of them here, from their owners (the state
 * each owner keeps; the sequence only reads its copy). */
static inline void sequence_inputs(drive_t *d)
{
    id_sequence_t *s = &d->seq;
    s->cal_done = drive_cal_done(d);
    s->test_done = drive_safety_test_done(d);
    s->adapt_ready = drive_adapt_ready(d);
    s->excite = drive_adapt_excite(d);
    s->fault = (uint16_t)(d->prot.trip.fault != FAULT_NONE);
    s->ramp_done = d->loop.speed_ramp.done;
    s->speed_err = _IQabs(d->loop.speed_ramp.out - d->sense.qep.speed);
    s->torque_limit = d->loop.pi_speed.sat;
    s->i_mf = d->id.reg.i_mf;
    s->i_tf = d->id.reg.i_tf;
    s->speed = d->sense.qep.speed;
    s->speed_ref = d->loop.speed_ramp.out;
    /* the acceleration ends where the voltage's headroom does (drive_target.h;
     * the low-pass in check_current) */
    s->volt_limit = (uint16_t)(s->state == ID_ACCELERATE && d->target.at_limit != 0u);
    if ((d->seq.vi_test != 0u) & (d->vi.done == 0u)) {
        drive_vi_slow(d);   /* the bridge's voltage-error test in CALIBRATE (drive_vi.c,
                               from flash); the test off or done: not even the call */
    }
    s->vi_done = drive_vi_done(d);
}

static void sequence(drive_t *d)
{
    id_sequence_t *s = &d->seq;
    sequence_inputs(d);
    id_sequence_step(s);
    /* (the observer's reset on entering MAGNETIZE: drive_adapt_slow's
     * state change, next) */
    /* the snapshots, taken by the background in the RLS's own order: the
     * events ride with the next queued sample (drive_rls_bg.c); with the
     * extraction go the covariance and the confidence's residual sums */
    if (s->magnetize_end != 0u || s->rls_restart != 0u) {
        d->id.rlsq.pending |= DRIVE_RLSQ_WINDOW;   /* a new RLS window begins */
    }
    if (s->extract_now != 0u) {
        d->id.rlsq.pending |= DRIVE_RLSQ_EXTRACT;
    }
    if (++d->id.live_div >= d->k.live_period) {
        d->id.live_div = 0u;
        d->id.rlsq.pending |= DRIVE_RLSQ_LIVE;
    }
}

/* Speed ramp and PI: the torque-current reference of the fast current loop. */
static void speed_loop(drive_t *d)
{
    const id_sequence_t *s = &d->seq;

    d->loop.speed_ramp.target = s->speed_cmd;
    /* RUN's excitation ramps faster (drive_adapt.h): a torque the tracker sees */
    d->loop.speed_ramp.step = (s->exciting != 0u) ? d->k.excite_step : d->k.ramp_step;
    ramp_gen_step(&d->loop.speed_ramp);
    if (s->speed_loop_on != 0u && d->prot.trip.fault == FAULT_NONE) {
        d->loop.pi_speed.ref = d->loop.speed_ramp.out;
        d->loop.pi_speed.fbk = d->sense.qep.speed;
        d->loop.pi_speed.ff = _IQ(0.0);
        pi_step(&d->loop.pi_speed);
        /* to the current loop as a ramp over the slow period, not a step
         * every DRIVE_SLOTS periods: a step of the reference would pass
         * the current PI's proportional gain to the voltage at once (the
         * soak's over-modulation at rated speed); the fast path adds
         * i_t_step every period and reaches the output, within
         * DRIVE_SLOTS - 1 LSB, one slow period later.  |out - ref| <= 2 pu
         * (both within +-i_max <= 1) */
        d->loop.i_t_step = (d->loop.pi_speed.out - d->loop.i_t_ref) / (int32_t)DRIVE_SLOTS;
    } else {
        pi_reset(&d->loop.pi_speed);
        d->loop.i_t_ref = _IQ(0.0);
        d->loop.i_t_step = _IQ(0.0);
    }
}

static void telemetry(drive_t *d)
{
    drive_telemetry_t *t = &d->telemetry;
    t->speed = d->sense.qep.speed;
    t->speed_ref = d->loop.speed_ramp.out;
    t->i_m = d->loop.park.ds;
    t->i_t = d->loop.park.qs;
    t->vdc = d->sense.bus.vdc;
}

/* The loops' voltage at the bus's limit: the vector the modulator got last
 * (svgen's input, the dead-time feed-forward included) within 5 % of the
 * hexagon's inscribed circle vdc / sqrt 3.  Below the circle the loops still
 * have a few % to act with: the bus ripple and the feed-forward's pole error
 * E move the limit by that much.  Scaling: _IQmag of svgen's input range
 * (|.| <= 32 pu) <= 45.3 pu, vdc < 128 pu times 0.55: Q24, no overflow. */
#define DRIVE_VLIM_OF_VDC (0.95 / DRIVE_SQRT3)   /* headroom 0.95 / sqrt 3 */

/* Current feedback check: the M-T currents against the references the
 * current loops followed in the last period (current_check.h; its 2 ms
 * filter needs no more than this slot's rate).  A trip latches the fault,
 * and the bridge is off in this same period (drive_slow_isr switches it off
 * after the slow task). */
static void check_current(drive_t *d)
{
    /* at the voltage limit the check holds (current_check.h): clamped onto
     * the hexagon in a control ISR since the last step, or no headroom now */
    const svgen_t *sv = &d->pwm.svgen;
    const _iq u = _IQmag(sv->ualpha, sv->ubeta);
    const _iq lim = _IQmpy(sv->vdc, _IQ(DRIVE_VLIM_OF_VDC));
    d->prot.feedback.limited |= (uint16_t)(u >= lim);
    /* low-passed, the acceleration's end (drive_target.h) */
    drive_target_step(&d->target, u, lim);   /* -> target.at_limit */
    d->prot.feedback.i_m_ref = d->loop.pi_id.ref;
    d->prot.feedback.i_m = d->loop.park.ds;
    d->prot.feedback.i_t_ref = d->loop.pi_iq.ref;
    d->prot.feedback.i_t = d->loop.park.qs;
    /* re-armed (filter zeroed) while the bridge is off, and during the
     * bridge's voltage-error test, whose alpha current has no M-T reference
     * (the test checks each of its current levels itself: FAULT_VI_CURVE) */
    d->prot.feedback.active = (uint16_t)(d->pwm.on_next != 0u && d->seq.vi_testing == 0u);
    current_check_step(&d->prot.feedback);
    d->prot.trip.current_fault = d->prot.feedback.fault;
    if (d->prot.feedback.fault != 0u) {
        protect_latch(&d->prot.trip, FAULT_CURRENT_SENSOR);
    }
}

static void task_checks(drive_t *d)
{
    check_current(d);
    /* the encoder's frozen test: no count in 50 ms against torque current */
    d->prot.enc.count = d->sense.qep.count;
    d->prot.enc.i_t = d->loop.park.qs;
    encoder_check_frozen(&d->prot.enc);
    drive_safety_stall(d);   /* a frozen trip: locked rotor or dead encoder (drive_safety.c) */
}

/* The current loops' voltage limits from the bus measured now, the one the
 * modulator divides by (not the nominal: a bus 10 % high left the loops
 * clamped at the nominal's 1 pu while the modulator, and the current
 * check's hold at its limit, had 10 % more; the healthy motor at rated
 * load tripped CURRENT_SENSOR): each axis within DRIVE_VMAX_OF_VLIN of
 * vdc / sqrt(3).  A vector beyond vdc / sqrt(3) the modulator clamps onto
 * its hexagon, its angle kept (over-modulation), and the current check
 * holds there (current_check.h).  A bus below 5 % of nominal keeps the last limits
 * (the modulator's vdc_fault; the undervoltage trip).  Scaling: vdc
 * saturated to 8 pu, vmax < 5.1: within the PI's +-16. */
static void voltage_limits(drive_t *d)
{
    const _iq vmax = _IQmpy(_IQsat(d->sense.bus.vdc, _IQ(8.0), _IQ(0.0)), _IQ(DRIVE_VMAX_OF_VLIN /
                                                                        DRIVE_SQRT3));
    if (vmax >= _IQ(0.05 * DRIVE_VMAX_OF_VLIN)) {
        (void)pi_set_limits(&d->loop.pi_id, -vmax, vmax);
        (void)pi_set_limits(&d->loop.pi_iq, -vmax, vmax);
    }
}

static void task_speed(drive_t *d)
{
    drive_safety_symmetrical(d, 0u);   /* the model check's positive sequence (drive_safety.h) */
    /* the encoder's speeds right before the speed loop uses them (every
     * sample of delay in its feedback costs phase at a reversal) */
    qep_speed_update(&d->sense.qep);
    speed_loop(d);
    /* the fast path's slow constants: the slip gain 1/(Tr i_mr) (one
     * division; i_mr moves with Tr >= 10 Ts) and the bus the SVPWM divides
     * by (its 1/vdc is recomputed only when this changes: once here) */
    if (d->frame.is_ifo != 0u) {
        ifo_update_slip_gain(&d->frame.ifo);
    }
    svgen_set_vdc(&d->pwm.svgen, d->sense.bus.vdc);   /* and 1/vdc, here, not in the control ISR */
    voltage_limits(d);
}

static void task_sequence(drive_t *d)
{
    sequence(d);
    drive_safety_state(d);   /* the sensor test disarmed on leaving CALIBRATE */
    drive_adapt_slow(d);
    telemetry(d);
}

/* The window mean of a sum of DRIVE_SLOTS samples, rounded half up: the
 * truncating product by the exact 1/DRIVE_SLOTS (Q30) is floor(), the half
 * LSB added first makes it round (|sum| < 64 pu: no wrap).  FLOAT: exact. */
static inline _iq window_mean(_iq sum)
{
#if MATH_TYPE == IQ_MATH
    return _IQmpyIQX(sum + ((int32_t)1 << (DRIVE_SLOTS_LOG2 - 1u)), GLOBAL_Q,
                     (int32_t)1 << (30u - DRIVE_SLOTS_LOG2), 30);   /* Q24 * Q30 (1/8) -> Q24 */
#else
    return sum * (1.0f / (float)DRIVE_SLOTS);
#endif
}

/* The rotor-flux observer's step on the window's means (flux_obs.h): the
 * mean voltage of its DRIVE_SLOTS periods, the trapezoidal mean current of
 * its DRIVE_SLOTS + 1 samples (sum of the window's samples less half the
 * change from the window's start sample to this one), this sample's
 * current and encoder angle; then the frame's angle from here on
 * (drive_step.c: theta advances by ws_f every period until the next step). */
static void task_observer_a(drive_t *d)
{
    flux_obs_t *o = &d->frame.fobs;
    const _iq ia = d->sense.clarke.alpha;
    const _iq ib = d->sense.clarke.beta;

    o->u_alpha = window_mean(d->frame.su_alpha);
    o->u_beta = window_mean(d->frame.su_beta);
    /* |sum| <= 9.6, |i - i0| <= 2.4 pu */
    o->i_mean_alpha = window_mean(d->frame.si_alpha - _IQmpy(ia - d->frame.i0_alpha, _IQ(0.5)));
    o->i_mean_beta = window_mean(d->frame.si_beta - _IQmpy(ib - d->frame.i0_beta, _IQ(0.5)));
    o->i_alpha = ia;
    o->i_beta = ib;
    o->theta_r = d->sense.qep.theta_elec;
    d->frame.su_alpha = d->frame.su_beta = _IQ(0.0);
    d->frame.si_alpha = d->frame.si_beta = _IQ(0.0);
    d->frame.i0_alpha = ia;
    d->frame.i0_beta = ib;
    flux_obs_step_a(o);
}

/* The observer's rotor flux, angle and speed from its models' state
 * (flux_obs_step_b); then the frame's angle from here on (drive_step.c:
 * theta advances by ws_f every period until the next step). */
static void task_observer_b(drive_t *d)
{
    const flux_obs_t *o = &d->frame.fobs;
    flux_obs_step_b(&d->frame.fobs);
    /* the frame stays on the encoder angle (as ifo at standstill, slip 0)
     * while the flux is near zero (its angle is noise) and through the
     * magnetisation: a flux rise is a transient the voltage model
     * integrates with its Rs error, which the correction removes only over
     * ~1/w_c (believed Rs +30 %: the observer flux reversed 7 ms into the
     * magnetisation).  The current builds the flux along the encoder angle,
     * so the observer's angle agrees with it when the acceleration starts.
     * The standstill sequence's INJECT holds it too: its current stays on
     * the axis the flux was built on (no torque by construction). */
    d->frame.fobs_hold = (uint16_t)(o->psi_mag < d->k.psi_min || d->seq.state == ID_MAGNETIZE ||
                                    d->seq.state == ID_INJECT);
    /* theta was the flux angle at the sample of part a, one period ago: this
     * sample's is one step further; the fast path adds the step from the
     * next one on (f_base Ts revolutions per pu speed: Q24 * Q30 -> Q24) */
    d->frame.obs_dtheta = _IQmpyIQX(o->ws_f, GLOBAL_Q, d->frame.ifo.k_theta, 30);
    d->frame.obs_theta = angle_wrap_unit(o->theta + d->frame.obs_dtheta);
}

/* The regression's window means and its first four filters (method §5). */
static void task_filters_a(drive_t *d)
{
    /* the regression's rotor speed over exactly the window the other six
     * signals were summed over (the mean of its one-period speeds) */
    d->id.reg.wr = qep_mean_speed(&d->sense.qep, &d->id.reg_count);
    /* the period-mean form's flux and ripple term (ident_regressor.h): ifo's
     * i_mr (one period ahead of the window's end: kf of a 0.25 % difference)
     * and the RLS's latest K2 (a 32-bit word the background writes whole) */
    d->id.reg.imr = d->frame.ifo.imr;
    d->id.reg.k2_hat = d->id.rls.theta[1];
    ident_regressor_filter_a(&d->id.reg);
}

/* Queue this slow period's rows for the background's RLS (drive_rls_bg.c)
 * with the events waiting for it; nothing when there is neither.  A full
 * queue drops the sample (counted) and keeps the events for the next. */
static void rls_push(drive_t *d, uint16_t update)
{
    drive_rls_queue_t *q = &d->id.rlsq;
    const ident_regressor_t *r = &d->id.reg;
    const uint16_t flags = (uint16_t)(q->pending | ((update != 0u) ? DRIVE_RLSQ_UPDATE : 0u));
    const uint16_t head = q->head;
    const uint16_t fill = (uint16_t)((head - q->tail) & (DRIVE_RLSQ_LEN - 1u));
    drive_rls_sample_t *e;

    if (flags == 0u) {
        return;
    }
    if (fill >= DRIVE_RLSQ_LEN - 1u) {
        if (q->dropped < 0xFFFFu) {
            q->dropped++;
        }
        return;
    }
    e = &q->e[head];
    e->y1 = r->y1;
    e->y2 = r->y2;
    e->i_mf = r->i_mf;
    e->u_mf = r->u_mf;
    e->i_tf = r->i_tf;
    e->u_tf = r->u_tf;
    e->wr_f = r->wr_f;
    e->c1 = r->m_mf;     /* the period-mean form's columns (0 otherwise) */
    e->d1 = r->wm_tf;
    e->c2 = r->m_tf;
    e->flags = flags;
    q->pending = 0u;
    q->head = (uint16_t)((head + 1u) & (DRIVE_RLSQ_LEN - 1u));   /* the entry first, then head */
    if (fill + 1u > q->max_fill) {
        q->max_fill = (uint16_t)(fill + 1u);
    }
}

/* The last two filters, the rows and whether the RLS may learn (method
 * §2-§5); the rows go to the background's RLS. */
static void task_filters_c(drive_t *d)
{
    uint16_t rls_on = d->seq.rls_on;

    ident_regressor_filter_c(&d->id.reg);
    if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
        /* not while the frame is held on the encoder angle, nor below ~10
         * w_c, where the current model (the believed Tr) steers the angle:
         * learn only where it does not (flux_obs.h); the observer's frame
         * above its crossover, or RUN on ifo, learns */
        if (d->frame.fobs_hold != 0u ||
            (d->frame.is_ifo == 0u && _IQabs(d->frame.fobs.ws_f) < d->k.rls_ws_min)) {
            rls_on = 0u;
        }
    }
    rls_push(d, rls_on);
    task_checks(d);
}

void drive_slow_task(drive_t *d, uint16_t slot)
{
    switch (slot) {
    case DRIVE_SLOT_SPEED:
        task_speed(d);
        break;
    case DRIVE_SLOT_FILTERS_A:
        task_filters_a(d);
        break;
    case DRIVE_SLOT_FILTERS_B:
        ident_regressor_filter_b(&d->id.reg);
        drive_safety_symmetrical(d, 1u);   /* the model check's other sequence tests */
        break;
    case DRIVE_SLOT_FILTERS_C:
        task_filters_c(d);
        break;
    case DRIVE_SLOT_SEQUENCE:
        task_sequence(d);
        break;
    case DRIVE_SLOT_OBSERVER_A:
        if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
            task_observer_a(d);
        }
        break;
    case DRIVE_SLOT_OBSERVER_B:
        if (d->k.orientation == DRIVE_ORIENT_FLUX_OBS) {
            task_observer_b(d);
            drive_adapt_track(d);
        }
        break;
    case DRIVE_SLOT_SAFETY:
        drive_safety_slow(d);   /* currents against the model, locked rotor (drive_safety.c) */
        break;
    default:
        break;
    }
    /* fault and state reach telemetry in the ISR that latched them */
    d->telemetry.state = (uint16_t)d->seq.state;
    d->telemetry.fault = (uint16_t)d->prot.trip.fault;
}

uint16_t drive_log_due(const drive_t *d)
{
    return (uint16_t)(d->sched.slow_slot == DRIVE_LOG_SLOT);
}
