/* app_id_sequence: the identification state machine (id_sequence.h) driven
 * by hand, sample by sample, against the sequence the header specifies:
 *   IDLE -> CALIBRATE -> MAGNETIZE -> ACCELERATE -> SETTLE -> RUN      (1 pass)
 *   ... SETTLE -> REFINE -> ACCELERATE (pass + 1) ... -> SETTLE -> RUN  (passes)
 * with the one-sample pulses (magnetize_end, extract_now, rls_restart),
 * the outputs of each state, the exact sample counts of the timed states
 * (times converted as round(t / Ts)), faults, stop and start.
 *
 * Rig: Ts = 1/15000 s; magnetise 10 ms (150 samples), settle at least
 * 2 ms (30), steady for 1 ms (15), at most 20 ms (300), RLS tail 4 ms
 * (60); tolerances 0.01 pu (speed), 0.01 pu (net change of the filtered i_M
 * over the hold window), 0.02 pu (of i_T); i_M ref 0.33 pu, target 0.9333 pu,
 * REFINE at 0.4 of it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "id_sequence.h"

#define TS_S (1.0f / 15000.0f)
#define N_MAG 150u
#define N_SMIN 30u
#define N_HOLD 15u
#define N_SMAX 300u
#define N_TAIL 60u

#if MATH_TYPE == IQ_MATH
static double to_d(_iq x) { return ldexp((double)x, -GLOBAL_Q); }
#define LSB (1.0 / 16777216.0)
#else
static double to_d(_iq x) { return (double)x; }
#define LSB 0.0
#endif

typedef struct {
    uint32_t magnetize_end, extract_now, rls_restart;   /* pulse counts */
} pulses_t;

static void seq_init(id_sequence_t *s)
{
    assert_int_equal(id_sequence_init(s, TS_S, 0.01f, 0.002f, 0.001f, 0.02f, 0.004f, _IQ(0.01),
                                      _IQ(0.01), _IQ(0.02), _IQ(0.33), _IQ(0.9333)),
                     0);
    assert_int_equal(s->magnetize_samples, N_MAG);
    assert_int_equal(s->settle_min_samples, N_SMIN);
    assert_int_equal(s->settle_hold_samples, N_HOLD);
    assert_int_equal(s->settle_max_samples, N_SMAX);
    assert_int_equal(s->rls_tail_samples, N_TAIL);
}

/* One sample; pulses counted; every pulse lasts one sample by construction
 * of the counts (a pulse seen on two consecutive samples fails). */
static void step(id_sequence_t *s, pulses_t *p)
{
    uint16_t me = s->magnetize_end, ex = s->extract_now, rr = s->rls_restart;
    id_sequence_step(s);
    if (s->magnetize_end != 0u) {
        assert_int_equal(me, 0u);
        p->magnetize_end++;
    }
    if (s->extract_now != 0u) {
        assert_int_equal(ex, 0u);
        p->extract_now++;
    }
    if (s->rls_restart != 0u) {
        assert_int_equal(rr, 0u);
        p->rls_restart++;
    }
}

/* Outputs of each state (header): PWM in MAGNETIZE..RUN and REFINE, and
 * in CALIBRATE while the sensor test runs (after the calibration, with the
 * test enabled, until test_done) and then the voltage-error test (with it
 * enabled, until vi_done); the speed loop in ACCELERATE, SETTLE,
 * RUN, REFINE; i_M ref with the PWM but not in the sensor test; speed
 * target (REFINE: refine_speed) with the speed loop. */
static void check_outputs(const id_sequence_t *s)
{
    const id_state_t st = s->state;
    const uint16_t test = (uint16_t)(st == ID_CALIBRATE && s->cal_done != 0u &&
                                     s->sensor_test != 0u && s->test_done == 0u);
    const uint16_t vi = (uint16_t)(st == ID_CALIBRATE && s->cal_done != 0u &&
                                   (s->sensor_test == 0u || s->test_done != 0u) &&
                                   s->vi_test != 0u && s->vi_done == 0u);
    const uint16_t pwm = (uint16_t)(st == ID_MAGNETIZE || st == ID_ACCELERATE ||
                                    st == ID_SETTLE || st == ID_RUN || st == ID_REFINE ||
                                    test != 0u || vi != 0u);
    const uint16_t spd = (uint16_t)(st == ID_ACCELERATE || st == ID_SETTLE || st == ID_RUN ||
                                    st == ID_REFINE);
    assert_int_equal(s->sensor_testing, test);
    assert_int_equal(s->vi_testing, vi);
    assert_int_equal(s->pwm_on, pwm);
    assert_int_equal(s->speed_loop_on, spd);
    assert_int_equal(s->calibrating, (uint16_t)(st == ID_CALIBRATE && s->cal_done == 0u));
    assert_true(s->im_cmd == ((pwm && st != ID_CALIBRATE) ? s->im_ref : _IQ(0.0)));
    if (!spd) {
        assert_true(s->speed_cmd == _IQ(0.0));
    } else if (st == ID_REFINE) {
        assert_true(s->speed_cmd == s->refine_speed);
    } else {
        assert_true(s->speed_cmd == s->speed_target);
    }
    if (st != ID_ACCELERATE && st != ID_SETTLE) {
        assert_int_equal(s->rls_on, 0u);
    }
}

