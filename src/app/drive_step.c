/**
 * The 15 kHz control ISR, in the order the F2812 runs it, and the slow ISR
 * that follows it, as a multi-rate schedule: every control ISR runs the
 * fast path, then requests the slow ISR (drive_slow_isr, the F2812's INT14
 * at a lower priority), which runs exactly one slow task in turn (slot =
 * period count modulo DRIVE_SLOTS, drive_slow.c).  The control ISR is the
 * same every period and never waits for a slow task: the current loop's
 * deadline is set by it alone; the slow ISR may be preempted by the next
 * control ISR and must end before that one ends (else an overrun, counted
 * and latched as the control ISR's own).  Each period carries one slow
 * task, an equal share: the worst period is the fast path plus the largest
 * slot (tools/bench_isr.py reports both ISRs and the period).
 *
 *   sample k (T1 underflow): ADC has sampled i_a, i_b, v_dc; T2CNT read
 *   fast path, every period (66.7 us):
 *   1. sensing        current scaling, bus, QEP angle and speed
 *   2. protections    trip -> PWM off in this same ISR
 *   3. voltage model  the voltage applied in period k-1 (duties of sample k-2)
 *   4. Clarke, Park   at the frame angle theta_k
 *   5. regression in  the period's voltage rotated into M-T at its middle,
 *                     the products w_s i, summed over the slow period
 *                     (ident_regressor_accumulate: the anti-alias mean)
 *   6. slow request   the slot whose slow task the slow ISR runs next
 *                     (drive_slow.c lists them: speed loop, the regression's
 *                     filters over three slots and the rows queued for the
 *                     background's RLS, the sequence and adaptation, the
 *                     observer over two, the model-based protections); what
 *                     it hands over (the speed loop's step, the observer's
 *                     angle and speed, the sequence's state) acts from the
 *                     next control ISR on, one period later than when it
 *                     ran inside this ISR: nothing of it is faster than
 *                     the slow period itself.  A fault it latches switches
 *                     the bridge off in the slow ISR, in the same period.
 *   7. current loops  d/q PIs with decoupling, current plausibility check
 *   8. orientation    (with 7, under its test of the frame) i_mr and the
 *                     slip angle (indirect; the frame angle of
 *                     the next sample is the encoder angle plus the slip)
 *   9. modulation     inverse Park at the middle of period k+1, dead-time
 *                     feed-forward, SVPWM
 *
 * Why each block runs where it does:
 *   - every period: what the current loop closes over (sensing, the frame
 *     angle, the PIs, the modulation: their bandwidth is hundreds of Hz at
 *     a 15 kHz sample rate, and every sample of delay costs phase), the
 *     protections (a trip must act in the ISR that sees it), and the
 *     voltage reconstruction and the per-sample regression inputs (the
 *     voltage of a period exists only in that period: it is rotated at its
 *     own mid-period angle and summed, never sampled).
 *   - at f_pwm / DRIVE_SLOTS (1.875 kHz), in the slow ISR: the speed loop (bandwidth a few
 *     Hz), the sequence (times of 0.1-1 s), the regression filters (10 Hz
 *     band: the 8-sample mean before them is the anti-alias stage, its
 *     nulls at the multiples of 1.875 kHz that would fold onto that band),
 *     the observer (its crossover 3 Hz), the checks with ms time constants.
 *   - in the background, on the ISR's queue of filtered rows: the RLS and
 *     its guard (drive_rls_bg.c: every sample once and in order; consecutive
 *     15 kHz samples of a 10 Hz signal add no information).
 *
 * Orientation (drive_control_t.orientation, fixed at drive_init):
 *   0 IFO       as above (the paper's; steps 4 and 8 run the ifo module).
 *   1 observer  step 4 sums the Clarke currents and the voltage of the
 *               period that just ended (the one the regression uses) over
 *               the slow period; the OBSERVER slot steps the rotor-flux
 *               observer (flux_obs.h) on the window's means and the encoder
 *               angle, and between its steps the frame angle advances every
 *               period by ws_f (the observer's flux speed: 0.53 ms of
 *               extrapolation, a few thousandths of a radian at a steady
 *               slip); step 5 uses the frame's actual angle step as w_s, and
 *               the RLS updates only while |w_s| > 10 w_c (drive_init.c:
 *               where the voltage model dominates and the angle does not
 *               depend on Tr); until the magnetisation ends the frame is
 *               held on the encoder angle (fobs_hold); step 7 decouples with
 *               ws_f and (Lm/Lr)|psi_r|; step 8 is empty; the observer is
 *               reset when the magnetisation starts.
 *               In RUN with tracking (run_ifo) the control frame is ifo's,
 *               on the tracked Tr (steps 4 and 8 as mode 0), while the
 *               observer runs on as the tracker's reference.
 *               In mode 0 the observer does not run (no cost).
 *
 * No float, no division but the documented _IQdiv calls inside the modules.
 */
