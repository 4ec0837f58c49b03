/**
 * @file id_sequence.h
 * The identification sequence of the paper's experiment (method §2, §6), as a
 * state machine run once per ISR sample:
 *
 *   IDLE -> CALIBRATE (current offsets, PWM off; then, with sensor_test, the
 *                      sensors' pulse test: the bridge switches, no
 *                      current reference, until the drive says test_done;
 *                      then, with vi_test and until vi_done, the bridge's
 *                      voltage error against the current at standstill
 *                      (vi_curve.h: the dead-time compensation's curve,
 *                      measured once per drive_init))
 *        -> MAGNETIZE (i_M to its reference, zero speed, >= 5 Tr)
 *        -> ACCELERATE (speed ramp to the target; RLS on: the transient that
 *                       excites the regression, method §2 "Excitation"; it
 *                       ends early, at the speed reached, when the drive
 *                       says the voltage has no headroom left (volt_limit),
 *                       and that speed becomes the target)
 *        -> SETTLE (speed reached; the RLS runs on for rls_tail_s, then
 *                   stops; wait for steady state, the precondition of the
 *                   parameter formulas (method §4: di/dt = 0): the speed
 *                   error small in every sample, and the filtered i_M and
 *                   i_T each within its tolerance of where they stood when
 *                   the hold window began (the net change over the window,
 *                   not the instantaneous di/dt: see the tolerances below))
 *        -> RUN (parameters extracted and published; RLS off; while the drive
 *               asks for torque, excite, the speed swings between the target
 *               and excite_low: a free shaft's acceleration and deceleration
 *               are its only torque)
 *   any  -> FAULT (from the protections; PWM off) ; STOP -> IDLE
 *   CALIBRATE, MAGNETIZE -> IDLE when the rotor turns (id_sequence_set_rest)
 *
 * The standstill sequence (static_id, id_sequence_set_static; beyond the
 * paper): the end of MAGNETIZE (with its wait for the standstill Rs and
 * sigma Ls) leads instead to
 *        -> INJECT (the frame held, i_M plus the drive's low-frequency
 *                   multisine: standstill_lf.h; no speed loop, no RLS;
 *                   for inject_samples: the test's own length and a margin)
 *        -> IDLE (the bridge off; static_done: the drive fits and judges
 *                 the set from what it measured)
 * The rotor never turns: the current stays on one axis of a fixed frame.
 *   INJECT -> IDLE when the rotor turns, as CALIBRATE and MAGNETIZE.
 *
 * Several passes (beyond the paper; passes > 1): the extraction at
 * the end of SETTLE then leads, while pass < passes, to
 *        -> REFINE (speed ramps down to refine_speed; the drive blends the
 *                   pass's parameters into its observer and controller and
 *                   says so with adapt_ready; RLS off)
 *        -> ACCELERATE again (pass + 1; rls_restart: the RLS starts afresh,
 *                   now in a frame computed with the identified model)
 * so each pass identifies with a better controller than the last: with the
 * believed model 30 % off, the first pass is a few % off, the next within
 * the accuracy of a controller that knows the motor.  passes = 1 is the
 * paper's sequence, unchanged.
 *
 * Waiting for the drive's model (id_sequence_set_wait): the drive computes a
 * new model outside the ISR and says with adapt_ready that it is applied.
 * REFINE always waits for it; with wait_magnetize the end of MAGNETIZE does
 * too (the standstill Rs and sigma Ls: magnetize_end pulses once at
 * magnetize_samples, and MAGNETIZE holds, at DC, until adapt_ready), so that
 * ACCELERATE never starts on a model about to change.  Each wait ends after
 * wait_max_samples without it (0: no limit): the sequence goes on with the
 * model in use and counts it in adapt_timeouts.
 *
 * It decides only; the drive applies its outputs.  Times are counted in ISR
 * samples (uint32_t, so > 3 days at 15 kHz before a wrap).
 */
#ifndef ID_SEQUENCE_H
#define ID_SEQUENCE_H

#include <stdint.h>
#include "IQmathLib.h"

typedef enum {
    ID_IDLE = 0,
    ID_CALIBRATE,
    ID_MAGNETIZE,
    ID_ACCELERATE,
    ID_SETTLE,
    ID_RUN,
    ID_FAULT,
    ID_REFINE,     /* between passes (passes > 1); after FAULT so the codes 0..6 keep their meaning */
    ID_INJECT      /* the standstill sequence's low-frequency injection (static_id) */
} id_state_t;

#define ID_PASSES_MAX 4u

