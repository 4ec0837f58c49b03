/* target_telemetry: the $T frame parsed back field by field by an
 * independent parser written here (sscanf + NMEA XOR checksum), the $C
 * commands, and the non-blocking drop when the ring is full. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "telemetry.h"

static telemetry_t s_t;

static size_t drain(telemetry_t *t, char *buf, size_t cap)
{
    size_t n = 0u;
    uint16_t c;
    while (n + 1u < cap && telemetry_tx_pop(t, &c) != 0u) {
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    return n;
}

static unsigned nmea_ck(const char *s)   /* XOR between '$' and '*' */
{
    unsigned ck = 0u;
    for (s++; *s != '\0' && *s != '*'; s++) {
        ck ^= (unsigned char)*s;
    }
    return ck;
}

static void test_frame_round_trip(void **state)
{
    drive_telemetry_t d;
    char buf[400];
    unsigned f[6], ck;
    unsigned q[TLM_Q24_FIELDS];
    int n;
    size_t len;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    d.state = 7u; d.fault = 0x12u; d.pwm_on = 1u; d.params_valid = 1u;
    d.speed = _IQ(0.5);    d.speed_ref = _IQ(-0.25); d.i_m = _IQ(0.328125);
    d.i_t = _IQ(-1.5);     d.vdc = _IQ(1.75);        d.Rs = _IQ(0.0625);
    d.Rr = _IQ(0.03125);   d.Lm = _IQ(1.25);         d.Lr = _IQ(1.5);
    d.psi_r = _IQ(-0.125); d.Tr = _IQ20(1000.0);   /* Q20: a large motor's Tr fits */
    assert_int_equal(telemetry_send(&s_t, &d, 4321u), 1);
    len = drain(&s_t, buf, sizeof buf);
    assert_int_equal(len, strlen(buf));
    assert_int_equal(len, 136u);   /* 2 + 6*5 + 11*9 + 5 characters */
    n = sscanf(buf, "$T,%4x,%4x,%4x,%4x,%4x,%4x,%8x,%8x,%8x,%8x,%8x,%8x,%8x,%8x,%8x,%8x,%8x*%2x\r\n",
               &f[0], &f[1], &f[2], &f[3], &f[4], &f[5], &q[0], &q[1], &q[2], &q[3], &q[4],
               &q[5], &q[6], &q[7], &q[8], &q[9], &q[10], &ck);
    assert_int_equal(n, 18);
    assert_int_equal(f[0], 0u); assert_int_equal(f[1], 7u); assert_int_equal(f[2], 0x12u);
    assert_int_equal(f[3], 1u); assert_int_equal(f[4], 1u); assert_int_equal(f[5], 4321u);
    /* dyadic values: their Q24 images are exact in both builds */
    assert_int_equal((int32_t)q[0], 8388608);      /* 0.5 * 2^24 */
    assert_int_equal((int32_t)q[1], -4194304);
    assert_int_equal((int32_t)q[2], 5505024);      /* 0.328125 * 2^24 */
    assert_int_equal((int32_t)q[3], -25165824);
    assert_int_equal((int32_t)q[4], 29360128);
    assert_int_equal((int32_t)q[10], 1048576000);  /* Tr in Q20 on the wire: 1000 * 2^20 */
    assert_int_equal(ck, nmea_ck(buf));
    assert_int_equal(buf[strlen(buf) - 2], '\r');
    assert_int_equal(s_t.seq, 1u);
}

/* $A (the adaptive sequence): the adaptation fields after their own header, the same
 * framing and checksum as $T; it counts in the same sequence. */