#include "drive_internal.h"

#include "angle.h"
#include "drive_adapt.h"
#include "drive_safety.h"

static inline void set_outputs_off(drive_t *d, hal_pwm_compare_t *out)
{
    out->cmpr[0] = out->cmpr[1] = out->cmpr[2] = d->k.t1pr;   /* upper switches off */
}

_iq drive_frame_angle(const drive_t *d)
{
    return d->frame.theta;
}

static inline void sense(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count)
{
    d->sense.phase.ia_raw = adc->ia_raw;
    d->sense.phase.ib_raw = adc->ib_raw;
    phase_current_step(&d->sense.phase);
    d->sense.bus.vdc_raw = adc->vdc_raw;
    dc_bus_measure(&d->sense.bus);   /* this period's bus: the drive needs no filtered one */
    d->sense.qep.count = qep_count;
    qep_angle_step(&d->sense.qep);   /* the speeds: FILTERS slot (drive_slow.c) */
}

static inline void protect(drive_t *d)
{
    d->prot.trip.ia = d->sense.phase.ia;
    d->prot.trip.ib = d->sense.phase.ib;
    d->prot.trip.ic = d->sense.phase.ic;
    d->prot.trip.vdc = d->sense.bus.vdc;
    d->prot.trip.pwm_on = d->pwm.on_next;
    d->prot.trip.adc_rail = (uint16_t)((d->sense.phase.rail | d->sense.bus.rail) != 0u);   /* one test, no branch */
    /* encoder plausibility: the jump test on this sample's count step (the
     * frozen test, 50 ms, in the FILTERS_C slot) */
    d->prot.enc.active = d->pwm.on_next;
    encoder_check_jump(&d->prot.enc, d->sense.qep.d1);
    d->prot.trip.encoder_fault = d->prot.enc.fault;
    protect_step(&d->prot.trip);
}

/* Calibrate the current offsets while the bridge is off (sequence CALIBRATE). */
static inline void calibrate(drive_t *d)
{
    phase_current_cal_t r;
    if (d->sense.phase.cal_left == 0u && d->sense.cal_done == 0u) {
        (void)phase_current_cal_start(&d->sense.phase, d->k.cal_samples);
    }
    r = phase_current_cal_step(&d->sense.phase);
    if (r == PHASE_CURRENT_CAL_DONE) {
        d->sense.cal_done = 1u;
    } else if (r == PHASE_CURRENT_CAL_REJECTED) {
        d->sense.cal_done = 1u;
        protect_latch(&d->prot.trip, FAULT_CURRENT_OFFSET);
    } else {
        /* busy */
    }
}

/* Voltage applied in the period that just ended: its duties (of sample
 * k-2) are in d->pwm.volt already, put there by the PWM pipeline at the end of
 * the last ISR. */
