/**
 * @file telemetry.h
 * The SCI-A telemetry protocol (portable C: frames are built in and parsed
 * from RAM rings; sci_f2812.c moves the bytes to and from the SCI FIFOs).
 *
 * ASCII frames in the NMEA style, one per line, so a terminal shows them and
 * a script parses them:
 *
 *   $T,<seq>,<state>,<fault>,<pwm_on>,<valid>,<load>,<speed>,<speed_ref>,
 *      <i_m>,<i_t>,<vdc>,<Rs>,<Rr>,<Lm>,<Lr>,<psi_r>,<Tr>*<CK>\r\n
 *
 *   seq .. load   4 hex digits (uint16: frame counter, id_state_t, fault
 *                 code, 0/1, 0/1, ISR load in T1 ticks)
 *   speed .. Tr   8 hex digits: the per-unit value in Q24, two's complement
 *                 (value = (int32)hex / 2^24; bases in base_values.h);
 *                 Tr in Q20 (value = (int32)hex / 2^20: up to 2048 pu time)
 *   CK            2 hex digits: XOR of every character between '$' and '*'
 *
 *   $A,<seq>,<pass>,<track_valid>,<tracked>,<Rs_dc>,<sigma_ls_dc>,<Rr_track>,
 *      <Tr_track>*<CK>\r\n                       (adaptation, after each $T)
 *
 *   seq .. tracked  4 hex digits (frame counter, identification pass, 0/1
 *                   tracker valid, 0/1 the published set is the fused one)
 *   Rs_dc .. Tr_track  8 hex digits, Q24 pu as above, Tr_track Q20 as Tr
 *                   (0: not measured)
 *
 *   $S,<seq>,<overruns>,<load>,<dropped>,<rx_errors>*<CK>\r\n   (after each $A)
 *
 *   all 4 hex digits: frame counter; control ISRs that overran their period
 *   since start-up (isr_monitor.h, saturating; 3 in a row latch fault 10);
 *   the worst ISR duration since the last frame in T1 ticks (as $T's load;
 *   FFFF: an ISR overran); telemetry frames dropped for lack of room; command
 *   frames rejected or receive errors recovered from.
 *
 *   $Q,<seq>,<reason>,<c_Rs>,<c_Rr>,<c_Lm>,<c_Lr>,<c_psi>,<c_Tr>,<residual>,
 *      <amp>*<CK>\r\n                                 (after each $S)
 *
 *   the publication's verdict on the last identification (reason: 4 hex
 *   digits, drive_pub_reason_t: 0 pending, 1 published, 2 not_converged,
 *   3 low_excitation, 4 high_residual, 5 low_confidence, 6 implausible,
 *   7 fault, 8 timeout, 9 stopped) and, 8 hex digits Q24, the confidence of
 *   each parameter of the set judged as a fraction (0.01 = 1 %; negative:
 *   not available), the regression's residual and its amplification
 *   (ident_conf.h)
 *
 * Commands to the drive, same framing:  $C,<c>*<CK>\r\n  with c =
 *   S start the identification sequence   X stop
 *   R reset a latched fault               D arm the data-log trigger
 * A frame with a bad checksum or format is ignored (counted in rx_errors).
 *
 * Non-blocking: telemetry_send drops the whole frame (counted in dropped)
 * when the TX ring lacks room; nothing ever waits for the UART.
 */
#ifndef TELEMETRY_H
#define TELEMETRY_H

#include <stdint.h>
#include "drive.h"

#define TLM_TX_SIZE   768u    /* characters: > 2 bursts of $T (136), $A (63), $S (32), $Q (89) */
#define TLM_TX_WORDS  384u    /* two 8-bit characters per 16-bit word */
#if TLM_TX_WORDS * 2u != TLM_TX_SIZE
#error "the TX ring packs two characters per word"
#endif
#define TLM_RX_SIZE   16u
#define TLM_Q24_FIELDS 11u
#define TLM_ADAPT_Q24_FIELDS 4u
#define TLM_QUALITY_Q24_FIELDS 8u

typedef enum {
    TLM_CMD_NONE = 0,
    TLM_CMD_START,
    TLM_CMD_STOP,
    TLM_CMD_RESET_FAULT,
    TLM_CMD_DLOG_ARM,
    TLM_CMD_SELECT_STANDSTILL,   /* "$C,Z": the next starts at standstill */
    TLM_CMD_SELECT_ROTATING      /* "$C,M": the next starts the configured rotating sequence */
} tlm_cmd_t;

typedef struct {
    /* outputs */
    uint16_t seq;       /* frames queued so far (wraps) */
    uint16_t dropped;   /* frames dropped for lack of room */
    uint16_t rx_errors; /* command frames rejected */
    /* state */
    /* character i of the ring in word i/2, its low byte if i is even, its high
     * byte if odd: the frames are ASCII, and a char is a 16-bit word on the
     * C28x, so one character per word would take 768 words of .ebss */
    uint16_t tx[TLM_TX_WORDS];
    uint16_t head, tail;       /* ring: write at head, read at tail */
    uint16_t rx[TLM_RX_SIZE];
    uint16_t rx_len;           /* 0 while waiting for '$' */
} telemetry_t;

void telemetry_init(telemetry_t *t);
/** Queue one $T frame.  Returns 1 if queued, 0 if dropped. */
uint16_t telemetry_send(telemetry_t *t, const drive_telemetry_t *s, uint16_t isr_load);
/** Queue one $A frame (the adaptive sequence: pass, track_valid, params_tracked; Rs_dc,
 *  sigma_ls_dc, Rr_track, Tr_track in Q24).  Returns 1 if queued, 0 if
 *  dropped.  The $T format is unchanged. */
uint16_t telemetry_send_adapt(telemetry_t *t, const drive_telemetry_t *s);
/** Queue one $S frame (ISR overruns, the ISR load as $T, the link's own
 *  dropped and rejected counts).  Returns 1 if queued, 0 if dropped. */
uint16_t telemetry_send_status(telemetry_t *t, const drive_telemetry_t *s, uint16_t isr_load);
/** Queue one $Q frame (the publication's reason, the six confidences, the
 *  residual and the amplification in Q24).  Returns 1 if queued, 0 if
 *  dropped. */
uint16_t telemetry_send_quality(telemetry_t *t, const drive_telemetry_t *s);
/** Next character to transmit; returns 0 when the ring is empty. */
uint16_t telemetry_tx_pop(telemetry_t *t, uint16_t *c);
/** Feed one received character; returns a command when a valid $C frame
 *  ends with this character, TLM_CMD_NONE otherwise. */
tlm_cmd_t telemetry_rx_byte(telemetry_t *t, uint16_t c);

#endif /* TELEMETRY_H */
