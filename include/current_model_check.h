/**
 * @file current_model_check.h
 * Model-based current plausibility: the current the applied voltage should
 * have produced, from the motor model with the drive's own parameters and
 * rotor-flux model, against the current the sensors report.  A protection
 * that relies on the sensors alone is blind to a sensor that lies: a
 * phase sensor reading 0 A, or one whose gain dropped, lets the current
 * loops drive the true current far above the trip level while every
 * measured value looks healthy (paper motor, phase b read as 0 A during
 * the magnetisation: -31 A true against an 18 A trip for 289 ms).
 *
 * The model (method §1 in the stationary frame, amplitude-invariant
 * alpha-beta, pu; psi_e = (Lm/Lr) psi_r, the drive's rotor-flux model):
 *
 *     u = Rs i + sigma Ls di/dt + d psi_e/dt
 *
 * integrated exactly over the slow task's window of n PWM periods (the
 * voltage is constant in the stator frame over each period, so its
 * integral is Ts times the sum of the periods' reconstructed voltages;
 * the rotor-flux term integrates to its change, whatever the speed; only
 * Rs i is approximated, by the trapezoid of the window's two current
 * samples, whose error is (w_e n Ts)^2 / 12 of a small term):
 *
 *     v(k) = Ts sum(u) - Rs n Ts (i(k) + i(k-n)) / 2 - (psi_e(k) - psi_e(k-n))
 *            - sigma Ls (i(k) - i(k-n))                       (pu flux)
 *     r(k) = lambda (r(k-1) + v(k)),   lambda = exp(-n Ts / tau_r)
 *
 * r is a stator-flux mismatch: sigma Ls times the current the voltage would
 * have produced beyond the measured one over the last ~tau_r.  With a
 * correct model it is the deviation of the true current from the measured
 * one (a sensor that reads 0 A while the true current rises at u/sigma Ls
 * makes r/sigma Ls follow the true current within tau_r); with a healthy
 * sensor it is the model's voltage error times tau_r.  Four tests on it,
 * each with its own cause bit, all reported as one fault (the current
 * measurement is not to be believed):
 *
 *   MISMATCH   |r| > sigma Ls r_max + r_allow + r_allow_emf, every slow
 *              step; and, at any speed once the positive sequence's
 *              low-pass has followed r for 3 tau_seq, the part of
 *              r the positive sequence's low-pass has not followed,
 *              |r - pos| > sigma Ls r_max + r_allow: a sensor that fails is
 *              a step, a model error of the back-EMF a slow fundamental,
 *              so the allowance for the latter (the caller's r_allow_emf)
 *              needs not blunt the test of the former
 *   (the sequence tests first take off the positive sequence, the
 *   fundamental, r e^{-j theta} low-passed and turned back: a model error
 *   is positive sequence, and what the low-passes let through of it is
 *   added to their levels, CMC_LEAK)
 *   UNBALANCE  the negative-sequence part of r (r e^{+j theta}: DC for a
 *              component turning against the fundamental), low-passed
 *              (tau_seq), above sigma Ls k_neg |i|.  A gain error e on one
 *              of the two sensors makes the measured vector an ellipse
 *              whose negative sequence is e/sqrt(3) of |i|; the current
 *              loop forces the MEASURED vector round, so the true current
 *              carries that negative sequence and the voltage the
 *              negative-sequence impedance (about w_e sigma Ls at speed)
 *              times it, which the model, fed with the round measured
 *              current, does not predict.  At standstill a gain error is
 *              a DC scaling (only Rs sees it: indistinguishable from an Rs
 *              error), so the test runs only while |w_s| > ws_min, after
 *              3 tau_seq at that speed.
 *   OFFSET     the DC part of r in the stationary frame, low-passed
 *              (tau_seq), above Rs tau_r d_max: an offset d appearing after
 *              the calibration makes the loop put -d of DC into the true
 *              current, which needs Rs d of DC voltage the model does not
 *              predict (r settles at Rs d tau_r).  Observable only while
 *              the frame turns (at standstill DC is DC); same gate.
 *   (a common gain error of both sensors is positive sequence only: it
 *   reads as a motor with other impedances and cannot be told from a
 *   parameter error with ia, ib alone; it is refused at start by the
 *   sensor test's absolute scale, sensor_test.h)
 *
 * Detection limits and healthy maxima measured over every scenario and
 * motor are in drive_safety.c (where the thresholds are set) and the README.
 *
 * Rates: current_model_check_accumulate every PWM period (the window's
 * voltage sum: two saturations and two additions), current_model_check_step
 * in the slow task.  Cost on the C28x (tools/bench_isr.py's model, which
 * errs high): accumulate 58 cycles per period; the step with the drive's
 * glue (drive_safety.c) ~840 cycles at standstill, ~1050 at speed (the
 * sequence tests' two halves alternate; the bench's sum of maxima over
 * both: 1310).  The drive runs the step in three ISRs: the residual in one
 * (~870), each half in its own (~210 and ~520).
 *
 * Scaling and overflow (Q24 pu throughout): each period's voltage is
 * saturated to +-4 pu before it is summed (the bridge cannot exceed
 * (2/3) vdc_max, below 2 pu), the sum of at most 8 periods to 32 pu; the
 * current and flux inputs to +-4 pu; Rs, sigma Ls to [0, 4] pu; n Ts below
 * 8 x 0.05 pu.  Every term of v is then below 32 pu, v below 64; r is
 * saturated to +-R_MAX = 4 pu (sat counts it), so |r|^2 < 32; the MISMATCH
 * level sigma Ls r_max + r_allow is below 4 + 4, its square below 64; the
 * positive sequence and the r - pos the other two low-passes take are
 * below 4 and 12 pu; every other squared level below 20 pu^2 (the source
 * says each bound).  Nothing wraps.
 */