static inline void voltage_model(drive_t *d)
{
    const _iq ia = d->sense.phase.ia;
    const _iq ib = d->sense.phase.ib;
    d->pwm.volt.vdc = d->sense.bus.vdc;
    /* the current in the middle of that period decides the dead-time sign:
     * the mean of its two end samples (Q24 + Q24 in range: |i| <= 32 pu;
     * the halving is the floor, as _IQmpy by 0.5) */
    d->pwm.volt.ia = _IQdiv2(ia + d->pwm.ia_prev);
    d->pwm.volt.ib = _IQdiv2(ib + d->pwm.ib_prev);
    /* and its change over the period places the current at each switching
     * edge (volt_calc.h); Q24 - Q24, |.| <= 2 pu */
    d->pwm.volt.dia = ia - d->pwm.ia_prev;
    d->pwm.volt.dib = ib - d->pwm.ib_prev;
    d->pwm.ia_prev = ia;
    d->pwm.ib_prev = ib;
    if (d->pwm.on_last != 0u) {
        volt_calc_step(&d->pwm.volt);
    } else {
        /* the bridge was off in that period: no voltage applied */
        d->pwm.volt.valpha = _IQ(0.0);
        d->pwm.volt.vbeta = _IQ(0.0);
    }
}

/* frame angle theta_k = encoder angle + integrated slip (ifo.h), and the
 * frame's speed over the period */
static inline void frame_from_ifo(drive_t *d)
{
    ifo_frame_from_rotor(&d->frame.ifo);
    d->frame.theta = d->frame.ifo.theta;
    d->frame.ws = d->frame.ifo.ws_frame;
}

static inline void transform_currents(drive_t *d)
{
    /* Clarke: alpha is i_a itself; kept in d->sense.clarke for the slow tasks */
    const _iq alpha = d->sense.phase.ia;
    const _iq beta = clarke_beta(alpha, d->sense.phase.ib);
    d->sense.clarke.alpha = alpha;
    d->sense.clarke.beta = beta;
    d->frame.ifo.theta_r = d->sense.qep.theta_elec;
    if (d->k.orientation != DRIVE_ORIENT_FLUX_OBS) {
        /* mode 0: the frame is always ifo's (drive_ifo_frame), one test */
        frame_from_ifo(d);
    } else {
        /* the observer's window (its step: drive_slow.c, OBSERVER slot):
         * the voltage of the period that just ended (0 while the bridge was
         * off; limited to the observer's input range, so that 8 of them
         * stay inside Q24) and this sample's current */
        d->frame.su_alpha += _IQsat(d->pwm.volt.valpha, _IQ(FLUX_OBS_IN_MAX), _IQ(-FLUX_OBS_IN_MAX));
        d->frame.su_beta += _IQsat(d->pwm.volt.vbeta, _IQ(FLUX_OBS_IN_MAX), _IQ(-FLUX_OBS_IN_MAX));
        d->frame.si_alpha += alpha;
        d->frame.si_beta += beta;
        if (d->frame.is_ifo != 0u) {
            frame_from_ifo(d);   /* RUN with tracking */
        } else {
            /* the observer's angle, carried between its steps on ws_f (it
             * ran at the last OBSERVER slot); or, held (magnetisation, no
             * flux), the encoder angle: the frame turns with the rotor */
            const _iq theta_prev = d->frame.theta;
            d->frame.obs_theta = angle_wrap_unit(d->frame.obs_theta + d->frame.obs_dtheta);
            d->frame.theta = (d->frame.fobs_hold != 0u) ? d->sense.qep.theta_elec : d->frame.obs_theta;
            /* the frame's actual speed over the period (the regression's
             * w_s): the angle step, whatever moved it; Q24 * Q20 -> Q24,
             * |step| < 0.5 */
            d->frame.ws = _IQmpyIQX(angle_diff_pu(d->frame.theta, theta_prev), GLOBAL_Q,
                                d->frame.ifo.inv_k_theta, 20);
        }
    }
    /* every frame angle is in [0, 1) (ifo wraps it, the observer's atan2 and
     * the encoder's count are there by construction): no wrap */
    d->loop.park.sine = _IQsinPU(d->frame.theta);
    d->loop.park.cosine = _IQcosPU(d->frame.theta);
    park_rotate(&d->loop.park, alpha, beta);
}

