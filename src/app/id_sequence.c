/* The identification sequence state machine.  See id_sequence.h. */
#include "id_sequence.h"

#include <string.h>

static uint32_t seconds_to_samples(float t_s, float Ts_s)
{
    return (uint32_t)(t_s / Ts_s + 0.5f);
}

int16_t id_sequence_init(id_sequence_t *s, float Ts_s, float magnetize_s,
                         float settle_min_s, float settle_hold_s, float settle_max_s,
                         float rls_tail_s,
                         _iq speed_tol, _iq im_tol, _iq it_tol, _iq im_ref,
                         _iq speed_target)
{
    memset(s, 0, sizeof *s);
    if (!(Ts_s > 0.0f) || !(magnetize_s > 0.0f) || !(settle_min_s >= 0.0f) ||
        !(settle_hold_s > 0.0f) || !(settle_max_s >= settle_hold_s) ||
        !(rls_tail_s >= 0.0f) || rls_tail_s > settle_max_s || !(im_tol > _IQ(0.0)) ||
        !(it_tol > _IQ(0.0))) {
        return 1;
    }
    s->magnetize_samples = seconds_to_samples(magnetize_s, Ts_s);
    s->settle_min_samples = seconds_to_samples(settle_min_s, Ts_s);
    s->settle_hold_samples = seconds_to_samples(settle_hold_s, Ts_s);
    s->settle_max_samples = seconds_to_samples(settle_max_s, Ts_s);
    s->rls_tail_samples = seconds_to_samples(rls_tail_s, Ts_s);
    s->speed_tol = speed_tol;
    s->im_tol = im_tol;
    s->it_tol = it_tol;
    s->im_ref = im_ref;
    s->speed_target = speed_target;
    s->state = ID_IDLE;
    s->passes = 1u;
    s->pass = 1u;
    return 0;
}

int16_t id_sequence_set_passes(id_sequence_t *s, uint16_t passes, _iq refine_fraction)
{
    if (passes < 1u || passes > ID_PASSES_MAX || refine_fraction < _IQ(0.0) ||
        refine_fraction > _IQ(1.0)) {
        return 1;
    }
    s->passes = passes;
    s->refine_fraction = refine_fraction;
    id_sequence_set_target(s, s->speed_target);
    return 0;
}

void id_sequence_set_target(id_sequence_t *s, _iq speed_target)
{
    s->speed_target = speed_target;
    /* Q24 * Q24 -> Q24, |speed_target| < 2 pu: no overflow */
    s->refine_speed = _IQmpy(speed_target, s->refine_fraction);
}

int16_t id_sequence_set_wait(id_sequence_t *s, uint16_t at_magnetize, uint32_t max_samples)
{
    if (at_magnetize > 1u) {
        return 1;
    }
    s->wait_magnetize = at_magnetize;
    s->wait_max_samples = max_samples;
    return 0;
}

int16_t id_sequence_set_static(id_sequence_t *s, uint16_t on, uint32_t inject_samples)
{
    if (on > 1u || (on != 0u && inject_samples == 0u)) {
        return 1;
    }
    s->static_id = on;
    s->inject_samples = inject_samples;
    return 0;
}

void id_sequence_set_rest(id_sequence_t *s, _iq rest_speed) { s->rest_speed = rest_speed; }

void id_sequence_set_excite(id_sequence_t *s, _iq floor) { s->excite_floor = floor; }

void id_sequence_start(id_sequence_t *s)
{
    /* the last run's INJECT is over and forgotten before the start shows:
     * the background judges a standstill set on static_done in IDLE, and
     * would otherwise judge the new run's empty one before the step takes
     * the start (the step writes static_done only on leaving IDLE, 0, and at
     * INJECT's end) */
    s->static_done = 0u;
    s->start_req = 1u;
}

void id_sequence_stop(id_sequence_t *s)
{
    /* the start first, then the stop (16-bit stores, in order): a step that
     * runs between them sees neither or the stop alone, never the start
     * after the stop */
    s->start_req = 0u;
    s->stop_req = 1u;
}

/* The outputs that follow from the state alone, looked up once per state
 * change instead of recomputed from the state in every step: the bridge on,
 * the speed loop, the RLS (SETTLE: only for its first rls_tail_samples, the
 * step's own compare), i_M to its reference.  CALIBRATE's phases (the
 * offsets, the sensor test, the bridge's test) are set by its own case. */