typedef struct {
    /* inputs (set by the drive each sample) */
    uint16_t cal_done;        /* offset calibration finished (ok or not) */
    uint16_t fault;           /* a latched fault exists */
    uint16_t ramp_done;       /* the speed reference reached its target */
    _iq speed_err;            /* |speed ref - speed|, pu, Q24 */
    uint16_t adapt_ready;     /* REFINE (and the end of MAGNETIZE with wait_magnetize): the drive
                                 has applied the model the state waits for */
    uint16_t test_done;       /* CALIBRATE: the sensor test passed (sensor_test.h) */
    uint16_t vi_done;         /* CALIBRATE: the voltage-error curve is measured and applied
                                 (vi_curve.h), or the drive gave up on it */
    _iq i_mf;                 /* i_M filtered (the regression's Butterworth), pu, Q24 */
    _iq i_tf;                 /* i_T filtered, pu, Q24 */
    uint16_t volt_limit;      /* ACCELERATE: the voltage has no headroom left (drive_target.h):
                                 the ramp ends here, at speed_ref, the new target */
    _iq speed_ref;            /* the speed ramp's output, pu, Q24 */
    _iq speed;                /* the rotor's speed, pu, Q24: CALIBRATE and MAGNETIZE need the
                                 rotor at rest */
    uint16_t torque_limit;    /* the speed loop's output (the torque current) is at its limit */
    uint16_t excite;          /* RUN: the drive asks for torque (a free shaft gives its tracker
                                 none): the speed swings between the target and excite_low */
    /* parameters (id_sequence_init) */
    uint32_t magnetize_samples;
    uint32_t settle_min_samples;   /* least time in SETTLE */
    uint32_t settle_hold_samples;  /* steady-state conditions must hold this long */
    uint32_t settle_max_samples;   /* give up waiting: extract anyway, flagged */
    uint32_t rls_tail_samples;     /* the RLS runs this long into SETTLE */
    _iq speed_tol;            /* steady: speed error below, pu */
    _iq im_tol, it_tol;       /* steady: the net change of i_mf, i_tf over the hold window
                                 within these, pu (drive_design.c: from the motor) */
    _iq im_ref;               /* magnetising current reference, pu */
    _iq speed_target;         /* pu */
    uint16_t passes;          /* 1 .. ID_PASSES_MAX (id_sequence_set_passes) */
    _iq refine_speed;         /* REFINE speed, pu: refine_fraction of speed_target */
    _iq refine_fraction;      /* Q24, [0, 1] */
    uint16_t wait_magnetize;  /* 1: MAGNETIZE ends only with adapt_ready (id_sequence_set_wait) */
    uint32_t wait_max_samples;/* longest wait for adapt_ready (0: no limit) */
    _iq rest_speed;           /* CALIBRATE, MAGNETIZE: the rotor is at rest while |speed| stays
                                 within this, pu (0: not checked; id_sequence_set_rest) */
    _iq excite_floor;         /* the lowest excite_low, pu (id_sequence_set_excite) */
    uint16_t sensor_test;     /* 1: CALIBRATE ends with the sensor test (0 after init) */
    uint16_t vi_test;         /* 1: then with the voltage-error test (0 after init) */
    uint16_t static_id;       /* 1: the standstill sequence (MAGNETIZE -> INJECT -> IDLE) */
    uint32_t inject_samples;  /* INJECT's length (the drive's test and a margin) */
    /* outputs */
    id_state_t state;
    uint16_t pwm_on;          /* the bridge should switch */
    uint16_t calibrating;     /* the drive runs the offset calibration */
    uint16_t sensor_testing;  /* the drive runs the sensor test (CALIBRATE, after the
                                 calibration; pwm_on is 1, im_cmd 0) */
    uint16_t vi_testing;      /* the drive runs the voltage-error test (CALIBRATE, after the
                                 sensor test; pwm_on is 1, im_cmd 0) */
    uint16_t speed_loop_on;   /* speed PI drives i_T; else i_T ref = 0 */
    uint16_t rls_on;          /* the RLS may update */
    uint16_t extract_now;     /* one-sample pulse: take the steady i_M, extract */
    uint16_t settle_timeout;  /* SETTLE ended by its time limit, not by steadiness */
    uint16_t torque_limited;  /* ... with the speed loop at its torque limit then (a load the
                                 torque current cannot carry at the target) */
    _iq im_cmd;               /* i_M reference to apply, pu */
    _iq speed_cmd;            /* speed target for the ramp, pu */
    uint16_t pass;            /* 1 .. passes: the pass under way (or last done) */
    uint16_t rls_restart;     /* one-sample pulse: ACCELERATE of pass >= 2 entered */
    uint16_t magnetize_end;   /* one-sample pulse: the magnetisation time is over (flux settled;
                                 the last sample of MAGNETIZE unless it waits for adapt_ready) */
    uint16_t adapt_timeouts;  /* waits for adapt_ready that ran out (saturating; 0 at start) */
    uint16_t target_lowered;  /* the acceleration ended at the voltage limit (volt_limit), below
                                 the target it started with (0 at start) */
    uint16_t rotor_moved;     /* the sequence went back to IDLE because the rotor turned in
                                 CALIBRATE, MAGNETIZE or INJECT (0 at start) */
    uint16_t static_done;     /* the standstill sequence's INJECT completed (0 at start) */
    uint16_t exciting;        /* RUN with excite: the speed swings (the drive's faster ramp) */
    _iq excite_low;           /* its lower speed, pu: EXCITE_LOW_OF_TARGET of the target, at
                                 least excite_floor, at most EXCITE_HIGH_OF_TARGET of it */
    /* state */
    uint32_t t_state;         /* samples in the current state */
    uint32_t t_steady;        /* samples in the hold window (speed steady in each) (SETTLE);
                                 samples waited for adapt_ready (MAGNETIZE, REFINE) */
    _iq win_im, win_it;       /* i_mf, i_tf where the hold window began */
    uint16_t excite_down;     /* the swing is on its way to excite_low */
    uint16_t start_req;
    uint16_t stop_req;
} id_sequence_t;