static void test_adapt_frame(void **state)
{
    drive_telemetry_t d;
    char buf[256];
    unsigned f[4], ck;
    unsigned q[TLM_ADAPT_Q24_FIELDS];
    int n;
    size_t len;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    d.pass = 2u; d.track_valid = 1u; d.params_tracked = 1u;
    d.Rs_dc = _IQ(0.59375); d.sigma_ls_dc = _IQ(0.859375);
    d.Rr_track = _IQ(0.25); d.Tr_track = _IQ20(300.25);
    assert_int_equal(telemetry_send(&s_t, &d, 0u), 1);
    (void)drain(&s_t, buf, sizeof buf);
    assert_int_equal(telemetry_send_adapt(&s_t, &d), 1);
    len = drain(&s_t, buf, sizeof buf);
    assert_int_equal(len, strlen(buf));
    assert_int_equal(len, 63u);   /* 2 + 4*5 + 4*9 + 5 characters */
    n = sscanf(buf, "$A,%4x,%4x,%4x,%4x,%8x,%8x,%8x,%8x*%2x\r\n", &f[0], &f[1], &f[2], &f[3],
               &q[0], &q[1], &q[2], &q[3], &ck);
    assert_int_equal(n, 9);
    assert_int_equal(f[0], 1u);   /* the second frame of this link */
    assert_int_equal(f[1], 2u); assert_int_equal(f[2], 1u); assert_int_equal(f[3], 1u);
    /* dyadic values: exact in both builds */
    assert_int_equal((int32_t)q[0], 9961472);     /* 0.59375 * 2^24 */
    assert_int_equal((int32_t)q[1], 14417920);    /* 0.859375 * 2^24 */
    assert_int_equal((int32_t)q[2], 4194304);
    assert_int_equal((int32_t)q[3], 314834944);   /* Tr_track in Q20: 300.25 * 2^20 */
    assert_int_equal(ck, nmea_ck(buf));
    assert_int_equal(s_t.seq, 2u);
}

/* $S: the ISR's overrun count and load, the link's own counters, 4 hex
 * digits each, the same framing and checksum; counted in the sequence. */
static void test_status_frame(void **state)
{
    drive_telemetry_t d;
    char buf[128];
    unsigned f[5], ck;
    int n;
    size_t len;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    d.isr_overruns = 0x1234u;
    s_t.dropped = 7u;
    s_t.rx_errors = 0xBEEFu;
    assert_int_equal(telemetry_send_status(&s_t, &d, 0xFFFFu), 1);
    len = drain(&s_t, buf, sizeof buf);
    assert_int_equal(len, strlen(buf));
    assert_int_equal(len, 32u);   /* 2 + 5*5 + 5 characters */
    n = sscanf(buf, "$S,%4x,%4x,%4x,%4x,%4x*%2x\r\n", &f[0], &f[1], &f[2], &f[3], &f[4], &ck);
    assert_int_equal(n, 6);
    assert_int_equal(f[0], 0u);
    assert_int_equal(f[1], 0x1234u);
    assert_int_equal(f[2], 0xFFFFu);
    assert_int_equal(f[3], 7u);
    assert_int_equal(f[4], 0xBEEFu);
    assert_int_equal(ck, nmea_ck(buf));
    assert_int_equal(s_t.seq, 1u);
}

/* $Q: the publication's reason (4 hex) and eight Q24 fields: the six
 * confidences (one negative: not available), the residual and the
 * amplification; same framing and checksum; counted in the sequence. */
static void test_quality_frame(void **state)
{
    drive_telemetry_t d;
    char buf[160];
    unsigned f[2], q[8], ck;
    int n;
    size_t len;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    d.publish_reason = 5u;                 /* low_confidence */
    d.conf[0] = -_IQ(1.0);                 /* not available */
    d.conf[1] = _IQ(0.03125);              /* dyadic values: exact in both builds */
    d.conf[5] = _IQ(0.25);
    d.conf_residual = _IQ(0.0009765625);   /* 2^-10 */
    d.conf_amp = _IQ(40.0);
    assert_int_equal(telemetry_send_quality(&s_t, &d), 1);
    len = drain(&s_t, buf, sizeof buf);
    assert_int_equal(len, strlen(buf));
    assert_int_equal(len, 89u);   /* 2 + 2*5 + 8*9 + 5 characters */
    n = sscanf(buf, "$Q,%4x,%4x,%8x,%8x,%8x,%8x,%8x,%8x,%8x,%8x*%2x\r\n", &f[0], &f[1], &q[0],
               &q[1], &q[2], &q[3], &q[4], &q[5], &q[6], &q[7], &ck);
    assert_int_equal(n, 11);
    assert_int_equal(f[0], 0u);
    assert_int_equal(f[1], 5u);
    assert_int_equal((int32_t)q[0], -16777216);
    assert_int_equal((int32_t)q[1], 524288);      /* 0.03125 * 2^24 */
    assert_int_equal((int32_t)q[2], 0);
    assert_int_equal((int32_t)q[5], 4194304);
    assert_int_equal((int32_t)q[6], 16384);
    assert_int_equal((int32_t)q[7], 671088640);   /* 40 * 2^24 */
    assert_int_equal(ck, nmea_ck(buf));
    assert_int_equal(s_t.seq, 1u);
}