/* steady inputs for SETTLE (or not): the speed error; the filtered
 * currents constant */
static void set_steady(id_sequence_t *s, int steady)
{
    s->speed_err = steady ? _IQ(0.005) : _IQ(0.02);
    s->i_mf = _IQ(0.33);
    s->i_tf = _IQ(0.1);
}

/* From IDLE to the entry of the first ACCELERATE: start, calibration
 * (done after 5 samples), MAGNETIZE for exactly N_MAG samples, the last of
 * which pulses magnetize_end (the step that leaves it). */
static void run_to_accelerate(id_sequence_t *s, pulses_t *p)
{
    uint32_t k;
    id_sequence_start(s);
    step(s, p);
    assert_int_equal(s->state, ID_CALIBRATE);
    assert_int_equal(s->pass, 1u);
    check_outputs(s);
    for (k = 0u; k < 5u; k++) {
        step(s, p);
        assert_int_equal(s->state, ID_CALIBRATE);
    }
    s->cal_done = 1u;
    step(s, p);
    assert_int_equal(s->state, ID_MAGNETIZE);
    /* the entry sample is the first of the N_MAG: N_MAG - 1 more stay */
    for (k = 1u; k < N_MAG; k++) {
        check_outputs(s);
        assert_int_equal(s->magnetize_end, 0u);
        step(s, p);
        assert_int_equal(s->state, ID_MAGNETIZE);
    }
    assert_int_equal(p->magnetize_end, 0u);
    step(s, p);
    assert_int_equal(s->state, ID_ACCELERATE);
    assert_int_equal(s->magnetize_end, 1u);
    assert_int_equal(p->magnetize_end, 1u);
    assert_int_equal(s->rls_restart, 0u);   /* pass 1: no restart pulse */
}

/* ACCELERATE until ramp_done (after @p n samples), then SETTLE: not steady
 * while t_state < @p unsteady, then steady.  Extraction on the sample at
 * which t_state >= settle_min and t_steady >= settle_hold; t_steady counts
 * the steady samples, the first at t_state k0 = max(unsteady, 1) (t_state
 * is 1 on the first sample after the entry), so t_state = max(N_SMIN, k0 +
 * N_HOLD - 1); the RLS runs for t_state <= N_TAIL.  Returns with the
 * extraction sample done (state: REFINE or RUN). */
static void run_pass(id_sequence_t *s, pulses_t *p, uint32_t n, uint32_t unsteady)
{
    uint32_t k, ex = p->extract_now;
    uint32_t k0 = (unsteady > 1u) ? unsteady : 1u;
    uint32_t t_ext = (k0 + N_HOLD - 1u > N_SMIN) ? k0 + N_HOLD - 1u : N_SMIN;
    assert_int_equal(s->state, ID_ACCELERATE);
    s->ramp_done = 0u;
    for (k = 0u; k < n; k++) {
        step(s, p);
        assert_int_equal(s->state, ID_ACCELERATE);
        assert_int_equal(s->rls_on, 1u);
        check_outputs(s);
    }
    s->ramp_done = 1u;
    set_steady(s, 0);
    step(s, p);
    assert_int_equal(s->state, ID_SETTLE);
    assert_int_equal(s->rls_on, 1u);
    for (k = 1u; k < t_ext; k++) {
        set_steady(s, k >= unsteady);
        step(s, p);
        assert_int_equal(s->state, ID_SETTLE);
        assert_int_equal(s->t_state, k);
        assert_int_equal(s->rls_on, (uint16_t)(k <= N_TAIL));
        assert_int_equal(s->extract_now, 0u);
        check_outputs(s);
    }
    set_steady(s, 1);
    step(s, p);
    assert_int_equal(s->extract_now, 1u);
    assert_int_equal(p->extract_now, ex + 1u);
    assert_int_equal(s->settle_timeout, 0u);
    assert_true(s->state == ID_REFINE || s->state == ID_RUN);
    check_outputs(s);
}

/* REFINE: speed_cmd = refine_speed, RLS off; it waits for settle_min,
 * ramp_done and adapt_ready (each missing one holds it), then ACCELERATE
 * with pass + 1 and a one-sample rls_restart. */
