/**
 * @file current_check.h
 * Current-feedback plausibility (protections): the measured M/T currents must
 * follow their references.  With two phase sensors a sensor that is lost
 * with its output at the zero-current level (1.5 V: a broken signal path
 * after the level shift, a dead sensor with a mid-rail bias) reads 0 A, is
 * not at an ADC rail and never exceeds the trip level, while the current
 * loops drive the true current of that phase far above it (measured on the
 * paper motor: 28 A peak against an 18 A trip within 100 ms).  The only
 * symptom in the measurements is that the currents no longer follow their
 * references: the measured vector is confined to one line of the
 * alpha-beta plane and cannot rotate, so i_M and i_T swing at twice the
 * electrical frequency.
 *
 *     e   = |i_M,ref - i_M| + |i_T,ref - i_T|                       (pu)
 *     e_f += a (e - e_f),  a = 1 - exp(-Ts / tau)    (first-order low-pass)
 *     fault when e_f > e_max while active
 *
 * A healthy drive's e is large only during a reference step, for about the
 * current loop's time constant; the low-pass turns that into e_f ~ step *
 * T_loop / tau.  drive_init sets tau and e_max (values and the healthy
 * maximum measured over every scenario are in drive_init.c).
 *
 * At the voltage limit the test holds (e_f kept, no update): while the
 * loops' voltage is at the bus's limit (`limited`, set by the caller: the
 * drive ORs in svgen's overmod in every control ISR and, in the step's own
 * slot, a vector within 5 % of vdc / sqrt 3, drive_slow.c), the currents cannot
 * follow their references whatever the sensors do, and a tracking error is
 * the drive's own (measured: the paper's sequence on the 15 kW motor, whose
 * rotor warms by 40 % untracked, reaches 599 V / sqrt 3 and tripped here on
 * a healthy sensor).  A sensor lost at 0 A drives the loops into that limit
 * too; then the model check (current_model_check.h), which compares the
 * currents with the voltages applied and not with the references, finds it
 * (0.3-4 ms on the paper motor, docs/protections.md).
 *
 * Scaling and overflow of current_check_step: Q24 throughout.  Each input
 * is saturated to +-4 pu before the differences (references and
 * measurements are within +-2.5 pu, so this never acts on a real value),
 * each |error| <= 8 pu, e <= 16 pu; the filter increment a (e - e_f) is a
 * rounded product with |e - e_f| <= 16, e_f stays in [0, 16].  Nothing can
 * wrap, whatever the inputs.
 */
#ifndef CURRENT_CHECK_H
#define CURRENT_CHECK_H

#include <stdint.h>
#include "IQmathLib.h"
#include "iq_rmpy.h"

typedef struct {
    /* inputs (Q24, pu) */
    _iq i_m_ref, i_m, i_t_ref, i_t;
    uint16_t active;      /* 1 while the current loops run */
    uint16_t limited;     /* sticky: the voltage was at the bus's limit since the last
                             step (set by the caller, header); each step reads and clears it */
    /* parameters */
    _iq k_filt;           /* Q24: a = 1 - exp(-Ts/tau) */
    _iq e_max;            /* Q24, pu */
    /* outputs */
    _iq e_f;              /* Q24, pu: filtered tracking error */
    uint16_t fault;       /* 1 once tripped, until current_check_reset */
} current_check_t;

typedef enum {
    CURRENT_CHECK_OK = 0,
    CURRENT_CHECK_ERR_ARG   /* Ts, tau not > 0, tau < Ts, or e_max not in (0, 4) pu */
} current_check_status_t;

/** Float, once.  On error the struct is zeroed with fault = 1. */
current_check_status_t current_check_init(current_check_t *c, float Ts_s, float tau_s,
                                          float e_max_pu);
static inline _iq current_check_abs_err(_iq ref, _iq meas)
{
    /* each input clamped to +-4 pu first (real ones are within 2.5 pu), so
     * the difference is within +-8 pu whatever the caller passes */
    return _IQabs(_IQsat(ref, _IQ(4.0), _IQ(-4.0)) - _IQsat(meas, _IQ(4.0), _IQ(-4.0)));
}

static inline void current_check_step(current_check_t *c)
{
    _iq e;
    if (c->active == 0u) {
        c->e_f = _IQ(0.0);
        c->limited = 0u;
        return;
    }
    if (c->limited != 0u) {
        c->limited = 0u;   /* at the voltage limit: hold (header) */
        return;
    }
    e = current_check_abs_err(c->i_m_ref, c->i_m) + current_check_abs_err(c->i_t_ref, c->i_t);   /* <= 16 pu */
    c->e_f += _IQrmpy(c->k_filt, e - c->e_f);                          /* Q24*Q24 -> Q24 */
    if (c->e_f > c->e_max) {
        c->fault = 1u;
    }
}
void current_check_reset(current_check_t *c);

#endif /* CURRENT_CHECK_H */
