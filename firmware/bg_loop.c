/**
 * @file bg_loop.c
 * The portable part of the background loop (see bg_loop.h).
 */
#include <stddef.h>

#include "bg_loop.h"

void bg_loop_init(bg_loop_t *b, uint16_t period_ticks)
{
    telemetry_init(&b->tlm);
    b->period_ticks = period_ticks;
    b->last_tlm = 0u;
    b->button_prev = 0u;
}

tlm_cmd_t bg_loop_button(bg_loop_t *b, uint16_t pressed)
{
    uint16_t now = (pressed != 0u) ? 1u : 0u;
    tlm_cmd_t cmd = (now != 0u && b->button_prev == 0u) ? TLM_CMD_START : TLM_CMD_NONE;
    b->button_prev = now;
    return cmd;
}

void bg_loop_apply(drive_t *d, datalog_t *dlog, tlm_cmd_t cmd)
{
    switch (cmd) {
    case TLM_CMD_START:
        drive_command(d, DRIVE_CMD_START_IDENT);
        break;
    case TLM_CMD_STOP:
        drive_command(d, DRIVE_CMD_STOP);
        break;
    case TLM_CMD_RESET_FAULT:
        drive_command(d, DRIVE_CMD_RESET_FAULT);
        break;
    case TLM_CMD_SELECT_STANDSTILL:
        drive_command(d, DRIVE_CMD_SELECT_STANDSTILL);
        break;
    case TLM_CMD_SELECT_ROTATING:
        drive_command(d, DRIVE_CMD_SELECT_ROTATING);
        break;
    case TLM_CMD_DLOG_ARM:
        if (dlog != NULL) {
            datalog_arm(dlog);
        }
        break;
    case TLM_CMD_NONE:
    default:
        break;
    }
}

uint16_t bg_loop_frame_due(bg_loop_t *b, uint16_t now)
{
    /* modulo-2^16 difference: correct across the tick counter's wrap */
    if ((uint16_t)(now - b->last_tlm) < b->period_ticks) {
        return 0u;
    }
    b->last_tlm = now;
    return 1u;
}

void bg_loop_send(bg_loop_t *b, const drive_t *d, uint16_t isr_load, drive_telemetry_t *tl)
{
    drive_get_telemetry(d, tl);
    (void)telemetry_send(&b->tlm, tl, isr_load);
    (void)telemetry_send_adapt(&b->tlm, tl);
    (void)telemetry_send_status(&b->tlm, tl, isr_load);
    (void)telemetry_send_quality(&b->tlm, tl);
}