static void run_refine(id_sequence_t *s, pulses_t *p)
{
    uint32_t k;
    uint16_t pass = s->pass;
    uint32_t rr = p->rls_restart;
    assert_int_equal(s->state, ID_REFINE);
    assert_true(s->speed_cmd == s->refine_speed);
    /* ramp not done yet (the speed falls to refine_speed), adapt ready */
    s->ramp_done = 0u;
    s->adapt_ready = 1u;
    for (k = 0u; k < 2u * N_SMIN; k++) {
        step(s, p);
        assert_int_equal(s->state, ID_REFINE);
        check_outputs(s);
    }
    /* ramp done, parameters not yet applied */
    s->ramp_done = 1u;
    s->adapt_ready = 0u;
    for (k = 0u; k < 2u * N_SMIN; k++) {
        step(s, p);
        assert_int_equal(s->state, ID_REFINE);
        assert_int_equal(s->pass, pass);
    }
    assert_int_equal(p->rls_restart, rr);
    s->adapt_ready = 1u;
    step(s, p);
    assert_int_equal(s->state, ID_ACCELERATE);
    assert_int_equal(s->pass, pass + 1u);
    assert_int_equal(s->rls_restart, 1u);
    assert_int_equal(p->rls_restart, rr + 1u);
    check_outputs(s);
    s->adapt_ready = 0u;
    s->ramp_done = 0u;   /* the drive's ramp heads for the new target from this sample */
}

/* passes = 3: three extractions, two REFINEs with their restart pulses,
 * RUN after the third; magnetize_end once.  Then stop -> IDLE, and START
 * resets the pass to 1. */
static void test_three_passes(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    assert_int_equal(s.passes, 1u);
    assert_int_equal(id_sequence_set_passes(&s, 3u, _IQ(0.4)), 0);
    assert_int_equal(s.passes, 3u);
    /* refine_speed = 0.4 target (Q24 product, truncated: < 1 LSB + the
     * operands' own < 1 LSB each) */
    assert_true(fabs(to_d(s.refine_speed) - 0.4 * 0.9333) <= 3.0 * LSB + 1e-7);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    check_outputs(&s);

    run_to_accelerate(&s, &p);
    run_pass(&s, &p, 200u, 100u);          /* pass 1: extraction at t_state 114 in SETTLE */
    assert_int_equal(s.state, ID_REFINE);
    assert_int_equal(s.pass, 1u);
    run_refine(&s, &p);
    assert_int_equal(s.pass, 2u);
    /* the restart pulse lasts one sample */
    step(&s, &p);
    assert_int_equal(s.rls_restart, 0u);
    assert_int_equal(s.state, ID_ACCELERATE);
    run_pass(&s, &p, 100u, 0u);            /* pass 2: steady at once: t_state = N_SMIN */
    assert_int_equal(s.state, ID_REFINE);
    /* REFINE with everything ready from its entry: leaves exactly when
     * t_state reaches settle_min */
    s.ramp_done = 1u;
    s.adapt_ready = 1u;
    for (k = 1u; k < N_SMIN; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_REFINE);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_ACCELERATE);
    assert_int_equal(s.pass, 3u);
    assert_int_equal(s.rls_restart, 1u);
    run_pass(&s, &p, 50u, 0u);
    assert_int_equal(s.state, ID_RUN);     /* pass 3 of 3 */
    assert_int_equal(s.pass, 3u);
    for (k = 0u; k < 1000u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_RUN);
        check_outputs(&s);
    }
    assert_int_equal(p.extract_now, 3u);
    assert_int_equal(p.rls_restart, 2u);
    assert_int_equal(p.magnetize_end, 1u);

    /* stop, start: pass back to 1 */
    id_sequence_stop(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    check_outputs(&s);
    assert_int_equal(s.pass, 3u);          /* the last done, until a new start */
    s.cal_done = 0u;
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    assert_int_equal(s.pass, 1u);
}

/* passes = 1 (the init's default): the paper's sequence, SETTLE -> RUN,
 * no REFINE, no restart pulse, pass stays 1; also with set_passes(1). */
static void test_one_pass(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k, c;
    (void)state;

    for (c = 0u; c < 2u; c++) {
        memset(&p, 0, sizeof p);
        seq_init(&s);
        if (c == 1u) {
            assert_int_equal(id_sequence_set_passes(&s, 1u, _IQ(0.4)), 0);
        }
        run_to_accelerate(&s, &p);
        run_pass(&s, &p, 200u, 100u);
        assert_int_equal(s.state, ID_RUN);
        assert_int_equal(s.pass, 1u);
        for (k = 0u; k < 500u; k++) {
            s.adapt_ready = (uint16_t)(k & 1u);
            step(&s, &p);
            assert_int_equal(s.state, ID_RUN);
        }
        assert_int_equal(p.extract_now, 1u);
        assert_int_equal(p.rls_restart, 0u);
        assert_int_equal(p.magnetize_end, 1u);
    }
}