/* The regression's inputs of this period (method §2, §7 points 1-2), into
 * the window sums the FILTERS slot averages: the voltage of the period
 * that just ended in the frame of theta_k (the Park's sin/cos; the filter
 * step turns the window back to the periods' middle, ident_regressor.h),
 * the frame's actual speed over that period. */
static inline void identify_accumulate(drive_t *d)
{
    ident_regressor_t *r = &d->id.reg;

    r->i_m = d->loop.park.ds;
    r->i_t = d->loop.park.qs;
    r->u_alpha = d->pwm.volt.valpha;
    r->u_beta = d->pwm.volt.vbeta;
    r->sin_k = d->loop.park.sine;
    r->cos_k = d->loop.park.cosine;
    r->ws = d->frame.ws;
    ident_regressor_accumulate(r);
}

/* The current loops' references: also while the sensor test holds the
 * loops (the current check compares the currents with them, drive_slow.c). */
static inline void control_refs(drive_t *d)
{
    d->loop.pi_id.ref = d->seq.im_cmd + d->loop.im_inject;
    d->loop.i_t_ref += d->loop.i_t_step;   /* the speed loop's output, held first-order (drive_slow.c) */
    d->loop.pi_iq.ref = d->loop.i_t_ref;
}

/* IFO's fast step: i_mr, slip (gain from the SPEED slot), slip angle for
 * theta_{k+1}; the rotor speed with an 8-sample lag instead of ~31:
 * orientation during acceleration.  Only with the IFO frame (the
 * observer ran at the Park transform). */
static inline void orient_ifo(drive_t *d)
{
    ifo_slip_fast(&d->frame.ifo, d->loop.park.ds, d->loop.park.qs, d->sense.qep.speed_raw);
}

static inline void orient(drive_t *d)
{
    if (d->frame.is_ifo != 0u) {
        orient_ifo(d);
    }
}

/* The current loops, and the orientation's fast step under the same test
 * of the frame (one per ISR): the PIs read nothing ifo_slip_fast writes
 * (their frame speed is ws_ctl, taken before), and the decoupling reads
 * i_mr before it moves, as when the orientation ran after them. */
static inline void control(drive_t *d)
{
    /* decoupling feed-forward (rotor-flux frame steady-state voltages):
     * u_d = -w_s sigma Ls i_T, u_q = w_s (sigma Ls i_M + (Lm/Lr) psi_r);
     * IFO: (Lm/Lr) psi_r = (Lm^2/Lr) i_mr; observer: (Lm/Lr) |psi_r|
     * (Q24 * Q24 -> Q24, both < 1 pu) */
    const _iq ws = d->frame.ws_ctl;
    _iq emf_flux;
    if (d->frame.is_ifo != 0u) {
        emf_flux = _IQmpy(d->k.lm2_lr, d->frame.ifo.imr);
        orient_ifo(d);
    } else {
        emf_flux = _IQmpy(d->frame.fobs.lm_lr, d->frame.fobs.psi_mag);
    }
    control_refs(d);
    pi_step_in(&d->loop.pi_id, d->loop.park.ds, -_IQmpy(ws, _IQmpy(d->k.sigma_ls, d->loop.park.qs)));
    pi_step_in(&d->loop.pi_iq, d->loop.park.qs, _IQmpy(ws, _IQmpy(d->k.sigma_ls, d->loop.park.ds) + emf_flux));
}