/** Times in seconds, Ts the sample period; tolerances in pu (im_tol, it_tol:
 *  the net change of the filtered i_M, i_T over the hold window).  rls_tail_s: how
 *  long the RLS keeps running into SETTLE (the end of the ramp, where i_T
 *  steps, still excites the regression; later, steady operation carries no
 *  information and only lets biases pull the estimates).  Returns 0, or 1 if
 *  a time is out of range. */
int16_t id_sequence_init(id_sequence_t *s, float Ts_s, float magnetize_s,
                         float settle_min_s, float settle_hold_s, float settle_max_s,
                         float rls_tail_s,
                         _iq speed_tol, _iq im_tol, _iq it_tol, _iq im_ref,
                         _iq speed_target);
/** Passes (1 .. ID_PASSES_MAX) and the REFINE speed as a fraction of the
 *  target speed (0 .. 1).  Returns 0, or 1 (nothing changed) if out of range.
 *  id_sequence_init sets 1 pass. */
int16_t id_sequence_set_passes(id_sequence_t *s, uint16_t passes, _iq refine_fraction);
/** The target speed (pu, Q24, |.| < 2) of the next identification, and the
 *  REFINE speed with it.  Background, while the sequence is IDLE (a start
 *  lowers the configured target to what the bus gives: drive_target.h). */
void id_sequence_set_target(id_sequence_t *s, _iq speed_target);
/** Wait for adapt_ready at the end of MAGNETIZE (@p at_magnetize 1) and at
 *  most @p max_samples for any wait (0: no limit).  Returns 0, or 1
 *  (nothing changed) if @p at_magnetize > 1.  id_sequence_init sets 0, 0. */
int16_t id_sequence_set_wait(id_sequence_t *s, uint16_t at_magnetize, uint32_t max_samples);
/** The rotor at rest in CALIBRATE and MAGNETIZE: |speed| within
 *  @p rest_speed (pu; 0: not checked; id_sequence_init sets 0).  Beyond, the
 *  sequence goes back to IDLE (bridge off) with rotor_moved: the bridge's
 *  test and the sensors' pulses at DC, the standstill sigma Ls and the
 *  flux's build-up on the encoder angle assume w = 0, and a rotor still
 *  coasting, or turned by its load, puts a back-EMF into them that their
 *  models do not have.  (A speed, not a displacement: a rotor on a free,
 *  frictionless shaft creeps under the current's noise torque, 0.3 r/min
 *  on the family's 4 kW 2-pole, harmless to every standstill test.) */
void id_sequence_set_rest(id_sequence_t *s, _iq rest_speed);
/** The swing of RUN's excitation (excite): from the target down to
 *  EXCITE_LOW_OF_TARGET of it, not below @p floor (pu: where the drive's
 *  frame and tracker still hold, drive_adapt.c), not above
 *  EXCITE_HIGH_OF_TARGET of it, and back, while excite lasts.
 *  id_sequence_init sets floor 0. */
void id_sequence_set_excite(id_sequence_t *s, _iq floor);
#define EXCITE_LOW_OF_TARGET 0.6
#define EXCITE_HIGH_OF_TARGET 0.9

/** The standstill sequence (@p on 1): MAGNETIZE ends in INJECT, not
 *  ACCELERATE (static_id), and INJECT lasts @p inject_samples.  Returns 0,
 *  or 1 (nothing changed) if @p on > 1, or on with no samples.
 *  id_sequence_init sets 0. */
int16_t id_sequence_set_static(id_sequence_t *s, uint16_t on, uint32_t inject_samples);

/** Request a start (background context): taken by the next step in IDLE;
 *  the last standstill sequence's static_done cleared at once. */
void id_sequence_start(id_sequence_t *s);
/** Request a stop (background context): the next step goes to IDLE, and a
 *  start requested before it and not yet taken is dropped (the later
 *  command wins: a start then a stop within one slow period ends idle). */
void id_sequence_stop(id_sequence_t *s);
/** Leave FAULT for IDLE (the caller has checked the cause is gone). */
void id_sequence_clear_fault(id_sequence_t *s);
void id_sequence_step(id_sequence_t *s);

#endif /* ID_SEQUENCE_H */
