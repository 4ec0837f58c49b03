/**
 * @file stall_check.h
 * Rotor plausibility beyond the encoder's own checks (encoder_check.h):
 * what the motor really does when the encoder and the model disagree.
 *
 *  - count step (every period, and over the slow task's window): the QEP's
 *    count difference cannot change by more than the encoder's
 *    quantisation between two consecutive periods (or windows): the
 *    mechanics allow a change of alpha T^2 counts (paper motor at its
 *    largest torque: 0.004 counts per period), so a step change beyond
 *        step_abs + |d(k-1)| / 4          counts
 *    (2 counts of quantisation and edge jitter, plus a quarter of the
 *    speed: no motor changes its speed by 25 % in 67 or 267 us) is the
 *    encoder, not the rotor; a window is also compared with the one before
 *    the last (a stop within a window spreads its step over two).  It catches a count stream that stops while
 *    the rotor turns at >= 3 counts per period (paper motor: 675 r/min;
 *    1.1 kW and 15 kW: 220 r/min) in the period it stops, and at >= 3
 *    counts per window (a quarter of that) within the window, before the
 *    rotor-flux model that turns with the encoder angle makes the model
 *    check (current_model_check.h) see the missing back-EMF as a current
 *    fault.  -> FAULT_ENCODER.
 *
 *  - locked rotor (slow task): when the encoder's frozen test trips (no
 *    count in 50 ms while |i_T| is high, encoder_check.h), either the
 *    encoder is dead and the rotor turns, or the rotor is locked.  The
 *    model check's residual r tells: a back-EMF of rotation that the
 *    drive's model (rotor speed from the encoder, i.e. 0) does not predict
 *    lies on the frame's T axis, r_T ~ tau_r w_r |psi_e| (psi_e = (Lm/Lr)
 *    psi_r), while the model's Rs error lies along the current vector (as
 *    large as the back-EMF at a few Hz: Rs 30 % off at the torque limit
 *    fakes 0.34 pu on the paper motor).  The cross product
 *        c = (r_T i_M - r_M i_T) sgn(i_T)  ~  tau_r w_r |psi_e| i_M
 *    removes the part along the current, and its sign says whether the
 *    rotor turns the way the torque pushes it.  A locked rotor agrees with
 *    the standstill model (slip = synchronous speed: c ~ 0; a believed Lm
 *    too large makes the model predict more than the motor: c < 0); a
 *    dead encoder on a turning rotor gives c > 0.  Decision:
 *    c < w_min tau_r |psi_e| i_M -> locked (FAULT_STALL), else the encoder
 *    (FAULT_ENCODER, the encoder check's own code).  Limit: a dead encoder
 *    on a rotor slower than w_min (in the residual's ~tau_r memory) reads
 *    as a stall; the safe state is the same (PWM off).
 *
 * Cost on the C28x (tools/bench_isr.py): the count step ~140 cycles per
 * slow step; the decision (5 multiplies, once per frozen trip) ~80 cycles.
 *
 * Scaling and overflow: count differences are int32_t (|d| <= 32768, so
 * every difference and |d|/4 stay below 2^17); r_M, r_T below 8 pu flux
 * (|r| <= 4 pu), currents saturated to +-4 pu: the cross product below 64;
 * the threshold (w_min tau_r) |psi_e| i_M below 8 x 4 x 4 = 128 would not
 * fit, so |psi_e| and i_M are saturated to 2 pu (a rated flux and current
 * are below 1.2 pu): below 32.
 */
#ifndef STALL_CHECK_H
#define STALL_CHECK_H

#include <stdint.h>
#include "IQmathLib.h"

typedef enum {
    STALL_CHECK_OK = 0,
    STALL_CHECK_ERR_ARG
} stall_check_status_t;

typedef struct {
    /* parameters */
    int32_t step_abs;      /* counts: the count step's allowance for quantisation */
    _iq w_min_tau;         /* Q24 pu: w_min tau_r (pu speed x pu time) */
    /* outputs */
    uint16_t enc_fault;    /* 1 once a count step was implausible, until reset */
    _iq cross;             /* Q24: the decision's c at the last frozen trip (diagnostic) */
    _iq cross_min;         /* Q24: its threshold there */
    /* state */
    uint16_t w_count;      /* T2CNT at the last window step */
    int32_t dw_prev;       /* the last window's count difference */
    int32_t dw_prev2;      /* the one before (a stop inside a window spreads over two) */
    uint16_t w_primed;     /* 0, 1 (w_count valid), 2 (dw_prev valid), 3 (dw_prev2 too) */
} stall_check_t;

/** step_abs_counts >= 1; w_min_pu in (0, 1]; tau_r_pu in (0, 8]. */
stall_check_status_t stall_check_init(stall_check_t *s, int32_t step_abs_counts,
                                      float w_min_pu, float tau_r_pu);

/** 1 if the count difference @p d cannot follow @p prev (see the file
 *  comment). */
static inline uint16_t stall_check_implausible(const stall_check_t *s, int32_t d, int32_t prev)
{
    const int32_t diff = d - prev;
    const int32_t step = (diff < 0) ? -diff : diff;
    const int32_t mag = (prev < 0) ? -prev : prev;
    return (uint16_t)(step > s->step_abs + (mag >> 2));   /* mag >= 0: the shift is /4 */
}

/** Every slow step while the bridge switches: the count over the window
 *  since the last call (T2CNT @p count, modulo 2^16). */
void stall_check_window_step(stall_check_t *s, uint16_t count, uint16_t active);

/** At a frozen-encoder trip: 1 for a locked rotor, 0 for a dead encoder.
 *  r_alpha, r_beta: the model check's residual (pu flux); sin/cos of the
 *  frame angle; psi_e: |(Lm/Lr) psi_r| of the drive's model (pu flux);
 *  i_m, i_t: the frame currents (pu). */
uint16_t stall_check_decide(stall_check_t *s, _iq r_alpha, _iq r_beta, _iq sin_t, _iq cos_t,
                            _iq psi_e, _iq i_m, _iq i_t);

void stall_check_reset(stall_check_t *s);

#endif /* STALL_CHECK_H */
