/**
 * @file publish_guard.h
 * Nothing learned while a fault developed stays published.  A fault is
 * latched some time after it begins (the encoder's frozen test 50 ms, the
 * sequence tests of the model check up to 3 tau_seq = 150 ms at speed):
 * what the identification extracted, or the tracker published, in that
 * time saw a lying sensor or a failing machine (paper motor, adaptive
 * sequence, encoder lost in RUN: the tracked Rr moved -4 % in the 50 ms
 * before the encoder fault latched, and stayed published).
 *
 * The guard keeps checkpoints of the published set, taken every window/2
 * while no fault is latched (three: the oldest is always between one and
 * one and a half windows old), and the time of every change of the set.
 * When a fault latches at t_f, a set published at or after t_f - window is
 * withdrawn: the newest checkpoint taken at or before t_f - window is put
 * back (or nothing is published, if it held nothing), and the fault's
 * code and the count are recorded.  An extraction still waiting while a
 * fault is latched is never published (the caller drops it).
 *
 * Time: ticks of the ISR's slow task (uint32_t: 13 days at 3.75 kHz),
 * written by the ISR (publish_guard_tick, one 32-bit store: atomic on the
 * C28x), read by the background.  Everything else runs in the background.
 * Cost: the ISR's tick and fault time ~25 cycles per slow step
 * (tools/bench_isr.py); the background pass ~100 cycles (comparisons and
 * copies of 6 words).
 */
#ifndef PUBLISH_GUARD_H
#define PUBLISH_GUARD_H

#include <stdint.h>
#include "IQmathLib.h"

/** One published set (the telemetry's fields, pu, Q24). */
typedef struct {
    _iq Rs, Rr, Lm, Lr, psi_r, Tr;
    uint16_t valid;          /* params_valid */
    uint16_t tracked;        /* params_tracked */
} publish_set_t;

#define PUBLISH_GUARD_CHECKPOINTS 3u

typedef struct {
    /* parameters */
    uint32_t window;         /* ticks: how long before a fault a set is suspect */
    /* ISR -> background */
    volatile uint32_t now;   /* ticks (slow steps) */
    volatile uint32_t t_fault;   /* tick at which the latched fault was seen */
    volatile uint16_t fault_code;    /* its code; 0: none since the last reset */
    /* outputs */
    uint16_t withdrawn;      /* sets withdrawn (saturating) */
    uint16_t reason;         /* the fault code of the last withdrawal */
    /* state (background) */
    publish_set_t cp[PUBLISH_GUARD_CHECKPOINTS];   /* checkpoints, newest first */
    uint32_t t_cp[PUBLISH_GUARD_CHECKPOINTS];
    uint16_t n_cp;           /* checkpoints held */
    publish_set_t last;      /* the set at the last pass */
    uint32_t t_change;       /* when it last changed */
    uint16_t changed_once;   /* t_change is valid */
    uint16_t handled;        /* the latched fault has been judged */
} publish_guard_t;

/** window_ticks >= 2.  Returns 0, or 1 (zeroed) for a bad window. */
int16_t publish_guard_init(publish_guard_t *g, uint32_t window_ticks);

/** ISR, every slow step: time, and the first slow step a fault is latched. */
static inline void publish_guard_tick(publish_guard_t *g, uint16_t fault_code)
{
    const uint32_t now = g->now + 1u;
    g->now = now;
    if ((uint16_t)((uint16_t)(fault_code != 0u) & (uint16_t)(g->fault_code == 0u)) != 0u) {
        g->t_fault = now;
        g->fault_code = fault_code;
    }
}

/** Background, after the pass's publishing, with the telemetry's set
 *  (in/out): note changes and checkpoints; when a fault is latched, judge
 *  once and, if the set is suspect, put the checkpoint back into @p s.
 *  Returns 1 if it withdrew the set in this call. */
uint16_t publish_guard_pass(publish_guard_t *g, publish_set_t *s);

/** Background, the fault reset: a new fault is judged again. */
void publish_guard_rearm(publish_guard_t *g);

#endif /* PUBLISH_GUARD_H */
