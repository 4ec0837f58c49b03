/* The standstill sequence (`[ident] sequence = standstill`, ident.static_id;
 * beyond the paper): the drive's side of the low-frequency injection
 * (standstill_lf.h) and of its fit and verdict (standstill_fit.h).
 *
 *   drive_static_init        drive_adapt_init's: the test's constants
 *   drive_static_slow        slot SEQUENCE while INJECT runs (flash set: the
 *                            state is the standstill sequence's alone)
 *   drive_static_background  once INJECT has ended: the fit, the
 *                            confidences, the publication or its refusal
 * The rotor must not turn: the encoder's displacement from INJECT's start
 * is watched, and a set from a rotor that moved more than
 * DRIVE_STATIC_MOVE_COUNTS is refused (rotor_turning).  The functions are
 * src/app's; the constants also set the simulator's run time. */
#ifndef DRIVE_STATIC_H
#define DRIVE_STATIC_H

#include "drive_types.h"

/* The least time the lock-in sums (both halves): 4 s, so that a small
 * motor's short periods (the paper motor's Tr = 20 ms) still average over
 * thousands of samples of the current's noise. */
#define DRIVE_STATIC_WINDOW_S 4.0f
/* Each harmonic's amplitude, of i_M: 0.25 (the multisine's trough at 0.44
 * i_M keeps every phase current's sign: standstill_lf.h). */
#define DRIVE_STATIC_AMPL_OF_IM 0.25f
/* Encoder counts the rotor may move from INJECT's start: the model holds
 * w_r = 0; a count of jitter at an edge is not a turn. */
#define DRIVE_STATIC_MOVE_COUNTS 1

/** Set-up (float, once).  0, or 1 if the test's constants are out of range
 *  (the configuration's check says which: DRIVE_LD_STATIC). */
int16_t drive_static_init(drive_t *d, const drive_config_t *c, float Ts);

/** Background, IDLE: the standstill sequence (@p on 1) or the configured
 *  rotating one for the next starts.  A drive whose standstill test or
 *  injection is not set up (ident.standstill = 0) marks the standstill one
 *  unavailable instead: its next starts are refused (no_standstill), never
 *  run turning. */
void drive_static_select(drive_t *d, uint16_t on);

/** Slot SEQUENCE, while the sequence is in INJECT. */
void drive_static_slow(drive_t *d);

/** Background: the verdict of a completed standstill sequence, once. */
void drive_static_background(drive_t *d);

#endif /* DRIVE_STATIC_H */