static inline void modulate(drive_t *d, hal_pwm_compare_t *out)
{
    /* the voltage computed now is applied over period k+1; rotate it at the
     * middle of that period: theta_k + 1.5 w_s Ts */
    const _iq step = _IQmpy(d->frame.ws_ctl, d->k.three_half_step);
    _iq sine, cosine, u_alpha, u_beta;
    /* from the Park's sin/cos of theta_k by the small step (angle.h) */
    angle_sincos_step(d->loop.park.sine, d->loop.park.cosine, d->frame.theta, step, &sine, &cosine);
    /* the current loops' outputs straight into the modulator's frame */
    ipark_rotate(d->loop.pi_id.out, d->loop.pi_iq.out, sine, cosine, &u_alpha, &u_beta);
    {
        /* dead-time feed-forward for period k+1: the phase currents in its
         * middle, extrapolated 1.5 periods on the change over the last one
         * (voltage_model's volt.dia/dib; Q24, |.| <= 4 pu): i + 1.5 di as
         * i + di + floor(di/2), which is _IQmpy(di, 1.5) bit for bit */
        _iq ff_a, ff_b;
        const _iq dia = d->pwm.volt.dia;
        const _iq dib = d->pwm.volt.dib;
        const _iq ia = d->sense.phase.ia + dia + _IQdiv2(dia);
        const _iq ib = d->sense.phase.ib + dib + _IQdiv2(dib);
        volt_calc_feedforward(&d->pwm.volt, d->sense.bus.vdc, ia, ib, &ff_a, &ff_b);
        d->pwm.svgen.ualpha = u_alpha + ff_a;
        d->pwm.svgen.ubeta = u_beta + ff_b;
    }
    /* the bus for the duties changes at the slow rate (drive_slow.c), so
     * that svgen divides once per slow period */
    svgen_step(&d->pwm.svgen);
    /* the voltage clamped onto the hexagon: the current-feedback check
     * holds until its next step (current_check.h) */
    d->prot.feedback.limited |= d->pwm.svgen.overmod;
    out->cmpr[0] = d->pwm.svgen.cmpr[0];
    out->cmpr[1] = d->pwm.svgen.cmpr[1];
    out->cmpr[2] = d->pwm.svgen.cmpr[2];
}

/* The body of drive_step, inline in drive_isr (no call per period). */
static inline void isr_body(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count,
                        hal_pwm_compare_t *out)
{
    uint16_t pwm_on;
    const uint16_t slot = d->sched.slot;

    if (d->k.config_status != DRIVE_CFG_OK) {
        set_outputs_off(d, out);
        d->telemetry.pwm_on = 0u;
        return;
    }
    d->sched.slot = (uint16_t)((slot + 1u) & (DRIVE_SLOTS - 1u));

    sense(d, adc, qep_count);
    protect(d);
    if (d->seq.calibrating != 0u) {
        calibrate(d);
    }
    voltage_model(d);
    drive_safety_fast(d);   /* the model check's window (drive_safety.h) */
    transform_currents(d);
    identify_accumulate(d);
    drive_adapt_fast(d);
    /* the slow task of this slot runs after this ISR, in the slow ISR
     * (drive_slow_isr): what it hands over (the speed loop's step, the
     * observer's angle and speed, the sequence's state, a check's fault)
     * acts from the next fast ISR on */
    d->sched.slow_late = (uint16_t)(d->sched.slow_due | d->sched.slow_busy);
    d->sched.slow_slot = slot;
    d->sched.slow_due = 1u;
    /* the frame speed for decoupling and the modulation angle (mode 1: the
     * observer's, from its last step) */
    d->frame.ws_ctl = drive_frame_speed(d);

    pwm_on = (uint16_t)((uint16_t)(d->seq.pwm_on != 0u) & (uint16_t)(d->prot.trip.fault == FAULT_NONE));
    if (pwm_on != 0u && (d->seq.sensor_testing | d->seq.vi_testing) == 0u) {
        control(d);   /* and the orientation's fast step */
        modulate(d, out);
    } else if (pwm_on != 0u) {
        /* the sensor test's pulses or the bridge's voltage-error test
         * (CALIBRATE): the test's voltage replaces the current loops' and
         * their modulation (drive_safety_modulate holds the PIs at zero and
         * runs the SVPWM on it), so neither is computed here: one modulation
         * per ISR, not two */
        control_refs(d);
        orient(d);
    } else {
        pi_reset(&d->loop.pi_id);
        pi_reset(&d->loop.pi_iq);
        set_outputs_off(d, out);
    }

    pwm_on = drive_safety_modulate(d, out, pwm_on);   /* the sensor test (drive_safety.h) */

    /* PWM pipeline (hal_pwm.h): shift the duties one period; the ones that
     * act in the period now starting go straight to the voltage model's
     * inputs (the next ISR reconstructs that period) */
    d->pwm.volt.da = d->pwm.duty_next[0];
    d->pwm.volt.db = d->pwm.duty_next[1];
    d->pwm.volt.dc = d->pwm.duty_next[2];
    d->pwm.on_last = d->pwm.on_next;
    d->pwm.duty_next[0] = d->pwm.svgen.da;
    d->pwm.duty_next[1] = d->pwm.svgen.db;
    d->pwm.duty_next[2] = d->pwm.svgen.dc;
    d->pwm.on_next = pwm_on;
    d->telemetry.pwm_on = pwm_on;
}