/* SETTLE never steady: extraction at settle_max, flagged settle_timeout. */
static void test_settle_timeout(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    run_to_accelerate(&s, &p);
    s.ramp_done = 1u;
    set_steady(&s, 0);
    step(&s, &p);
    assert_int_equal(s.state, ID_SETTLE);
    for (k = 1u; k < N_SMAX; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_SETTLE);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_RUN);
    assert_int_equal(s.extract_now, 1u);
    assert_int_equal(s.settle_timeout, 1u);
    assert_int_equal(s.torque_limited, 0u);   /* the speed loop was not at its limit */
}

/* The same with the speed loop at its torque limit when the time runs out
 * (a load the torque current cannot carry at the target): flagged
 * torque_limited, the verdict's torque_limit; a loop that was at its limit
 * earlier in SETTLE but not at the end is a plain timeout. */
static void test_settle_timeout_torque_limited(void **state)
{
    uint16_t at_end;
    (void)state;
    for (at_end = 0u; at_end <= 1u; at_end++) {
        id_sequence_t s;
        pulses_t p = {0u, 0u, 0u};
        uint32_t k;
        seq_init(&s);
        run_to_accelerate(&s, &p);
        s.ramp_done = 1u;
        set_steady(&s, 0);
        s.torque_limit = 1u;
        step(&s, &p);
        for (k = 1u; k < N_SMAX; k++) {
            step(&s, &p);
        }
        s.torque_limit = at_end;
        step(&s, &p);
        assert_int_equal(s.state, ID_RUN);
        assert_int_equal(s.settle_timeout, 1u);
        assert_int_equal(s.torque_limited, at_end);
    }
}

/* Steady state is the net change of the filtered currents over the hold
 * window, not their instantaneous derivative: a ripple that swings i_M by
 * 0.9 tolerance from one sample to the next (a derivative of 0.009 pu per
 * sample, 135 pu/s: any derivative threshold would refuse it) confirms on
 * the same sample as constant currents, max(N_SMIN, N_HOLD) = N_SMIN. */
static void test_settle_ripple_confirms(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    run_to_accelerate(&s, &p);
    s.ramp_done = 1u;
    set_steady(&s, 1);
    step(&s, &p);
    assert_int_equal(s.state, ID_SETTLE);   /* entered: t_state 1 at the next sample */
    for (k = 1u; k <= N_SMIN; k++) {
        s.i_mf = _IQ(0.33) + ((k & 1u) ? _IQ(0.009) : _IQ(0.0));
        s.i_tf = _IQ(0.1) + ((k & 1u) ? -_IQ(0.018) : _IQ(0.0));
        step(&s, &p);
        if (k < N_SMIN) {
            assert_int_equal(s.state, ID_SETTLE);
            assert_int_equal(s.extract_now, 0u);
        }
    }
    assert_int_equal(s.extract_now, 1u);
    assert_int_equal(s.settle_timeout, 0u);
    assert_int_equal(s.state, ID_RUN);
}

/* A drift of the filtered i_M (i_T) beyond its tolerance over each hold
 * window keeps SETTLE waiting, whatever the speed; once it stops, the
 * window opened next confirms N_HOLD samples later.  The ramp: 1.5
 * tolerance per window (0.1 tolerance per sample over 15). */
static void settle_drift(int which)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k, stop = 3u * N_SMIN;
    _iq tol;

    seq_init(&s);
    tol = (which == 0) ? s.im_tol : s.it_tol;
    run_to_accelerate(&s, &p);
    s.ramp_done = 1u;
    set_steady(&s, 1);
    step(&s, &p);
    assert_int_equal(s.state, ID_SETTLE);
    for (k = 1u; k < stop; k++) {
        _iq d = _IQmpyI32(_IQmpy(tol, _IQ(0.1)), (int32_t)k);
        if (which == 0) {
            s.i_mf = _IQ(0.33) + d;
        } else {
            s.i_tf = _IQ(0.1) + d;
        }
        step(&s, &p);
        assert_int_equal(s.state, ID_SETTLE);
        assert_int_equal(s.extract_now, 0u);
    }
    /* held from here: a window that closed at a multiple of N_HOLD opens at
     * the next sample; the one open at `stop` still carries the ramp */
    for (k = stop; k < stop + 2u * N_HOLD + 1u && s.extract_now == 0u; k++) {
        step(&s, &p);
    }
    assert_int_equal(s.extract_now, 1u);
    assert_int_equal(s.settle_timeout, 0u);
    /* the first window entirely after the stop confirms: within 2 N_HOLD */
    assert_true(k > stop + N_HOLD - 1u);
}