#ifndef CURRENT_MODEL_CHECK_H
#define CURRENT_MODEL_CHECK_H

#include <stdint.h>
#include "IQmathLib.h"
#include "iq_rmpy.h"

/** Why the check tripped (cause bits). */
#define CMC_MISMATCH 0x1u
#define CMC_UNBALANCE 0x2u
#define CMC_OFFSET 0x4u

/** Input and state bounds (pu), see the file comment. */
#define CMC_IN_MAX 4.0f
#define CMC_R_MAX 4.0f
/** What the sequence low-passes let through of the part of r the positive
 *  sequence has not followed, which a transient of the model's error makes
 *  large (the low-passed positive sequence lags its change by tau_seq): the
 *  negative sequence's first-order low-pass passes 1/(2 |w_s| tau_seq) of
 *  it (it turns at 2 w_s there), the DC's 1/(|w_s| tau_seq).  Its size is
 *  taken in the positive sequence's own frame, low-passed (lag_d, lag_q):
 *  there a model's transient is slow and stays, while what a sensor adds
 *  (a negative sequence at 2 w_e, an offset at w_e) is filtered out, so the
 *  allowance does not grow with a fault.  Added to the UNBALANCE and
 *  OFFSET levels as CMC_Q_LEAK times that gain (at the gate, times
 *  ws_min / |w_s|) times |lag|.  Without it a healthy 4 kW 2-pole with the
 *  believed Tr 30 % off latched UNBALANCE 80 ms into its second pass's
 *  acceleration (the torque's step after REFINE: |r - pos| 0.025 pu, the
 *  level 0.003). */
#define CMC_Q_LEAK 1.0f
/** What the sequence low-passes let through of the positive sequence that
 *  is left after its removal (its phasor lags the residual while the model
 *  error changes with the speed): added to the UNBALANCE and OFFSET levels
 *  in proportion to the positive sequence.  Measured on the 15 kW motor
 *  with the believed Lm 30 % low (|pos| 30 A at 0.44 pu, accelerating):
 *  2.3 %; twice that. */
#define CMC_LEAK 0.05f
/** Largest bridge allowance, pu flux (with the leak's 0.5: the levels' sum
 *  below 1, their squares in Q24). */
#define CMC_BRIDGE_ALLOW_MAX 0.5f

/** The largest window (periods) the sums are sized for. */
#define CMC_N_MAX 8u

typedef enum {
    CMC_OK = 0,
    CMC_ERR_ARG   /* a time not > 0, tau below the slow period, a level out of range */
} cmc_status_t;