/* The slow task the last fast ISR requested (drive_slow.c), once.  A fault
 * it latched turns the bridge off in this same period, as one the fast
 * path finds: the fast ISR has already set the period's outputs, so they
 * are switched off here (returns 1: the caller's outputs go off now). */
static uint16_t slow_run(drive_t *d)
{
    if (d->sched.slow_due == 0u) {
        return 0u;
    }
    d->sched.slow_due = 0u;   /* first: a request made while the task runs is kept */
    d->sched.slow_busy = 1u;
    drive_slow_task(d, d->sched.slow_slot);
    d->sched.slow_busy = 0u;
    if (d->prot.trip.fault != FAULT_NONE && d->pwm.on_next != 0u) {
        d->pwm.on_next = 0u;   /* the voltage model: no voltage in this period */
        d->telemetry.pwm_on = 0u;
        return 1u;
    }
    return 0u;
}

void drive_step(drive_t *d, const hal_adc_sample_t *adc, uint16_t qep_count,
                hal_pwm_compare_t *out)
{
    isr_body(d, adc, qep_count, out);
    if (slow_run(d) != 0u) {
        set_outputs_off(d, out);
    }
}

void drive_slow_isr(drive_t *d)
{
    if (slow_run(d) != 0u) {
        hal_pwm_disable();
    }
}

void drive_set_hw_trip(drive_t *d, uint16_t tripped) { d->prot.trip.hw_trip = tripped; }

uint16_t drive_isr(drive_t *d)
{
    hal_adc_sample_t adc;
    hal_pwm_compare_t cmp;

    hal_adc_read(&adc);
    d->prot.trip.hw_trip = hal_pwm_tripped();
    isr_body(d, &adc, hal_qep_read_count(), &cmp);
    hal_pwm_write(&cmp);
    if (d->telemetry.pwm_on != 0u) {
        hal_pwm_enable();
    } else {
        hal_pwm_disable();
    }
    if (d->sched.slow_due != 0u) {
        hal_slow_isr_request();   /* the slow ISR runs when this one returns */
    }
    /* last: did this ISR run past its period, or find the last slow task
     * unfinished?  Several in a row latch a fault and the bridge goes off
     * now (isr_monitor.h) */
    d->prot.ovr.overrun = (uint16_t)(hal_isr_overrun() | d->sched.slow_late);
    isr_monitor_step(&d->prot.ovr);
    d->telemetry.isr_overruns = d->prot.ovr.count;
    if (d->prot.ovr.fault != 0u) {
        protect_latch(&d->prot.trip, FAULT_ISR_OVERRUN);
        hal_pwm_disable();
    }
    return d->prot.ovr.overrun;
}

void drive_get_log_signals(const drive_t *d, _iq sig[4])
{
    sig[0] = d->telemetry.i_m;
    sig[1] = d->telemetry.i_t;
    sig[2] = d->telemetry.speed;
    sig[3] = d->telemetry.Rr;
}