#define OUT_PWM 1u
#define OUT_SPEED 2u
#define OUT_RLS 4u
#define OUT_IM 8u
static const uint16_t k_state_out[] = {
    0u,                                     /* IDLE */
    0u,                                     /* CALIBRATE: its case */
    OUT_PWM | OUT_IM,                       /* MAGNETIZE */
    OUT_PWM | OUT_IM | OUT_SPEED | OUT_RLS, /* ACCELERATE */
    OUT_PWM | OUT_IM | OUT_SPEED | OUT_RLS, /* SETTLE: rls_on until the tail's end */
    OUT_PWM | OUT_IM | OUT_SPEED,           /* RUN */
    0u,                                     /* FAULT */
    OUT_PWM | OUT_IM | OUT_SPEED,           /* REFINE */
    OUT_PWM | OUT_IM                        /* INJECT */
};

static void enter(id_sequence_t *s, id_state_t next)
{
    const uint16_t f = k_state_out[(uint16_t)next];

    s->state = next;
    s->t_state = 0u;
    s->t_steady = 0u;
    s->pwm_on = (uint16_t)(f & OUT_PWM);
    s->speed_loop_on = (uint16_t)((f & OUT_SPEED) >> 1);
    s->rls_on = (uint16_t)((f & OUT_RLS) >> 2);
    s->im_cmd = ((f & OUT_IM) != 0u) ? s->im_ref : _IQ(0.0);
    /* CALIBRATE starts with the offsets (its case sets the later phases) */
    s->calibrating = (uint16_t)(next == ID_CALIBRATE);
    s->sensor_testing = 0u;
    s->vi_testing = 0u;
}

void id_sequence_clear_fault(id_sequence_t *s)
{
    if (s->state == ID_FAULT) {
        enter(s, ID_IDLE);
    }
}

/* CALIBRATE's outputs in one of its phases (one of the three flags set):
 * the bridge switches for either test. */
static void calibrate_phase(id_sequence_t *s, uint16_t cal, uint16_t sensor, uint16_t vi)
{
    s->calibrating = cal;
    s->sensor_testing = sensor;
    s->vi_testing = vi;
    s->pwm_on = (uint16_t)(sensor | vi);
}

/* Has the drive's model arrived?  Else one more sample of waiting; 1 also
 * when the wait has run out (counted: the sequence goes on with the model
 * in use). */
static uint16_t model_ready(id_sequence_t *s)
{
    if (s->adapt_ready != 0u) {
        return 1u;
    }
    s->t_steady++;
    if (s->wait_max_samples != 0u && s->t_steady >= s->wait_max_samples) {
        if (s->adapt_timeouts < 0xFFFFu) {
            s->adapt_timeouts++;
        }
        return 1u;
    }
    return 0u;
}

/* The rotor left its rest in a state that needs it (CALIBRATE, MAGNETIZE). */
static uint16_t rotor_turned(const id_sequence_t *s)
{
    return (uint16_t)(s->rest_speed > _IQ(0.0) && _IQabs(s->speed) > s->rest_speed);
}

/* RUN's excitation: down to excite_low and back up, turning at each end
 * the ramp reaches (Q24 * Q24 -> Q24, |speed_target| < 2 pu). */
static void excite_step(id_sequence_t *s)
{
    if (s->exciting == 0u) {
        _iq low = _IQmpy(s->speed_target, _IQ(EXCITE_LOW_OF_TARGET));
        const _iq high = _IQmpy(s->speed_target, _IQ(EXCITE_HIGH_OF_TARGET));
        if (_IQabs(low) < s->excite_floor) {
            low = (s->speed_target < 0) ? -s->excite_floor : s->excite_floor;
        }
        if (_IQabs(low) > _IQabs(high)) {
            low = high;
        }
        s->excite_low = low;
        s->exciting = 1u;
        s->excite_down = 1u;
    } else if (s->ramp_done != 0u) {
        s->excite_down ^= 1u;
    } else {
        /* on its way */
    }
    s->speed_cmd = (s->excite_down != 0u) ? s->excite_low : s->speed_target;
}