typedef struct {
    /* inputs, every PWM period (current_model_check_accumulate) */
    /* inputs, every slow step (set before current_model_check_step) */
    _iq i_alpha, i_beta;      /* Q24 pu: measured stator current at this sample */
    _iq psi_alpha, psi_beta;  /* Q24 pu flux: (Lm/Lr) psi_r of the drive's rotor-flux model
                                 at this sample */
    _iq rs;                   /* Q24 pu of Z_base: Rs of the model in use */
    _iq sigma_ls;             /* Q24 pu of L_base: sigma Ls of the model in use */
    _iq sin_t, cos_t;         /* Q24: the frame (fundamental) angle at this sample */
    _iq ws;                   /* Q24 pu of w_base: the frame's speed */
    uint16_t active;          /* 1: the check may trip (0: re-armed, state cleared) */
    _iq r_allow;              /* Q24 pu flux: added to the MISMATCH level (>= 0, at most 2):
                                 what the caller cannot rule out (drive_safety.c: the
                                 back-EMF a rotor may have gained while the encoder shows no
                                 motion) */
    _iq r_allow_emf;          /* Q24 pu flux: added too (>= 0, at most 2), but only to the
                                 test of |r|, not of the part the positive sequence has not
                                 followed: the model's back-EMF error (slow, fundamental) */
    uint16_t rebase;          /* 1 (a pulse, cleared here): the model the inputs come from
                                 changed since the last step (a pass's blend, the frame's
                                 hand-over): this window's flux step is the model's, not the
                                 motor's; the window is not summed, and the test of r - pos
                                 waits 3 tau_seq for the positive sequence to follow */
    /* parameters (current_model_check_init) */
    _iq ts;                   /* Q24 pu time: one PWM period */
    _iq lambda;               /* Q24: exp(-Ts_slow / tau_r) */
    _iq k_seq;                /* Q24: 1 - exp(-Ts_slow / tau_seq) */
    _iq r_max;                /* Q24 pu current: MISMATCH level (times sigma Ls) */
    _iq k_neg;                /* Q24: UNBALANCE level per pu of |i| (times sigma Ls) */
    _iq d_max_tau;            /* Q24 pu current x pu time: OFFSET level d_max tau_r
                                 (times Rs) */
    _iq ws_min;               /* Q24 pu: the sequence tests run above this |w_s| */
    _iq k_qneg, k_qdc;        /* Q24: CMC_Q_LEAK / (2 ws_min tau_seq), CMC_Q_LEAK / (ws_min
                                 tau_seq) (pu time), each at most 1 */
    _iq bridge_allow;         /* Q24 pu flux, [0, CMC_BRIDGE_ALLOW_MAX]: the bridge's residual
                                 after the dead-time compensation, added to the UNBALANCE
                                 and OFFSET levels (current_model_check_set_bridge; 0 from
                                 init) */
    uint16_t seq_settle;      /* slow steps at speed before the sequence tests may trip */
    /* outputs */
    _iq r_alpha, r_beta;      /* Q24 pu flux: the residual r */
    _iq pos_d, pos_q;         /* Q24 pu flux: positive-sequence part of r (frame), low-passed */
    _iq neg_alpha, neg_beta;  /* Q24 pu flux: negative-sequence part of r, low-passed */
    _iq dc_alpha, dc_beta;    /* Q24 pu flux: DC part of r, low-passed */
    _iq r2, neg2, dc2;        /* Q24 pu^2: |r|^2, |neg|^2, |dc|^2 (diagnostic) */
    _iq q2;                   /* Q24 pu^2: |r - pos|^2, the fast MISMATCH's */
    _iq lag_d, lag_q;         /* Q24 pu flux: r - pos in the positive sequence's frame,
                                 low-passed (tau_seq): its lag in a transient (|.| < 8) */
    uint16_t fault;           /* 1 once tripped, until current_model_check_reset */
    uint16_t cause;           /* CMC_x bits */
    /* state */
    _iq su_alpha, su_beta;    /* Q24 pu: the window's voltage sum */
    uint16_t n;               /* periods summed */
    uint16_t n_off;           /* periods of the window with the bridge off */
    uint16_t primed;          /* the previous sample below is valid */
    uint16_t at_speed;        /* slow steps with |w_s| > ws_min, saturating at seq_settle */
    uint16_t model_n;         /* sequence steps since the model last stepped (rebase),
                                 saturating at seq_settle: the fast MISMATCH waits for it */
    uint16_t phase;           /* the sequence tests' half of the next window (0, 1) */
    uint16_t seq_due;         /* 1: the residual ran, its half is still to run */
    uint16_t slow;            /* the last residual's |w_s| was within ws_min: UNBALANCE and
                                 OFFSET wait (the positive sequence runs on) */
    _iq thr;                  /* Q24 pu flux: the last residual's MISMATCH level (< 6): the
                                 fast test's; abs(r)'s is thr + r_allow_emf */
    _iq neg_level2, dc_level2;/* Q24 pu^2: the last sequence test's UNBALANCE and OFFSET
                                 levels, squared as compared (< 11, < 25) */
    _iq i_alpha_prev, i_beta_prev, psi_alpha_prev, psi_beta_prev;
} current_model_check_t;