static void test_settle_im_drift_waits(void **state)
{
    (void)state;
    settle_drift(0);
}

static void test_settle_it_drift_waits(void **state)
{
    (void)state;
    settle_drift(1);
}

/* A tolerance that is not positive is refused (it would never hold). */
static void test_settle_tolerance_positive(void **state)
{
    id_sequence_t s;
    (void)state;
    assert_int_equal(id_sequence_init(&s, TS_S, 0.01f, 0.002f, 0.001f, 0.02f, 0.004f, _IQ(0.01),
                                      _IQ(0.0), _IQ(0.02), _IQ(0.33), _IQ(0.9333)), 1);
    assert_int_equal(id_sequence_init(&s, TS_S, 0.01f, 0.002f, 0.001f, 0.02f, 0.004f, _IQ(0.01),
                                      _IQ(0.01), -_IQ(0.02), _IQ(0.33), _IQ(0.9333)), 1);
}

/* A fault in REFINE (that of pass 2 of 3): FAULT at once (PWM off, no
 * restart pulse), it stays there when the fault goes and a start comes
 * (not without clear); cleared -> IDLE; a start then begins at pass 1. */
static void test_fault_in_refine(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    assert_int_equal(id_sequence_set_passes(&s, 3u, _IQ(0.5)), 0);
    run_to_accelerate(&s, &p);
    run_pass(&s, &p, 100u, 0u);
    run_refine(&s, &p);
    run_pass(&s, &p, 100u, 0u);
    assert_int_equal(s.state, ID_REFINE);
    assert_int_equal(s.pass, 2u);
    s.ramp_done = 1u;
    s.adapt_ready = 1u;
    for (k = 0u; k < N_SMIN / 2u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_REFINE);
    }
    s.fault = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_FAULT);
    assert_int_equal(s.rls_restart, 0u);
    check_outputs(&s);
    for (k = 0u; k < 100u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_FAULT);
    }
    s.fault = 0u;
    for (k = 0u; k < 100u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_FAULT);
    }
    id_sequence_start(&s);                 /* ignored in FAULT */
    step(&s, &p);
    assert_int_equal(s.state, ID_FAULT);
    id_sequence_clear_fault(&s);
    assert_int_equal(s.state, ID_IDLE);
    s.cal_done = 0u;
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    assert_int_equal(s.pass, 1u);
    assert_int_equal(p.rls_restart, 1u);   /* only pass 1 -> 2 */
    assert_int_equal(p.extract_now, 2u);
}

/* With wait_magnetize: magnetize_end pulses once at N_MAG (the flux has
 * settled), then MAGNETIZE holds (PWM on, i_M ref, no speed loop, at DC)
 * until adapt_ready, and leaves on the sample that sees it; a second start
 * waits again.  adapt_timeouts stays 0. */
static void test_magnetize_wait(void **state)
{
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    assert_int_equal(id_sequence_set_wait(&s, 1u, 1000u), 0);
    id_sequence_start(&s);
    step(&s, &p);
    s.cal_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    for (k = 1u; k < N_MAG; k++) {
        step(&s, &p);
    }
    assert_int_equal(p.magnetize_end, 0u);
    /* the magnetisation time is over: the pulse, and the hold */
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    assert_int_equal(s.magnetize_end, 1u);
    for (k = 0u; k < 500u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_MAGNETIZE);
        assert_int_equal(s.magnetize_end, 0u);
        check_outputs(&s);
    }
    assert_int_equal(p.magnetize_end, 1u);
    s.adapt_ready = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_ACCELERATE);
    assert_int_equal(s.magnetize_end, 0u);
    assert_int_equal(s.adapt_timeouts, 0u);
    assert_int_equal(p.magnetize_end, 1u);
    check_outputs(&s);
}

/* The waits run out after wait_max samples: MAGNETIZE (the sample at N_MAG
 * is the first of the wait) and REFINE (from the sample on which settle_min
 * and ramp_done hold), each counted in adapt_timeouts; a new start clears
 * the count.  wait_max 0: no limit (the three-pass test waits 2 N_SMIN). */