void id_sequence_step(id_sequence_t *s)
{
    s->extract_now = 0u;
    s->rls_restart = 0u;
    s->magnetize_end = 0u;
    if (s->fault != 0u) {
        if (s->state != ID_FAULT) {
            enter(s, ID_FAULT);
        }
    } else if (s->stop_req != 0u) {
        enter(s, ID_IDLE);
    }
    s->stop_req = 0u;
    if (s->t_state < 0xFFFFFFFFu) {
        s->t_state++;
    }

    if ((s->state == ID_CALIBRATE || s->state == ID_MAGNETIZE || s->state == ID_INJECT) &&
        rotor_turned(s) != 0u) {
        s->rotor_moved = 1u;
        enter(s, ID_IDLE);
    }

    switch (s->state) {
    case ID_IDLE:
        if (s->start_req != 0u) {
            s->pass = 1u;
            s->adapt_timeouts = 0u;
            s->target_lowered = 0u;
            s->settle_timeout = 0u;
            s->torque_limited = 0u;
            s->rotor_moved = 0u;
            s->static_done = 0u;
            enter(s, ID_CALIBRATE);
        }
        break;
    case ID_CALIBRATE:
        /* its phases in turn: the offsets, the sensor test, the bridge's
         * test (each while its input says it is not done), then MAGNETIZE;
         * the bridge switches for the two tests, with no current reference */
        if (s->cal_done == 0u) {
            calibrate_phase(s, 1u, 0u, 0u);
        } else if (s->sensor_test != 0u && s->test_done == 0u) {
            calibrate_phase(s, 0u, 1u, 0u);
        } else if (s->vi_test != 0u && s->vi_done == 0u) {
            calibrate_phase(s, 0u, 0u, 1u);
        } else {
            enter(s, ID_MAGNETIZE);
        }
        break;
    case ID_MAGNETIZE:
        if (s->t_state >= s->magnetize_samples) {
            /* once: t_state counts up by one per step */
            s->magnetize_end = (uint16_t)(s->t_state == s->magnetize_samples);
            if (s->wait_magnetize == 0u || model_ready(s) != 0u) {
                enter(s, (s->static_id != 0u) ? ID_INJECT : ID_ACCELERATE);
            }
        }
        break;
    case ID_ACCELERATE:
        if (s->volt_limit != 0u && s->ramp_done == 0u) {
            /* the voltage's headroom is gone: the speed reached is the target
             * (this pass's and the next ones'); the ramp stands there */
            id_sequence_set_target(s, s->speed_ref);
            s->target_lowered = 1u;
            enter(s, ID_SETTLE);
        } else if (s->ramp_done != 0u) {
            enter(s, ID_SETTLE);
        } else {
            /* accelerating */
        }
        break;
    case ID_SETTLE: {
        /* steady: the speed error small in every sample of the hold window,
         * and the filtered currents' net change over it within tolerance.
         * A window that fails the currents' test closes; the next sample
         * opens another.  (|i| < 4 pu: the differences cannot overflow.) */
        uint16_t held = 0u;
        s->rls_on = (uint16_t)(s->t_state <= s->rls_tail_samples);
        if (s->speed_err >= s->speed_tol) {
            s->t_steady = 0u;
        } else {
            if (s->t_steady == 0u) {
                s->win_im = s->i_mf;
                s->win_it = s->i_tf;
            }
            s->t_steady++;
            if (s->t_steady >= s->settle_hold_samples) {
                held = (uint16_t)(_IQabs(s->i_mf - s->win_im) <= s->im_tol &&
                                  _IQabs(s->i_tf - s->win_it) <= s->it_tol);
                if (held == 0u) {
                    s->t_steady = 0u;
                }
            }
        }
        if (s->t_state >= s->settle_min_samples && held != 0u) {
            s->settle_timeout = 0u;
            s->torque_limited = 0u;
            s->extract_now = 1u;
        } else if (s->t_state >= s->settle_max_samples) {
            s->settle_timeout = 1u;
            s->torque_limited = s->torque_limit;
            s->extract_now = 1u;
        } else {
            /* still waiting */
        }
        if (s->extract_now != 0u) {
            enter(s, (s->pass < s->passes) ? ID_REFINE : ID_RUN);
        }
        break;
    }
    case ID_REFINE:
        /* ramp_done refers to refine_speed here: control ran with it since
         * the entry; settle_min_samples lets the parameters blend in */
        if (s->t_state >= s->settle_min_samples && s->ramp_done != 0u &&
            model_ready(s) != 0u) {
            s->pass++;
            s->rls_restart = 1u;
            enter(s, ID_ACCELERATE);
        }
        break;
    case ID_INJECT:
        if (s->t_state >= s->inject_samples) {
            s->static_done = 1u;
            enter(s, ID_IDLE);
        }
        break;
    case ID_RUN:
    case ID_FAULT:
    default:
        break;
    }
    s->start_req = 0u;

    /* the outputs of the (new) state: enter() and the cases above; the
     * speed target may change in RUN (drive_set_speed) */
    if (s->speed_loop_on == 0u) {
        s->speed_cmd = _IQ(0.0);
    } else if (s->state == ID_REFINE) {
        s->speed_cmd = s->refine_speed;
    } else if (s->state == ID_RUN && s->excite != 0u) {
        excite_step(s);
    } else {
        s->exciting = 0u;
        s->speed_cmd = s->speed_target;
    }
}
