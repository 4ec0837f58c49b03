/**
 * @file bg_loop.h
 * The portable part of the background loop (main.c on the F2812; the
 * simulator's serial link, host_sim/sim/sim_serial.c, on the host): the
 * command dispatch and the telemetry frame timing.  Portable C (no
 * registers): the board's own parts (SCI FIFOs, button pin, trip latch, LED,
 * watchdog) stay in main.c.
 *
 * One pass of the board's loop, in this order:
 *   drive_background();
 *   bg_loop_apply(.., bg_loop_button(.., pin));        start button edge
 *   bg_loop_apply(.., <command from the SCI bytes>);   $C,S / X / R / D
 *   if (bg_loop_frame_due(.., isr_ticks()))            every 750 periods:
 *       bg_loop_send(.., isr_load_max(), ..);          $T, $A, $S and $Q
 * (isr_load_max() resets the worst ISR time: it is read only when a frame
 * goes out, so the load field covers the whole frame period.)
 */
#ifndef BG_LOOP_H
#define BG_LOOP_H

#include <stdint.h>
#include "datalog.h"
#include "drive.h"
#include "telemetry.h"

/* 20 telemetry frame bursts per second: one every 750 control periods at 15 kHz */
#define BG_TLM_PERIOD_TICKS 750u

typedef struct {
    /* parameters */
    uint16_t period_ticks;   /* control periods between two frame pairs */
    /* state */
    uint16_t last_tlm;       /* tick of the last frame pair */
    uint16_t button_prev;    /* start button at the last pass, 0/1 */
    telemetry_t tlm;         /* the protocol's rings (telemetry.h) */
} bg_loop_t;

/** Rings empty, the first frame pair period_ticks after tick 0. */
void bg_loop_init(bg_loop_t *b, uint16_t period_ticks);
/** The start button (1 = pressed): TLM_CMD_START on a press, TLM_CMD_NONE
 *  otherwise (holding it does not repeat). */
tlm_cmd_t bg_loop_button(bg_loop_t *b, uint16_t pressed);
/** Hand a command to the drive (START, STOP, RESET_FAULT: drive_command,
 *  acted on by the next drive_background) or to the data log (DLOG_ARM;
 *  @p dlog may be NULL where there is none).  The board clears its own trip
 *  latch before a RESET_FAULT (main.c).  TLM_CMD_NONE does nothing. */
void bg_loop_apply(drive_t *d, datalog_t *dlog, tlm_cmd_t cmd);
/** 1 when period_ticks control periods have passed since the last frame
 *  pair (@p now: the ISR tick counter, modulo 2^16, correct across its
 *  wrap); the pair is then counted as sent at @p now.  0 otherwise. */
uint16_t bg_loop_frame_due(bg_loop_t *b, uint16_t now);
/** Queue a $T frame (with @p isr_load), an $A, an $S and a $Q frame of the
 *  drive's telemetry snapshot, which @p tl receives.  Each frame is queued whole or
 *  dropped and counted (telemetry_send). */
void bg_loop_send(bg_loop_t *b, const drive_t *d, uint16_t isr_load, drive_telemetry_t *tl);

#endif /* BG_LOOP_H */