static void test_wait_timeouts(void **state)
{
    const uint32_t n_wait = 40u;
    id_sequence_t s;
    pulses_t p = {0u, 0u, 0u};
    uint32_t k;
    (void)state;

    seq_init(&s);
    assert_int_equal(id_sequence_set_passes(&s, 2u, _IQ(0.4)), 0);
    assert_int_equal(id_sequence_set_wait(&s, 1u, n_wait), 0);
    id_sequence_start(&s);
    step(&s, &p);
    s.cal_done = 1u;
    step(&s, &p);
    for (k = 1u; k < N_MAG; k++) {
        step(&s, &p);
    }
    for (k = 1u; k < n_wait; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_MAGNETIZE);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_ACCELERATE);
    assert_int_equal(s.adapt_timeouts, 1u);
    assert_int_equal(p.magnetize_end, 1u);

    run_pass(&s, &p, 100u, 0u);
    assert_int_equal(s.state, ID_REFINE);
    s.ramp_done = 1u;
    /* settle_min first (t_state N_SMIN is the first sample of the wait) */
    for (k = 1u; k < N_SMIN + n_wait - 1u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_REFINE);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_ACCELERATE);
    assert_int_equal(s.pass, 2u);
    assert_int_equal(s.rls_restart, 1u);
    assert_int_equal(s.adapt_timeouts, 2u);

    /* stop, start: the count starts afresh */
    id_sequence_stop(&s);
    step(&s, &p);
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    assert_int_equal(s.adapt_timeouts, 0u);

    /* set_wait: at_magnetize 0 or 1 only */
    {
        id_sequence_t before = s;
        assert_int_equal(id_sequence_set_wait(&s, 2u, 5u), 1);
        assert_memory_equal(&s, &before, sizeof s);
    }
}

/* id_sequence_set_passes: 1 .. 4 passes and a fraction in [0, 1];
 * otherwise 1 and nothing changed. */
static void test_set_passes(void **state)
{
    id_sequence_t s, before;
    (void)state;

    seq_init(&s);
    before = s;
    assert_int_equal(id_sequence_set_passes(&s, 0u, _IQ(0.4)), 1);
    assert_int_equal(id_sequence_set_passes(&s, ID_PASSES_MAX + 1u, _IQ(0.4)), 1);
    assert_int_equal(id_sequence_set_passes(&s, 2u, _IQ(-0.01)), 1);
    assert_int_equal(id_sequence_set_passes(&s, 2u, _IQ(1.01)), 1);
#if MATH_TYPE == IQ_MATH
    assert_int_equal(id_sequence_set_passes(&s, 2u, _IQ(1.0) + 1), 1);
    assert_int_equal(id_sequence_set_passes(&s, 2u, -1), 1);
#endif
    assert_memory_equal(&s, &before, sizeof s);
    /* the edges */
    assert_int_equal(id_sequence_set_passes(&s, ID_PASSES_MAX, _IQ(1.0)), 0);
    assert_int_equal(s.passes, ID_PASSES_MAX);
    assert_true(s.refine_speed == s.speed_target);
    assert_int_equal(id_sequence_set_passes(&s, 1u, _IQ(0.0)), 0);
    assert_true(s.refine_speed == _IQ(0.0));
    assert_int_equal(s.passes, 1u);
}

/* The sensor test at the end of CALIBRATE (sensor_test = 1): after the
 * calibration the sequence stays in CALIBRATE with the bridge switching
 * and no current reference until the drive says test_done; then
 * MAGNETIZE on the next sample.  A fault there goes to FAULT; a new start
 * runs the test again (the drive clears test_done with the new run). */
static void test_sensor_test_in_calibrate(void **state)
{
    id_sequence_t s;
    pulses_t p;
    uint32_t k;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    assert_int_equal(s.sensor_test, 0u);   /* off after init: the paper's sequence unchanged */
    s.sensor_test = 1u;
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    check_outputs(&s);
    assert_int_equal(s.pwm_on, 0u);
    s.cal_done = 1u;
    for (k = 0u; k < 40u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_CALIBRATE);
        assert_int_equal(s.sensor_testing, 1u);
        assert_int_equal(s.pwm_on, 1u);
        assert_true(s.im_cmd == _IQ(0.0));
        assert_int_equal(s.speed_loop_on, 0u);
        assert_int_equal(s.rls_on, 0u);
        check_outputs(&s);
    }
    s.test_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    assert_int_equal(s.sensor_testing, 0u);
    assert_true(s.im_cmd == s.im_ref);
    check_outputs(&s);
    /* stop, a new start with the test's verdict cleared, and a fault in it */
    id_sequence_stop(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    s.cal_done = 0u;
    s.test_done = 0u;
    id_sequence_start(&s);
    step(&s, &p);
    s.cal_done = 1u;
    step(&s, &p);
    assert_int_equal(s.sensor_testing, 1u);
    s.fault = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_FAULT);
    assert_int_equal(s.pwm_on, 0u);
    assert_int_equal(s.sensor_testing, 0u);
    check_outputs(&s);
}