/**
 * Float, once.  Ts_s: PWM period; slots: PWM periods per slow step (the
 * window, 1..CMC_N_MAX); w_base_rad_s: the time base; tau_r_s: the
 * residual's memory; tau_seq_s: the sequence low-passes; r_max_pu: MISMATCH
 * level (pu current); k_neg: UNBALANCE level (negative-sequence current per
 * unit of |i|); d_max_pu: OFFSET level (pu current); ws_min_pu: the speed
 * above which the sequence tests run.  On error: zeroed with fault = 1.
 */
cmc_status_t current_model_check_init(current_model_check_t *c, float Ts_s, uint16_t slots,
                                      float w_base_rad_s, float tau_r_s, float tau_seq_s,
                                      float r_max_pu, float k_neg, float d_max_pu,
                                      float ws_min_pu);

/**
 * Float, once, after init: the sequence tests' allowance for the bridge's
 * voltage error the dead-time compensation leaves, k_bridge e_pole tau_r
 * (pu flux: a voltage error held over the residual's memory), added to the
 * UNBALANCE and OFFSET levels like the leak (the -5th harmonic reaches
 * OFFSET's low-pass at -5 w_e, UNBALANCE's at -4 w_e: the same allowance
 * covers both; without it the family's 55 kW 6-pole 690 V, 3.5 us, reached
 * 0.83 of OFFSET's level at its nominal point and tripped CURRENT_SENSOR on
 * a healthy sensor at i_M x0.8 and x1.2 and a half-rate ramp).  e_pole_pu: one pole's
 * saturated error (vdc td/Ts + v_drop), pu; k_bridge: the fraction left.
 * Why: the compensation's error is a harmonic voltage (the -5th turns at
 * -4 w_e in the negative sequence's frame, 60 Hz at the tests' 0.3 pu of
 * 50 Hz, what the 50 ms low-pass lets through is 1/19 of it) that scales with
 * the bridge's E, not with sigma Ls: a 690 V motor of sigma 0.05 with a
 * 3.5 us dead time reached 0.98 of a level set from sigma Ls alone.
 * CMC_ERR_ARG (allowance unchanged) if the result is not in
 * [0, CMC_BRIDGE_ALLOW_MAX].
 */
cmc_status_t current_model_check_set_bridge(current_model_check_t *c, float e_pole_pu,
                                            float k_bridge, float tau_r_s, float w_base_rad_s);

/** Every PWM period: the voltage applied over the period that just ended
 *  (Q24 pu, 0 while the bridge was off) and whether the bridge switched in
 *  it.  Two saturations, two additions. */
static inline void current_model_check_accumulate(current_model_check_t *c, _iq u_alpha,
                                                  _iq u_beta, uint16_t on)
{
    c->su_alpha += _IQsat(u_alpha, _IQ(CMC_IN_MAX), _IQ(-CMC_IN_MAX));
    c->su_beta += _IQsat(u_beta, _IQ(CMC_IN_MAX), _IQ(-CMC_IN_MAX));
    c->n++;
    c->n_off |= (uint16_t)(on ^ 1u);
}

/** Every slow step, after the window's accumulate calls (inputs set):
 *  current_model_check_residual and then its half of the sequence tests. */
void current_model_check_step(current_model_check_t *c);

/** The same in two parts, for a caller that spreads them over two ISRs
 *  (the drive's multi-rate schedule, drive_safety.c): the residual and its
 *  MISMATCH test over the window (the inputs set, after the window's
 *  accumulate calls), ... */
void current_model_check_residual(current_model_check_t *c);

/** ... and, before the next residual, the sequence tests' half `phase`
 *  (0: the positive sequence's low-pass; 1: the negative sequence, the DC
 *  and their tests, these only while the residual's |w_s| was above ws_min)
 *  on that residual: it runs only when `phase` is the half due in this
 *  window (the halves alternate from window to window), otherwise returns
 *  at once.  A caller that calls
 *  both halves, each in its own ISR, has each ISR carry one half at most. */
void current_model_check_half(current_model_check_t *c, uint16_t phase);

/** Clear the fault and the state (the drive's fault reset). */
void current_model_check_reset(current_model_check_t *c);

#endif /* CURRENT_MODEL_CHECK_H */
