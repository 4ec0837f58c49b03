/**
 * @file sim_serial.h
 * The board's serial link on the host (motor_sim --serial PATH): a
 * pseudo-terminal whose slave side a PC program (imfoc, a terminal, pyserial)
 * opens as it would the USB-serial adapter on the board's SCI-A.  The bytes
 * go through the firmware's own protocol and background loop (telemetry.c,
 * bg_loop.c: the code main.c runs on the F2812): $T and $A frame pairs every
 * 750 ISRs (20 per second at 15 kHz), $C,S / X / R / D commands to
 * drive_command.  Host differences: the $T load field is 0 (no ISR timer on
 * the host) and $C,D is accepted but arms nothing (no data log on the host).
 *
 * The link is paced like a UART at the nominal baud rate (115200 8N1: 11 520
 * characters per simulated second); while no program has the port open the
 * characters go nowhere, as from a board with no cable.  The slave is raw
 * (cfmakeraw) at the nominal rate, which a pty otherwise ignores.
 *
 * sim_serial_hook() is a sim_options_t background_hook: after each
 * drive_background (1 kHz) it sleeps to hold the wall clock at the
 * simulated time divided by realtime_factor, moves the bytes, and ends the
 * run when the client closes the port (unless keep_open) or on SIGINT /
 * SIGTERM.
 */
#ifndef SIM_SERIAL_H
#define SIM_SERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "drive.h"

typedef struct {
    const char *link_path;     /* becomes a symlink to the pty's slave (/dev/pts/N) */
    double realtime_factor;    /* simulated seconds per wall second; 0: unpaced */
    uint32_t baud;             /* nominal; character rate baud / 10 (8N1); 0: the
                                  board's (BOARD_SCI_BAUD, 115200) */
    uint16_t keep_open;        /* 1: run on when the client closes the port */
} sim_serial_options_t;

typedef struct sim_serial sim_serial_t;

/** Create the pty and the symlink, install the SIGINT/SIGTERM handler.
 *  NULL on error with the reason in @p err. */
sim_serial_t *sim_serial_open(const sim_serial_options_t *o, char *err, size_t err_len);
/** The slave's device name (/dev/pts/N). */
const char *sim_serial_slave_name(const sim_serial_t *s);
/** The background hook (sim_run.h): returns 1 to end the run. */
int sim_serial_hook(void *ctx, drive_t *d, uint64_t isr_count, double t_s);
/** Why the run ended: "duration", "port closed by the client", "signal". */
const char *sim_serial_end_reason(const sim_serial_t *s);
/** Commands applied and frames queued / dropped (for the end-of-run line). */
void sim_serial_counts(const sim_serial_t *s, uint32_t *cmds, uint32_t *frames, uint16_t *dropped,
                       uint16_t *rx_errors);
/** Remove the symlink (if it is still ours), close the pty, free. */
void sim_serial_close(sim_serial_t *s);

#endif /* SIM_SERIAL_H */