/* The bridge's voltage-error test after the sensor test (vi_test = 1): the
 * sensor test first (sensor_testing, not vi_testing), then, once test_done,
 * the voltage-error test with the bridge switching and no current
 * reference until the drive says vi_done; then MAGNETIZE.  A measured
 * curve stays measured (vi_done is the drive's, once per drive_init): a
 * new start goes from the sensor test straight to MAGNETIZE. */
static void test_vi_test_in_calibrate(void **state)
{
    id_sequence_t s;
    pulses_t p;
    uint32_t k;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    assert_int_equal(s.vi_test, 0u);   /* off after init */
    s.sensor_test = 1u;
    s.vi_test = 1u;
    id_sequence_start(&s);
    step(&s, &p);
    s.cal_done = 1u;
    step(&s, &p);
    assert_int_equal(s.sensor_testing, 1u);
    assert_int_equal(s.vi_testing, 0u);
    check_outputs(&s);
    s.test_done = 1u;
    for (k = 0u; k < 40u; k++) {
        step(&s, &p);
        assert_int_equal(s.state, ID_CALIBRATE);
        assert_int_equal(s.sensor_testing, 0u);
        assert_int_equal(s.vi_testing, 1u);
        assert_int_equal(s.pwm_on, 1u);
        assert_true(s.im_cmd == _IQ(0.0));
        assert_int_equal(s.speed_loop_on, 0u);
        check_outputs(&s);
    }
    s.vi_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    assert_int_equal(s.vi_testing, 0u);
    check_outputs(&s);
    id_sequence_stop(&s);
    step(&s, &p);
    s.test_done = 0u;
    id_sequence_start(&s);
    step(&s, &p);
    step(&s, &p);
    assert_int_equal(s.sensor_testing, 1u);
    s.test_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    check_outputs(&s);
}

/* A start then a stop before the next step: the later command wins, IDLE
 * with the bridge off (the stop drops the start still pending; before, the
 * step took the stop, then the start, and ran CALIBRATE).  A stop then a
 * start from IDLE: the start. */
static void test_start_then_stop_before_a_step(void **state)
{
    id_sequence_t s;
    pulses_t p;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    id_sequence_start(&s);
    id_sequence_stop(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    assert_int_equal(s.pwm_on, 0u);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    id_sequence_stop(&s);
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
}

/* The standstill sequence (set_static): MAGNETIZE ends in INJECT, which
 * lasts exactly inject_samples (its entry sample the first), then IDLE with
 * the bridge off and static_done; the speed loop never runs.  A new start
 * clears static_done at once, before the step takes it (the background
 * judges a standstill set on static_done in IDLE: a stale one would be
 * judged again with the new run's empty sums), and the next step is
 * CALIBRATE. */
static void test_static_inject(void **state)
{
    id_sequence_t s;
    pulses_t p;
    uint32_t k;
    const uint32_t n_inject = 40u;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    assert_int_equal(id_sequence_set_static(&s, 1u, 0u), 1);
    assert_int_equal(id_sequence_set_static(&s, 2u, n_inject), 1);
    assert_int_equal(id_sequence_set_static(&s, 1u, n_inject), 0);
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    s.cal_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    for (k = 1u; k < N_MAG; k++) {
        step(&s, &p);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_INJECT);
    assert_int_equal(p.magnetize_end, 1u);
    for (k = 1u; k < n_inject; k++) {
        assert_int_equal(s.pwm_on, 1u);
        assert_int_equal(s.speed_loop_on, 0u);
        assert_int_equal(s.static_done, 0u);
        step(&s, &p);
        assert_int_equal(s.state, ID_INJECT);
    }
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    assert_int_equal(s.static_done, 1u);
    assert_int_equal(s.pwm_on, 0u);
    step(&s, &p);
    assert_int_equal(s.static_done, 1u);   /* until the next start */
    id_sequence_start(&s);
    assert_int_equal(s.static_done, 0u);   /* before any step */
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    assert_int_equal(p.extract_now, 0u);
}

/* The rotor at rest in CALIBRATE and MAGNETIZE: |speed| above rest_speed
 * sends the sequence back to IDLE (bridge off) with rotor_moved; at the
 * limit it stays; ACCELERATE ignores it; a new start clears rotor_moved. */
static void test_rotor_must_rest(void **state)
{
    id_sequence_t s;
    pulses_t p;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    id_sequence_set_rest(&s, _IQ(0.01));
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    s.speed = _IQ(0.01);   /* at the limit: at rest */
    step(&s, &p);
    assert_int_equal(s.state, ID_CALIBRATE);
    s.speed = -_IQ(0.0101);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    assert_int_equal(s.rotor_moved, 1u);
    assert_int_equal(s.pwm_on, 0u);
    /* MAGNETIZE */
    s.speed = _IQ(0.0);
    id_sequence_start(&s);
    step(&s, &p);
    assert_int_equal(s.rotor_moved, 0u);
    s.cal_done = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_MAGNETIZE);
    s.speed = _IQ(0.02);
    step(&s, &p);
    assert_int_equal(s.state, ID_IDLE);
    assert_int_equal(s.rotor_moved, 1u);
}