static void test_ring_full_drops_whole_frames(void **state)
{
    drive_telemetry_t d;
    char buf[2048];
    uint16_t sent = 0u, i;
    size_t len;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    for (i = 0u; i < 10u; i++) {
        sent = (uint16_t)(sent + telemetry_send(&s_t, &d, 0u));
    }
    /* a frame is 2+6*5+11*9+5 = 136 characters; the ring keeps 767: 5 fit */
    assert_int_equal(sent, 5u);
    assert_int_equal(s_t.dropped, 5u);
    len = drain(&s_t, buf, sizeof buf);
    assert_int_equal(len, 5u * 136u);
    /* no partial frame: every frame starts with $T */
    assert_int_equal(buf[136], '$');
    assert_int_equal(buf[544], '$');
}

/* The ring packs two characters per word: 63-character $A frames start at
 * odd and even positions in turn and wrap over the ring's end at every
 * parity; each comes out exactly as the first one did. */
static void test_packed_ring_wraps_at_any_position(void **state)
{
    drive_telemetry_t d;
    char first[100], buf[100];
    uint16_t i, odd_starts = 0u;
    (void)state;
    telemetry_init(&s_t);
    memset(&d, 0, sizeof d);
    d.pass = 2u; d.track_valid = 1u; d.Rs_dc = _IQ(0.0625); d.Tr_track = _IQ(-3.5);
    assert_int_equal(telemetry_send_adapt(&s_t, &d), 1);
    assert_int_equal(drain(&s_t, first, sizeof first), 63u);   /* 2 + 4*5 + 4*9 + 5 */
    for (i = 1u; i < 3u * TLM_TX_SIZE / 63u; i++) {
        odd_starts = (uint16_t)(odd_starts + (s_t.head & 1u));
        s_t.seq = 0u;   /* the same frame every time */
        assert_int_equal(telemetry_send_adapt(&s_t, &d), 1);
        assert_int_equal(drain(&s_t, buf, sizeof buf), 63u);
        assert_string_equal(buf, first);
    }
    assert_true(odd_starts >= 10u);   /* half of the 35 frames started at an odd position */
}

static tlm_cmd_t feed(const char *s)
{
    tlm_cmd_t last = TLM_CMD_NONE;
    for (; *s != '\0'; s++) {
        tlm_cmd_t c = telemetry_rx_byte(&s_t, (uint16_t)(unsigned char)*s);
        if (c != TLM_CMD_NONE) {
            last = c;
        }
    }
    return last;
}

static void test_commands(void **state)
{
    char frame[16];
    const char cmds[4] = { 'S', 'X', 'R', 'D' };
    const tlm_cmd_t want[4] = { TLM_CMD_START, TLM_CMD_STOP, TLM_CMD_RESET_FAULT, TLM_CMD_DLOG_ARM };
    int i;
    (void)state;
    telemetry_init(&s_t);
    for (i = 0; i < 4; i++) {
        snprintf(frame, sizeof frame, "$C,%c*", cmds[i]);
        snprintf(frame + 5, sizeof frame - 5, "%02X\r\n", nmea_ck(frame));
        assert_int_equal(feed(frame), want[i]);
    }
    assert_int_equal(s_t.rx_errors, 0u);
    /* bad checksum, unknown command, garbage, over-long: all rejected */
    assert_int_equal(feed("$C,S*00\r\n"), TLM_CMD_NONE);
    assert_int_equal(feed("$C,Q*"), TLM_CMD_NONE);
    assert_int_equal(feed("noise\r\n"), TLM_CMD_NONE);
    assert_int_equal(feed("$C,SSSSSSSSSSSSSSSSSSSS*00\r\n"), TLM_CMD_NONE);
    assert_true(s_t.rx_errors >= 3u);
    /* a good frame after the garbage still works */
    snprintf(frame, sizeof frame, "$C,S*%02X\n", 'C' ^ ',' ^ 'S');
    assert_int_equal(feed(frame), TLM_CMD_START);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_round_trip),
        cmocka_unit_test(test_adapt_frame),
        cmocka_unit_test(test_status_frame),
        cmocka_unit_test(test_quality_frame),
        cmocka_unit_test(test_ring_full_drops_whole_frames),
        cmocka_unit_test(test_packed_ring_wraps_at_any_position),
        cmocka_unit_test(test_commands),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
