/* target_bg_loop: the portable background loop shared by main.c and the
 * simulator's serial link: frame timing (every 750 ticks, across the 16-bit
 * tick wrap), the start-button edge, the command dispatch to the drive and
 * the data log, and the frames it queues (parsed back with sscanf). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "bg_loop.h"
#include "drive_types.h"

static bg_loop_t s_b;
static drive_t s_d;
static datalog_t s_log;

static void test_frames_every_period_across_the_wrap(void **state)
{
    uint32_t tick;
    uint16_t n = 0u, last = 0u, first = 0u;
    (void)state;
    bg_loop_init(&s_b, BG_TLM_PERIOD_TICKS);
    /* the tick counter as isr_ticks() gives it: uint16, wrapping every 4.37 s */
    for (tick = 1u; tick <= 200000u; tick++) {
        uint16_t now = (uint16_t)tick;
        if (bg_loop_frame_due(&s_b, now) != 0u) {
            if (n == 0u) {
                first = now;
            } else {
                assert_int_equal((uint16_t)(now - last), BG_TLM_PERIOD_TICKS);
            }
            last = now;
            n++;
        }
    }
    assert_int_equal(first, 750u);
    assert_int_equal(n, 200000u / 750u);   /* 266: none lost or doubled at the 3 wraps */
    /* polled less often than every tick (a slow background pass): the next
     * pair goes out at the first pass at or after the period */
    bg_loop_init(&s_b, BG_TLM_PERIOD_TICKS);
    assert_int_equal(bg_loop_frame_due(&s_b, 749u), 0u);
    assert_int_equal(bg_loop_frame_due(&s_b, 760u), 1u);
    assert_int_equal(bg_loop_frame_due(&s_b, 1509u), 0u);
    assert_int_equal(bg_loop_frame_due(&s_b, 1510u), 1u);
}

static void test_button_starts_on_the_press_edge_only(void **state)
{
    (void)state;
    bg_loop_init(&s_b, BG_TLM_PERIOD_TICKS);
    assert_int_equal(bg_loop_button(&s_b, 0u), TLM_CMD_NONE);
    assert_int_equal(bg_loop_button(&s_b, 1u), TLM_CMD_START);
    assert_int_equal(bg_loop_button(&s_b, 1u), TLM_CMD_NONE);   /* held */
    assert_int_equal(bg_loop_button(&s_b, 7u), TLM_CMD_NONE);   /* any non-zero: pressed */
    assert_int_equal(bg_loop_button(&s_b, 0u), TLM_CMD_NONE);
    assert_int_equal(bg_loop_button(&s_b, 1u), TLM_CMD_START);
}

static void test_commands_reach_the_drive_and_the_log(void **state)
{
    (void)state;
    memset(&s_d, 0, sizeof s_d);
    assert_int_equal(datalog_init(&s_log, 2u, _IQ(0.1)), 0u);
    bg_loop_apply(&s_d, &s_log, TLM_CMD_START);
    assert_int_equal(s_d.cmd_requests, DRIVE_CMD_BIT(DRIVE_CMD_START_IDENT));
    /* a second source in the same period (the button, then an SCI frame):
     * both requests are kept, none replaces the other */
    bg_loop_apply(&s_d, &s_log, TLM_CMD_STOP);
    bg_loop_apply(&s_d, &s_log, TLM_CMD_RESET_FAULT);
    bg_loop_apply(&s_d, &s_log, TLM_CMD_START);                 /* repeated: once */
    assert_int_equal(s_d.cmd_requests, DRIVE_CMD_BIT(DRIVE_CMD_START_IDENT) |
                                           DRIVE_CMD_BIT(DRIVE_CMD_STOP) |
                                           DRIVE_CMD_BIT(DRIVE_CMD_RESET_FAULT));
    bg_loop_apply(&s_d, &s_log, TLM_CMD_NONE);                  /* nothing changes */
    assert_int_equal(s_d.cmd_requests, 0xEu);
    assert_int_equal(s_log.state, DLOG_FREE);
    bg_loop_apply(&s_d, &s_log, TLM_CMD_DLOG_ARM);
    assert_int_equal(s_log.state, DLOG_ARMED);
    assert_int_equal(s_d.cmd_requests, 0xEu);   /* the log's, not the drive's */
    bg_loop_apply(&s_d, NULL, TLM_CMD_DLOG_ARM);                /* no log (the host): ignored */
}

static void test_send_queues_the_drive_snapshot(void **state)
{
    char buf[512];
    size_t n = 0u;
    uint16_t c;
    drive_telemetry_t tl;
    unsigned f[6], pass;
    (void)state;
    memset(&s_d, 0, sizeof s_d);
    s_d.telemetry.state = 5u;
    s_d.telemetry.params_valid = 1u;
    s_d.telemetry.pass = 2u;
    s_d.telemetry.publish_reason = 1u;   /* published */
    bg_loop_init(&s_b, BG_TLM_PERIOD_TICKS);
    bg_loop_send(&s_b, &s_d, 1234u, &tl);
    assert_int_equal(tl.state, 5u);
    while (n + 1u < sizeof buf && telemetry_tx_pop(&s_b.tlm, &c) != 0u) {
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    assert_int_equal(n, 136u + 63u + 32u + 89u);   /* one $T, one $A, one $S and one $Q */
    assert_int_equal(sscanf(buf, "$T,%4x,%4x,%4x,%4x,%4x,%4x,", &f[0], &f[1], &f[2], &f[3],
                            &f[4], &f[5]), 6);
    assert_int_equal(f[1], 5u);
    assert_int_equal(f[4], 1u);
    assert_int_equal(f[5], 1234u);
    assert_int_equal(sscanf(buf + 136, "$A,%4x,%4x,", &f[0], &pass), 2);
    assert_int_equal(f[0], 1u);
    assert_int_equal(pass, 2u);
    /* $S: its sequence number and the same ISR load */
    assert_int_equal(sscanf(buf + 136 + 63, "$S,%4x,%4x,%4x,", &f[0], &f[1], &f[2]), 3);
    assert_int_equal(f[0], 2u);
    assert_int_equal(f[2], 1234u);
    /* $Q: its sequence number and the publication's reason */
    assert_int_equal(sscanf(buf + 136 + 63 + 32, "$Q,%4x,%4x,", &f[0], &f[1]), 2);
    assert_int_equal(f[0], 3u);
    assert_int_equal(f[1], 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_every_period_across_the_wrap),
        cmocka_unit_test(test_button_starts_on_the_press_edge_only),
        cmocka_unit_test(test_commands_reach_the_drive_and_the_log),
        cmocka_unit_test(test_send_queues_the_drive_snapshot),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