/* The voltage's headroom ends ACCELERATE: SETTLE at once, the ramp's output
 * the new target (and the REFINE speed with it), target_lowered; without
 * volt_limit the target stays. */
static void test_volt_limit_ends_acceleration(void **state)
{
    id_sequence_t s;
    pulses_t p;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    assert_int_equal(id_sequence_set_passes(&s, 2u, _IQ(0.4)), 0);
    run_to_accelerate(&s, &p);
    s.speed_ref = _IQ(0.7);
    step(&s, &p);
    assert_int_equal(s.state, ID_ACCELERATE);
    assert_true(s.speed_target == _IQ(0.9333));
    s.volt_limit = 1u;
    step(&s, &p);
    assert_int_equal(s.state, ID_SETTLE);
    assert_true(s.speed_target == _IQ(0.7));
    assert_true(s.speed_cmd == _IQ(0.7));
    assert_true(fabs(to_d(s.refine_speed) - 0.28) <= 2.0 * LSB + 1e-7);
    assert_int_equal(s.target_lowered, 1u);
    /* the target set afresh (the drive's start) */
    id_sequence_set_target(&s, _IQ(0.9333));
    assert_true(fabs(to_d(s.refine_speed) - 0.4 * 0.9333) <= 2.0 * LSB + 1e-7);
}

/* RUN's excitation: the speed command swings from the target to
 * EXCITE_LOW_OF_TARGET of it (at least the floor, at most
 * EXCITE_HIGH_OF_TARGET) and back at each end the ramp reaches; without
 * excite, the target. */
static void test_excitation_swings(void **state)
{
    id_sequence_t s;
    pulses_t p;
    unsigned k;
    (void)state;
    memset(&p, 0, sizeof p);
    seq_init(&s);
    id_sequence_set_excite(&s, _IQ(0.3));
    run_to_accelerate(&s, &p);
    run_pass(&s, &p, 10u, 0u);
    assert_int_equal(s.state, ID_RUN);
    s.excite = 1u;
    s.ramp_done = 0u;
    step(&s, &p);
    assert_int_equal(s.exciting, 1u);
    assert_true(fabs(to_d(s.speed_cmd) - 0.6 * 0.9333) <= 2.0 * LSB + 1e-7);   /* 0.56 > floor 0.3 */
    for (k = 0u; k < 3u; k++) {
        step(&s, &p);
        assert_true(s.speed_cmd == s.excite_low);   /* on its way */
    }
    s.ramp_done = 1u;
    step(&s, &p);
    assert_true(s.speed_cmd == s.speed_target);     /* turned at the low end */
    step(&s, &p);
    assert_true(s.speed_cmd == s.excite_low);       /* and at the high one */
    s.excite = 0u;
    step(&s, &p);
    assert_int_equal(s.exciting, 0u);
    assert_true(s.speed_cmd == s.speed_target);
    /* a floor above the high end: the swing's low end is EXCITE_HIGH_OF_TARGET */
    id_sequence_set_excite(&s, _IQ(0.92));
    s.excite = 1u;
    step(&s, &p);
    assert_true(fabs(to_d(s.excite_low) - 0.9 * 0.9333) <= 2.0 * LSB + 1e-7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sensor_test_in_calibrate),
        cmocka_unit_test(test_start_then_stop_before_a_step),
        cmocka_unit_test(test_static_inject),
        cmocka_unit_test(test_rotor_must_rest),
        cmocka_unit_test(test_volt_limit_ends_acceleration),
        cmocka_unit_test(test_excitation_swings),
        cmocka_unit_test(test_vi_test_in_calibrate),
        cmocka_unit_test(test_three_passes),
        cmocka_unit_test(test_one_pass),
        cmocka_unit_test(test_settle_timeout),
        cmocka_unit_test(test_settle_timeout_torque_limited),
        cmocka_unit_test(test_settle_ripple_confirms),
        cmocka_unit_test(test_settle_im_drift_waits),
        cmocka_unit_test(test_settle_it_drift_waits),
        cmocka_unit_test(test_settle_tolerance_positive),
        cmocka_unit_test(test_fault_in_refine),
        cmocka_unit_test(test_set_passes),
        cmocka_unit_test(test_magnetize_wait),
        cmocka_unit_test(test_wait_timeouts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
